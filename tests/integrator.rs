//! The integrators against known answers: energy, determinism, finite output.

use crate::common::*;
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

/// Renders the test box in chunks of `chunk_paths` on `threads` threads, stopping when `go_on`
/// says so.
fn render_in_chunks(
    chunk_paths: usize,
    threads: usize,
    go_on: impl FnMut(foton::integrator::Progress) -> bool + Send,
) -> (Vec<Vec3>, foton::integrator::RenderStats) {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
        .install(|| {
            let (world, _) = foton::scene::build::build_world(test_box(), &options(4, 6));
            let mut renderer = foton::integrator::Renderer::new(world);
            renderer.set_chunk_paths(chunk_paths);
            let stats = renderer.render(go_on);
            (renderer.image(), stats)
        })
}

/// Chunks change where a pass's paths are traced, never what they compute: several chunks per
/// pass (97 paths, the last one ragged, against the test box's 1200 pixels) give the image of
/// one chunk per pass, bit for bit, on 1 and on 3 threads.
#[test]
fn chunks_per_pass_do_not_change_the_image() {
    let (whole, stats) = render_in_chunks(1 << 20, 1, |_| true);
    assert_eq!((stats.passes, stats.paths), (4, 4 * 1200));
    assert!(stats.complete_passes);
    for threads in [1, 3] {
        let (chunked, stats) = render_in_chunks(97, threads, |_| true);
        assert_eq!((stats.passes, stats.paths), (4, 4 * 1200));
        assert!(whole == chunked, "{threads} threads");
    }
}

/// Progress comes after every chunk, and a render stopped within a pass keeps the samples of
/// its finished chunks (those pixels have one sample more) and says the pass is incomplete. On
/// 2 and 3 threads, the chunks the other threads traced past the stop are dropped.
#[test]
fn a_render_stops_within_a_pass_and_keeps_its_chunks() {
    for threads in [2, 3] {
        let mut told = Vec::new();
        let (one_pass, _) = render_in_chunks(97, threads, |p| p.passes_done < 1);
        let (partial, stats) = render_in_chunks(97, threads, |p| {
            told.push((p.paths_done, p.paths_total, p.passes_done));
            p.paths_done < 1200 + 3 * 97
        });
        let expected: Vec<_> = (1..=16)
            .map(|chunk| {
                let done = (chunk * 97).min(1200) + if chunk > 13 { (chunk - 13) * 97 } else { 0 };
                (done as u64, 4 * 1200, u32::from(chunk >= 13))
            })
            .collect();
        assert_eq!(told, expected, "{threads} threads");
        assert_eq!((stats.passes, stats.paths), (1, 1200 + 3 * 97));
        assert!(!stats.complete_passes);
        // The second pass's chunks reached pixels 0..291 only: the others keep their first
        // sample.
        assert!(partial[3 * 97..] == one_pass[3 * 97..], "{threads} threads");
        assert!(partial[..3 * 97] != one_pass[..3 * 97], "{threads} threads");
    }
}

#[test]
fn every_pixel_is_finite_and_non_negative_for_both_integrators() {
    for integrator in [IntegratorKind::PathTracer, IntegratorKind::RayCaster] {
        let options = foton::scene::build::RenderOptions {
            integrator: Some(integrator),
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
        let camera = looking_down(eye, 4.0);
        let mut scene = empty_scene(camera, 8, 8);
        scene.materials.push(material);
        let floor = scene.materials.len() - 1;
        let null = null_material(&mut scene);
        ground(&mut scene, floor);
        // Its normal down: the rectangle emits towards the floor.
        downward_square(&mut scene, half, 1.0, null, Some(emitter(Vec3::ONE)));
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

/// A matte floor lit by a point light and by an area light, seen from below a sheet of `null`
/// material that lies between the floor and both lights (and a null sphere around the point
/// light). An invisible surface lets light through as it lets camera rays through, so each
/// integrator's image equals, to float rounding, the one without the sheet and sphere; the
/// lights are delta or sampled with the same random numbers in both, so the two images differ
/// only where a shadow ray is wrongly stopped (a stopped ray there blackens the whole floor).
/// The rounding: a BSDF-sampled ray that passed the sheet starts there, so its hit on the lamp
/// is rounded differently and with it the hit's MIS weight, by a relative 2.4e-6 with uniform
/// light selection and 1.2e-5 with the light BVH, which gives the lamp fewer light samples
/// and its BSDF-sampled hits more weight (measured); 1e-4 bounds it, far below a stopped ray.
#[test]
fn shadow_rays_pass_through_null_surfaces() {
    let v = Vec3::new;
    let scene = |with_null: bool| {
        let eye = v(0.0, 0.0, 0.5);
        let camera = looking_down(eye, 60.0);
        let mut scene = empty_scene(camera, 8, 8);
        let floor = matte(&mut scene, Vec3::splat(0.5));
        let null = null_material(&mut scene);
        ground(&mut scene, floor);
        downward_square(&mut scene, 1.0, 3.0, null, Some(emitter(Vec3::ONE)));
        scene.lights.push(LightDesc::Point {
            position: v(0.3, 0.0, 2.0),
            intensity: Vec3::splat(2.0),
        });
        if with_null {
            quad(
                &mut scene,
                [
                    v(-5., -5., 1.),
                    v(5., -5., 1.),
                    v(5., 5., 1.),
                    v(-5., 5., 1.),
                ],
                null,
                None,
            );
            sphere(&mut scene, v(0.3, 0.0, 2.0), 0.1, null);
        }
        scene
    };
    for integrator in [IntegratorKind::PathTracer, IntegratorKind::RayCaster] {
        let options = foton::scene::build::RenderOptions {
            integrator: Some(integrator),
            ..options(4, 3)
        };
        let open = render(scene(false), &options);
        let veiled = render(scene(true), &options);
        let mean = open.iter().sum::<Vec3>() / open.len() as f32;
        assert!(
            mean.min_element() > 0.05,
            "{integrator:?}: a dark floor {mean}"
        );
        for (a, b) in open.iter().zip(&veiled) {
            assert!(
                (*a - *b).abs().max_element() <= 1e-4 * a.max_element(),
                "{integrator:?}: {b} behind null surfaces, {a} without"
            );
        }
    }
}

/// No self-intersection at large scales or grazing angles: a matte floor of albedo rho under a
/// distant light of radiance E at angle theta from its normal reflects rho E cos(theta) / pi
/// towards every direction, and with nothing else in the scene every other path escapes, so
/// each sample of each pixel is exactly that, up to float rounding (no noise to allow for). A
/// ray leaving the floor that hits the floor again instead (shadow acne on the shadow ray, or a
/// bounce that does not escape) changes a sample by all of its value, a pixel by at least
/// 1/spp of it. Floors: the course's plane (a mesh) scaled by 20 at the origin, a 2000-unit
/// mesh 3e4 units away, and an infinite plane as far; light at 0 and 85 degrees, the camera at
/// 5 degrees above the floor.
///
/// Flat surfaces alone do not catch a broken offset (the triangle and plane tests give a ray
/// that starts on their surface no hit at t > 0, so this passes with a fixed 1e-6 offset); the
/// white furnace below does, with a sphere 3e4 units from the origin.
#[test]
fn no_self_intersection_at_large_scales_or_grazing_angles() {
    use foton::scene::desc::{Geometry, ShapeDesc};
    let spp = 16;
    let far = Vec3::new(3e4, -2e4, 1e3);
    for (centre, half, infinite) in [
        (Vec3::ZERO, 20.0, false),
        (far, 1000.0, false),
        (far, 1000.0, true),
    ] {
        for light_degrees in [0.0f32, 85.0] {
            let view = 5.0f32.to_radians();
            let eye = centre + 0.5 * half * Vec3::new(0.0, -view.cos(), view.sin());
            let mut scene = empty_scene(look_at(eye, centre, 2.0), 8, 8);
            let floor = matte(&mut scene, Vec3::splat(0.5));
            if infinite {
                scene.shapes.push(ShapeDesc {
                    geometry: Geometry::Plane { normal: Vec3::Z },
                    object_to_world: Mat4::from_translation(centre),
                    material: Some(floor),
                    area_light: None,
                    location: location(),
                });
            } else {
                let corner = |x: f32, y: f32| centre + half * Vec3::new(x, y, 0.0);
                let corners = [(-1., -1.), (1., -1.), (1., 1.), (-1., 1.)];
                quad(&mut scene, corners.map(|(x, y)| corner(x, y)), floor, None);
            }
            let theta = light_degrees.to_radians();
            scene.lights.push(LightDesc::Distant {
                direction_to_light: Vec3::new(theta.sin(), 0.0, theta.cos()),
                radiance: Vec3::splat(std::f32::consts::PI),
            });
            let expected = 0.5 * theta.cos();
            for integrator in [IntegratorKind::PathTracer, IntegratorKind::RayCaster] {
                let options = foton::scene::build::RenderOptions {
                    integrator: Some(integrator),
                    ..options(spp, 4)
                };
                for pixel in render(scene.clone(), &options) {
                    assert!(
                        (pixel - Vec3::splat(expected)).abs().max_element() < 1e-3 * expected,
                        "{integrator:?}, floor at {centre} of half-size {half} (infinite: \
                         {infinite}), light at {light_degrees} degrees: {pixel} against {expected}"
                    );
                }
            }
        }
    }
}

/// The white furnace (above) with the sphere, of radius 1000, 3e4 units from the origin: a
/// sphere's quadratic loses bits there, so a shadow ray or a bounce that starts too close to
/// the surface finds it again and darkens the sphere. Every pixel of the sphere's centre is 0.5
/// within 1% of the mean (the origin furnace's bound at this sample count).
#[test]
fn white_furnace_far_from_the_origin_has_no_self_intersection() {
    let centre = Vec3::new(3e4, -2e4, 1e3);
    let eye = centre - Vec3::new(0.0, 4000.0, 0.0);
    let mut scene = empty_scene(look_at(eye, centre, 30.0), 48, 48);
    let grey = matte(&mut scene, Vec3::splat(0.5));
    sphere(&mut scene, centre, 1000.0, grey);
    scene.lights.push(LightDesc::Infinite {
        radiance: Vec3::ONE,
        map: None,
        light_to_world: Mat4::IDENTITY,
    });
    let image = render(scene, &options(64, 16));
    let mut sum = Vec3::ZERO;
    for y in 18..30 {
        for x in 18..30 {
            sum += image[y * 48 + x];
        }
    }
    let mean = sum / 144.0;
    for c in mean.to_array() {
        assert!((c - 0.5).abs() < 0.01, "sphere mean {mean}, expected 0.5");
    }
}
