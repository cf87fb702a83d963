//! The sun as a disc (`src/light/sun_disc.rs`): its cone sampling against its density, the
//! irradiance it gives against the delta light's, its penumbra against the geometry, and what
//! `--verbose` says of it.

use std::f32::consts::{FRAC_PI_4, PI};

use crate::common::*;
use foton::light::sun_disc::SunDiscLight;
use foton::scene::desc::{LightDesc, SceneDesc};
use foton::settings::IntegratorKind;
use glam::{Vec2, Vec3};

/// A small deterministic generator (SplitMix64) for the Monte Carlo checks.
struct Rng(u64);

impl Rng {
    fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// The sampled directions are uniform over the cone: a chi-square test over 8 bins of
/// (1 - cos theta) / (1 - cos theta_max) (uniform for a uniform cone: the solid angle between
/// two polar angles is proportional to the difference of their cosines) times 8 bins of phi,
/// each expected to hold N / 64 samples. The 1% critical value of chi-square with 63 degrees
/// of freedom is 92.0.
#[test]
fn cone_samples_are_uniform_over_the_cone() {
    let axis = Vec3::new(-0.4, 0.3, 0.866).normalize();
    let sin_theta_max = 0.3f32;
    let sun = SunDiscLight::new(axis, Vec3::ONE, sin_theta_max);
    let one_minus_cos_max = 1.0 - (1.0 - sin_theta_max * sin_theta_max).sqrt();
    // The frame the test measures phi in (any frame around the axis will do).
    let x = axis.cross(Vec3::Z).normalize();
    let y = axis.cross(x);
    let n = 64_000;
    let mut bins = [0u32; 64];
    let mut rng = Rng(7);
    for _ in 0..n {
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let sample = sun.sample(u);
        assert!(!sample.delta && sample.pdf == sun.pdf());
        let w = sample.wi;
        let radial = ((1.0 - w.dot(axis)) / one_minus_cos_max).clamp(0.0, 0.999_999);
        let phi = w.dot(y).atan2(w.dot(x)).rem_euclid(2.0 * PI) / (2.0 * PI);
        bins[(radial * 8.0) as usize * 8 + ((phi * 8.0) as usize).min(7)] += 1;
    }
    let expected = n as f32 / 64.0;
    let chi2: f32 = bins
        .iter()
        .map(|&c| (c as f32 - expected).powi(2) / expected)
        .sum();
    assert!(chi2 < 92.0, "chi-square {chi2}: {bins:?}");
}

/// The density is one over the region `contains` accepts: directions uniform on the sphere
/// fall in the cone with probability Omega / 4 pi, Omega = 1 / pdf; the count of N = 400,000
/// is checked within 5 binomial standard deviations.
#[test]
fn density_is_one_over_the_cones_solid_angle() {
    let axis = Vec3::new(0.2, 0.9, -0.1).normalize();
    let sun = SunDiscLight::new(axis, Vec3::ONE, 0.5);
    let n = 400_000;
    let mut rng = Rng(3);
    let mut inside = 0;
    for _ in 0..n {
        let z = 1.0 - 2.0 * rng.next_f32();
        let phi = 2.0 * PI * rng.next_f32();
        let r = (1.0 - z * z).max(0.0).sqrt();
        if sun.contains(Vec3::new(r * phi.cos(), r * phi.sin(), z)) {
            inside += 1;
        }
    }
    let p = 1.0 / (sun.pdf() as f64 * 4.0 * std::f64::consts::PI);
    let expected = p * n as f64;
    let sigma = (n as f64 * p * (1.0 - p)).sqrt();
    assert!(
        (inside as f64 - expected).abs() < 5.0 * sigma,
        "{inside} inside against {expected} +- {sigma}"
    );
}

/// The wall's height, the sine of the disc's half-angle and the disc's radiance.
const WALL: f32 = 1.0;
const SIN_THETA_MAX: f32 = 0.1;
const RADIANCE: f32 = 100.0;
const ALBEDO: f32 = 0.5;
/// The image: 128 columns across the floor from x = -2.1 to 0.1, 16 rows.
const WIDTH: usize = 128;
const HEIGHT: usize = 16;
const X_MIN: f32 = -2.1;
const PIXEL: f32 = 2.2 / WIDTH as f32;

/// A grey floor, a black wall in the plane x = 0 of height `WALL` (infinite along y), and the
/// sun 45 degrees high on the +x side: the wall shades the floor out to s = -x = WALL tan(45
/// degrees) = WALL. A camera straight above x = -1 sees the floor from x = -2.1 to 0.1 (the
/// wall hides only x > 0 from it).
fn wall_scene(light: LightDesc) -> SceneDesc {
    let height = 20.0;
    let fov = 2.0 * (0.5 * HEIGHT as f32 * PIXEL / height).atan().to_degrees();
    let mut scene = empty_scene(
        looking_down(Vec3::new(-1.0, 0.0, height), fov),
        WIDTH as u32,
        HEIGHT as u32,
    );
    let floor = matte(&mut scene, Vec3::splat(ALBEDO));
    ground(&mut scene, floor);
    let black = matte(&mut scene, Vec3::ZERO);
    let v = |y: f32, z: f32| Vec3::new(0.0, y, z);
    let big = 1000.0;
    quad(
        &mut scene,
        [v(-big, 0.0), v(big, 0.0), v(big, WALL), v(-big, WALL)],
        black,
        None,
    );
    scene.lights.push(light);
    scene
}

fn sun_direction() -> Vec3 {
    Vec3::new(FRAC_PI_4.sin(), 0.0, FRAC_PI_4.cos())
}

/// The disc, and the delta light of the same irradiance on a surface facing it: the integral
/// of cos over a cone of half-angle theta_max around the normal is pi sin^2 theta_max (the
/// projected disc), L pi sin^2 theta_max = L Omega (1 + cos theta_max) / 2, 0.25% below
/// L Omega here and 3e-6 below it for the real sun.
fn lights() -> (LightDesc, LightDesc) {
    let disc = LightDesc::SunDisc {
        direction_to_light: sun_direction(),
        radiance: Vec3::splat(RADIANCE),
        sin_theta_max: SIN_THETA_MAX,
    };
    let delta = LightDesc::Distant {
        direction_to_light: sun_direction(),
        radiance: Vec3::splat(RADIANCE * PI * SIN_THETA_MAX * SIN_THETA_MAX),
    };
    (disc, delta)
}

/// Each column's mean over the rows, and the distance s = -x of its centre from the wall.
fn columns(image: &[Vec3]) -> Vec<(f32, f32)> {
    (0..WIDTH)
        .map(|i| {
            let sum: f32 = (0..HEIGHT).map(|j| image[j * WIDTH + i].y).sum();
            let x = X_MIN + (i as f32 + 0.5) * PIXEL;
            (-x, sum / HEIGHT as f32)
        })
        .collect()
}

/// The distance from the wall at which the columns cross `fraction` of `lit`, interpolated
/// between the two columns around the crossing (the profile rises with s).
fn crossing(profile: &[(f32, f32)], lit: f32, fraction: f32) -> f32 {
    let level = fraction * lit;
    let mut by_distance = profile.to_vec();
    by_distance.sort_by(|a, b| a.0.total_cmp(&b.0));
    let k = by_distance
        .iter()
        .rposition(|&(_, value)| value < level)
        .expect("a column below the level");
    let ((s0, v0), (s1, v1)) = (by_distance[k], by_distance[k + 1]);
    s0 + (s1 - s0) * (level - v0) / (v1 - v0)
}

/// The disc's shadow edge is soft by the disc's angular size and the delta sun's is sharp; away
/// from the edge both give the floor the same radiance.
///
/// The floor at distance s behind the wall sees the part of the disc whose directions, in the
/// xz plane, are less than atan(s / WALL) from the zenith: none for s < WALL tan(45 - theta_max),
/// all for s > WALL tan(45 + theta_max). Inside, the visible fraction is that of a disc below a
/// chord (the disc's 0.1 radians are small enough to be flat): F(t) = 1 - (acos t - t sqrt(1 -
/// t^2)) / pi at offset t (in disc radii) from its centre, 10% at t = -0.6870 and 90% at
/// +0.6870, and ds / d(angle) = WALL / cos^2(45 degrees) = 2 WALL; so the 10-90% width is
/// 2 x 0.6870 theta_max x 2 WALL = 0.2754 (16 columns), centred on s = WALL. The delta sun's
/// edge is one pixel wide (the box filter). Lit floor: albedo / pi x the irradiance,
/// L pi sin^2 theta_max cos 45.
#[test]
fn disc_shadow_is_soft_by_the_discs_size() {
    let (disc, delta) = lights();
    let options = options(64, 2);
    let soft = columns(&render(wall_scene(disc), &options));
    let sharp = columns(&render(wall_scene(delta), &options));
    let irradiance = RADIANCE * PI * SIN_THETA_MAX * SIN_THETA_MAX * FRAC_PI_4.cos();
    let lit = ALBEDO / PI * irradiance;

    let theta_max = SIN_THETA_MAX.asin();
    let (umbra, full) = (
        WALL * (FRAC_PI_4 - theta_max).tan(),
        WALL * (FRAC_PI_4 + theta_max).tan(),
    );
    // Away from the edges: the columns s >= 0.1 (the wall hides x > 0 from the camera).
    let region = |profile: &[(f32, f32)], from: f32, to: f32| -> Vec<f32> {
        profile
            .iter()
            .filter(|&&(s, _)| s >= from && s <= to)
            .map(|&(_, value)| value)
            .collect()
    };
    for (name, profile) in [("disc", &soft), ("delta", &sharp)] {
        for value in region(profile, 0.1, umbra - 2.0 * PIXEL) {
            assert!(value == 0.0, "{name}: umbra {value}");
        }
    }
    let expected_width = 2.0 * 0.6870 * theta_max * 2.0 * WALL;
    let soft_width = crossing(&soft, lit, 0.9) - crossing(&soft, lit, 0.1);
    assert!(
        (soft_width - expected_width).abs() < 2.0 * PIXEL,
        "disc penumbra 10-90% {soft_width} against {expected_width}"
    );
    let soft_middle = crossing(&soft, lit, 0.5);
    assert!(
        (soft_middle - WALL).abs() < 1.5 * PIXEL,
        "disc penumbra centred at {soft_middle}"
    );
    let sharp_width = crossing(&sharp, lit, 0.9) - crossing(&sharp, lit, 0.1);
    assert!(sharp_width < 1.5 * PIXEL, "delta edge 10-90% {sharp_width}");
    assert!((crossing(&sharp, lit, 0.5) - WALL).abs() < PIXEL);

    // The lit floor: the delta light gives exactly `lit`; the disc's columns agree within 5
    // standard errors of their mean (their spread over the columns, each the mean of 16 x 64
    // samples).
    let sharp_lit = region(&sharp, full + 2.0 * PIXEL, 10.0);
    for value in &sharp_lit {
        assert!(
            (value / lit - 1.0).abs() < 1e-3,
            "delta lit {value} against {lit}"
        );
    }
    let soft_lit = region(&soft, full + 2.0 * PIXEL, 10.0);
    let n = soft_lit.len() as f32;
    assert!(n >= 40.0, "{n} lit columns");
    let mean = soft_lit.iter().sum::<f32>() / n;
    let variance = soft_lit.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / (n - 1.0);
    let standard_error = (variance / n).sqrt();
    assert!(
        (mean - lit).abs() < 5.0 * standard_error + 1e-4 * lit,
        "disc lit {mean} against {lit} +- 5 x {standard_error}"
    );
}

/// The disc is seen by camera rays and in mirrors (escaped rays inside its cone), by the path
/// tracer and the ray caster; a ray beside it sees nothing.
#[test]
fn camera_and_mirror_see_the_disc() {
    let radiance = Vec3::new(3.0, 2.0, 1.0);
    // A camera looking straight at the sun, with a field of view well inside the disc.
    let axis = Vec3::new(0.0, 1.0, 1.0).normalize();
    let mut facing = empty_scene(look_at(Vec3::ZERO, axis, 1.0), 4, 4);
    let grey = matte(&mut facing, Vec3::splat(0.5));
    // Something to render that the camera does not see.
    sphere(&mut facing, Vec3::new(0.0, 0.0, -100.0), 1.0, grey);
    facing.lights.push(LightDesc::SunDisc {
        direction_to_light: axis,
        radiance,
        sin_theta_max: 0.1,
    });
    let mut beside = facing.clone();
    beside.camera = look_at(Vec3::ZERO, Vec3::new(0.0, 1.0, 0.5), 1.0);
    // A mirror floor under a camera looking down at it along the reflection of the axis.
    let mut mirrored = facing.clone();
    mirrored.camera = look_at(Vec3::new(0.0, -1.0, 1.0), Vec3::ZERO, 1.0);
    mirrored.shapes.clear();
    mirrored
        .materials
        .push(foton::scene::desc::MaterialDesc::Mirror {
            reflectance: foton::scene::desc::ColorParam::Constant(Vec3::ONE),
        });
    let mirror = mirrored.materials.len() - 1;
    ground(&mut mirrored, mirror);
    for integrator in [IntegratorKind::PathTracer, IntegratorKind::RayCaster] {
        let options = foton::scene::build::RenderOptions {
            integrator: Some(integrator),
            ..options(4, 4)
        };
        for (name, scene, expected) in [
            ("facing", &facing, radiance),
            ("mirror", &mirrored, radiance),
            ("beside", &beside, Vec3::ZERO),
        ] {
            for pixel in render(scene.clone(), &options) {
                assert!(
                    (pixel - expected).abs().max_element() < 1e-4 * radiance.x,
                    "{integrator:?}, {name}: {pixel} against {expected}"
                );
            }
        }
    }
}

/// `--verbose` names the sun disc among the lights and turns MIS on for it (BSDF-sampled rays
/// can reach it); `relsize` 0 keeps the delta distant light, with MIS off.
#[test]
fn verbose_reports_the_sun_disc() {
    let dir = temp_dir("sun-disc-verbose");
    for (relsize, kind, mis) in [("1", "1 sun disc", "MIS on"), ("0", "1 distant", "MIS off")] {
        let scene = dir.join(format!("sun-{relsize}.lxs"));
        std::fs::write(
            &scene,
            format!(
                "LookAt 0 -5 1  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" [30]\n\
                 WorldBegin\nLightSource \"sun\" \"vector sundir\" [0 -1 1] \"float gain\" [1e-6] \
                 \"float relsize\" [{relsize}]\nMaterial \"matte\"\n\
                 Shape \"sphere\" \"float radius\" [1]\nWorldEnd\n"
            ),
        )
        .unwrap();
        let out = dir.join(format!("sun-{relsize}.pfm"));
        let output = foton(&[
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--spp",
            "1",
            "--resolution",
            "8x8",
            "--verbose",
        ]);
        assert!(output.status.success(), "{}", stderr(&output));
        let text = format!("{}{}", stdout(&output), stderr(&output));
        assert!(
            text.contains(&format!("lights: 1 ({kind}); {mis}")),
            "relsize {relsize}: {text}"
        );
    }
}
