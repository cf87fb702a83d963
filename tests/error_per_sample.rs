//! Error per sample: the MIS weights after null surfaces, and variance ratios of the sampling
//! techniques at a fixed sample count, with bounds from the sampling distribution of the ratio.
//!
//! A variance is estimated from two renders with different seeds: over k pixels, the sum of
//! squared differences of the two images, (a1 - a2)^2, estimates 2 k sigma^2 / spp. Treating
//! pixels as independent and their means as normal, the ratio of two such sums for techniques
//! X and Y is (sigma_X^2 / sigma_Y^2) F(k, k). So "X has less variance than Y" is asserted as
//! "the observed ratio is below the 0.001 quantile of F(k, k)": if X were no better than Y, a
//! ratio that low would occur with probability at most 1e-3 (the seeds are fixed, so each
//! test passes or fails deterministically). ln F(k, k) is close to normal with variance 4 / k,
//! so that quantile is exp(-3.09 * 2 / sqrt(k)).

use crate::common::*;
use foton::film::Reconstruction;
use foton::integrator::Renderer;
use foton::light::LightSelection;
use foton::sampling::SamplerKind;
use foton::scene::build::{RenderOptions, build_world};
use foton::scene::desc::{ColorParam, LightDesc, MaterialDesc, SceneDesc};
use foton::settings::Techniques;
use glam::{Mat4, Vec3};

fn render_with(desc: SceneDesc, options: &RenderOptions, techniques: Techniques) -> Vec<Vec3> {
    let (mut world, _) = build_world(desc, options);
    world.insert_resource(techniques);
    let mut renderer = Renderer::new(world);
    renderer.render(|_| true);
    renderer.image()
}

/// The 0.001 quantile of F(k, k), by the normal approximation of ln F.
fn f_lower_quantile(k: usize) -> f64 {
    (-3.09 * 2.0 / (k as f64).sqrt()).exp()
}

/// The default techniques but `light_selection`, and filter importance sampling, whose pixels are
/// independent.
fn selecting(light_selection: LightSelection) -> Techniques {
    Techniques {
        light_selection,
        film: Reconstruction::FilterImportance,
        ..Techniques::default()
    }
}

/// Asserts that a variance ratio (of technique X's over Y's, over `k` pixel-channels) lies below
/// the 0.001 quantile of F(k, k): X has less variance than Y.
fn assert_less_variance(ratio: f64, k: usize, what: &str) {
    let bound = f_lower_quantile(k);
    assert!(
        ratio < bound,
        "variance ratio {what} {ratio:.3}, bound {bound:.3}"
    );
}

/// Sum over pixels and channels of the squared difference of two renders with other seeds.
fn variance_sum(scene: impl Fn() -> SceneDesc, spp: u32, techniques: Techniques) -> f64 {
    variance_sum_with(scene, spp, techniques, SamplerKind::Sobol)
}

/// [`variance_sum`] with another sampler.
fn variance_sum_with(
    scene: impl Fn() -> SceneDesc,
    spp: u32,
    techniques: Techniques,
    sampler: SamplerKind,
) -> f64 {
    let [a, b] = [11, 12].map(|seed| {
        render_with(
            scene(),
            &RenderOptions {
                seed,
                sampler,
                ..options(spp, 8)
            },
            techniques,
        )
    });
    a.iter()
        .zip(&b)
        .map(|(x, y)| (*x - *y).as_dvec3().length_squared())
        .sum()
}

/// After a null surface, light sampling would still have sampled from the floor point, so an
/// emitter's MIS weight must use that point. A null quad 5e-4 below a 2 x 2 emitter at height 1
/// (beyond the shadow rays' stopping point, so it blocks none) sees the emitter from almost no
/// distance: with its position as the previous vertex, the light pdf is ~0, the BSDF-sampled
/// hit takes weight ~1 on top of the light sample's own weight, and the floor comes out about
/// 1.5x too bright. With the fix it reflects 0.5 F, F the centre form factor (as in
/// tests/integrator.rs), within 1% (there: measured spread well under that at this count).
#[test]
fn emitter_mis_weight_uses_the_last_scattering_vertex_after_a_null_surface() {
    let mut scene = empty_scene(looking_down(Vec3::new(0.0, 0.0, 0.5), 4.0), 8, 8);
    let floor = matte(&mut scene, Vec3::splat(0.5));
    let null = null_material(&mut scene);
    let v = Vec3::new;
    ground(&mut scene, floor);
    let z = 1.0 - 5e-4;
    quad(
        &mut scene,
        [v(-2., -2., z), v(2., -2., z), v(2., 2., z), v(-2., 2., z)],
        null,
        None,
    );
    downward_square(&mut scene, 1.0, 1.0, null, Some(emitter(Vec3::ONE)));
    let image = render(scene, &options(512, 4));
    let mean = image.iter().sum::<Vec3>() / image.len() as f32;
    let (a, h) = (1.0f32, 1.0f32);
    let (x, y) = (a / h, a / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    let form_factor =
        4.0 / (2.0 * std::f32::consts::PI) * (x / sx * (y / sx).atan() + y / sy * (x / sy).atan());
    let expected = 0.5 * form_factor;
    for c in mean.to_array() {
        assert!(
            (c - expected).abs() < 0.01 * expected,
            "{mean} against the analytic {expected}"
        );
    }
}

/// A matte floor under a sky and a small bright lamp: the sky has most of the power (its
/// flux over the scene's cross-section), the lamp lights the floor under it. The sky is a map
/// (0.25 and 0.35 in two halves): next-event estimation leaves a constant sky to BSDF sampling,
/// so only a varying one competes with the lamp for light samples.
fn sky_and_lamp() -> SceneDesc {
    let mut scene = empty_scene(looking_down(Vec3::new(0.0, 0.0, 3.0), 40.0), 32, 32);
    let floor = matte(&mut scene, Vec3::splat(0.6));
    let null = null_material(&mut scene);
    let v = Vec3::new;
    quad(
        &mut scene,
        [
            v(-8., -8., 0.),
            v(8., -8., 0.),
            v(8., 8., 0.),
            v(-8., 8., 0.),
        ],
        floor,
        None,
    );
    let (s, h) = (0.15, 1.5);
    quad(
        &mut scene,
        [v(-s, -s, h), v(-s, s, h), v(s, s, h), v(s, -s, h)],
        null,
        Some(emitter(Vec3::splat(40.0))),
    );
    scene.textures.push(foton::scene::desc::ImageTexture {
        name: "two halves".into(),
        path: "two-halves.exr".into(),
        width: 2,
        height: 1,
        texels: std::sync::Arc::new(vec![Vec3::splat(0.25), Vec3::splat(0.35)]).into(),
        scale: glam::Vec2::ONE,
        delta: glam::Vec2::ZERO,
        wrap: Default::default(),
    });
    scene.lights.push(LightDesc::Infinite {
        radiance: Vec3::ONE,
        map: Some(0),
        light_to_world: Mat4::IDENTITY,
    });
    scene
}

/// Uniform selection (half the samples to the lamp) and the defensive mix of power and uniform
/// (a quarter or more) instead of a few percent: less variance than selection by power on the
/// floor the lamp lights.
#[test]
fn uniform_and_mixed_light_selection_have_less_variance_than_power_under_a_sky() {
    let power = variance_sum(sky_and_lamp, 8, selecting(LightSelection::Power));
    let k = 32 * 32 * 3;
    for selection in [LightSelection::Uniform, LightSelection::Mixed] {
        let ratio = variance_sum(sky_and_lamp, 8, selecting(selection)) / power;
        assert_less_variance(ratio, k, &format!("{selection:?} / power"));
    }
}

/// A Cornell-style box lit by a ceiling lamp: paths live long, so Russian roulette from the
/// second bounce adds variance that starting later avoids.
#[test]
fn later_russian_roulette_has_less_variance() {
    let techniques = |rr_depth| Techniques {
        rr_depth,
        film: Reconstruction::FilterImportance,
        ..Techniques::default()
    };
    let late = variance_sum(test_box, 8, techniques(5));
    let early = variance_sum(test_box, 8, techniques(1));
    let k = 40 * 30 * 3;
    let ratio = late / early;
    assert_less_variance(ratio, k, "rr-depth 5 / 1");
}

/// Splatting with a wide Gaussian spreads each sample over about 16 pixels, where filter
/// importance sampling gives it to one: at equal samples the variance falls several times.
/// Splatting correlates neighbouring pixels, so the bound counts one independent value per
/// 4 x 4 block: k = pixels / 16.
#[test]
fn splatting_a_wide_filter_has_less_variance_than_filter_importance_sampling() {
    let scene = || {
        let mut scene = sky_and_lamp();
        scene.filter.kind = foton::scene::desc::FilterKind::Gaussian { alpha: 2.0 };
        scene.filter.radius = glam::Vec2::splat(2.0);
        scene
    };
    let techniques = |film| Techniques {
        film,
        ..Techniques::default()
    };
    // Stratified, not Sobol': the Sobol' sampler's padded draws stratify each pixel's own
    // samples of the light, which filter importance sampling keeps together and splatting
    // spreads over its neighbours with uneven weights; on this scene (8 spp) that alone made
    // the ratio 1.035.
    let sampler = SamplerKind::Stratified;
    let splat = variance_sum_with(scene, 8, techniques(Reconstruction::Splat), sampler);
    let fis = variance_sum_with(
        scene,
        8,
        techniques(Reconstruction::FilterImportance),
        sampler,
    );
    let k = 32 * 32 * 3 / 16;
    let ratio = splat / fis;
    assert_less_variance(ratio, k, "splat / fis");
}

/// Splatting is consistent: under a uniform sky, a diffuse furnace sphere still reflects its
/// albedo (0.5) in the middle of the sphere, as with filter importance sampling.
#[test]
fn splatting_keeps_the_furnace_mean() {
    let mut scene = empty_scene(look_at(Vec3::new(0.0, -4.0, 0.0), Vec3::ZERO, 30.0), 48, 48);
    scene.materials.push(MaterialDesc::Diffuse {
        reflectance: ColorParam::Constant(Vec3::splat(0.5)),
    });
    sphere(&mut scene, Vec3::ZERO, 1.0, 0);
    scene.lights.push(LightDesc::Infinite {
        radiance: Vec3::ONE,
        map: None,
        light_to_world: Mat4::IDENTITY,
    });
    scene.filter.kind = foton::scene::desc::FilterKind::Gaussian { alpha: 2.0 };
    scene.filter.radius = glam::Vec2::splat(2.0);
    let image = render_with(
        scene,
        &options(64, 16),
        Techniques {
            film: Reconstruction::Splat,
            ..Techniques::default()
        },
    );
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
    assert!((image[0] - Vec3::ONE).abs().max_element() < 1e-4);
}

/// A matte floor 0.1 under a 2 x 2 lamp, seen from between them: from the floor the lamp
/// subtends up to 5.7 sr, where sampling it by area (density d^2 / (cos A), d from 0.1 to 1.4)
/// is far from the cos / d^2 it lights with, and sampling it uniformly in solid angle leaves
/// only the floor's cosine to vary. The variance ratio is bounded as above (that the density
/// is right is `light::area`'s unit tests' concern).
#[test]
fn solid_angle_rectangles_have_less_variance_close_to_a_lamp() {
    let lamp_over_floor = || {
        let mut scene = empty_scene(looking_down(Vec3::new(0.0, 0.0, 0.05), 90.0), 16, 16);
        let floor = matte(&mut scene, Vec3::splat(0.5));
        let null = null_material(&mut scene);
        ground(&mut scene, floor);
        downward_square(&mut scene, 1.0, 0.1, null, Some(emitter(Vec3::ONE)));
        scene
    };
    let techniques = |solid_angle_rectangles| Techniques {
        solid_angle_rectangles,
        ..Techniques::default()
    };
    let k = 16 * 16 * 3;
    let ratio = variance_sum(lamp_over_floor, 8, techniques(true))
        / variance_sum(lamp_over_floor, 8, techniques(false));
    assert_less_variance(ratio, k, "solid angle / area");
}

/// A floor under a 6 x 6 grid of small lamps (0.3 wide, at height 0.8, 1.5 apart, of four
/// brightnesses), seen from above: each floor point is lit mostly by the lamps near it.
fn grid_of_lamps() -> SceneDesc {
    let mut scene = empty_scene(looking_down(Vec3::new(0.0, 0.0, 6.0), 80.0), 24, 24);
    let floor = matte(&mut scene, Vec3::splat(0.5));
    let null = null_material(&mut scene);
    ground(&mut scene, floor);
    for k in 0..36 {
        let centre = Vec3::new((k % 6) as f32 - 2.5, (k / 6) as f32 - 2.5, 0.0) * 1.5;
        let (s, h) = (0.15, 0.8);
        let v = |dx: f32, dy: f32| centre + Vec3::new(dx, dy, h);
        let radiance = Vec3::splat([5.0, 10.0, 20.0, 40.0][k % 4]);
        quad(
            &mut scene,
            [v(-s, -s), v(-s, s), v(s, s), v(s, -s)],
            null,
            Some(emitter(radiance)),
        );
    }
    scene
}

/// The light BVH gives the near lamps most of the light samples where uniform selection gives
/// each 1 / 36: less variance on the floor (one-sided bound as above).
#[test]
fn the_light_bvh_has_less_variance_than_uniform_selection_under_many_lamps() {
    let uniform = variance_sum(grid_of_lamps, 4, selecting(LightSelection::Uniform));
    let bvh = variance_sum(grid_of_lamps, 4, selecting(LightSelection::Bvh));
    let k = 24 * 24 * 3;
    let ratio = bvh / uniform;
    assert_less_variance(ratio, k, "bvh / uniform");
}

/// The light BVH's choice is unbiased, its MIS weights included (the probability a BSDF-sampled
/// hit on a lamp is weighted with must be the one light sampling would have chosen it with):
/// the image's mean with it and with uniform selection agree within 4.5 standard deviations of
/// their difference. Each mean's variance is that of a pixel over the pixels' count (pixels
/// independent with filter importance sampling); a pixel's variance is half the mean squared
/// difference of two seeds' renders (`variance_sum`).
#[test]
fn the_light_bvh_keeps_the_mean() {
    let spp = 16;
    let k = (24 * 24) as f64;
    let mean_and_variance = |selection| {
        let image = render_with(grid_of_lamps(), &options(spp, 8), selecting(selection));
        let mean = image.iter().map(|p| p.as_dvec3()).sum::<glam::DVec3>() / k;
        // Over the three channels: the variance of one channel's pixel, from two seeds.
        let pixel_variance =
            variance_sum(grid_of_lamps, spp, selecting(selection)) / (2.0 * 3.0 * k);
        (mean, pixel_variance / k)
    };
    let (uniform, uniform_variance) = mean_and_variance(LightSelection::Uniform);
    let (bvh, bvh_variance) = mean_and_variance(LightSelection::Bvh);
    let sigma = (uniform_variance + bvh_variance).sqrt();
    for (a, b) in uniform.to_array().into_iter().zip(bvh.to_array()) {
        assert!(
            (a - b).abs() < 4.5 * sigma,
            "uniform {uniform} against bvh {bvh}, sigma {sigma:.2e}"
        );
    }
}
