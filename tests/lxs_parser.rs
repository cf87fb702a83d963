//! The LuxRender loader on small scenes written by the tests, and on the course's scenes.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use foton::material::texels::ReadTexel;
use foton::scene::desc::{
    ColorParam, FilterKind, Geometry, LightDesc, MaterialDesc, SceneDesc, SceneError, SpotFalloff,
    ToneMap, Wrap,
};
use foton::scene::lxs::load;
use foton::texture::{TexParam, TextureNode};
use glam::{Mat4, Vec2, Vec3, Vec4};

/// A fresh, empty folder for one test.
fn temp_folder(name: &str) -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let unique = NEXT.fetch_add(1, Ordering::Relaxed);
    let dir =
        std::env::temp_dir().join(format!("foton-lxs-{}-{unique}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, relative: &str, text: &str) -> PathBuf {
    let path = dir.join(relative);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(&path, text).unwrap();
    path
}

/// Writes `text` as `scene.lxs` in a fresh folder and loads it.
fn load_text(name: &str, text: &str) -> Result<SceneDesc, SceneError> {
    let dir = temp_folder(name);
    load(&write(&dir, "scene.lxs", text))
}

fn scene(name: &str, text: &str) -> SceneDesc {
    load_text(name, text).unwrap_or_else(|e| panic!("{e}"))
}

fn error(name: &str, text: &str) -> SceneError {
    match load_text(name, text) {
        Ok(_) => panic!("{name}: loaded, expected an error"),
        Err(e) => e,
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    a.abs_diff_eq(b, 1e-5)
}

/// Equal to 1e-5 of the larger.
fn close_rel(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() <= 1e-5 * a.abs().max(b.abs()).max_element()
}

const PI64: f64 = std::f64::consts::PI;

/// Luminance with the weights of LuxRender's `RGBColor::Y()`, in f64.
fn luminance64(c: Vec3) -> f64 {
    0.212671 * f64::from(c.x) + 0.715160 * f64::from(c.y) + 0.072169 * f64::from(c.z)
}

/// LuxRender's area light by hand: a one-sided Lambertian emitter of radiance L gain on area A
/// emits the luminous flux pi A Y(L) gain; `power` W at `efficacy` lm/W rescale it to
/// power * efficacy lm.
fn luxrender_area_radiance(l: Vec3, gain: f64, power: f64, efficacy: f64, area: f64) -> Vec3 {
    let scale = gain * power * efficacy / (PI64 * area * luminance64(l));
    l * scale as f32
}

fn messages(scene: &SceneDesc) -> Vec<String> {
    scene.warnings.iter().map(|w| w.to_string()).collect()
}

/// A triangle mesh's positions, normals, uvs and indices.
type MeshParts<'a> = (
    &'a [Vec3],
    Option<&'a [Vec3]>,
    Option<&'a [Vec2]>,
    &'a [[u32; 3]],
);

fn mesh(geometry: &Geometry) -> MeshParts<'_> {
    match geometry {
        Geometry::TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
        } => (positions, normals.as_deref(), uvs.as_deref(), indices),
        other => panic!("not a mesh: {other:?}"),
    }
}

const WORLD: &str = "WorldBegin\nWorldEnd\n";

// ---------------------------------------------------------------- camera, film, options

#[test]
fn look_at_and_perspective_camera() {
    let s = scene(
        "camera",
        "LookAt 0 -10 0  0 0 0  0 0 1\n\
         Camera \"perspective\" \"float fov\" [45] \"float screenwindow\" [-1 1 -0.5 0.5]\n\
         \"float lensradius\" [0.1] \"float focaldistance\" [5]\n\
         WorldBegin\nShape \"sphere\"\nWorldEnd\n",
    );
    let c = &s.camera;
    assert_eq!((c.kind.name(), c.fov_degrees), ("pinhole", 45.0));
    // x right = dir x up = (0,1,0) x (0,0,1) = (1,0,0); y = x x dir = (0,0,1); z = dir.
    assert!(c.camera_to_world.abs_diff_eq(
        Mat4::from_cols(Vec4::X, Vec4::Z, Vec4::Y, Vec4::new(0.0, -10.0, 0.0, 1.0)),
        1e-6
    ));
    assert_eq!(c.screen_window, Some([-1.0, 1.0, -0.5, 0.5]));
    assert_eq!((c.lens_radius, c.focal_distance), (0.1, 5.0));
    assert_eq!(c.location.line, 2);
    // The camera transform does not leak into the world.
    assert_eq!(s.shapes[0].object_to_world, Mat4::IDENTITY);
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
}

#[test]
fn camera_transform_is_the_inverse_ctm_and_the_world_starts_afresh() {
    let s = scene(
        "camera_ctm",
        "Translate 1 2 3\nCamera \"perspective\"\nWorldBegin\nShape \"sphere\"\nWorldEnd\n",
    );
    assert_eq!(
        s.camera.camera_to_world,
        Mat4::from_translation(Vec3::new(-1.0, -2.0, -3.0))
    );
    assert_eq!(s.shapes[0].object_to_world, Mat4::IDENTITY);
}

#[test]
fn defaults_without_camera_film_or_filter() {
    let s = scene("defaults", WORLD);
    assert_eq!(
        (s.camera.kind.name(), s.camera.fov_degrees),
        ("pinhole", 90.0)
    );
    assert_eq!(s.camera.camera_to_world, Mat4::IDENTITY);
    assert_eq!((s.camera.lens_radius, s.camera.focal_distance), (0.0, 1e6));
    assert_eq!(s.camera.screen_window, None);
    assert_eq!((s.film.x_resolution, s.film.y_resolution), (640, 480));
    assert_eq!(s.film.gamma, 2.2);
    assert_eq!(s.film.tonemap, ToneMap::AutoLinear);
    assert_eq!(s.film.filename, None);
    assert_eq!(s.filter.kind, FilterKind::Box);
    assert_eq!(s.filter.radius, Vec2::splat(0.5));
    assert_eq!((s.pixel_samples, s.max_depth), (None, None));
}

#[test]
fn fisheye_environment_and_orthographic_cameras() {
    let projection = |text: &str| {
        let camera = scene("projection", &format!("{text}\n{WORLD}")).camera;
        (camera.kind.name(), camera.fov_degrees)
    };
    assert_eq!(
        projection("Camera \"fisheye\" \"float fov\" [180]"),
        ("fisheye", 180.0)
    );
    assert_eq!(
        projection("Camera \"fisheye\" \"float fov\" [220]"),
        ("fisheye", 220.0)
    );
    assert_eq!(projection("Camera \"fisheye\""), ("fisheye", 180.0));
    assert_eq!(projection("Camera \"environment\"").0, "equirectangular");
    let s = scene(
        "ortho",
        &format!("Camera \"orthographic\" \"float screenwindow\" [-2 2 -1 1]\n{WORLD}"),
    );
    assert_eq!(s.camera.kind.name(), "orthographic");
    assert_eq!(s.camera.screen_window, Some([-2.0, 2.0, -1.0, 1.0]));
}

#[test]
fn film_sampler_and_integrator() {
    let s = scene(
        "film",
        &format!(
            "Film \"fleximage\" \"integer xresolution\" [960] \"integer yresolution\" [540]\n\
             \"float gamma\" [1.8] \"string filename\" [\"out.Scene\"] \"string tonemapkernel\" [\"autolinear\"]\n\
             \"bool write_png\" [\"true\"] \"float colorspace_white\" [0.3 0.3]\n\
             Sampler \"random\" \"integer pixelsamples\" [64]\n\
             SurfaceIntegrator \"path\" \"integer maxdepth\" [7]\n{WORLD}"
        ),
    );
    assert_eq!((s.film.x_resolution, s.film.y_resolution), (960, 540));
    assert_eq!(s.film.gamma, 1.8);
    assert_eq!(s.film.filename.as_deref(), Some("out.Scene"));
    assert_eq!(s.film.tonemap, ToneMap::AutoLinear);
    assert_eq!((s.pixel_samples, s.max_depth), (Some(64), Some(7)));
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));

    let s = scene(
        "eyedepth",
        &format!(
            "SurfaceIntegrator \"bidirectional\" \"integer eyedepth\" [16] \"integer lightdepth\" [16]\n{WORLD}"
        ),
    );
    assert_eq!(s.max_depth, Some(16));

    let s = scene(
        "film_extension",
        &format!("Film \"fleximage\" \"string filename\" [\"render.PNG\"]\n{WORLD}"),
    );
    assert_eq!(s.film.filename.as_deref(), Some("render"));
}

#[test]
fn linear_tonemap_uses_luxrenders_exposure_formula() {
    let s = scene(
        "linear",
        &format!(
            "Film \"fleximage\" \"string tonemapkernel\" [\"linear\"] \"float linear_sensitivity\" [200]\n\
             \"float linear_exposure\" [0.5] \"float linear_fstop\" [2] \"float linear_gamma\" [1]\n{WORLD}"
        ),
    );
    // 0.5 / 2^2 * 200 * 0.65 / 10 * (118/255)^1
    let expected = 0.5 / 4.0 * 200.0 * 0.65 / 10.0 * (118.0 / 255.0);
    match s.film.tonemap {
        ToneMap::Linear { scale } => assert!((scale - expected).abs() < 1e-5, "{scale}"),
        other => panic!("{other:?}"),
    }
    let s = scene(
        "reinhard",
        &format!("Film \"fleximage\" \"string tonemapkernel\" [\"reinhard\"]\n{WORLD}"),
    );
    // LuxRender's reinhard defaults (`tonemaps/reinhard.cpp`): prescale 1, postscale 1, burn 7.
    assert_eq!(
        s.film.tonemap,
        ToneMap::Reinhard {
            prescale: 1.0,
            postscale: 1.0,
            burn: 7.0
        }
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let s = scene(
        "drago",
        &format!("Film \"fleximage\" \"string tonemapkernel\" [\"drago\"]\n{WORLD}"),
    );
    assert_eq!(s.film.tonemap, ToneMap::Linear { scale: 1.0 });
    assert_eq!(s.warnings.len(), 1);
    assert!(s.warnings[0].message.contains("drago"));
}

#[test]
fn pixel_filters_and_their_defaults() {
    let filter = |text: &str| scene("filter", &format!("{text}\n{WORLD}"));
    let s = filter("PixelFilter \"box\"");
    assert_eq!(
        (s.filter.kind, s.filter.radius),
        (FilterKind::Box, Vec2::splat(0.5))
    );
    let s = filter("PixelFilter \"gaussian\"");
    assert_eq!(s.filter.kind, FilterKind::Gaussian { alpha: 2.0 });
    assert_eq!(s.filter.radius, Vec2::splat(2.0));
    let s = filter(
        "PixelFilter \"gaussian\" \"float alpha\" [4] \"float xwidth\" [1.5] \"float ywidth\" [2.5]",
    );
    assert_eq!(s.filter.kind, FilterKind::Gaussian { alpha: 4.0 });
    assert_eq!(s.filter.radius, Vec2::new(1.5, 2.5));
    let s = filter("PixelFilter \"blackmanharris\"");
    assert_eq!(
        (s.filter.kind, s.filter.radius),
        (FilterKind::BlackmanHarris, Vec2::splat(2.0))
    );
    let s = filter("PixelFilter \"mitchell\" \"float xwidth\" [3] \"float B\" [0.75]");
    assert_eq!(
        (s.filter.kind, s.filter.radius),
        (
            FilterKind::Mitchell {
                b: 0.75,
                c: 1.0 / 3.0
            },
            Vec2::new(3.0, 2.0)
        )
    );
    let s = filter("PixelFilter \"sinc\"");
    assert_eq!(s.filter.kind, FilterKind::Sinc { tau: 3.0 });
    let s = filter("PixelFilter \"catmullrom\" \"float xwidth\" [3]");
    assert_eq!(
        (s.filter.kind, s.filter.radius),
        (FilterKind::Box, Vec2::splat(0.5))
    );
    assert_eq!(s.warnings.len(), 1);
    assert_eq!(s.warnings[0].location.line, 1);
}

// ---------------------------------------------------------------- transforms and blocks

#[test]
fn translate_then_scale_applies_scale_first() {
    let s = scene(
        "translate_scale",
        "WorldBegin\nTranslate 1 2 3\nScale 2 2 2\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [1 0 0  0 1 0  0 0 1]\nWorldEnd\n",
    );
    let m = s.shapes[0].object_to_world;
    let (positions, ..) = mesh(&s.shapes[0].geometry);
    let world: Vec<Vec3> = positions.iter().map(|&p| m.transform_point3(p)).collect();
    assert_eq!(
        world,
        vec![
            Vec3::new(3.0, 2.0, 3.0),
            Vec3::new(1.0, 4.0, 3.0),
            Vec3::new(1.0, 2.0, 5.0)
        ]
    );
}

#[test]
fn transform_concat_rotate_identity() {
    let s = scene(
        "transforms",
        "WorldBegin\n\
         Transform [1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1]\nShape \"sphere\"\n\
         ConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1]\nShape \"sphere\"\n\
         Identity\nRotate 90 0 0 1\nShape \"sphere\"\n\
         Identity\nShape \"sphere\"\nWorldEnd\n",
    );
    let m: Vec<Mat4> = s.shapes.iter().map(|s| s.object_to_world).collect();
    assert_eq!(m[0].transform_point3(Vec3::ZERO), Vec3::new(5.0, 6.0, 7.0));
    assert_eq!(m[1].transform_point3(Vec3::X), Vec3::new(7.0, 6.0, 7.0));
    assert!(close(m[2].transform_point3(Vec3::X), Vec3::Y));
    assert_eq!(m[3], Mat4::IDENTITY);
}

#[test]
fn attribute_blocks_restore_ctm_material_and_area_light_transform_blocks_only_ctm() {
    let s = scene(
        "blocks",
        "WorldBegin\n\
         MakeNamedMaterial \"a\" \"string type\" [\"matte\"]\n\
         MakeNamedMaterial \"b\" \"string type\" [\"mirror\"]\n\
         NamedMaterial \"a\"\n\
         AttributeBegin\n Translate 1 0 0\n NamedMaterial \"b\"\n\
           AreaLightSource \"area\" \"color L\" [1 2 3]\n Shape \"sphere\"\nAttributeEnd\n\
         Shape \"sphere\"\n\
         TransformBegin\n Translate 0 1 0\n NamedMaterial \"b\"\n Shape \"sphere\"\nTransformEnd\n\
         Shape \"sphere\"\nWorldEnd\n",
    );
    let at = |i: usize| s.shapes[i].object_to_world.transform_point3(Vec3::ZERO);
    assert_eq!((at(0), s.shapes[0].material), (Vec3::X, Some(1)));
    assert!(s.shapes[0].area_light.is_some());
    assert_eq!((at(1), s.shapes[1].material), (Vec3::ZERO, Some(0)));
    assert_eq!(s.shapes[1].area_light, None);
    assert_eq!((at(2), s.shapes[2].material), (Vec3::Y, Some(1)));
    // TransformEnd restores the CTM but keeps the material set inside.
    assert_eq!((at(3), s.shapes[3].material), (Vec3::ZERO, Some(1)));
}

#[test]
fn reverse_orientation_flips_meshes_and_planes_within_its_block() {
    let s = scene(
        "reverse",
        "WorldBegin\nAttributeBegin\nReverseOrientation\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [0 0 1 0 0 1 0 0 1]\n\
         Shape \"plane\" \"normal N\" [0 1 0]\nAttributeEnd\n\
         Shape \"plane\" \"normal N\" [0 1 0]\nWorldEnd\n",
    );
    let (_, normals, _, indices) = mesh(&s.shapes[0].geometry);
    assert_eq!(indices, &[[0, 2, 1]]);
    assert_eq!(normals.unwrap()[0], -Vec3::Z);
    assert_eq!(s.shapes[1].geometry, Geometry::Plane { normal: -Vec3::Y });
    assert_eq!(s.shapes[2].geometry, Geometry::Plane { normal: Vec3::Y });
}

// ---------------------------------------------------------------- materials and textures

#[test]
fn materials_of_every_kind() {
    let s = scene(
        "materials",
        "WorldBegin\n\
         MakeNamedMaterial \"m\" \"color Kd\" [0.1 0.2 0.3] \"float sigma\" [0] \"string type\" [\"matte\"]\n\
         MakeNamedMaterial \"r\" \"color Kr\" [0.7 0.7 0.7] \"float film\" [0] \"float filmindex\" [1.33] \"string type\" [\"mirror\"]\n\
         MakeNamedMaterial \"g\" \"color Kr\" [1 1 1] \"color Kt\" [0.9 0.9 0.9] \"float index\" [1.52] \"float cauchyb\" [0] \"bool architectural\" [\"false\"] \"string type\" [\"glass\"]\n\
         MakeNamedMaterial \"uv\" \"color Kr\" [1 0.5 0] \"float uroughness\" [0.075] \"float vroughness\" [0.2] \"string type\" [\"metal2\"]\n\
         MakeNamedMaterial \"course\" \"float roughness\" [0.3] \"string type\" [\"metal2\"]\n\
         MakeNamedMaterial \"n\" \"string type\" [\"null\"]\n\
         MakeNamedMaterial \"x\" \"string namedmaterial1\" [\"m\"] \"string namedmaterial2\" [\"r\"] \"float amount\" [0.25] \"string type\" [\"mix\"]\n\
         Material \"matte\"\n\
         Shape \"sphere\"\nWorldEnd\n",
    );
    let c = |r: f32, g: f32, b: f32| ColorParam::Constant(Vec3::new(r, g, b));
    assert_eq!(
        s.materials,
        vec![
            MaterialDesc::Diffuse {
                reflectance: c(0.1, 0.2, 0.3)
            },
            MaterialDesc::Mirror {
                reflectance: c(0.7, 0.7, 0.7)
            },
            MaterialDesc::Dielectric {
                reflectance: c(1.0, 1.0, 1.0),
                transmittance: c(0.9, 0.9, 0.9),
                ior: 1.52
            },
            MaterialDesc::RoughConductor {
                specular: c(1.0, 0.5, 0.0),
                alpha_u: 0.075,
                alpha_v: 0.2
            },
            MaterialDesc::RoughConductor {
                specular: c(1.0, 1.0, 1.0),
                alpha_u: 0.3,
                alpha_v: 0.3
            },
            MaterialDesc::Null,
            MaterialDesc::Mix {
                first: 0,
                second: 1,
                amount: ColorParam::Constant(Vec3::splat(0.25))
            },
            // LuxRender's matte default Kd (`materials/matte.cpp`).
            MaterialDesc::Diffuse {
                reflectance: c(0.9, 0.9, 0.9)
            },
        ]
    );
    // `Material` sets the current material directly.
    assert_eq!(s.shapes[0].material, Some(7));
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
}

#[test]
fn material_quirks_warn() {
    let s = scene(
        "material_warnings",
        "WorldBegin\n\
         MakeNamedMaterial \"a\" \"float sigma\" [20] \"string type\" [\"matte\"]\n\
         MakeNamedMaterial \"b\" \"float uroughness\" [0.1] \"float vroughness\" [0.1] \"int roughness\" [10] \"string type\" [\"metal2\"]\n\
         MakeNamedMaterial \"c\" \"color Kd\" [1 0 0] \"string type\" [\"cloth\"]\n\
         Material \"glass\" \"float bogus\" [1]\nWorldEnd\n",
    );
    assert_eq!(
        s.materials[1],
        MaterialDesc::RoughConductor {
            specular: ColorParam::Constant(Vec3::ONE),
            alpha_u: 0.1,
            alpha_v: 0.1,
        }
    );
    assert_eq!(
        s.materials[2],
        MaterialDesc::Diffuse {
            reflectance: ColorParam::Constant(Vec3::splat(0.5))
        }
    );
    // matte's sigma is Oren-Nayar's, in degrees, with LuxRender's default Kd 0.9.
    assert_eq!(
        s.materials[0],
        MaterialDesc::RoughDiffuse {
            reflectance: ColorParam::Constant(Vec3::splat(0.9)),
            sigma_degrees: ColorParam::Constant(Vec3::splat(20.0)),
        }
    );
    let w = messages(&s);
    assert_eq!(w.len(), 3, "{w:?}");
    assert!(w[0].contains(":3: warning: metal2: \"roughness\" ignored"));
    assert!(w[1].contains(":4: warning: material type \"cloth\" unsupported: grey matte"));
    assert!(
        w[2].contains(":5: warning: Material \"glass\": unknown parameter \"float bogus\" ignored")
    );
}

/// Writes a 2x1 image: a mid-grey texel (128) and a white one.
fn write_image(dir: &Path, relative: &str) -> PathBuf {
    let path = dir.join(relative);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    let image = image::RgbImage::from_fn(2, 1, |x, _| {
        if x == 0 {
            image::Rgb([128, 128, 128])
        } else {
            image::Rgb([255, 255, 255])
        }
    });
    image.save(&path).unwrap();
    path
}

#[test]
fn imagemap_texture_decodes_with_gamma_gain_and_mapping() {
    let dir = temp_folder("imagemap");
    write_image(&dir, "tex/grey.png");
    let path = write(
        &dir,
        "scene.lxs",
        "WorldBegin\n\
         Texture \"wood\" \"color\" \"imagemap\" \"string filename\" [\"tex/grey.png\"] \"float gain\" [2]\n\
         \"float uscale\" [3] \"float vscale\" [-1] \"float udelta\" [0.5] \"float vdelta\" [1]\n\
         \"string wrap\" [\"repeat\"] \"float maxanisotropy\" [8] \"integer discardmipmaps\" [0]\n\
         Texture \"plain\" \"color\" \"imagemap\" \"string filename\" [\"tex/grey.png\"] \"float gamma\" [1]\n\
         MakeNamedMaterial \"m\" \"texture Kd\" [\"wood\"] \"string type\" [\"matte\"]\n\
         MakeNamedMaterial \"k\" \"texture Kr\" [\"plain\"] \"string type\" [\"metal2\"]\nWorldEnd\n",
    );
    let s = load(&path).unwrap();
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
    assert_eq!(s.textures.len(), 2);
    let t = &s.textures[0];
    assert_eq!((t.name.as_str(), t.width, t.height), ("wood", 2, 1));
    assert_eq!(t.path, dir.join("tex/grey.png"));
    let grey = (128.0f32 / 255.0).powf(2.2) * 2.0;
    assert!(
        close(t.texels.texel(0), Vec3::splat(grey)),
        "{:?}",
        t.texels
    );
    assert!(close(t.texels.texel(1), Vec3::splat(2.0)));
    assert_eq!(
        (t.scale, t.delta),
        (Vec2::new(3.0, -1.0), Vec2::new(0.5, 1.0))
    );
    assert!(close(
        s.textures[1].texels.texel(0),
        Vec3::splat(128.0 / 255.0)
    ));
    assert_eq!(
        s.materials[0],
        MaterialDesc::Diffuse {
            reflectance: ColorParam::Texture(0)
        }
    );
    assert!(matches!(
        s.materials[1],
        MaterialDesc::RoughConductor {
            specular: ColorParam::Texture(1),
            ..
        }
    ));
}

#[test]
fn imagemap_wrap_modes_are_read_and_an_unknown_one_warned() {
    let dir = temp_folder("wrap");
    write_image(&dir, "t.png");
    let mut text = String::from("WorldBegin\n");
    for wrap in ["black", "white", "clamp", "repeat", "mirror"] {
        text += &format!(
            "Texture \"{wrap}\" \"color\" \"imagemap\" \"string filename\" [\"t.png\"] \"string wrap\" [\"{wrap}\"]\n"
        );
    }
    text +=
        "Texture \"default\" \"color\" \"imagemap\" \"string filename\" [\"t.png\"]\nWorldEnd\n";
    let s = load(&write(&dir, "scene.lxs", &text)).unwrap();
    let wraps: Vec<Wrap> = s.textures.iter().map(|t| t.wrap).collect();
    use Wrap::*;
    assert_eq!(wraps, [Black, White, Clamp, Repeat, Repeat, Repeat]);
    let w = messages(&s);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains(":6: warning: Texture \"mirror\": unknown wrap \"mirror\": repeat used"),
        "{w:?}"
    );
}

#[test]
fn glass_dispersion_and_thin_film_are_warned_not_silently_dropped() {
    let dir = temp_folder("glass-options");
    let path = write(
        &dir,
        "scene.lxs",
        "WorldBegin\n\
         Texture \"b\" \"float\" \"constant\" \"float value\" [0.05]\n\
         Material \"glass\" \"texture cauchyb\" [\"b\"] \"float film\" [300] \"float filmindex\" [1.4]\n\
         Material \"roughglass\" \"float cauchyb\" [0.01]\n\
         Material \"glass\" \"float cauchyb\" [0] \"float film\" [0] \"float filmindex\" [1.5]\nWorldEnd\n",
    );
    let w = messages(&load(&path).unwrap());
    assert_eq!(w.len(), 3, "{w:?}");
    assert!(w[0].contains(":3: warning: glass: dispersion (\"cauchyb\") is not rendered"));
    assert!(w[1].contains(":3: warning: glass: the thin film (\"film\") is not rendered"));
    assert!(w[2].contains(":4: warning: roughglass: dispersion (\"cauchyb\") is not rendered"));
}

#[test]
fn jpg_gif_and_bmp_textures_decode() {
    let dir = temp_folder("formats");
    for name in ["t.jpg", "t.gif", "t.bmp"] {
        write_image(&dir, name);
    }
    let path = write(
        &dir,
        "scene.lxs",
        "WorldBegin\n\
         Texture \"j\" \"color\" \"imagemap\" \"string filename\" [\"t.jpg\"]\n\
         Texture \"g\" \"color\" \"imagemap\" \"string filename\" [\"t.gif\"]\n\
         Texture \"b\" \"color\" \"imagemap\" \"string filename\" [\"t.bmp\"]\nWorldEnd\n",
    );
    let s = load(&path).unwrap();
    assert_eq!(s.textures.len(), 3);
    for t in &s.textures {
        assert_eq!((t.width, t.height), (2, 1));
        assert!(
            (t.texels.texel(1) - Vec3::ONE).abs().max_element() < 0.05,
            "{}: {:?}",
            t.name,
            t.texels
        );
    }
}

#[test]
fn course_texture_dialect_loads_with_warnings() {
    let dir = temp_folder("dialect");
    write_image(&dir, "texture/metal-1.png");
    let path = write(
        &dir,
        "scene_2/scene_2.lxs",
        "WorldBegin\n\
         Texture \"metal1\"\n\t\"string filename\" [\"texture/metal-1.png\"]\n\
         MakeNamedMaterial \"m\" \"texture Kr\" [metal1] \"int roughness\" [0.10] \"string type\" [\"metal2\"]\n\
         Shape \"sphere\" \"float radius\" [1] \"float bogus\" [3]\nWorldEnd\n",
    );
    let s = load(&path).unwrap();
    assert_eq!(s.textures[0].path, dir.join("texture/metal-1.png"));
    assert_eq!(
        s.materials[0],
        MaterialDesc::RoughConductor {
            specular: ColorParam::Texture(0),
            alpha_u: 0.1,
            alpha_v: 0.1
        }
    );
    let w = messages(&s);
    assert_eq!(w.len(), 5, "{w:?}");
    let file = dir.join("scene_2/scene_2.lxs").display().to_string();
    assert_eq!(
        w[0],
        format!("{file}:2: warning: Texture \"metal1\" has no type and class: read as an imagemap")
    );
    assert_eq!(
        w[1],
        format!(
            "{file}:2: warning: files found in a parent folder of the file naming them; the first: \
             Texture \"metal1\" \"texture/metal-1.png\" as {}",
            dir.join("texture/metal-1.png").display()
        )
    );
    assert_eq!(
        w[2],
        format!("{file}:4: warning: \"texture Kr\": texture name written without quotes")
    );
    assert_eq!(
        w[3],
        format!("{file}:4: warning: \"int roughness\" has a fractional value: read as a float")
    );
    assert_eq!(
        w[4],
        format!("{file}:5: warning: Shape \"sphere\": unknown parameter \"float bogus\" ignored")
    );
}

#[test]
fn constant_procedural_and_unsupported_textures() {
    let s = scene(
        "constant_texture",
        "WorldBegin\n\
         Texture \"c\" \"color\" \"constant\" \"color value\" [0.2 0.4 0.6]\n\
         Texture \"s\" \"color\" \"scale\" \"texture tex1\" [\"c\"] \"float tex2\" [0.5]\n\
         Texture \"b\" \"color\" \"brick\"\n\
         MakeNamedMaterial \"a\" \"texture Kd\" [\"c\"] \"string type\" [\"matte\"]\n\
         MakeNamedMaterial \"b\" \"texture Kd\" [\"s\"] \"string type\" [\"matte\"]\n\
         MakeNamedMaterial \"c\" \"texture Kd\" [\"b\"] \"string type\" [\"matte\"]\nWorldEnd\n",
    );
    assert_eq!(
        s.materials[0],
        MaterialDesc::Diffuse {
            reflectance: ColorParam::Constant(Vec3::new(0.2, 0.4, 0.6))
        }
    );
    // `scale` is a graph node multiplying its inputs (a constant texture is inlined).
    assert_eq!(
        s.materials[1],
        MaterialDesc::Diffuse {
            reflectance: ColorParam::Texture(0)
        }
    );
    assert_eq!(
        s.texture_graph.nodes[0],
        TextureNode::Scale {
            tex1: TexParam::Value(Vec3::new(0.2, 0.4, 0.6)),
            tex2: TexParam::Value(Vec3::splat(0.5)),
        }
    );
    assert_eq!(
        s.materials[2],
        MaterialDesc::Diffuse {
            reflectance: ColorParam::Constant(Vec3::splat(0.5))
        }
    );
    assert_eq!(s.warnings.len(), 1);
    assert!(
        s.warnings[0]
            .message
            .contains("class \"brick\" unsupported")
    );
}

/// LuxRender 1.x's `dots` hands `inside` and `outside` to a constructor that stores them the
/// other way round (`textures/dots.h`: `DotsTexture(m, c1, c2)` sets `outsideDot = c1`, and
/// is called with `inside` first), so the dots show `outside` and the ground `inside`.
#[test]
fn dots_show_luxrenders_swapped_inside_and_outside() {
    let s = scene(
        "dots",
        "WorldBegin\n\
         Texture \"d\" \"color\" \"dots\" \"color inside\" [1 0 0] \"color outside\" [0 0 1]\n\
         Texture \"e\" \"float\" \"dots\"\nWorldEnd\n",
    );
    let dots = |i: usize| match &s.texture_graph.nodes[i] {
        TextureNode::Dots {
            inside, outside, ..
        } => (*inside, *outside),
        other => panic!("not dots: {other:?}"),
    };
    assert_eq!(
        dots(0),
        (TexParam::Value(Vec3::Z), TexParam::Value(Vec3::X))
    );
    // The defaults (inside 1, outside 0) give dots of 0 on a ground of 1.
    assert_eq!(dots(1), (TexParam::float(0.0), TexParam::float(1.0)));
}

/// The Blender procedurals are graph nodes with LuxRender 1.x's names and defaults
/// (`textures/blender_*.h`, `blender_base.cpp`); an unknown type or basis name is warned and
/// read as the default, as LuxRender does.
#[test]
fn blender_textures_read_luxrenders_parameters() {
    let s = scene(
        "blender",
        "WorldBegin\n\
         Texture \"b\" \"float\" \"blender_blend\" \"string type\" [\"quad\"] \"bool flipxy\" [\"true\"] \"float bright\" [1.2]\n\
         Texture \"m\" \"float\" \"blender_magic\" \"integer noisedepth\" [3] \"float turbulence\" [4]\n\
         Texture \"w\" \"float\" \"blender_wood\" \"string type\" [\"rings\"] \"string noisebasis2\" [\"saw\"]\n\
         \"string noisebasis\" [\"blender_original\"] \"float noisesize\" [0.25] \"float turbulence\" [5]\n\
         Texture \"x\" \"float\" \"blender_blend\" \"string type\" [\"spiral\"] \"float tex1\" [0.2]\n\
         Texture \"n\" \"float\" \"blender_wood\" \"string type\" [\"ringnoise\"] \"string noisetype\" [\"hard_noise\"]\n\
         Texture \"c\" \"color\" \"blender_clouds\" \"string type\" [\"color\"] \"string noisebasis\" [\"improved_perlin\"] \"integer noisedepth\" [4]\n\
         Texture \"a\" \"float\" \"blender_marble\" \"string type\" [\"sharper\"] \"string noisebasis2\" [\"tri\"] \"float noisesize\" [0.5]\n\
         Texture \"g\" \"float\" \"blender_musgrave\" \"string type\" [\"hetero_terrain\"] \"float h\" [0.5] \"float octs\" [3.5]\n\
         Texture \"d\" \"float\" \"blender_distortednoise\" \"string type\" [\"voronoi_f2_f1\"] \"string noisebasis\" [\"cell_noise\"] \"float distamount\" [2] \"float nabla\" [0.02]\n\
         Texture \"s\" \"float\" \"blender_stucci\" \"string type\" [\"wall_out\"] \"string noisebasis\" [\"perlin\"]\n\
         Texture \"v\" \"float\" \"blender_voronoi\" \"string distmetric\" [\"minkovsky\"] \"float minkovsky_exp\" [3] \"integer coltype\" [2] \"float w2\" [-0.5]\n\
         Texture \"z\" \"float\" \"blender_noise\"\n\
         WorldEnd\n",
    );
    use foton::texture::blender::{
        BlendKind, BlenderPattern, MarbleSharpness, StucciKind, VoronoiColor, Waveform,
    };
    use foton::texture::blender_noise::{BlenderNoise, DistanceMetric, NoiseBasis};
    use foton::texture::musgrave::{Musgrave, MusgraveKind};
    let node = |i: usize| match &s.texture_graph.nodes[i] {
        TextureNode::Blender {
            texture,
            tex1,
            tex2,
            ..
        } => (*texture, *tex1, *tex2),
        other => panic!("not a Blender texture: {other:?}"),
    };
    let pattern = |i: usize| node(i).0.pattern;
    let (b, tex1, tex2) = node(0);
    assert_eq!(
        b.pattern,
        BlenderPattern::Blend {
            kind: BlendKind::Quadratic,
            flip_xy: true
        }
    );
    assert_eq!((b.bright, b.contrast), (1.2, 1.0));
    assert_eq!((tex1, tex2), (TexParam::float(0.0), TexParam::float(1.0)));
    assert_eq!(
        pattern(1),
        BlenderPattern::Magic {
            depth: 3,
            turbulence: 4.0
        }
    );
    let soft = |basis| BlenderNoise {
        basis,
        size: 0.25,
        hard: false,
    };
    assert_eq!(
        pattern(2),
        BlenderPattern::Wood {
            rings: true,
            wave: Waveform::Saw,
            noise: None,
            turbulence: 5.0,
        }
    );
    let (x, tex1, _) = node(3);
    assert_eq!(
        x.pattern,
        BlenderPattern::Blend {
            kind: BlendKind::Linear,
            flip_xy: false
        }
    );
    assert_eq!(tex1, TexParam::float(0.2));
    assert_eq!(
        pattern(4),
        BlenderPattern::Wood {
            rings: true,
            wave: Waveform::Sine,
            noise: Some(BlenderNoise {
                hard: true,
                ..soft(NoiseBasis::BlenderOriginal)
            }),
            turbulence: 5.0,
        }
    );
    assert_eq!(
        pattern(5),
        BlenderPattern::Clouds {
            noise: soft(NoiseBasis::ImprovedPerlin),
            depth: 4,
            color: true
        }
    );
    assert_eq!(
        pattern(6),
        BlenderPattern::Marble {
            noise: BlenderNoise {
                size: 0.5,
                ..soft(NoiseBasis::BlenderOriginal)
            },
            depth: 2,
            turbulence: 5.0,
            wave: Waveform::Triangle,
            sharpness: MarbleSharpness::Sharper,
        }
    );
    assert_eq!(
        pattern(7),
        BlenderPattern::Musgrave {
            fractal: Musgrave {
                kind: MusgraveKind::HeteroTerrain,
                h: 0.5,
                lacunarity: 2.0,
                octaves: 3.5,
                offset: 1.0,
                gain: 1.0,
                basis: NoiseBasis::BlenderOriginal,
            },
            size: 0.25,
            outscale: 1.0,
        }
    );
    assert_eq!(
        pattern(8),
        BlenderPattern::DistortedNoise {
            size: 0.25,
            amount: 2.0,
            distortion: NoiseBasis::CellNoise,
            basis: NoiseBasis::VoronoiF2F1,
        }
    );
    assert_eq!(
        pattern(9),
        BlenderPattern::Stucci {
            noise: soft(NoiseBasis::BlenderOriginal),
            turbulence: 5.0,
            kind: StucciKind::WallOut,
        }
    );
    assert_eq!(
        pattern(10),
        BlenderPattern::Voronoi {
            metric: DistanceMetric::Minkowski(3.0),
            weights: [1.0, -0.5, 0.0, 0.0],
            size: 0.25,
            outscale: 1.0,
            color: VoronoiColor::CellsEdged,
        }
    );
    assert_eq!(pattern(11), BlenderPattern::Noise { depth: 2 });
    assert_eq!(s.texture_graph.nodes.len(), 12);
    let w = messages(&s);
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].contains("\"type\" \"spiral\" unknown: \"lin\""),
        "{w:?}"
    );
    assert!(
        w[1].contains("blender_stucci: \"noisebasis\" \"perlin\" unknown"),
        "{w:?}"
    );
}

// ---------------------------------------------------------------- shapes

#[test]
fn spheres_meshes_and_planes() {
    let s = scene(
        "shapes",
        "WorldBegin\n\
         Shape \"sphere\" \"float radius\" [0.25]\n\
         Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" [0 0 0 1 0 0 1 1 0 0 1 0]\n\
         \"normal N\" [0 0 1 0 0 1 0 0 1 0 0 1] \"float uv\" [0 0 1 0 1 1 0 1]\n\
         Shape \"mesh\" \"integer triindices\" [0 1 2] \"point P\" [0 0 0 1 0 0 0 1 0] \"float st\" [0 0 1 0 0 1]\n\
         \"bool generatetangents\" [\"false\"] \"string name\" [\"m\"]\n\
         Shape \"plane\" \"normal N\" [0 -2 0] \"string name\" [\"Plano1\"]\nWorldEnd\n",
    );
    assert_eq!(s.shapes.len(), 4);
    assert_eq!(s.shapes[0].geometry, Geometry::Sphere { radius: 0.25 });
    assert_eq!(s.shapes[0].location.line, 2);
    let (p, n, uv, i) = mesh(&s.shapes[1].geometry);
    assert_eq!(p[2], Vec3::new(1.0, 1.0, 0.0));
    assert_eq!(n.unwrap(), &[Vec3::Z; 4]);
    assert_eq!(uv.unwrap()[2], Vec2::new(1.0, 1.0));
    assert_eq!(i, &[[0, 1, 2], [0, 2, 3]]);
    let (p, n, uv, i) = mesh(&s.shapes[2].geometry);
    assert_eq!((p.len(), n, i), (3, None, &[[0u32, 1, 2]][..]));
    assert_eq!(uv.unwrap()[2], Vec2::new(0.0, 1.0));
    assert_eq!(s.shapes[3].geometry, Geometry::Plane { normal: -Vec3::Y });
    assert_eq!(s.shapes[0].material, None);
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
}

#[test]
fn box_is_closed_centred_and_wound_outwards() {
    let s = scene(
        "box",
        "WorldBegin\nShape \"box\" \"float width\" [10] \"float height\" [2] \"float depth\" [5]\nWorldEnd\n",
    );
    let (p, n, _, triangles) = mesh(&s.shapes[0].geometry);
    assert_eq!((triangles.len(), n), (12, None));
    let min = p.iter().fold(Vec3::MAX, |a, &b| a.min(b));
    let max = p.iter().fold(Vec3::MIN, |a, &b| a.max(b));
    assert_eq!(
        (min, max),
        (Vec3::new(-5.0, -1.0, -2.5), Vec3::new(5.0, 1.0, 2.5))
    );
    let mut area = 0.0;
    for &[a, b, c] in triangles {
        let (a, b, c) = (p[a as usize], p[b as usize], p[c as usize]);
        let normal = (b - a).cross(c - a);
        let centroid = (a + b + c) / 3.0;
        assert!(normal.dot(centroid) > 0.0, "inward triangle {a} {b} {c}");
        area += normal.length() / 2.0;
    }
    assert!((area - 2.0 * (10.0 * 2.0 + 10.0 * 5.0 + 2.0 * 5.0)).abs() < 1e-3);
}

#[test]
fn plymesh_fans_polygons_and_reads_normals_and_uv() {
    let dir = temp_folder("ply");
    write(
        &dir,
        "models/quad.ply",
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n\
         element face 2\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n2 2 0 0 0 1 0.5 0.5\n\
         4 0 1 2 3\n3 1 4 2\n",
    );
    let path = write(
        &dir,
        "scene.lxs",
        "WorldBegin\nShape \"plymesh\" \"string filename\" [\"models/quad.ply\"]\nWorldEnd\n",
    );
    let s = load(&path).unwrap();
    let (p, n, uv, i) = mesh(&s.shapes[0].geometry);
    assert_eq!(p[4], Vec3::new(2.0, 2.0, 0.0));
    assert_eq!(n.unwrap()[1], Vec3::Z);
    assert_eq!(uv.unwrap()[4], Vec2::new(0.5, 0.5));
    assert_eq!(i, &[[0, 1, 2], [0, 2, 3], [1, 4, 2]]);
}

#[test]
fn mesh_without_points_is_skipped_with_a_warning() {
    let s = scene(
        "empty_mesh",
        "WorldBegin\nShape \"mesh\" \"bool generatetangents\" [\"false\"] \"string name\" [\"Plane\"]\nWorldEnd\n",
    );
    assert!(s.shapes.is_empty());
    assert_eq!(s.warnings.len(), 1);
    assert_eq!(s.warnings[0].location.line, 2);
}

// ---------------------------------------------------------------- lights

#[test]
fn point_spot_and_distant_lights_go_through_the_ctm() {
    let s = scene(
        "lights",
        "WorldBegin\n\
         TransformBegin\nTranslate 0 0 5\n\
         LightSource \"point\" \"point from\" [1 0 0] \"color L\" [1 0.5 0.25] \"float gain\" [4]\n\
         \"bool flipz\" [\"true\"] \"float power\" [0] \"float efficacy\" [0] \"float importance\" [1]\n\
         LightSource \"spot\" \"point from\" [0 0 0] \"point to\" [0 0 -1] \"float coneangle\" [22.5]\n\
         \"float conedeltaangle\" [3.375] \"color L\" [2 2 2] \"float gain\" [0.5]\nTransformEnd\n\
         Rotate 90 0 0 1\n\
         LightSource \"distant\" \"point from\" [1 0 0] \"point to\" [0 0 0] \"color L\" [3 3 3]\nWorldEnd\n",
    );
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
    assert_eq!(
        s.lights[0],
        LightDesc::Point {
            position: Vec3::new(1.0, 0.0, 5.0),
            intensity: Vec3::new(4.0, 2.0, 1.0)
        }
    );
    assert_eq!(
        s.lights[1],
        LightDesc::Spot {
            position: Vec3::new(0.0, 0.0, 5.0),
            direction: -Vec3::Z,
            intensity: Vec3::ONE,
            cone_angle: 22.5,
            cone_delta_angle: 3.375,
            falloff: SpotFalloff::SmoothCosine,
        }
    );
    match s.lights[2] {
        LightDesc::Distant {
            direction_to_light,
            radiance,
        } => {
            assert!(close(direction_to_light, Vec3::Y), "{direction_to_light}");
            assert_eq!(radiance, Vec3::splat(3.0));
        }
        ref other => panic!("{other:?}"),
    }
}

/// A point light of intensity I emits 4 pi I in all; with `power` and `efficacy` LuxRender
/// rescales the gain so that its luminous flux 4 pi Y(I) is power * efficacy.
#[test]
fn point_light_power_sets_its_luminous_flux() {
    let s = scene(
        "point_power",
        "WorldBegin
         LightSource \"point\" \"color L\" [1 0.5 0.25] \"float gain\" [4] \"float power\" [60] \"float efficacy\" [17]\n         LightSource \"point\" \"color L\" [1 0.5 0.25] \"float power\" [60] \"float efficacy\" [0]\nWorldEnd\n",
    );
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
    let l = Vec3::new(1.0, 0.5, 0.25);
    let intensity = |light: &LightDesc| match light {
        LightDesc::Point { intensity, .. } => *intensity,
        other => panic!("{other:?}"),
    };
    // gain * power * efficacy / (4 pi Y(L)): the file's gain scales the flux asked for.
    let expected = l * (4.0 * 60.0 * 17.0 / (4.0 * PI64 * luminance64(l))) as f32;
    assert!(close_rel(intensity(&s.lights[0]), expected), "{expected}");
    let flux = 4.0 * PI64 * luminance64(intensity(&s.lights[0]));
    assert!((flux / (4.0 * 60.0 * 17.0) - 1.0).abs() < 1e-5, "{flux}");
    // Efficacy 0: no power normalisation, L * gain as written.
    assert_eq!(intensity(&s.lights[1]), l);
}

/// LuxRender's spot light counts its flux over the cone, the falloff band at half weight:
/// 2 pi Y(I) (1 - (cos(coneangle - conedeltaangle) + cos(coneangle)) / 2).
#[test]
fn spot_light_power_sets_its_luminous_flux() {
    let s = scene(
        "spot_power",
        "WorldBegin\n\
         LightSource \"spot\" \"color L\" [0.2 1 0.5] \"float gain\" [3] \"float coneangle\" [40] \"float conedeltaangle\" [10] \"float power\" [25] \"float efficacy\" [17]\nWorldEnd\n",
    );
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
    let LightDesc::Spot { intensity, .. } = s.lights[0] else {
        panic!("{:?}", s.lights[0]);
    };
    let l = Vec3::new(0.2, 1.0, 0.5);
    let band = 1.0 - 0.5 * (30f64.to_radians().cos() + 40f64.to_radians().cos());
    let expected = l * (3.0 * 25.0 * 17.0 / (2.0 * PI64 * luminance64(l) * band)) as f32;
    assert!(close_rel(intensity, expected), "{intensity} {expected}");
}

#[test]
fn infinite_lights_constant_and_mapped() {
    let dir = temp_folder("infinite");
    write_image(&dir, "sky.png");
    let path = write(
        &dir,
        "scene.lxs",
        "WorldBegin\nLightSource \"infinite\" \"color L\" [0.5 0.5 0.5] \"float gain\" [2]\n\
         AttributeBegin\nRotate 90 1 0 0\n\
         LightSource \"infinite\" \"string mapname\" [\"sky.png\"]\nAttributeEnd\nWorldEnd\n",
    );
    let s = load(&path).unwrap();
    assert_eq!(
        s.lights[0],
        LightDesc::Infinite {
            radiance: Vec3::ONE,
            map: None,
            light_to_world: Mat4::IDENTITY
        }
    );
    match &s.lights[1] {
        LightDesc::Infinite {
            radiance,
            map: Some(0),
            light_to_world,
        } => {
            assert_eq!(*radiance, Vec3::ONE);
            assert!(light_to_world.abs_diff_eq(Mat4::from_rotation_x(90f32.to_radians()), 1e-6));
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        (s.textures[0].name.as_str(), s.textures[0].width),
        ("sky.png", 2)
    );
}

#[test]
fn area_light_applies_to_following_shapes_in_its_block() {
    let s = scene(
        "area",
        "WorldBegin\nAttributeBegin #  \"Area\"\n\
         AreaLightSource \"area\" \"float importance\" [1] \"float power\" [100] \"float efficacy\" [17]\n\
         \"color L\" [1 0.9 0.6] \"integer nsamples\" [1] \"float gain\" [2]\n\
         Shape \"sphere\" \"float radius\" [0.05]\nShape \"sphere\"\nAttributeEnd # \"\"\n\
         Shape \"sphere\"\nWorldEnd\n",
    );
    // Each shape's radiance puts the asked-for flux on its own area.
    let l = Vec3::new(1.0, 0.9, 0.6);
    for (shape, radius) in [(&s.shapes[0], 0.05), (&s.shapes[1], 1.0)] {
        let expected = luxrender_area_radiance(l, 2.0, 100.0, 17.0, 4.0 * PI64 * radius * radius);
        let radiance = shape.area_light.expect("an emitter").radiance;
        assert!(close_rel(radiance, expected), "{radiance} {expected}");
    }
    assert_eq!(s.shapes[2].area_light, None);
    assert!(s.lights.is_empty());
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
}

/// LuxRender 1.x's area light defaults to `power` 100 W and `efficacy` 17 lm/W
/// (`lights/area.cpp`, `CreateAreaLight`), so a light written without them is normalised to
/// 1700 lm as well; `power` 0 turns the normalisation off.
#[test]
fn area_light_without_power_gets_luxrenders_default_flux() {
    let s = scene(
        "area_default",
        "WorldBegin\nAttributeBegin\n\
         AreaLightSource \"area\" \"color L\" [1 0.5 0.25] \"float gain\" [30]\n\
         Shape \"sphere\" \"float radius\" [2]\nAttributeEnd\n\
         AttributeBegin\nAreaLightSource \"area\" \"color L\" [1 0.5 0.25] \"float power\" [0]\n\
         Shape \"sphere\"\nAttributeEnd\nWorldEnd\n",
    );
    let l = Vec3::new(1.0, 0.5, 0.25);
    let expected = luxrender_area_radiance(l, 30.0, 100.0, 17.0, 4.0 * PI64 * 4.0);
    let radiance = s.shapes[0].area_light.expect("an emitter").radiance;
    assert!(close_rel(radiance, expected), "{radiance} {expected}");
    assert_eq!(s.shapes[1].area_light.expect("an emitter").radiance, l);
}

// ---------------------------------------------------------------- includes and paths

#[test]
fn includes_resolve_next_to_the_including_file_then_in_parent_folders() {
    let dir = temp_folder("include");
    write(
        &dir,
        "scene/sub/materials.lxm",
        "MakeNamedMaterial \"m\" \"string type\" [\"matte\"]\n",
    );
    write(
        &dir,
        "shared.lxo",
        "NamedMaterial \"m\"\nShape \"sphere\"\n",
    );
    let path = write(
        &dir,
        "scene/scene.lxs",
        "WorldBegin\nInclude \"sub/materials.lxm\"\nInclude \"shared.lxo\"\nWorldEnd\n",
    );
    let s = load(&path).unwrap();
    assert_eq!((s.materials.len(), s.shapes.len()), (1, 1));
    assert_eq!(s.shapes[0].material, Some(0));
    assert_eq!(s.shapes[0].location.file, dir.join("shared.lxo"));
    assert_eq!(s.shapes[0].location.line, 2);
    assert_eq!(s.warnings.len(), 1);
    assert_eq!(
        s.warnings[0].location,
        foton::scene::desc::Location::line(path.clone(), 3)
    );
    assert!(s.warnings[0].message.contains("found in a parent folder"));
}

#[test]
fn include_cycles_are_errors() {
    let dir = temp_folder("cycle");
    let path = write(&dir, "a.lxs", "Include \"a.lxs\"\n");
    let e = load(&path).unwrap_err();
    assert_eq!(e.location.line, 1);
    assert!(e.message.contains("includes itself"), "{e}");
}

// ---------------------------------------------------------------- errors and warnings

#[test]
fn unknown_directives_and_parameters_warn_with_file_and_line() {
    let s = scene(
        "unknown",
        "Renderer \"sampler\"\nAccelerator \"qbvh\"\nFoo \"bar\" \"float x\" [1]\n\
         WorldBegin\nLightGroup \"default\"\nShape \"sphere\" \"float size\" [2]\nShape \"cone\"\nWorldEnd\n",
    );
    let w = messages(&s);
    assert_eq!(w.len(), 3, "{w:?}");
    assert!(w[0].ends_with("scene.lxs:3: warning: unknown directive Foo ignored"));
    assert!(w[1].ends_with(
        "scene.lxs:6: warning: Shape \"sphere\": unknown parameter \"float size\" ignored"
    ));
    assert!(w[2].ends_with("scene.lxs:7: warning: Shape \"cone\" unsupported: skipped"));
    assert_eq!(s.shapes.len(), 1);
}

/// `(name, scene text, line, message)`: each must fail with exactly that line and message.
const ERRORS: &[(&str, &str, usize, &str)] = &[
    (
        "bad_number",
        "WorldBegin\nShape \"sphere\" \"float radius\" [1x]\nWorldEnd\n",
        2,
        "bad number 1x",
    ),
    (
        "unterminated",
        "WorldBegin\nShape \"sphere\n",
        2,
        "unterminated string \"sphere",
    ),
    (
        "attribute_end",
        "WorldBegin\nAttributeEnd\nWorldEnd\n",
        2,
        "AttributeEnd without AttributeBegin",
    ),
    (
        "transform_end",
        "TransformEnd\n",
        1,
        "TransformEnd without TransformBegin",
    ),
    (
        "mismatched_end",
        "AttributeBegin\nTransformEnd\n",
        2,
        "TransformEnd does not match the AttributeBegin at ",
    ),
    ("world_end", "WorldEnd\n", 1, "WorldEnd without WorldBegin"),
    (
        "open_attribute",
        "WorldBegin\nAttributeBegin\n",
        2,
        "AttributeBegin is never closed",
    ),
    (
        "open_world",
        "\nWorldBegin\n",
        2,
        "WorldBegin is never closed by WorldEnd",
    ),
    (
        "world_end_open_block",
        "WorldBegin\nTransformBegin\nWorldEnd\n",
        3,
        "WorldEnd while the TransformBegin at ",
    ),
    (
        "look_at_8",
        "LookAt 0 0 0 1 1 1 0 0\n",
        1,
        "LookAt: 8 values, expected 9",
    ),
    (
        "transform_15",
        "Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0]\n",
        1,
        "Transform: 15 values, expected 16",
    ),
    (
        "look_at_degenerate",
        "LookAt 0 0 0 0 0 0 0 0 1\n",
        1,
        "LookAt: eye, look and up do not define a view",
    ),
    (
        "named_material",
        "WorldBegin\n\nNamedMaterial \"nope\"\nWorldEnd\n",
        3,
        "NamedMaterial \"nope\": no such material",
    ),
    (
        "unknown_texture",
        "WorldBegin\nMaterial \"matte\" \"texture Kd\" [\"nope\"]\nWorldEnd\n",
        2,
        "\"Kd\" names texture \"nope\", which is not defined",
    ),
    (
        "mix_unknown",
        "WorldBegin\nMaterial \"mix\" \"string namedmaterial1\" [\"a\"] \"string namedmaterial2\" [\"b\"]\nWorldEnd\n",
        2,
        "mix: \"namedmaterial1\" \"a\": no such material",
    ),
    (
        "index_range",
        "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [0 1 3] \"point P\" [0 0 0 1 0 0 0 1 0]\nWorldEnd\n",
        2,
        "trianglemesh: index 3 out of range (3 vertices)",
    ),
    (
        "index_count",
        "WorldBegin\nShape \"mesh\" \"integer triindices\" [0 1] \"point P\" [0 0 0 1 0 0 0 1 0]\nWorldEnd\n",
        2,
        "mesh: 2 indices, not a multiple of 3",
    ),
    (
        "p_count",
        "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [0 1 2]\n\"point P\" [0 0 0 1 0 0 0 1]\nWorldEnd\n",
        3,
        "\"point P\": 8 values, not a multiple of 3",
    ),
    (
        "normal_count",
        "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [0 0 1]\nWorldEnd\n",
        2,
        "trianglemesh: 1 normals for 3 vertices",
    ),
    (
        "fov_values",
        "Camera \"perspective\" \"float fov\" [45 50]\n",
        1,
        "\"float fov\": 2 values, expected 1",
    ),
    (
        "param_type",
        "Film \"fleximage\" \"integer xresolution\" [\"big\"]\n",
        1,
        "\"integer xresolution\": expected numbers",
    ),
    (
        "resolution",
        "Film \"fleximage\" \"integer xresolution\" [0]\n",
        1,
        "\"xresolution\" 0 must be positive",
    ),
    (
        "missing_type",
        "Shape\n",
        1,
        "Shape: expected a quoted name or type",
    ),
    (
        "stray_value",
        "\n[1 2]\n",
        2,
        "expected a directive, found [",
    ),
    (
        "stray_argument",
        "WorldBegin\n[1 2]\n",
        2,
        "WorldBegin: unexpected [",
    ),
    (
        "rotate_axis",
        "Rotate 30 0 0 0\n",
        1,
        "Rotate: the axis is zero",
    ),
    (
        "missing_include",
        "WorldBegin\nInclude \"nothing.lxo\"\nWorldEnd\n",
        2,
        "Include \"nothing.lxo\": file not found (looked in ",
    ),
    (
        "missing_texture",
        "WorldBegin\nTexture \"t\" \"color\" \"imagemap\" \"string filename\" [\"none.png\"]\nWorldEnd\n",
        2,
        "Texture \"t\" \"none.png\": file not found (looked in ",
    ),
    (
        "missing_ply",
        "WorldBegin\nShape \"plymesh\" \"string filename\" [\"none.ply\"]\nWorldEnd\n",
        2,
        "plymesh \"none.ply\": file not found (looked in ",
    ),
];

#[test]
fn malformed_scenes_are_errors_naming_file_line_and_text() {
    for &(name, text, line, message) in ERRORS {
        let e = error(name, text);
        assert_eq!(e.location.line, line, "{name}: {e}");
        assert!(e.location.file.ends_with("scene.lxs"), "{name}: {e}");
        assert!(e.message.starts_with(message), "{name}: {e}");
        assert!(
            e.to_string()
                .contains(&format!("scene.lxs:{line}: error: {message}")),
            "{name}: {e}"
        );
    }
}

#[test]
fn missing_file_errors_say_where_they_looked() {
    let dir = temp_folder("missing");
    let path = write(
        &dir,
        "scene_1/scene_1.lxs",
        "WorldBegin\n\nInclude \"scene_1.lxo\"\nWorldEnd\n",
    );
    let e = load(&path).unwrap_err();
    let folder = std::path::absolute(dir.join("scene_1")).unwrap();
    assert_eq!(
        e.to_string(),
        format!(
            "{}:3: error: Include \"scene_1.lxo\": file not found (looked in {} and its parent folders)",
            path.display(),
            folder.display()
        )
    );
}

#[test]
fn errors_in_included_files_name_the_included_line() {
    let dir = temp_folder("included_error");
    write(&dir, "geometry.lxo", "Shape \"sphere\"\n\nLookAt 1 2\n");
    let path = write(
        &dir,
        "scene.lxs",
        "WorldBegin\nInclude \"geometry.lxo\"\nWorldEnd\n",
    );
    let e = load(&path).unwrap_err();
    assert_eq!(e.location.file, dir.join("geometry.lxo"));
    assert_eq!(e.location.line, 3);
    assert_eq!(e.message, "LookAt: 2 values, expected 9");
}

#[test]
fn undecodable_images_and_ply_files_are_errors() {
    let dir = temp_folder("undecodable");
    write(&dir, "bad.png", "this is not a png");
    write(
        &dir,
        "bad.ply",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\nnope\n",
    );
    let path = write(
        &dir,
        "scene.lxs",
        "WorldBegin\nTexture \"t\" \"color\" \"imagemap\" \"string filename\" [\"bad.png\"]\nWorldEnd\n",
    );
    let e = load(&path).unwrap_err();
    assert_eq!(e.location.line, 2);
    assert!(
        e.message
            .starts_with("Texture \"t\" \"bad.png\": cannot decode"),
        "{e}"
    );
    let path = write(
        &dir,
        "ply.lxs",
        "WorldBegin\nShape \"plymesh\" \"string filename\" [\"bad.ply\"]\nWorldEnd\n",
    );
    let e = load(&path).unwrap_err();
    assert_eq!(e.location.line, 2);
    assert!(e.message.starts_with("plymesh \"bad.ply\": "), "{e}");
}

/// A scene using most of the format, to mutate.
const FUZZ_SEED: &str = "LookAt 0 -5 1  0 0 1  0 0 1\n\
Camera \"perspective\" \"float fov\" [49.1] \"float screenwindow\" [-1 1 -0.5625 0.5625]\n\
Film \"fleximage\" \"integer xresolution\" [96] \"integer yresolution\" [54] \"string tonemapkernel\" [\"linear\"]\n\
PixelFilter \"gaussian\" \"float xwidth\" [2] \"float ywidth\" [2]\n\
Sampler \"random\" \"integer pixelsamples\" [4]\n\
WorldBegin\n\
Texture \"c\" \"color\" \"constant\" \"color value\" [0.2 0.4 0.6]\n\
MakeNamedMaterial \"a\" \"texture Kd\" [c] \"float sigma\" [0] \"string type\" [\"matte\"]\n\
MakeNamedMaterial \"b\" \"color Kr\" [1 1 1] \"int roughness\" [0.1] \"string type\" [\"metal2\"]\n\
MakeNamedMaterial \"x\" \"string namedmaterial1\" [\"a\"] \"string namedmaterial2\" [\"b\"] \"string type\" [\"mix\"]\n\
AttributeBegin #  \"Area\"\n\
Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 1 5 1]\n\
NamedMaterial \"a\"\n\
AreaLightSource \"area\" \"color L\" [1 1 1] \"float power\" [100] \"float efficacy\" [17]\n\
Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" [-1 1 0 1 1 0 1 -1 0 -1 -1 0] \"float uv\" [0 0 1 0 1 1 0 1]\n\
AttributeEnd # \"\"\n\
TransformBegin\nTranslate 1 2 3\nRotate 30 0 1 0\nScale 2 2 2\n\
LightSource \"spot\" \"point from\" [0 0 0] \"point to\" [0 0 -1] \"float coneangle\" [30]\n\
TransformEnd\n\
LightSource \"distant\" \"point from\" [0 0 1] \"point to\" [0 0 0]\n\
Shape \"box\" \"float width\" [2] \"float height\" [1] \"float depth\" [3]\n\
Shape \"plane\" \"normal N\" [0 0 1]\n\
Shape \"sphere\" \"float radius\" [1]\n\
WorldEnd\n";

#[test]
fn random_mutations_never_panic() {
    assert!(load_text("fuzz_seed", FUZZ_SEED).is_ok());
    fuzz(FUZZ_SEED, &temp_folder("fuzz"), 400);
}

// ---------------------------------------------------------------- the course's scenes

/// Mutates `seed` `count` times, loading each from `dir`: `load` must return, never panic.
fn fuzz(seed: &str, dir: &Path, count: usize) {
    let path = dir.join("scene.lxs");
    let alphabet = b" \n\"[]#.-0123456789eAaWorldBegin";
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut random = move |n: usize| {
        // xorshift64
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    for _ in 0..count {
        let mut bytes = seed.as_bytes().to_vec();
        for _ in 0..1 + random(4) {
            let at = random(bytes.len());
            match random(3) {
                0 => bytes[at] = alphabet[random(alphabet.len())],
                1 => {
                    bytes.remove(at);
                }
                _ => {
                    let end = (at + random(40)).min(bytes.len());
                    let chunk = bytes[at..end].to_vec();
                    let to = random(bytes.len());
                    bytes.splice(to..to, chunk);
                }
            }
        }
        std::fs::write(&path, &bytes).unwrap();
        let _ = load(&path);
    }
}

/// `scenes/itba` of the shared folder: `$FOTON_SHARED`, else `../shared`, else `/work/shared`.
fn course_scenes() -> Option<PathBuf> {
    let candidates = [
        std::env::var_os("FOTON_SHARED").map(PathBuf::from),
        Some(Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared")),
        Some(PathBuf::from("/work/shared")),
    ];
    let found = candidates
        .into_iter()
        .flatten()
        .map(|shared| shared.join("scenes/itba"))
        .find(|scenes| scenes.is_dir());
    if found.is_none() {
        println!("skipped: ../shared not found");
    }
    found
}

#[test]
fn course_scenes_load_with_the_expected_contents() {
    let Some(scenes) = course_scenes() else {
        return;
    };
    // (scene, shapes, lights, materials, textures, area-lit shapes)
    let expected = [
        ("CornellBox/cornell-box.lxs", 8, 0, 5, 0, 1),
        ("CornellBoxSphere/cornell-box.lxs", 8, 0, 5, 0, 1),
        ("metal2_scene/untitled.lxs", 4, 0, 4, 0, 1),
        ("pikachu/untitled.lxs", 5, 2, 5, 0, 0),
        ("charizard/untitled.lxs", 2, 1, 2, 2, 0),
        ("scene_2/scene_2.lxs", 6, 1, 6, 2, 0),
    ];
    for (name, shapes, lights, materials, textures, emitters) in expected {
        let s = load(&scenes.join(name)).unwrap_or_else(|e| panic!("{e}"));
        let area_lit = s.shapes.iter().filter(|s| s.area_light.is_some()).count();
        assert_eq!(
            (
                s.shapes.len(),
                s.lights.len(),
                s.materials.len(),
                s.textures.len(),
                area_lit
            ),
            (shapes, lights, materials, textures, emitters),
            "{name}"
        );
        assert_eq!(
            (s.camera.kind.name(), s.camera.fov_degrees),
            ("pinhole", 49.134342),
            "{name}"
        );
        assert_eq!(s.max_depth, Some(16), "{name}");
        assert_eq!(s.filter.kind, FilterKind::BlackmanHarris, "{name}");
    }
}

#[test]
fn cornell_box_details() {
    let Some(scenes) = course_scenes() else {
        return;
    };
    let s = load(&scenes.join("CornellBox/cornell-box.lxs")).unwrap();
    assert_eq!((s.film.x_resolution, s.film.y_resolution), (960, 540));
    assert_eq!(s.film.filename.as_deref(), Some("cornell-box.Scene.00244"));
    // Its one departure: LuxRender's bidirectional integrator, path traced.
    let w = messages(&s);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("SurfaceIntegrator \"bidirectional\""),
        "{w:?}"
    );
    let light = s.shapes.last().unwrap();
    assert_eq!(light.geometry, Geometry::Sphere { radius: 0.05 });
    // The sphere is scaled uniformly by k: its area is 4 pi (k r)^2.
    let m = glam::Mat3::from_mat4(light.object_to_world);
    let k = f64::from(m.x_axis.length());
    assert!(
        m.abs_diff_eq(glam::Mat3::from_diagonal(Vec3::splat(k as f32)), 1e-4),
        "{m}"
    );
    let radius = 0.05 * k;
    let expected = luxrender_area_radiance(
        Vec3::new(1.0, 0.919_171_9, 0.623_396_5),
        2.0,
        100.0,
        17.0,
        4.0 * PI64 * radius * radius,
    );
    let radiance = light.area_light.expect("an emitter").radiance;
    assert!(close_rel(radiance, expected), "{radiance} {expected}");
    assert_eq!(s.materials[light.material.unwrap()], MaterialDesc::Null);
    assert!(close(
        light.object_to_world.transform_point3(Vec3::ZERO),
        Vec3::new(0.120_537_62, 2.863_173_5, 5.453_133)
    ));
}

#[test]
fn metal2_scene_is_not_mirrored() {
    let Some(scenes) = course_scenes() else {
        return;
    };
    let s = load(&scenes.join("metal2_scene/untitled.lxs")).unwrap();
    let world_to_camera = s.camera.camera_to_world.inverse();
    let left = world_to_camera.transform_point3(Vec3::new(-3.0, 0.0, 1.0));
    let right = world_to_camera.transform_point3(Vec3::new(0.0, 0.0, 1.0));
    assert!(left.z > 0.0 && right.z > 0.0, "both in front of the camera");
    assert!(
        left.x / left.z < right.x / right.z,
        "(-3,0,1) must appear left of (0,0,1)"
    );
    assert!(s.materials.contains(&MaterialDesc::RoughConductor {
        specular: ColorParam::Constant(Vec3::ONE),
        alpha_u: 0.075,
        alpha_v: 0.075,
    }));
}

#[test]
fn charizard_and_scene_2_textures_resolve_through_parent_folders() {
    let Some(scenes) = course_scenes() else {
        return;
    };
    let s = load(&scenes.join("charizard/untitled.lxs")).unwrap();
    assert_eq!(s.textures[0].name, "D.001_color");
    assert_eq!(
        (s.textures[0].scale, s.textures[0].delta),
        (Vec2::new(1.0, -1.0), Vec2::new(0.0, 1.0))
    );
    let (_, normals, uvs, _) = mesh(&s.shapes[0].geometry);
    assert!(normals.is_some() && uvs.is_some());
    let s = load(&scenes.join("scene_2/scene_2.lxs")).unwrap();
    assert!(s.textures[0].path.ends_with("texture/metal-1.jpg"));
    assert!(s.materials.contains(&MaterialDesc::Diffuse {
        reflectance: ColorParam::Texture(1)
    }));
    assert!(s.materials.contains(&MaterialDesc::RoughConductor {
        specular: ColorParam::Texture(0),
        alpha_u: 0.2,
        alpha_v: 0.2,
    }));
    assert_eq!(
        s.lights[0],
        LightDesc::Point {
            position: Vec3::new(0.0, -1.0, 1.0),
            intensity: Vec3::ONE
        }
    );
}

#[test]
fn course_scenes_without_geometry_name_the_missing_include() {
    let Some(scenes) = course_scenes() else {
        return;
    };
    let expected = [
        ("scene_hard/scene_hard.lxs", 69, "scene_hard.lxo"),
        ("scene_1/scene_1.lxs", 77, "scene_1.lxo"),
        ("scene_3/scene_3.lxs", 77, "scene_3.lxo"),
        (
            "glass_bunny/glass_bunny.lxs",
            77,
            "barebone-bunny/Scene/00002/LuxRender-Geometry.lxo",
        ),
        (
            "Dragon/dragon.lxs",
            69,
            "dragon/Scene/00001/LuxRender-Geometry.lxo",
        ),
        (
            "Sponza/sponza.lxs",
            69,
            "sponza/Scene/00001/LuxRender-Geometry.lxo",
        ),
    ];
    for (name, line, include) in expected {
        let path = scenes.join(name);
        let e = load(&path).unwrap_err();
        assert_eq!(e.location.file, path, "{name}");
        assert_eq!(e.location.line, line, "{name}");
        assert!(
            e.message.starts_with(&format!(
                "Include \"{include}\": file not found (looked in "
            )),
            "{name}: {e}"
        );
    }
}

#[test]
fn random_mutations_of_a_course_scene_never_panic() {
    let Some(scenes) = course_scenes() else {
        return;
    };
    // The Cornell box with its includes inlined, so that every part of it gets mutated.
    let folder = scenes.join("CornellBox");
    let main = std::fs::read_to_string(folder.join("cornell-box.lxs")).unwrap();
    let inlined: String = main
        .lines()
        .map(|line| match line.strip_prefix("Include \"") {
            Some(rest) => std::fs::read_to_string(folder.join(rest.trim_end_matches('"'))).unwrap(),
            None => line.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert_eq!(
        load_text("cornell_inlined", &inlined).unwrap().shapes.len(),
        8
    );
    fuzz(&inlined, &temp_folder("fuzz_cornell"), 300);
}

/// A type name LuxRender does not have (a typo, or another renderer's) is a warning naming the
/// line and the name; LuxRender's names are not.
#[test]
fn unknown_type_names_are_warnings() {
    let s = scene(
        "unknown_types",
        &format!(
            "SurfaceIntegrator \"pathh\"\nSampler \"sobolx\"\nFilm \"rgb\" \"integer xresolution\" [8]\n\
             Renderer \"samplr\"\nAccelerator \"qbvh\"\nSampler \"metropolis\"\n{WORLD}"
        ),
    );
    let w = messages(&s);
    assert_eq!(w.len(), 4, "{w:?}");
    for (i, name) in ["pathh", "sobolx", "rgb", "samplr"].iter().enumerate() {
        assert!(
            w[i].contains(&format!(":{}: warning: unknown", i + 1)) && w[i].contains(name),
            "{w:?}"
        );
    }
    assert_eq!(s.film.x_resolution, 8);
}

// ---------------------------------------------------------------- real LuxRender scenes' needs

#[test]
fn directlighting_is_the_ray_caster_and_integrators_foton_lacks_warn_once() {
    let s = scene(
        "directlighting",
        &format!("SurfaceIntegrator \"directlighting\" \"integer maxdepth\" [5]\n{WORLD}"),
    );
    assert_eq!(
        s.integrator,
        Some(foton::settings::IntegratorKind::RayCaster)
    );
    assert_eq!(s.max_depth, Some(5));
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
    for kind in [
        "bidirectional",
        "sppm",
        "exphotonmap",
        "igi",
        "distributedpath",
    ] {
        let s = scene(kind, &format!("SurfaceIntegrator \"{kind}\"\n{WORLD}"));
        assert_eq!(s.integrator, None);
        let w = messages(&s);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains(&format!("\"{kind}\"")) && w[0].contains("path tracer"),
            "{w:?}"
        );
    }
}

/// `glass2`'s index is the shape's interior volume's `fresnel` over its exterior's
/// (`materials/glass2.cpp`): 1.5 inside alone, 1.5 / 1.33 in water, 1 with no volume (the
/// interior's default `fresnel` is 1.5); `AttributeEnd` restores the volumes. What foton does
/// not render (clear absorption, homogeneous scattering) is warned once per kind.
#[test]
fn glass2_takes_its_index_from_the_interior_and_exterior_volumes() {
    let s = scene(
        "volumes",
        "WorldBegin\nMakeNamedVolume \"glass\" \"clear\" \"float fresnel\" [1.5] \
         \"color absorption\" [1 0 0]\n\
         MakeNamedVolume \"water\" \"homogeneous\" \"float fresnel\" [1.33] \"color sigma_s\" [1 1 1]\n\
         MakeNamedVolume \"default\" \"clear\"\n\
         Material \"glass2\"\nShape \"sphere\"\n\
         AttributeBegin\nInterior \"glass\"\nShape \"sphere\"\nExterior \"water\"\nShape \"sphere\"\n\
         Shape \"sphere\"\nAttributeEnd\nShape \"sphere\"\n\
         Interior \"default\"\nShape \"sphere\"\nWorldEnd\n",
    );
    let ior = |k: usize| match &s.materials[s.shapes[k].material.unwrap()] {
        MaterialDesc::Dielectric { ior, .. } => *ior,
        other => panic!("{other:?}"),
    };
    let iors: Vec<f32> = (0..6).map(ior).collect();
    assert_eq!(iors, [1.0, 1.5, 1.5 / 1.33, 1.5 / 1.33, 1.0, 1.5]);
    assert_eq!(s.shapes[2].material, s.shapes[3].material, "made once");
    let w = messages(&s);
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].contains(":2: warning: volume \"clear\": \"absorption\""),
        "{w:?}"
    );
    assert!(
        w[1].contains(":3: warning: volume \"homogeneous\""),
        "{w:?}"
    );
    let e = scene("no_volume", "WorldBegin\nInterior \"nothing\"\nWorldEnd\n");
    assert!(
        messages(&e)[0].contains("no such volume"),
        "{:?}",
        messages(&e)
    );
}

#[test]
fn camera_without_depth_of_field_as_luxblend_writes_it_is_a_pinhole() {
    let s = scene(
        "no_dof",
        &format!(
            "Camera \"perspective\" \"float fov\" [40] \"float lensradius\" [0] \
             \"float focaldistance\" [0]\n{WORLD}"
        ),
    );
    assert_eq!(s.camera.lens_radius, 0.0);
    assert!(s.camera.focal_distance > 0.0);
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
    let e = error(
        "dof_at_zero",
        &format!(
            "Camera \"perspective\" \"float lensradius\" [0.1] \"float focaldistance\" [0]\n{WORLD}"
        ),
    );
    assert!(e.message.contains("focaldistance"), "{e}");
}

/// LuxBlend 2.5 writes the names in an included `.lxo` relative to the main `.lxs`, which is
/// where LuxRender looks: found there without a warning.
#[test]
fn names_in_included_files_resolve_against_the_main_scene_silently() {
    let dir = temp_folder("main_dir");
    write(
        &dir,
        "scene/geometry/objects.lxo",
        "Include \"materials.lxm\"\nShape \"sphere\"\n",
    );
    write(&dir, "scene/materials.lxm", "Material \"matte\"\n");
    let path = write(
        &dir,
        "scene/scene.lxs",
        "WorldBegin\nInclude \"geometry/objects.lxo\"\nWorldEnd\n",
    );
    let s = load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((s.materials.len(), s.shapes.len()), (1, 1));
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
}

/// LuxRender's quadrics: a disk of radius r keeps its area pi r² in the plane z = height
/// facing +z; a cylinder its area 2 pi r h with normals pointing out.
#[test]
fn disk_and_cylinder_shapes() {
    let s = scene(
        "quadrics",
        "WorldBegin\nShape \"disk\" \"float radius\" [2] \"float height\" [0.5]\n\
         Shape \"disk\" \"float radius\" [2] \"float innerradius\" [1] \"float phimax\" [90]\n\
         Shape \"cylinder\" \"float radius\" [1] \"float zmin\" [0] \"float zmax\" [3]\nWorldEnd\n",
    );
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
    let area_and_normal = |geometry: &Geometry| {
        let (positions, _, uvs, indices) = mesh(geometry);
        assert!(uvs.is_some());
        let mut area = 0.0;
        let mut normal_sum = Vec3::ZERO;
        for &[a, b, c] in indices {
            let [pa, pb, pc] = [a, b, c].map(|i| positions[i as usize]);
            let cross = (pb - pa).cross(pc - pa);
            area += 0.5 * cross.length();
            normal_sum += cross.normalize() * pa.truncate().extend(0.0).length().signum();
        }
        (area, positions.to_vec(), normal_sum)
    };
    let (area, positions, normals) = area_and_normal(&s.shapes[0].geometry);
    assert!((area - std::f32::consts::PI * 4.0).abs() < 1e-3, "{area}");
    assert!(positions.iter().all(|p| p.z == 0.5));
    assert!(normals.normalize().dot(Vec3::Z) > 0.999, "{normals}");
    let (area, positions, _) = area_and_normal(&s.shapes[1].geometry);
    assert!(
        (area - 0.25 * std::f32::consts::PI * 3.0).abs() < 1e-3,
        "{area}"
    );
    assert!(positions.iter().all(|p| p.x >= -1e-4 && p.y >= -1e-4));
    let (area, positions, _) = area_and_normal(&s.shapes[2].geometry);
    assert!(
        (area - 2.0 * std::f32::consts::PI * 3.0).abs() < 1e-3,
        "{area}"
    );
    let (_, normals, _, indices) = mesh(&s.shapes[2].geometry);
    for &[a, b, c] in indices {
        let [pa, pb, pc] = [a, b, c].map(|i| positions[i as usize]);
        let outward = ((pa + pb + pc) / 3.0).truncate().extend(0.0);
        assert!((pb - pa).cross(pc - pa).dot(outward) > 0.0);
        assert!(normals.unwrap()[a as usize].dot(outward) > 0.0);
    }
}

/// The shapes a scene draws, its instances expanded into their groups' members placed by
/// the instance's map (as `scene::build` places them).
fn expanded_shapes(scene: &SceneDesc) -> Vec<foton::scene::desc::ShapeDesc> {
    (scene.shapes.iter())
        .flat_map(|shape| match shape.geometry {
            Geometry::Instance { group } => (scene.shape_groups[group].iter())
                .map(|member| foton::scene::desc::ShapeDesc {
                    object_to_world: shape.object_to_world * member.object_to_world,
                    ..member.clone()
                })
                .collect(),
            _ => vec![shape.clone()],
        })
        .collect()
}

/// `ObjectInstance` draws the object's shapes under the instance's transformation times their
/// own: the same shapes as writing them out in place. The object is one shape group placed
/// twice; its emitting shape is copied into each instance instead.
#[test]
fn object_instances_equal_their_shapes_written_out() {
    let instanced = scene(
        "instanced",
        "WorldBegin\nMaterial \"matte\"\nObjectBegin \"pair\"\nTranslate 0 0 1\n\
         Shape \"sphere\" \"float radius\" [0.5]\nShape \"disk\" \"float radius\" [2]\n\
         AttributeBegin\nAreaLightSource \"area\" \"color L\" [1 1 1]\nShape \"disk\" \"float radius\" [0.1]\nAttributeEnd\nObjectEnd\n\
         Shape \"sphere\" \"float radius\" [3]\n\
         AttributeBegin\nTranslate 5 0 0\nObjectInstance \"pair\"\nAttributeEnd\n\
         AttributeBegin\nRotate 90 0 0 1\nScale 2 2 2\nObjectInstance \"pair\"\nAttributeEnd\nWorldEnd\n",
    );
    let written_out = scene(
        "written_out",
        "WorldBegin\nMaterial \"matte\"\nShape \"sphere\" \"float radius\" [3]\n\
         AttributeBegin\nTranslate 5 0 0\nTranslate 0 0 1\n\
         Shape \"sphere\" \"float radius\" [0.5]\nShape \"disk\" \"float radius\" [2]\n\
         AreaLightSource \"area\" \"color L\" [1 1 1]\nShape \"disk\" \"float radius\" [0.1]\nAttributeEnd\n\
         AttributeBegin\nRotate 90 0 0 1\nScale 2 2 2\nTranslate 0 0 1\n\
         Shape \"sphere\" \"float radius\" [0.5]\nShape \"disk\" \"float radius\" [2]\n\
         AreaLightSource \"area\" \"color L\" [1 1 1]\nShape \"disk\" \"float radius\" [0.1]\nAttributeEnd\nWorldEnd\n",
    );
    assert!(instanced.warnings.is_empty(), "{:?}", messages(&instanced));
    assert_eq!(instanced.shape_groups.len(), 1);
    assert_eq!(instanced.shape_groups[0].len(), 2);
    let instances = (instanced.shapes.iter())
        .filter(|s| matches!(s.geometry, Geometry::Instance { .. }))
        .count();
    assert_eq!(instances, 2);
    // Shape order aside (each instance, then its copied emitter), the same shapes.
    let key = |s: &foton::scene::desc::ShapeDesc| {
        let t = s.object_to_world.w_axis;
        (
            format!("{:?}", s.geometry),
            [t.x, t.y, t.z].map(|v| (v * 1e3).round() as i64),
        )
    };
    let mut a = expanded_shapes(&instanced);
    let mut b = expanded_shapes(&written_out);
    a.sort_by_key(key);
    b.sort_by_key(key);
    assert_eq!(a.len(), 7);
    assert_eq!(a.len(), b.len());
    for (a, b) in a.iter().zip(&b) {
        assert!(
            a.object_to_world.abs_diff_eq(b.object_to_world, 1e-5),
            "{} {}",
            a.object_to_world,
            b.object_to_world
        );
        assert_eq!(format!("{:?}", a.geometry), format!("{:?}", b.geometry));
        assert_eq!(a.material, b.material);
        assert_eq!(a.area_light.is_some(), b.area_light.is_some());
    }
    assert_eq!(
        instanced.notes,
        [
            "2 ObjectInstance of 1 objects: 4 shapes placed as instances of shared shapes, \
          2 emitting shapes copied (the instance level emits no light)"
        ]
    );
    let e = error(
        "no_object",
        "WorldBegin\nObjectInstance \"nothing\"\nWorldEnd\n",
    );
    assert_eq!(e.location.line, 2);
}

/// LuxRender 1.x's `mesh` takes `quadindices` (4 per quad) beside `triindices`: each quad is
/// split into two triangles of the same winding, so a unit square and a triangle keep their
/// area (1.5) and face +z; a count not a multiple of 4, or an index out of range, is an error.
#[test]
fn quad_meshes_are_split_into_triangles() {
    let s = scene(
        "quads",
        "WorldBegin\nShape \"mesh\" \"integer quadindices\" [0 1 2 3] \"integer triindices\" [1 4 2] \
         \"point P\" [0 0 0 1 0 0 1 1 0 0 1 0 2 0 0]\nWorldEnd\n",
    );
    assert!(s.warnings.is_empty(), "{:?}", messages(&s));
    let (positions, _, _, indices) = mesh(&s.shapes[0].geometry);
    assert_eq!(indices, [[1, 4, 2], [0, 1, 2], [0, 2, 3]]);
    let mut area = 0.0;
    for &[a, b, c] in indices {
        let [pa, pb, pc] = [a, b, c].map(|i| positions[i as usize]);
        let cross = (pb - pa).cross(pc - pa);
        assert!(cross.z > 0.0);
        area += 0.5 * cross.length();
    }
    assert!((area - 1.5).abs() < 1e-6, "{area}");
    let e = error(
        "bad_quads",
        "WorldBegin\nShape \"trianglemesh\" \"integer quadindices\" [0 1 2] \"point P\" [0 0 0 1 0 0 1 1 0]\nWorldEnd\n",
    );
    assert!(e.message.contains("multiple of 4"), "{e}");
    let e = error(
        "quad_range",
        "WorldBegin\nShape \"trianglemesh\" \"integer quadindices\" [0 1 2 7] \"point P\" [0 0 0 1 0 0 1 1 0]\nWorldEnd\n",
    );
    assert!(e.message.contains("index 7 out of range"), "{e}");
}
