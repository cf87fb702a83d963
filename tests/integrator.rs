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
