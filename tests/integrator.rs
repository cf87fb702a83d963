//! The integrators against known answers: energy, determinism, finite output.

mod common;

use common::*;
use foton::scene::desc::LightDesc;
use foton::settings::IntegratorKind;
use glam::{Mat4, Vec3};

/// A diffuse sphere of albedo 0.5 under a uniform environment of radiance 1 reflects exactly
/// 0.5 (it is convex: every reflected ray escapes), and the background is exactly 1.
#[test]
fn white_furnace_diffuse_sphere_reflects_its_albedo() {
    let mut scene = empty_scene(look_at(Vec3::new(0.0, -4.0, 0.0), Vec3::ZERO, 30.0), 48, 48);
    let grey = matte(&mut scene, Vec3::splat(0.5));
    sphere(&mut scene, Vec3::ZERO, 1.0, grey);
    scene.lights.push(LightDesc::Infinite {
        radiance: Vec3::ONE,
        map: None,
        light_to_world: Mat4::IDENTITY,
    });
    let image = render(scene, &options(64, 16));
    let at = |x: usize, y: usize| image[y * 48 + x];
    // The sphere spans about 29 degrees of the 30 degree view: its centre 12 x 12 pixels.
    let mut sum = Vec3::ZERO;
    for y in 18..30 {
        for x in 18..30 {
            sum += at(x, y);
        }
    }
    let mean = sum / 144.0;
    for c in mean.to_array() {
        assert!((c - 0.5).abs() < 0.01, "sphere mean {mean}, expected 0.5");
    }
    for (x, y) in [(0, 0), (47, 0), (0, 47), (47, 47)] {
        assert!(
            (at(x, y) - Vec3::ONE).abs().max_element() < 1e-4,
            "background {}",
            at(x, y)
        );
    }
}

#[test]
fn same_seed_gives_the_same_image_whatever_the_thread_count() {
    let render_with = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool")
            .install(|| render(test_box(), &options(4, 6)))
    };
    let one = render_with(1);
    let three = render_with(3);
    assert_eq!(one, three);
    let other_seed = render(
        test_box(),
        &foton::scene::build::RenderOptions {
            seed: 7,
            ..options(4, 6)
        },
    );
    assert_ne!(one, other_seed, "the seed must change the noise");
}

#[test]
fn every_pixel_is_finite_and_non_negative_for_both_integrators() {
    for integrator in [IntegratorKind::PathTracer, IntegratorKind::RayCaster] {
        let options = foton::scene::build::RenderOptions {
            integrator,
            ..options(8, 10)
        };
        let image = render(test_box(), &options);
        assert!(
            image
                .iter()
                .all(|p| p.is_finite() && p.min_element() >= 0.0)
        );
        let mean = image.iter().sum::<Vec3>() / image.len() as f32;
        assert!(
            mean.min_element() > 0.01,
            "{integrator:?} image is black: {mean}"
        );
    }
}

/// A point under the centre of a parallel rectangular emitter of radiance L and half-sizes
/// a, b at height h sees it with form factor F = 4 * (1 / 2pi) * (X / sqrt(1 + X^2) *
/// atan(Y / sqrt(1 + X^2)) + Y / sqrt(1 + Y^2) * atan(X / sqrt(1 + Y^2))), X = a / h, Y = b / h
/// (four corner rectangles; Howell's catalogue of configuration factors, B-3), so a matte floor
/// of albedo rho reflects rho * L * F.
fn centre_form_factor(a: f32, b: f32, h: f32) -> f32 {
    let (x, y) = (a / h, b / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    4.0 / (2.0 * std::f32::consts::PI) * (x / sx * (y / sx).atan() + y / sy * (x / sy).atan())
}

/// Under an emitting rectangle of radiance 1 at height 1, a surface reflects its directional
/// albedo times the rectangle's share of the hemisphere: for a huge one, 0.5 for a matte of
/// albedo 0.5 and 0.8785 at normal view for a GGX conductor with F0 = 1 and alpha 0.3 (its
/// single-scattering albedo, by independent quadrature in tests/bsdf.rs); for a 2 x 2 one over
/// the matte, 0.5 * F = 0.277. Light sampling and BSDF sampling both find the emitter, so this
/// checks their MIS weights: with the small emitter both strategies carry weight.
#[test]
fn area_light_reflection_matches_the_analytic_answer() {
    use foton::scene::desc::{ColorParam, MaterialDesc};
    let matte = MaterialDesc::Diffuse {
        reflectance: ColorParam::Constant(Vec3::splat(0.5)),
    };
    let metal = MaterialDesc::RoughConductor {
        specular: ColorParam::Constant(Vec3::ONE),
        alpha_u: 0.3,
        alpha_v: 0.3,
    };
    for (material, half, expected) in [
        (
            matte.clone(),
            1000.0,
            0.5 * centre_form_factor(1000.0, 1000.0, 1.0),
        ),
        (metal, 1000.0, 0.8785),
        (matte, 1.0, 0.5 * centre_form_factor(1.0, 1.0, 1.0)),
    ] {
        let eye = Vec3::new(0.0, 0.0, 0.5);
        // Looking straight down: camera x = world x, y = world y, forward = world -z.
        let mut camera = look_at(eye, Vec3::new(0.0, 1.0, 0.0), 4.0);
        camera.camera_to_world = Mat4::from_cols(
            Vec3::X.extend(0.0),
            Vec3::Y.extend(0.0),
            Vec3::NEG_Z.extend(0.0),
            eye.extend(1.0),
        );
        let mut scene = empty_scene(camera, 8, 8);
        scene.materials.push(material);
        let floor = scene.materials.len() - 1;
        scene.materials.push(MaterialDesc::Null);
        let null = scene.materials.len() - 1;
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let big = 1000.0;
        quad(
            &mut scene,
            [
                v(-big, -big, 0.),
                v(big, -big, 0.),
                v(big, big, 0.),
                v(-big, big, 0.),
            ],
            floor,
            None,
        );
        // Winding with the normal down: the rectangle emits towards the floor.
        quad(
            &mut scene,
            [
                v(-half, -half, 1.),
                v(-half, half, 1.),
                v(half, half, 1.),
                v(half, -half, 1.),
            ],
            null,
            Some(emitter(Vec3::ONE)),
        );
        let image = render(scene, &options(512, 4));
        let mean = image.iter().sum::<Vec3>() / image.len() as f32;
        for c in mean.to_array() {
            assert!(
                (c - expected).abs() < 0.01 * expected,
                "{mean} against the analytic {expected} (emitter half-size {half})"
            );
        }
    }
}
