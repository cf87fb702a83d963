//! LuxRender materials read from `.lxs` text and rendered: bump maps and float parameters
//! given by spatially varying textures, each against a closed form.

use std::path::PathBuf;

use std::f32::consts::PI;

use crate::common;
use foton::scene::desc::{ColorParam, LightDesc, MaterialDesc, Roughness, SceneDesc};
use foton::settings::IntegratorKind;
use glam::Vec3;

/// Loads `world` (material and texture lines) over a 2 x 2 quad at z = 0 with uvs 0..1, lit
/// straight down by a distant light and seen from above by a camera that sees only the quad.
fn quad_scene(name: &str, world: &str) -> SceneDesc {
    quad_scene_lit_from(name, 1.0, world)
}

/// [`quad_scene`] with the distant light at z = `light_z` (1: the camera's side, -1: behind).
fn quad_scene_lit_from(name: &str, light_z: f32, world: &str) -> SceneDesc {
    let dir: PathBuf = std::env::temp_dir().join(format!("foton-lxs-materials-{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.lxs");
    let text = format!(
        r#"LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" [20]
Film "fleximage" "integer xresolution" [32] "integer yresolution" [32]
WorldBegin
LightSource "distant" "point from" [0 0 {light_z}] "point to" [0 0 0] "color L" [1 1 1]
{world}
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point P" [-1 -1 0  1 -1 0  1 1 0  -1 1 0] "float uv" [0 0  1 0  1 1  0 1]
WorldEnd
"#
    );
    std::fs::write(&path, text).unwrap();
    foton::scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The mean of the image: one bounce of the path tracer, so only the distant light's direct
/// light (sampled exactly: no noise but the mixes' choices).
fn mean_radiance(desc: SceneDesc, spp: u32) -> f32 {
    let mut options = common::options(spp, 1);
    options.integrator = Some(IntegratorKind::PathTracer);
    let image = common::render(desc, &options);
    image.iter().map(|p| p.element_sum() / 3.0).sum::<f32>() / image.len() as f32
}

/// A ramp displacement h = 2u over a quad 2 wide (dp/du = 2x) has slope dh/dx = 1: the bumped
/// normal (-1, 0, 1) / sqrt 2 sees the overhead light at cos = 1 / sqrt 2, so the matte quad
/// is 1 / sqrt 2 as bright as without the bump map. The light and the camera's one bounce are
/// exact (a delta light, a Lambertian), so the ratio is exact up to float rounding.
#[test]
fn a_bump_map_tilts_the_shading_normal_by_its_slope() {
    let ramp = r#"Texture "ramp" "float" "bilerp" "float v00" [0] "float v01" [0] "float v10" [2] "float v11" [2]"#;
    let flat = quad_scene(
        "flat",
        &format!("{ramp}\nMaterial \"matte\" \"color Kd\" [0.5 0.5 0.5]"),
    );
    let bumped = quad_scene(
        "bumped",
        &format!(
            "{ramp}\nMaterial \"matte\" \"color Kd\" [0.5 0.5 0.5] \"texture bumpmap\" [\"ramp\"]"
        ),
    );
    assert!(bumped.warnings.is_empty(), "{:?}", bumped.warnings);
    let ratio = mean_radiance(bumped, 2) / mean_radiance(flat, 2);
    assert!(
        (ratio - std::f32::consts::FRAC_1_SQRT_2).abs() < 2e-3,
        "bumped / flat {ratio}"
    );
}

/// matte's `sigma` from a varying texture (here one whose value is 30 degrees everywhere):
/// Oren-Nayar lit and seen along the normal is A R / pi with A = 1 - s^2 / (2 (s^2 + 0.33)),
/// s = 30 degrees in radians, against R / pi for the Lambertian.
#[test]
fn matte_sigma_from_a_texture() {
    let texture = r#"Texture "s" "float" "bilerp" "float v00" [30] "float v01" [30] "float v10" [30] "float v11" [30]"#;
    let lambert = quad_scene("lambert", "Material \"matte\" \"color Kd\" [0.5 0.5 0.5]");
    let rough = quad_scene(
        "rough",
        &format!(
            "{texture}\nMaterial \"matte\" \"color Kd\" [0.5 0.5 0.5] \"texture sigma\" [\"s\"]"
        ),
    );
    assert!(rough.warnings.is_empty(), "{:?}", rough.warnings);
    let s2 = 30f32.to_radians().powi(2);
    let a = 1.0 - s2 / (2.0 * (s2 + 0.33));
    // The camera sees the quad up to 7 degrees off the normal; with the light along the normal
    // Oren-Nayar's B term vanishes (beta = 0), so the ratio is A everywhere.
    let ratio = mean_radiance(rough, 1) / mean_radiance(lambert, 1);
    assert!(
        (ratio - a).abs() < 2e-3,
        "Oren-Nayar / Lambert {ratio}, A = {a}"
    );
}

/// mix's `amount` from a varying texture (0.25 everywhere): a quarter of white matte and three
/// quarters of black reflect as a quarter-white matte. Each sample picks one side, so the
/// image mean over N = 32 x 32 pixels x 16 spp choices has a relative standard deviation of
/// sqrt(0.25 * 0.75 / N) / 0.25 = 1.4%; the bound is 4 of them (the default amount, 0.5, would
/// give a ratio of 2).
#[test]
fn mix_amount_from_a_texture() {
    let texture = r#"Texture "a" "float" "bilerp" "float v00" [0.25] "float v01" [0.25] "float v10" [0.25] "float v11" [0.25]
MakeNamedMaterial "black" "string type" ["matte"] "color Kd" [0 0 0]
MakeNamedMaterial "white" "string type" ["matte"] "color Kd" [1 1 1]"#;
    let mixed = quad_scene(
        "mixed",
        &format!(
            "{texture}\nMaterial \"mix\" \"string namedmaterial1\" [\"black\"] \"string namedmaterial2\" [\"white\"] \"texture amount\" [\"a\"]"
        ),
    );
    assert!(mixed.warnings.is_empty(), "{:?}", mixed.warnings);
    let quarter = quad_scene(
        "quarter",
        "Material \"matte\" \"color Kd\" [0.25 0.25 0.25]",
    );
    let ratio = mean_radiance(mixed, 16) / mean_radiance(quarter, 16);
    assert!((ratio - 1.0).abs() < 0.056, "mix / quarter matte {ratio}");
}

/// The one material of `desc`, with its warnings.
fn only_material(desc: &SceneDesc) -> &MaterialDesc {
    assert_eq!(desc.materials.len(), 1, "{:?}", desc.materials);
    &desc.materials[0]
}

/// `metal` with a built-in `name` is the exact-Fresnel conductor with that metal's n and k:
/// gold's index has n well below 1 in red and above 1 in blue (its colour), and Blinn's
/// exponent 1 / roughness becomes the Beckmann-equivalent alpha sqrt(2 / (e + 2)).
#[test]
fn metal_by_name_is_a_measured_conductor() {
    let desc = quad_scene(
        "metal-gold",
        r#"Material "metal" "string name" ["gold"] "float roughness" [0.5]"#,
    );
    assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
    let MaterialDesc::Conductor {
        eta,
        k,
        roughness: Some(Roughness {
            alpha_u, alpha_v, ..
        }),
        ..
    } = only_material(&desc)
    else {
        panic!("{:?}", desc.materials)
    };
    assert!(eta.x < 0.5 && eta.z > 1.0 && k.x > 2.0, "{eta} {k}");
    let expected = (2.0f32 / (2.0 + 2.0)).sqrt();
    assert!((alpha_u - expected).abs() < 1e-6 && alpha_v == alpha_u);
}

/// `name` naming an `.nk` file (Luxpop: Angstroms, n, k) next to the scene: a flat index reads
/// back as itself; an unknown name is a warning and aluminium (LuxRender's fallback); a
/// malformed file is an error naming the `.nk` file and its line.
#[test]
fn metal_from_an_nk_file() {
    let dir = std::env::temp_dir().join("foton-lxs-materials-metal-nk");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("flat.nk"),
        "; flat index\n3000 0.5 3.0\n9000 0.5 3.0\n",
    )
    .unwrap();
    std::fs::write(dir.join("broken.nk"), "3000 0.5 3.0\n9000 0.5 x\n").unwrap();
    let material = |world: &str| {
        std::fs::write(
            dir.join("scene.lxs"),
            format!(
                "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n{world}\n\
                 Shape \"sphere\"\nWorldEnd\n"
            ),
        )
        .unwrap();
        foton::scene::load(&dir.join("scene.lxs"))
    };
    let desc = material(r#"Material "metal" "string name" ["flat.nk"]"#).unwrap();
    let MaterialDesc::Conductor { eta, k, .. } = only_material(&desc) else {
        panic!("{:?}", desc.materials)
    };
    assert!(
        (*eta - Vec3::splat(0.5)).abs().max_element() < 1e-4,
        "{eta}"
    );
    assert!((*k - Vec3::splat(3.0)).abs().max_element() < 1e-4, "{k}");

    let unknown = material(r#"Material "metal" "string name" ["unobtainium"]"#).unwrap();
    assert!(
        unknown
            .warnings
            .iter()
            .any(|w| w.message.contains("unobtainium")),
        "{:?}",
        unknown.warnings
    );
    assert!(matches!(
        only_material(&unknown),
        MaterialDesc::Conductor { .. }
    ));

    let error = material(r#"Material "metal" "string name" ["broken.nk"]"#).unwrap_err();
    assert!(error.location.file.ends_with("broken.nk"), "{error}");
    assert_eq!(error.location.line, 2, "{error}");
}

/// `mattetranslucent` lit from the camera's side, then from behind: with one bounce the
/// distant light (radiance 1, normal incidence, sampled exactly) gives R / pi and then T / pi,
/// to float rounding. `energyconserving` scales T by 1 - R.
#[test]
fn matte_translucent_reflects_kr_and_transmits_kt() {
    let material =
        r#"Material "mattetranslucent" "color Kr" [0.3 0.3 0.3] "color Kt" [0.5 0.5 0.5]"#;
    let above = quad_scene("translucent-above", material);
    assert!(above.warnings.is_empty(), "{:?}", above.warnings);
    let reflected = mean_radiance(above, 2) * PI;
    assert!((reflected - 0.3).abs() < 1e-5, "R: {reflected}");
    let below = quad_scene_lit_from("translucent-below", -1.0, material);
    let transmitted = mean_radiance(below, 2) * PI;
    assert!((transmitted - 0.5).abs() < 1e-5, "T: {transmitted}");

    let conserving = quad_scene(
        "translucent-conserving",
        &format!("{material} \"bool energyconserving\" [\"true\"]"),
    );
    let MaterialDesc::DiffuseTranslucent {
        transmittance: ColorParam::Constant(t),
        ..
    } = only_material(&conserving)
    else {
        panic!("{:?}", conserving.materials)
    };
    assert!(
        (*t - Vec3::splat(0.5 * 0.7)).abs().max_element() < 1e-6,
        "{t}"
    );
}

/// `LightSource "sky"` is the Preetham sky as an environment light: a white matte quad under
/// it (the distant light off) renders blue-white and lit, with no warning. `sunsky` adds the
/// sun as a distant light, without a warning, carrying the disc's illuminance; the sun overhead adds its irradiance E over
/// pi to the white quad's radiance: the mean of the sunsky render less that of the sky alone
/// is E / pi within five standard errors (box filter: the pixels are independent estimates,
/// and the quad, lit evenly, fills the image, so the pixels' spread is the noise).
#[test]
fn sky_light_renders() {
    let dir = std::env::temp_dir().join("foton-lxs-materials-sky");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = |light: &str| {
        let path = dir.join("scene.lxs");
        std::fs::write(
            &path,
            format!(
                "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [20]\n\
                 Film \"fleximage\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n\
                 PixelFilter \"box\"\nWorldBegin\n{light}\nMaterial \"matte\" \"color Kd\" [1 1 1]\n\
                 Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n\
                 \"point P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]\nWorldEnd\n"
            ),
        )
        .unwrap();
        foton::scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
    };
    let sky = scene(
        r#"LightSource "sky" "float gain" [0.001] "float turbidity" [2.2] "vector sundir" [0.3 0.2 0.9]"#,
    );
    assert!(sky.warnings.is_empty(), "{:?}", sky.warnings);
    let image = common::render(sky, &common::options(16, 1));
    let mean = image.iter().copied().sum::<Vec3>() / image.len() as f32;
    assert!(mean.is_finite() && mean.min_element() > 0.0, "{mean}");
    assert!(
        mean.z > mean.x,
        "a clear sky lights the quad blue-white: {mean}"
    );

    let light = |kind: &str| {
        format!(
            r#"LightSource "{kind}" "float gain" [0.001] "vector sundir" [0 0 1] "float relsize" [1]"#
        )
    };
    let sunsky = scene(&light("sunsky"));
    assert!(sunsky.warnings.is_empty(), "{:?}", sunsky.warnings);
    assert_eq!(sunsky.lights.len(), 2, "{:?}", sunsky.lights);
    let sun_irradiance = sunsky
        .lights
        .iter()
        .find_map(|light| match light {
            LightDesc::SunDisc {
                direction_to_light,
                radiance,
                sin_theta_max,
            } => {
                assert!((*direction_to_light - Vec3::Z).length() < 1e-6);
                // The integral of cos over the cone around the normal: pi sin^2 theta_max.
                Some(*radiance * PI * sin_theta_max * sin_theta_max)
            }
            _ => None,
        })
        .expect("sunsky has a sun disc");
    // The sun overhead at turbidity 2 has luminance 1.4964e9 cd/m^2 (the module's formulas
    // evaluated independently in Python, as in `scene::lxs::sun`'s tests), over a disc of
    // 6.7906e-5 sr (pi sin^2 theta_max is 3e-6 less): 101,610 lux on a surface facing it (the
    // clear-sky direct normal illuminance, about 1e5 lux), times the gain.
    let illuminance = foton::film::luminance(sun_irradiance) / 0.001;
    assert!(
        (illuminance / 101_610.0 - 1.0).abs() < 0.01,
        "{illuminance} lux"
    );
    let sky_alone = scene(&light("sky"));
    let (mean_sunsky, se_sunsky) =
        mean_and_standard_error(&common::render(sunsky, &common::options(16, 1)));
    let (mean_sky, se_sky) =
        mean_and_standard_error(&common::render(sky_alone, &common::options(16, 1)));
    let expected = sun_irradiance / PI;
    let standard_error = (se_sunsky * se_sunsky + se_sky * se_sky).map(f32::sqrt);
    let difference = mean_sunsky - mean_sky;
    assert!(
        ((difference - expected).abs() - 5.0 * standard_error).max_element() < 0.0,
        "sun adds {difference}, expected {expected} +- 5 x {standard_error}"
    );
    let sun = scene(&light("sun"));
    assert!(sun.warnings.is_empty(), "{:?}", sun.warnings);
    assert!(
        matches!(sun.lights[..], [LightDesc::SunDisc { .. }]),
        "{:?}",
        sun.lights
    );
    // `relsize` 0: LuxRender's older point-like sun, a delta light of the disc's radiance.
    let point_like = scene(
        r#"LightSource "sun" "float gain" [0.001] "vector sundir" [0 0 1] "float relsize" [0]"#,
    );
    assert!(
        matches!(point_like.lights[..], [LightDesc::Distant { radiance, .. }]
            if (radiance / 0.001 - sun_radiance_of(&sun)).abs().max_element() < 1.0),
        "{:?}",
        point_like.lights
    );
    let below = scene(r#"LightSource "sun" "vector sundir" [0 0.2 -1]"#);
    assert!(
        below.lights.is_empty() && below.warnings.is_empty(),
        "{:?}",
        below.lights
    );
}

/// The radiance of a scene's one sun disc.
fn sun_radiance_of(scene: &SceneDesc) -> Vec3 {
    match scene.lights[..] {
        [LightDesc::SunDisc { radiance, .. }] => radiance / 0.001,
        _ => panic!("{:?}", scene.lights),
    }
}

/// The mean of the pixels and its standard error (the pixels' standard deviation over the
/// square root of their number), per channel.
fn mean_and_standard_error(image: &[Vec3]) -> (Vec3, Vec3) {
    let n = image.len() as f32;
    let mean = image.iter().copied().sum::<Vec3>() / n;
    let variance = image.iter().map(|&p| (p - mean) * (p - mean)).sum::<Vec3>() / (n - 1.0);
    (mean, (variance / n).map(f32::sqrt))
}

/// `shinymetal`: Ks and Kr as given, Schlick's r = uroughness x vroughness and anisotropy
/// v^2 / u^2 - 1 for u > v (LuxRender 1.x's `SchlickDistribution(u * v, anisotropy)`); a
/// positive `film` is a thin film of that thickness and `filmindex`, without a warning.
#[test]
fn shinymetal_reads_its_parameters() {
    let desc = quad_scene(
        "shinymetal",
        r#"Material "shinymetal" "color Ks" [0.8 0.6 0.4] "color Kr" [0.3 0.3 0.3] "float uroughness" [0.2] "float vroughness" [0.05]"#,
    );
    assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
    let MaterialDesc::FittedConductor {
        glossy: ColorParam::Constant(glossy),
        mirror: ColorParam::Constant(mirror),
        roughness,
        anisotropy,
        film: None,
    } = only_material(&desc)
    else {
        panic!("{:?}", desc.materials)
    };
    assert_eq!(*glossy, Vec3::new(0.8, 0.6, 0.4));
    assert_eq!(*mirror, Vec3::splat(0.3));
    assert!((roughness - 0.2 * 0.05).abs() < 1e-7, "{roughness}");
    let expected = 0.05f32.powi(2) / 0.2f32.powi(2) - 1.0;
    assert!((anisotropy - expected).abs() < 1e-6, "{anisotropy}");
    let film = quad_scene(
        "shinymetal-film",
        r#"Material "shinymetal" "float film" [300] "float filmindex" [1.4]"#,
    );
    assert!(film.warnings.is_empty(), "{:?}", film.warnings);
    assert!(
        matches!(
            only_material(&film),
            MaterialDesc::FittedConductor {
                anisotropy: 0.0,
                film: Some((300.0, 1.4)),
                ..
            }
        ),
        "{:?}",
        film.materials
    );
}

/// `velvet` with LuxRender 1.x's defaults (Kd 0.3, p1 -2, p2 20, p3 2, thickness 0.1) and its
/// clamps (coefficients to [-100, 100], thickness to [0, 1]).
#[test]
fn velvet_reads_its_parameters_and_defaults() {
    let defaults = quad_scene("velvet", r#"Material "velvet""#);
    assert!(defaults.warnings.is_empty(), "{:?}", defaults.warnings);
    assert_eq!(
        only_material(&defaults),
        &MaterialDesc::Velvet {
            reflectance: ColorParam::Constant(Vec3::splat(0.3)),
            legendre: [-2.0, 20.0, 2.0],
            thickness: 0.1,
        }
    );
    let clamped = quad_scene(
        "velvet-clamped",
        r#"Material "velvet" "float p1" [500] "float p2" [1] "float p3" [-300] "float thickness" [3]"#,
    );
    let MaterialDesc::Velvet {
        legendre,
        thickness,
        ..
    } = only_material(&clamped)
    else {
        panic!("{:?}", clamped.materials)
    };
    assert_eq!((*legendre, *thickness), ([100.0, 1.0, -100.0], 1.0));
}

/// `carpaint` by `name` takes the preset's values (here "blue": a blue base, its third lobe
/// the sharpest, M3 = 0.02) and ignores Kd; an unknown name is a warning and "ford f8", also
/// the default of each parameter given without a name.
#[test]
fn carpaint_presets_and_parameters() {
    let lobes = |desc: &SceneDesc| match only_material(desc) {
        MaterialDesc::CarPaint {
            diffuse: ColorParam::Constant(kd),
            lobes,
            ..
        } => (*kd, lobes.clone()),
        other => panic!("{other:?}"),
    };
    let blue = quad_scene(
        "carpaint-blue",
        r#"Material "carpaint" "string name" ["blue"] "color Kd" [1 1 1]"#,
    );
    assert!(blue.warnings.is_empty(), "{:?}", blue.warnings);
    let (kd, blue_lobes) = lobes(&blue);
    assert!(kd.z > 4.0 * kd.x && kd.z < 0.2, "{kd}");
    assert_eq!((blue_lobes[2].f0, blue_lobes[2].roughness), (0.17, 0.02));

    let unknown = quad_scene(
        "carpaint-unknown",
        r#"Material "carpaint" "string name" ["no such paint"]"#,
    );
    assert_eq!(unknown.warnings.len(), 1, "{:?}", unknown.warnings);
    let manual = quad_scene(
        "carpaint-manual",
        r#"Material "carpaint" "float M3" [0.05] "color Ks1" [0.5 0.5 0.5]"#,
    );
    assert!(manual.warnings.is_empty(), "{:?}", manual.warnings);
    let (ford_kd, ford) = lobes(&unknown);
    let (manual_kd, manual_lobes) = lobes(&manual);
    assert_eq!(manual_kd, ford_kd);
    // Float parameters pass through a colour's mean: equal up to rounding.
    assert_eq!(manual_lobes[1].specular, ford[1].specular);
    assert!((manual_lobes[1].f0 - ford[1].f0).abs() < 1e-6);
    assert!((manual_lobes[1].roughness - ford[1].roughness).abs() < 1e-6);
    assert_eq!(manual_lobes[2].roughness, 0.05);
    assert_eq!(
        manual_lobes[0].specular,
        ColorParam::Constant(Vec3::splat(0.5))
    );
    assert_ne!(ford[2].roughness, 0.05);
}

/// `mattetranslucent`'s `sigma` makes both lobes Oren-Nayar (LuxRender's `OrenNayar` and
/// `BRDFToBTDF(OrenNayar)`): lit along the normal from either side and seen within 7 degrees
/// of it, the mirrored light direction is the normal, so B's term vanishes and both the
/// reflected and the transmitted radiance are A times the Lambertian lobes'
/// (A = 1 - s^2 / (2 (s^2 + 0.33)), s = 30 degrees in radians).
#[test]
fn matte_translucent_sigma_makes_oren_nayar_lobes() {
    let lambertian =
        r#"Material "mattetranslucent" "color Kr" [0.3 0.3 0.3] "color Kt" [0.5 0.5 0.5]"#;
    let rough = format!("{lambertian} \"float sigma\" [30]");
    let s2 = 30f32.to_radians().powi(2);
    let a = 1.0 - s2 / (2.0 * (s2 + 0.33));
    for light_z in [1.0, -1.0] {
        let smooth = quad_scene_lit_from("translucent-smooth", light_z, lambertian);
        let oren_nayar = quad_scene_lit_from("translucent-rough", light_z, &rough);
        assert!(oren_nayar.warnings.is_empty(), "{:?}", oren_nayar.warnings);
        let ratio = mean_radiance(oren_nayar, 1) / mean_radiance(smooth, 1);
        assert!(
            (ratio - a).abs() < 2e-3,
            "light at z = {light_z}: Oren-Nayar / Lambert {ratio}, A = {a}"
        );
    }
}

/// `glossytranslucent`: LuxRender 1.x's defaults (Kd, Kt, Ks 1, roughness 0.1 squared), the
/// index scaling Ks by ((n - 1) / (n + 1))^2, the front coating copied to the back unless
/// `onesided` is false, then the `backface_*` parameters with their own defaults (0: black,
/// the roughness clamped to 6e-3).
#[test]
fn glossytranslucent_reads_both_coatings() {
    let read = |name: &str, params: &str| {
        let s = quad_scene(name, &format!("Material \"glossytranslucent\" {params}"));
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
        match s.materials.last().unwrap().clone() {
            MaterialDesc::GlossyTranslucent {
                diffuse,
                transmittance,
                front,
                back,
            } => (diffuse, transmittance, front, back),
            other => panic!("{other:?}"),
        }
    };
    let constant = |c: ColorParam| match c {
        ColorParam::Constant(c) => c,
        other => panic!("{other:?}"),
    };
    let (kd, kt, front, back) = read("gt_defaults", "");
    assert_eq!((constant(kd), constant(kt)), (Vec3::ONE, Vec3::ONE));
    assert_eq!(constant(front.specular), Vec3::ONE);
    assert!((front.roughness - 0.01).abs() < 1e-7);
    assert!(!front.multibounce && front.anisotropy == 0.0);
    assert_eq!(front, back);
    let (_, _, front, back) = read(
        "gt_two_sided",
        "\"float index\" [1.5] \"bool multibounce\" [\"true\"] \"float d\" [0.3] \
         \"bool onesided\" [\"false\"] \"color backface_Ks\" [0.5 0.5 0.5] \
         \"float backface_uroughness\" [0.5] \"float uroughness\" [0.1] \"float vroughness\" [0.3]",
    );
    // Schlick's anisotropy of the clamped u and v: 1 - u^2 / v^2 for u < v, v^2 / u^2 - 1 else
    // (the back's v is its default 0, clamped to 6e-3).
    assert!(
        (front.anisotropy - (1.0 - 1.0 / 9.0)).abs() < 1e-6,
        "{}",
        front.anisotropy
    );
    let back_anisotropy = (6e-3f32 / 0.5).powi(2) - 1.0;
    assert!(
        (back.anisotropy - back_anisotropy).abs() < 1e-6,
        "{}",
        back.anisotropy
    );
    assert!((constant(front.specular).x - 0.04).abs() < 1e-6);
    assert!(front.multibounce && front.depth == 0.3);
    assert_eq!(constant(back.specular), Vec3::splat(0.5));
    assert!(
        (back.roughness - 0.5 * 6e-3).abs() < 1e-7,
        "{}",
        back.roughness
    );
    assert!(!back.multibounce && back.depth == 0.0);
}

/// `glossy`: Schlick's r = u v and anisotropy from `uroughness` u and `vroughness` v (each
/// clamped to [1e-4, 1]), 0 for u = v (LuxRender 1.x's `glossy2.cpp`).
#[test]
fn glossy_reads_its_anisotropy() {
    let read = |name: &str, params: &str| {
        let s = quad_scene(name, &format!("Material \"glossy\" {params}"));
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
        match s.materials.last().unwrap().clone() {
            MaterialDesc::CoatedDiffuse {
                roughness,
                anisotropy,
                ..
            } => (roughness, anisotropy),
            other => panic!("{other:?}"),
        }
    };
    assert_eq!(read("glossy_defaults", ""), (0.1 * 0.1, 0.0));
    let (roughness, anisotropy) = read(
        "glossy_anisotropic",
        "\"float uroughness\" [0.4] \"float vroughness\" [0.1]",
    );
    assert!((roughness - 0.04).abs() < 1e-7, "{roughness}");
    assert!((anisotropy - (0.0625 - 1.0)).abs() < 1e-6, "{anisotropy}");
}

/// A sphere in front of a checkered wall, lit by a point light placed so that the sphere's
/// shadow (shadow rays do not pass through glass) falls outside the view, rendered by the ray
/// caster (`directlighting`: the specular chains through the glass followed, direct light at
/// the wall): `sphere` is the sphere's material and volume lines.
fn glass_sphere_image(name: &str, sphere: &str) -> Vec<Vec3> {
    let text = format!(
        "LookAt 0 -4 1  0 0 1  0 0 1\nCamera \"perspective\" \"float fov\" [40]\n\
         Film \"fleximage\" \"integer xresolution\" [48] \"integer yresolution\" [48]\n\
         SurfaceIntegrator \"directlighting\" \"integer maxdepth\" [8]\n\
         WorldBegin\nLightSource \"point\" \"point from\" [8 -1 1] \"color L\" [100 100 100]\n\
         Texture \"checks\" \"color\" \"checkerboard\" \"float uscale\" [8] \"float vscale\" [8] \
         \"color tex1\" [0.9 0.9 0.9] \"color tex2\" [0.1 0.1 0.1]\n\
         AttributeBegin\nMaterial \"matte\" \"texture Kd\" \"checks\"\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \
         \"point P\" [-3 2 -1 3 2 -1 3 2 4 -3 2 4] \"float uv\" [0 0 1 0 1 1 0 1]\nAttributeEnd\n\
         AttributeBegin\nTranslate 0 0 1\n{sphere}\nShape \"sphere\" \"float radius\" [0.8]\n\
         AttributeEnd\nWorldEnd\n"
    );
    let dir = std::env::temp_dir().join(format!("foton-glass2-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.lxs");
    std::fs::write(&path, text).unwrap();
    let desc = foton::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
    common::render(desc, &common::options(4, 8))
}

/// `glass2` inside a volume of `fresnel` 1.5 renders as `glass` of index 1.5, bit for bit;
/// inside a volume of `fresnel` 1 the interface neither reflects nor bends, so the sphere is
/// invisible: the image is the one without it (the ray caster's paths through the sphere
/// carry weight 1 exactly, so the two differ only where the sphere's rounding moves a ray by
/// an ulp: at most a handful of the 2,304 pixels, none by more than the wall's contrast).
#[test]
fn glass2_in_a_volume_renders_as_glass_of_its_index() {
    let glass = glass_sphere_image("glass", "Material \"glass\" \"float index\" [1.5]");
    let glass2 = glass_sphere_image(
        "glass2",
        "MakeNamedVolume \"v\" \"clear\" \"float fresnel\" [1.5]\nInterior \"v\"\nMaterial \"glass2\"",
    );
    assert_eq!(glass, glass2);
    let unit = glass_sphere_image(
        "glass2_unit",
        "MakeNamedVolume \"v\" \"clear\" \"float fresnel\" [1]\nInterior \"v\"\nMaterial \"glass2\"",
    );
    let without = glass_sphere_image("none", "Material \"null\"");
    let differing = |a: &[Vec3], b: &[Vec3]| {
        a.iter()
            .zip(b)
            .filter(|(x, y)| (**x - **y).abs().max_element() > 1e-4)
            .count()
    };
    assert!(
        differing(&glass, &without) > 200,
        "the glass sphere shows: {}",
        differing(&glass, &without)
    );
    assert!(
        differing(&unit, &without) <= 5,
        "the index-1 sphere is invisible: {} pixels differ",
        differing(&unit, &without)
    );
}

/// A noise-based Blender texture (`blender_voronoi`, F1 at noise size 0.25) as a matte's Kd,
/// rendered: the image follows the texture. The expected image evaluates the texture graph
/// at 4 x 4 points in each pixel's footprint on the quad (the camera at z = 5 with a 20 degree
/// field of view sees x and y in [-t, t], t = 5 tan 10 degrees; image right is world +x,
/// image top world +y) times 1 / pi (a white distant light along the normal). The
/// correlation of the two images over the 32 x 32 pixels must be above 0.9 and their means
/// within 3% (16 spp; measured 0.99997 and 1.00004), and the pixels must vary (relative
/// standard deviation 0.32 measured, bound 0.2): a grey stand-in fails that; the texture
/// mirrored in x correlates 0.12.
#[test]
fn a_blender_noise_texture_renders_its_pattern() {
    let desc = quad_scene(
        "voronoi",
        "Texture \"v\" \"float\" \"blender_voronoi\" \"float noisesize\" [0.25]\n\
         Material \"matte\" \"texture Kd\" [\"v\"]",
    );
    assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
    let graph = desc.texture_graph.clone();
    let texture = foton::texture::TexParam::Texture(graph.nodes.len() - 1);
    let half_width = 5.0 * 10f32.to_radians().tan();
    let expected_image = |mirrored: bool| -> Vec<f32> {
        let mut image = Vec::new();
        for j in 0..32 {
            for i in 0..32 {
                let mut sum = 0.0;
                for (a, b) in (0..16).map(|k| (k % 4, k / 4)) {
                    let sx = (i as f32 + (a as f32 + 0.5) / 4.0) / 32.0;
                    let sy = (j as f32 + (b as f32 + 0.5) / 4.0) / 32.0;
                    let x = (2.0 * sx - 1.0) * half_width * if mirrored { -1.0 } else { 1.0 };
                    let y = (1.0 - 2.0 * sy) * half_width;
                    let sp = foton::texture::ShadingPoint {
                        p: Vec3::new(x, y, 0.0),
                        uv: glam::Vec2::new((x + 1.0) / 2.0, (y + 1.0) / 2.0),
                        n: Vec3::Z,
                        object: 0,
                    };
                    sum += graph.eval_float(texture, &sp, &|_, _| Vec3::ZERO);
                }
                image.push(sum / 16.0 / PI);
            }
        }
        image
    };
    let mut options = common::options(16, 1);
    options.integrator = Some(IntegratorKind::PathTracer);
    let rendered: Vec<f32> = common::render(desc, &options)
        .iter()
        .map(|p| p.element_sum() / 3.0)
        .collect();
    let correlation = |a: &[f32], b: &[f32]| {
        let n = a.len() as f32;
        let (ma, mb) = (a.iter().sum::<f32>() / n, b.iter().sum::<f32>() / n);
        let cov: f32 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
        let va: f32 = a.iter().map(|x| (x - ma) * (x - ma)).sum();
        let vb: f32 = b.iter().map(|y| (y - mb) * (y - mb)).sum();
        cov / (va * vb).sqrt()
    };
    let expected = expected_image(false);
    let r = correlation(&rendered, &expected);
    let mirrored = correlation(&rendered, &expected_image(true));
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let ratio = mean(&rendered) / mean(&expected);
    // The pattern itself varies: Voronoi F1 over cells 0.25 wide spans most of [0, 1], so the
    // pixels' standard deviation is a large fraction of their mean (a grey stand-in: 0).
    let deviation = (rendered
        .iter()
        .map(|v| (v - mean(&rendered)).powi(2))
        .sum::<f32>()
        / rendered.len() as f32)
        .sqrt();
    let relative_deviation = deviation / mean(&rendered);
    println!(
        "correlation {r} (mirrored {mirrored}), mean ratio {ratio}, relative deviation {relative_deviation}"
    );
    assert!(relative_deviation > 0.2, "{relative_deviation}");
    assert!(r > 0.9, "correlation {r} (mirrored {mirrored})");
    assert!((ratio - 1.0).abs() < 0.03, "mean ratio {ratio}");
}

/// A bumped `glass2` in a volume of `fresnel` 1.5 renders bit for bit as the same bump map on
/// `glass` of index 1.5 (LuxRender 1.x bumps any material, `core/material.cpp`, and `glass2`
/// reads its index from the volumes whatever its bump map), and the bump map shows: the image
/// differs from the unbumped glass's in many pixels.
#[test]
fn bumped_glass2_keeps_its_volumes_index() {
    let bump = "Texture \"n\" \"float\" \"blender_clouds\" \"float noisesize\" [0.1]\n\
                Texture \"b\" \"float\" \"scale\" \"texture tex1\" [\"n\"] \"float tex2\" [0.02]\n";
    let glass = glass_sphere_image(
        "glass_bumped",
        &format!("{bump}Material \"glass\" \"float index\" [1.5] \"texture bumpmap\" [\"b\"]"),
    );
    let glass2 = glass_sphere_image(
        "glass2_bumped",
        &format!(
            "{bump}MakeNamedVolume \"v\" \"clear\" \"float fresnel\" [1.5]\nInterior \"v\"\n\
             Material \"glass2\" \"texture bumpmap\" [\"b\"]"
        ),
    );
    assert!(glass == glass2, "bumped glass2 differs from bumped glass");
    let smooth = glass_sphere_image("glass_smooth", "Material \"glass\" \"float index\" [1.5]");
    let differing = glass
        .iter()
        .zip(&smooth)
        .filter(|(x, y)| (**x - **y).abs().max_element() > 1e-3)
        .count();
    assert!(differing > 100, "the bump map shows in {differing} pixels");
}
