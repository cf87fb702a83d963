//! LuxRender 0.x's scene vocabulary: the `multiimage` film (its tone map read as fleximage's,
//! its output settings warned once) and the materials `plastic`, `substrate`, `primer`,
//! `felt`, `clay`, `bluepaint`, `skin` with their parameters and defaults.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use foton::scene::desc::{ColorParam, MaterialDesc, SceneDesc, ToneMap};
use foton::scene::lxs::load_with;
use glam::Vec3;

fn load(name: &str, text: &str, defines: &[(&str, &str)]) -> SceneDesc {
    let dir = std::env::temp_dir().join(format!("foton-lxs-legacy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path: PathBuf = dir.join(format!("{name}.lxs"));
    std::fs::write(&path, text).unwrap();
    let defines: Vec<(String, String)> = defines
        .iter()
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    load_with(&path, &defines).unwrap_or_else(|e| panic!("{e}"))
}

const WORLD: &str = "WorldBegin\nShape \"sphere\" \"float radius\" [1]\nWorldEnd\n";

/// old-allmaterials' Film line (LuxBlend 0.1), with its output settings.
const MULTIIMAGE: &str = "# Lux Render v0.1 Scene File
Film \"multiimage\" \"integer xresolution\" [64] \"integer yresolution\" [48]
    \"string tonemapper\" [\"reinhard\"] \"float reinhard_burn\" [5.5]
    \"float reinhard_prescale\" [1.5] \"float reinhard_postscale\" [0.8] \"float gamma\" [2.0]
    \"float dither\" [0.0] \"float bloomwidth\" [0.0] \"float bloomradius\" [0.0]
    \"integer ldr_displayinterval\" [12] \"string igi_filename\" [\"a.igi\"]
    \"integer igi_writeinterval\" [120] \"string hdr_filename\" [\"a.exr\"]
    \"integer hdr_writeinterval\" [120] \"string ldr_filename\" [\"a.tga\"]
    \"integer ldr_writeinterval\" [120]
";

/// The multiimage film's Reinhard parameters reach the tone map: LuxRender 0.x's absolute
/// operator for the 0.1 scene, 1.x's when read as 1.6; its resolution and gamma are read; the
/// seven output settings give one warning naming them, and nothing else is warned.
#[test]
fn multiimage_reinhard_is_read_and_outputs_warned_once() {
    let scene = load("multiimage", &format!("{MULTIIMAGE}{WORLD}"), &[]);
    assert_eq!(
        scene.film.tonemap,
        ToneMap::ReinhardAbsolute {
            prescale: 1.5,
            postscale: 0.8,
            burn: 5.5
        }
    );
    assert_eq!(
        (
            scene.film.x_resolution,
            scene.film.y_resolution,
            scene.film.gamma
        ),
        (64, 48, 2.0)
    );
    let messages: Vec<&str> = scene.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(messages.len(), 1, "{messages:?}");
    for name in [
        "ldr_displayinterval",
        "igi_filename",
        "igi_writeinterval",
        "hdr_filename",
        "hdr_writeinterval",
        "ldr_filename",
        "ldr_writeinterval",
    ] {
        assert!(messages[0].contains(name), "{name}: {messages:?}");
    }
    let one_x = load(
        "multiimage-1x",
        &format!("{MULTIIMAGE}{WORLD}"),
        &[("lux_version", "1.6")],
    );
    assert_eq!(
        one_x.film.tonemap,
        ToneMap::Reinhard {
            prescale: 1.5,
            postscale: 0.8,
            burn: 5.5
        }
    );
}

/// `multiimage`'s defaults (`MultiImageFilm::CreateFilm`): tone mapper `reinhard`, burn 6 (not
/// fleximage's 7); `contrast` reads `contrast_displayadaptationY`; a bloom or dither that would
/// change the image is warned as not applied; an unknown tone mapper is warned.
#[test]
fn multiimage_defaults_and_other_tone_mappers() {
    let scene = load(
        "multiimage-defaults",
        &format!("# Lux Render v0.1 Scene File\nFilm \"multiimage\"\n{WORLD}"),
        &[],
    );
    assert_eq!(
        scene.film.tonemap,
        ToneMap::ReinhardAbsolute {
            prescale: 1.0,
            postscale: 1.0,
            burn: 6.0
        }
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let contrast = load(
        "multiimage-contrast",
        &format!(
            "Film \"multiimage\" \"string tonemapper\" [\"contrast\"] \
             \"float contrast_displayadaptationY\" [20] \"float bloomwidth\" [0.1] \
             \"float dither\" [0.5]\n{WORLD}"
        ),
        &[],
    );
    assert_eq!(contrast.film.tonemap, ToneMap::Contrast { ywa: 20.0 });
    let messages: Vec<&str> = contrast
        .warnings
        .iter()
        .map(|w| w.message.as_str())
        .collect();
    assert_eq!(messages.len(), 2, "{messages:?}");
    assert!(messages[0].contains("bloomwidth") && messages[1].contains("dither"));
    let unknown = load(
        "multiimage-nonlinear",
        &format!("Film \"multiimage\" \"string tonemapper\" [\"nonlinear\"]\n{WORLD}"),
        &[],
    );
    assert_eq!(unknown.film.tonemap, ToneMap::Linear { scale: 1.0 });
    assert_eq!(unknown.warnings.len(), 1);
}

fn material(kind_and_params: &str) -> (MaterialDesc, usize) {
    static FILES: AtomicUsize = AtomicUsize::new(0);
    let scene = load(
        &format!("material-{}", FILES.fetch_add(1, Ordering::Relaxed)),
        &format!(
            "WorldBegin\nMaterial {kind_and_params}\nShape \"sphere\" \"float radius\" [1]\nWorldEnd\n"
        ),
        &[],
    );
    let last = scene.materials.last().cloned().expect("a material");
    (last, scene.warnings.len())
}

/// `plastic` (`materials/plastic.cpp`): Kd 1, Ks 1, roughness 0.1 as Blinn's exponent 1 / r;
/// given values, constant textures included, are read.
#[test]
fn plastic_parameters_and_defaults() {
    let (defaults, warnings) = material("\"plastic\"");
    assert_eq!(warnings, 0);
    let MaterialDesc::BlinnPlastic {
        diffuse,
        specular,
        exponent,
    } = defaults
    else {
        panic!("{defaults:?}");
    };
    assert_eq!(diffuse, ColorParam::Constant(Vec3::ONE));
    assert_eq!(specular, ColorParam::Constant(Vec3::ONE));
    assert!((exponent - 10.0).abs() < 1e-4, "{exponent}");
    let (given, _) = material(
        "\"plastic\" \"color Kd\" [1 0.7588 0] \"color Ks\" [0.4 0.4 0.4] \"float roughness\" [0.01]",
    );
    let MaterialDesc::BlinnPlastic {
        diffuse, exponent, ..
    } = given
    else {
        panic!("{given:?}");
    };
    assert_eq!(diffuse, ColorParam::Constant(Vec3::new(1.0, 0.7588, 0.0)));
    assert!((exponent - 100.0).abs() < 1e-3, "{exponent}");
}

/// `substrate` (`materials/substrate.cpp`): Kd 0.5, Ks 0.5, uroughness and vroughness 0.1,
/// the exponents their inverses along u and v; 0 roughness clamps at pbrt-v1's 10,000.
#[test]
fn substrate_parameters_and_defaults() {
    let (defaults, warnings) = material("\"substrate\"");
    assert_eq!(warnings, 0);
    let MaterialDesc::FresnelBlend {
        diffuse,
        specular,
        exponents,
    } = defaults
    else {
        panic!("{defaults:?}");
    };
    assert_eq!(diffuse, ColorParam::Constant(Vec3::splat(0.5)));
    assert_eq!(specular, ColorParam::Constant(Vec3::splat(0.5)));
    assert!((exponents.0 - 10.0).abs() < 1e-4 && (exponents.1 - 10.0).abs() < 1e-4);
    let (given, _) = material("\"substrate\" \"float uroughness\" [0.01] \"float vroughness\" [0]");
    let MaterialDesc::FresnelBlend { exponents, .. } = given else {
        panic!("{given:?}");
    };
    assert!((exponents.0 - 100.0).abs() < 1e-3, "{exponents:?}");
    assert_eq!(exponents.1, 10_000.0);
}

/// The measured materials load as their Lafortune fits, each its own, without a warning (a
/// `bumpmap` is their only parameter).
#[test]
fn measured_materials_load_their_fits() {
    let mut diffuse = Vec::new();
    for kind in ["primer", "felt", "clay", "bluepaint", "skin"] {
        let (desc, warnings) = material(&format!("\"{kind}\""));
        assert_eq!(warnings, 0, "{kind}");
        let MaterialDesc::Lafortune(fit) = desc else {
            panic!("{kind}: {desc:?}");
        };
        diffuse.push(fit.diffuse);
    }
    // primer, felt and clay's diffuse albedos as their sources give them.
    assert_eq!(diffuse[0], Vec3::new(0.118230, 0.121218, 0.133209));
    assert_eq!(diffuse[1], Vec3::splat(0.025865));
    assert_eq!(diffuse[2], Vec3::new(0.383626, 0.260749, 0.274207));
    for (i, a) in diffuse.iter().enumerate() {
        for b in &diffuse[i + 1..] {
            assert_ne!(a, b);
        }
    }
}
