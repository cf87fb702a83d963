//! A constant sky under next-event estimation with MIS: light sampling leaves it to BSDF
//! sampling (pbrt-v4's `UniformInfiniteLight` with `allowIncompletePDF`), and its share of the
//! light samples goes to the other lights. Exact where that is exact (the furnace), unbiased
//! against light-sampling the sky and with less variance, and the ray caster still samples it.

use std::sync::Arc;

use crate::common::*;
use foton::light::Light;
use foton::light::infinite::{Environment, InfiniteLight};
use foton::scene::build::RenderOptions;
use foton::scene::desc::{ColorParam, ImageTexture, LightDesc, MaterialDesc, SceneDesc};
use foton::settings::IntegratorKind;
use glam::{Mat3, Mat4, Vec2, Vec3};

/// A diffuse sphere of albedo 0.5 under a sky of radiance 1: every BSDF-sampled ray from the
/// (convex) sphere escapes with f cos / pdf = 0.5 and MIS weight 1, so each sample is exactly
/// 0.5, up to float rounding. With light samples of the sky each sample varies (by the cosine
/// and the MIS weights), by far more than the tolerance.
#[test]
fn a_diffuse_sphere_under_a_constant_sky_reflects_exactly_its_albedo_in_every_sample() {
    let mut scene = empty_scene(look_at(Vec3::new(0.0, -4.0, 0.0), Vec3::ZERO, 30.0), 32, 32);
    let grey = matte(&mut scene, Vec3::splat(0.5));
    sphere(&mut scene, Vec3::ZERO, 1.0, grey);
    scene.lights.push(constant_sky(Vec3::ONE));
    for spp in [1, 4] {
        let image = render(scene.clone(), &options(spp, 8));
        // The sphere covers a disc of radius 16 / tan(15 deg) / sqrt(15) = 15.4 px around the
        // centre; pixels within 12 px lie wholly on it.
        let mut inside = 0;
        for y in 0..32 {
            for x in 0..32 {
                let (dx, dy) = (x as f32 + 0.5 - 16.0, y as f32 + 0.5 - 16.0);
                if dx.hypot(dy) < 12.0 {
                    inside += 1;
                    let pixel = image[y * 32 + x];
                    assert!(
                        (pixel - Vec3::splat(0.5)).abs().max_element() < 1e-5,
                        "{spp} spp, pixel ({x}, {y}): {pixel}"
                    );
                }
            }
        }
        assert!(inside > 400);
        assert_eq!(image[0], Vec3::ONE, "the sky itself");
    }
}

fn constant_sky(radiance: Vec3) -> LightDesc {
    LightDesc::Infinite {
        radiance,
        map: None,
        light_to_world: Mat4::IDENTITY,
    }
}

/// A 16 x 8 map of radiance 1 with one texel 0.1 % brighter: not constant, so next-event
/// estimation samples it (by its luminance, a map within 1 % of constant has no compensated
/// distribution): the estimator before the constant sky was left to BSDF sampling. The texel
/// changes the light a point receives by at most 0.001 / 128 of the sky's.
fn almost_constant_map() -> ImageTexture {
    let mut texels = vec![Vec3::ONE; 16 * 8];
    texels[40] = Vec3::splat(1.001);
    ImageTexture {
        name: "almost constant".into(),
        path: "almost-constant.exr".into(),
        width: 16,
        height: 8,
        texels: Arc::new(texels).into(),
        scale: Vec2::ONE,
        delta: Vec2::ZERO,
        wrap: Default::default(),
    }
}

/// A matte floor and a rough metal sphere, a small bright lamp above, under a sky: direct
/// light from both, shadows, and glossy reflections of the sky and the lamp.
fn floor_sphere_and_lamp(sky_map: bool) -> SceneDesc {
    let mut scene = empty_scene(look_at(Vec3::new(0.0, -4.0, 2.5), Vec3::ZERO, 40.0), 40, 30);
    let floor = matte(&mut scene, Vec3::splat(0.6));
    scene.materials.push(MaterialDesc::RoughConductor {
        specular: ColorParam::Constant(Vec3::new(0.9, 0.7, 0.5)),
        alpha_u: 0.5,
        alpha_v: 0.5,
    });
    let metal = scene.materials.len() - 1;
    let null = null_material(&mut scene);
    ground(&mut scene, floor);
    sphere(&mut scene, Vec3::new(0.0, 0.0, 0.8), 0.8, metal);
    let v = Vec3::new;
    let (s, h) = (0.6, 3.0);
    quad(
        &mut scene,
        [v(-s, -s, h), v(-s, s, h), v(s, s, h), v(s, -s, h)],
        null,
        Some(emitter(Vec3::splat(4.0))),
    );
    let mut sky = constant_sky(Vec3::splat(0.4));
    if sky_map {
        scene.textures.push(almost_constant_map());
        if let LightDesc::Infinite { map, .. } = &mut sky {
            *map = Some(0);
        }
    }
    scene.lights.push(sky);
    scene
}

/// Per pixel, the sum of the three channels of two renders with other seeds: their
/// differences and their mean.
struct SeedPair {
    differences: Vec<f64>,
    means: Vec<f64>,
}

fn seed_pair(scene: impl Fn() -> SceneDesc, spp: u32) -> SeedPair {
    let [a, b] = [21, 22].map(|seed| {
        render(
            scene(),
            &RenderOptions {
                seed,
                ..options(spp, 8)
            },
        )
    });
    let total = |c: &Vec3| f64::from(c.x + c.y + c.z);
    SeedPair {
        differences: a.iter().zip(&b).map(|(x, y)| total(x) - total(y)).collect(),
        means: a
            .iter()
            .zip(&b)
            .map(|(x, y)| 0.5 * (total(x) + total(y)))
            .collect(),
    }
}

impl SeedPair {
    /// Sum of squared differences: 2 sum_p sigma_p^2 in expectation (sigma_p^2 the variance
    /// of pixel p's estimate).
    fn squares(&self) -> f64 {
        self.differences.iter().map(|d| d * d).sum()
    }

    /// The degrees of freedom of `squares` (Satterthwaite): a sum of k independent d_p^2, each
    /// sigma_p^2 chi^2(1) scaled, is approximately chi^2(k_eff) scaled, with
    /// k_eff = (sum sigma_p^2)^2 / sum sigma_p^4; E d^4 = 3 sigma^4 (normal d) estimates the
    /// denominator. Pixels of unequal noise (fireflies) count as fewer than k.
    fn degrees_of_freedom(&self) -> f64 {
        let fourth: f64 = self.differences.iter().map(|d| d.powi(4)).sum();
        self.squares().powi(2) / (fourth / 3.0)
    }
}

/// The constant sky left to BSDF sampling against the same sky light-sampled (the almost
/// constant map), at 8 spp:
/// - unbiased: the image means differ by less than four standard deviations of their
///   difference. Each image mean (over k pixels, two seeds averaged) has variance
///   sum_p sigma_p^2 / (2 k^2) = squares / (4 k^2), from the seed pair itself.
/// - less variance: the ratio of the two `squares` is (variance ratio) x F(k1, k2); if the
///   new estimator were no better, a ratio below the 0.001 quantile of F would occur with
///   probability at most 1e-3. ln F(k1, k2) is close to normal with variance 2/k1 + 2/k2.
#[test]
fn leaving_a_constant_sky_to_bsdf_sampling_is_unbiased_and_has_less_variance() {
    let env = |map| {
        Light::Environment(Environment::new(&InfiniteLight {
            radiance: Vec3::ONE,
            map,
            light_to_world: Mat3::IDENTITY,
        }))
    };
    let almost = almost_constant_map();
    let almost = foton::material::texture::ImageTexture {
        width: almost.width,
        height: almost.height,
        texels: almost.texels.to_linear(),
        scale: almost.scale,
        delta: almost.delta,
        wrap: almost.wrap,
    };
    assert!(!env(None).is_sampled_for_mis());
    assert!(env(Some(almost)).is_sampled_for_mis());

    let spp = 8;
    let constant = seed_pair(|| floor_sphere_and_lamp(false), spp);
    let sampled = seed_pair(|| floor_sphere_and_lamp(true), spp);
    let k = constant.means.len() as f64;
    let mean = |pair: &SeedPair| pair.means.iter().sum::<f64>() / k;
    let sd = ((constant.squares() + sampled.squares()) / (4.0 * k * k)).sqrt();
    let (m_constant, m_sampled) = (mean(&constant), mean(&sampled));
    // The brighter texel: at most 0.001 / 128 of the sky's part, below 1e-5 of the mean.
    let bound = 4.0 * sd + 1e-5 * m_sampled;
    assert!(
        (m_constant - m_sampled).abs() < bound,
        "image means {m_constant} (BSDF-sampled sky) and {m_sampled} (light-sampled), bound {bound}"
    );

    let (k1, k2) = (constant.degrees_of_freedom(), sampled.degrees_of_freedom());
    let quantile = (-3.09 * (2.0 / k1 + 2.0 / k2).sqrt()).exp();
    let ratio = constant.squares() / sampled.squares();
    println!(
        "means {m_constant} and {m_sampled} (bound {bound}); variance ratio {ratio:.3}, bound {quantile:.3} (effective k {k1:.0}, {k2:.0})"
    );
    assert!(
        ratio < quantile,
        "variance ratio {ratio:.3}, bound {quantile:.3} (effective k {k1:.0}, {k2:.0})"
    );
}

/// The ray caster has no BSDF sampling: it must keep sampling the sky. A matte floor of albedo
/// rho under a sky of radiance L reflects rho L. One light sample, uniform on the sphere,
/// gives X = rho L 4 cos(theta) above the floor (probability 1/2) and 0 below: E X = rho L and
/// E X^2 = 16 rho^2 L^2 / 2 * E[cos^2 | above] = 8/3 rho^2 L^2, so Var X = 5/3 (rho L)^2; the
/// image mean over n samples is within 4 sqrt(5 / 3n) rho L (stratified samples do better).
#[test]
fn the_ray_caster_still_samples_a_constant_sky() {
    let mut scene = empty_scene(looking_down(Vec3::new(0.0, 0.0, 2.0), 40.0), 24, 24);
    let floor = matte(&mut scene, Vec3::splat(0.6));
    ground(&mut scene, floor);
    scene.lights.push(constant_sky(Vec3::splat(0.5)));
    let spp = 4;
    let image = render(
        scene,
        &RenderOptions {
            integrator: Some(IntegratorKind::RayCaster),
            ..options(spp, 1)
        },
    );
    let n = (image.len() * spp as usize) as f32;
    let mean = image.iter().sum::<Vec3>() / image.len() as f32;
    let expected = 0.6 * 0.5;
    let bound = 4.0 * (5.0 / (3.0 * n)).sqrt() * expected;
    assert!(
        (mean - Vec3::splat(expected)).abs().max_element() < bound,
        "floor {mean}, expected {expected} within {bound}"
    );
}
