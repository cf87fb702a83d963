//! Scenes built in code for the integration tests, and small image helpers.

pub mod bsdf_estimates;
pub mod bsdf_outputs;
pub mod chi_square;

use std::path::PathBuf;
use std::process::{Command, Output};

use foton::film::luminance;
use foton::integrator::Renderer;
use foton::scene::build::{RenderOptions, build_world};
use foton::scene::desc::*;
use glam::{Mat4, Vec3};

/// Runs the foton binary with `args`.
pub fn foton(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_foton"))
        .args(args)
        .output()
        .expect("the foton binary runs")
}

/// A fresh folder in the temporary directory, named by `name` and this process.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("foton-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

pub fn location() -> Location {
    Location::line("test", 1)
}

/// A camera at `eye` looking at `target`, z up, as `LookAt` makes it.
pub fn look_at(eye: Vec3, target: Vec3, fov_degrees: f32) -> CameraDesc {
    let dir = (target - eye).normalize();
    let right = dir.cross(Vec3::Z).normalize();
    let up = right.cross(dir);
    CameraDesc {
        kind: &foton::camera::pinhole::CAMERA,
        fov_degrees,
        camera_to_world: Mat4::from_cols(
            right.extend(0.0),
            up.extend(0.0),
            dir.extend(0.0),
            eye.extend(1.0),
        ),
        screen_window: None,
        lens_radius: 0.0,
        focal_distance: 1e6,
        location: location(),
    }
}

/// A camera looking straight down from `eye`: camera x = world x, y = world y.
pub fn looking_down(eye: Vec3, fov: f32) -> CameraDesc {
    let mut camera = look_at(eye, eye + Vec3::Y, fov);
    camera.camera_to_world = Mat4::from_cols(
        Vec3::X.extend(0.0),
        Vec3::Y.extend(0.0),
        Vec3::NEG_Z.extend(0.0),
        eye.extend(1.0),
    );
    camera
}

pub fn empty_scene(camera: CameraDesc, width: u32, height: u32) -> SceneDesc {
    let mut scene = SceneDesc::empty(location());
    scene.camera = camera;
    scene.film.x_resolution = width;
    scene.film.y_resolution = height;
    scene
}

pub fn matte(scene: &mut SceneDesc, albedo: Vec3) -> MaterialId {
    scene.materials.push(MaterialDesc::Diffuse {
        reflectance: ColorParam::Constant(albedo),
    });
    scene.materials.len() - 1
}

/// An invisible material (`Null`): light passes through surfaces that have it.
pub fn null_material(scene: &mut SceneDesc) -> MaterialId {
    scene.materials.push(MaterialDesc::Null);
    scene.materials.len() - 1
}

pub fn sphere(scene: &mut SceneDesc, centre: Vec3, radius: f32, material: MaterialId) {
    scene.shapes.push(ShapeDesc {
        geometry: Geometry::Sphere { radius },
        object_to_world: Mat4::from_translation(centre),
        material: Some(material),
        area_light: None,
        location: location(),
    });
}

/// A floor at z = 0, 2000 units on a side, facing +z: for the scene it lights, an infinite plane.
pub fn ground(scene: &mut SceneDesc, material: MaterialId) {
    let big = 1000.0;
    let v = |x: f32, y: f32| Vec3::new(x, y, 0.0);
    quad(
        scene,
        [v(-big, -big), v(big, -big), v(big, big), v(-big, big)],
        material,
        None,
    );
}

/// An axis-aligned quad with corners in order (normal by the right-hand rule).
pub fn quad(
    scene: &mut SceneDesc,
    corners: [Vec3; 4],
    material: MaterialId,
    area_light: Option<AreaLightDesc>,
) {
    scene.shapes.push(ShapeDesc {
        geometry: Geometry::TriangleMesh {
            positions: corners.to_vec(),
            normals: None,
            uvs: None,
            indices: vec![[0, 1, 2], [0, 2, 3]],
        },
        object_to_world: Mat4::IDENTITY,
        material: Some(material),
        area_light,
        location: location(),
    });
}

/// The square [-half, half]^2 at height `z`, wound with its normal down (-z): a ceiling, or with
/// `area_light` a lamp shining on the floor.
pub fn downward_square(
    scene: &mut SceneDesc,
    half: f32,
    z: f32,
    material: MaterialId,
    area_light: Option<AreaLightDesc>,
) {
    let v = |x: f32, y: f32| Vec3::new(x, y, z);
    quad(
        scene,
        [
            v(-half, -half),
            v(-half, half),
            v(half, half),
            v(half, -half),
        ],
        material,
        area_light,
    );
}

pub fn emitter(radiance: Vec3) -> AreaLightDesc {
    AreaLightDesc { radiance }
}

/// A small closed Cornell-style box with a diffuse sphere, a glass sphere, a metal sphere,
/// an area light and a point light: every kind of material and light path.
pub fn test_box() -> SceneDesc {
    let mut scene = empty_scene(
        look_at(Vec3::new(0.0, -3.5, 1.0), Vec3::new(0.0, 0.0, 1.0), 40.0),
        40,
        30,
    );
    let white = matte(&mut scene, Vec3::splat(0.7));
    let red = matte(&mut scene, Vec3::new(0.6, 0.1, 0.1));
    scene.materials.push(MaterialDesc::Dielectric {
        reflectance: ColorParam::Constant(Vec3::ONE),
        transmittance: ColorParam::Constant(Vec3::ONE),
        ior: 1.5,
    });
    let glass = scene.materials.len() - 1;
    scene.materials.push(MaterialDesc::RoughConductor {
        specular: ColorParam::Constant(Vec3::splat(0.9)),
        alpha_u: 0.1,
        alpha_v: 0.1,
    });
    let metal = scene.materials.len() - 1;
    let null = null_material(&mut scene);
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    quad(
        &mut scene,
        [
            v(-1., -1., 0.),
            v(1., -1., 0.),
            v(1., 1., 0.),
            v(-1., 1., 0.),
        ],
        white,
        None,
    );
    downward_square(&mut scene, 1.0, 2.0, white, None);
    quad(
        &mut scene,
        [v(-1., 1., 0.), v(1., 1., 0.), v(1., 1., 2.), v(-1., 1., 2.)],
        white,
        None,
    );
    quad(
        &mut scene,
        [
            v(-1., -1., 0.),
            v(-1., 1., 0.),
            v(-1., 1., 2.),
            v(-1., -1., 2.),
        ],
        red,
        None,
    );
    quad(
        &mut scene,
        [v(1., -1., 0.), v(1., -1., 2.), v(1., 1., 2.), v(1., 1., 0.)],
        white,
        None,
    );
    quad(
        &mut scene,
        [
            v(-0.3, -0.3, 1.99),
            v(-0.3, 0.3, 1.99),
            v(0.3, 0.3, 1.99),
            v(0.3, -0.3, 1.99),
        ],
        null,
        Some(emitter(Vec3::splat(10.0))),
    );
    sphere(&mut scene, v(-0.5, 0.3, 0.3), 0.3, metal);
    sphere(&mut scene, v(0.5, -0.2, 0.3), 0.3, glass);
    sphere(&mut scene, v(0.0, 0.5, 0.6), 0.25, white);
    scene.lights.push(LightDesc::Point {
        position: v(0.5, 0.5, 1.5),
        intensity: Vec3::splat(0.5),
    });
    scene
}

pub fn render(desc: SceneDesc, options: &RenderOptions) -> Vec<Vec3> {
    let (world, _) = build_world(desc, options);
    let mut renderer = Renderer::new(world);
    renderer.render(|_| true);
    renderer.image()
}

/// Renders and returns the film itself: its sample counts as well as its image (the film drops
/// NaN, infinite and negative samples, so only its rejection count reveals them).
pub fn render_film(desc: SceneDesc, options: &RenderOptions) -> foton::film::Film {
    let (world, _) = build_world(desc, options);
    let mut renderer = Renderer::new(world);
    renderer.render(|_| true);
    renderer.world.resource::<foton::film::Film>().clone()
}

pub fn options(spp: u32, max_depth: u32) -> RenderOptions {
    RenderOptions {
        samples_per_pixel: Some(spp),
        max_depth: Some(max_depth),
        ..RenderOptions::default()
    }
}

/// Where the course's shared scenes are, if present.
pub fn shared_scenes() -> Option<PathBuf> {
    shared_scene_folder("itba")
}

/// `scenes/FOLDER` of the shared folder (`$FOTON_SHARED`, else `../shared`), if present; says
/// that the test is skipped where it is not.
pub fn shared_scene_folder(folder: &str) -> Option<PathBuf> {
    let candidates = [
        std::env::var("FOTON_SHARED").ok().map(PathBuf::from),
        Some(PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../shared"
        ))),
    ];
    let found = candidates
        .into_iter()
        .flatten()
        .map(|p| p.join("scenes").join(folder))
        .find(|p| p.is_dir());
    if found.is_none() {
        eprintln!(
            "skipped: ../shared/scenes/{folder} not found (set FOTON_SHARED to the shared folder)"
        );
    }
    found
}

/// Box-averages a `w` x `h` image down by `factor` in each axis.
pub fn downsample(pixels: &[Vec3], w: usize, h: usize, factor: usize) -> Vec<f32> {
    let (dw, dh) = (w / factor, h / factor);
    let mut out = vec![0.0; dw * dh];
    for y in 0..dh * factor {
        for x in 0..dw * factor {
            out[(y / factor) * dw + x / factor] += luminance(pixels[y * w + x]);
        }
    }
    out.iter().map(|v| v / (factor * factor) as f32).collect()
}

/// Pearson correlation of two equally long series.
pub fn correlation(a: &[f32], b: &[f32]) -> f32 {
    let n = a.len() as f32;
    let (ma, mb) = (a.iter().sum::<f32>() / n, b.iter().sum::<f32>() / n);
    let cov: f32 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f32 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f32 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}
