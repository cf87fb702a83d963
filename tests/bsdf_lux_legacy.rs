//! LuxRender 0.x's own BSDFs (pbrt-v1's): `plastic` (Lambertian plus a Blinn lobe),
//! `substrate` (Ashikhmin-Shirley's FresnelBlend) and the measured Lafortune fits of `primer`,
//! `felt`, `clay`, `bluepaint` and `skin`. Sampling against eval and pdf (values and a
//! chi-square histogram), reciprocity, the sampled albedo against a quadrature of eval, energy
//! where the model conserves it, and known values computed by hand from the sources'
//! formulas and coefficients.

mod common;

use std::f32::consts::PI;

use foton::bsdf::lafortune::{LafortuneFit, LafortuneLobe};
use foton::bsdf::phong_distribution::PhongDistribution;
use foton::bsdf::{BlinnPlastic, Bsdf, FresnelBlend, Lafortune};
use foton::scene::desc::MaterialDesc;
use glam::{Vec2, Vec3};

use common::bsdf_estimates::{
    assert_samples_match_eval, assert_sampling_follows_pdf, outgoing, quadrature, sampled_albedo,
};
use common::bsdf_outputs::assert_finite_outputs;

fn wo(theta: f32) -> Vec3 {
    outgoing(theta)
}

fn plastic(kd: f32, ks: f32, roughness: f32) -> Bsdf {
    Bsdf::BlinnPlastic(BlinnPlastic {
        diffuse: Vec3::new(kd, kd * 0.7, kd * 0.4),
        specular: Vec3::splat(ks),
        distribution: PhongDistribution::from_roughness(roughness, roughness),
    })
}

fn substrate(kd: f32, ks: f32, u: f32, v: f32) -> Bsdf {
    Bsdf::FresnelBlend(FresnelBlend {
        diffuse: Vec3::splat(kd),
        specular: Vec3::splat(ks),
        distribution: PhongDistribution::from_roughness(u, v),
    })
}

/// The fit LuxRender's loader gives for a material type (`primer`, ...).
fn measured(kind: &str) -> &'static LafortuneFit {
    let text = format!(
        "WorldBegin\nMaterial \"{kind}\"\nShape \"sphere\" \"float radius\" [1]\nWorldEnd\n"
    );
    let dir = std::env::temp_dir().join(format!("foton-lux-legacy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{kind}.lxs"));
    std::fs::write(&path, text).unwrap();
    let scene = foton::scene::load(&path).unwrap();
    assert!(scene.warnings.is_empty(), "{kind}: {:?}", scene.warnings);
    match scene.materials.last() {
        Some(MaterialDesc::Lafortune(fit)) => fit,
        other => panic!("{kind}: {other:?}"),
    }
}

const MEASURED: [&str; 5] = ["primer", "felt", "clay", "bluepaint", "skin"];

fn lafortune(kind: &str) -> Bsdf {
    Bsdf::Lafortune(Lafortune {
        fit: measured(kind),
    })
}

/// Cases smooth enough for a quadrature of eval over the hemisphere.
fn smooth_cases() -> Vec<Bsdf> {
    let mut cases = vec![
        plastic(0.5, 0.5, 0.1),
        plastic(0.2, 1.0, 0.03),
        substrate(0.8, 0.05, 0.1, 0.1),
        substrate(0.5, 0.3, 0.05, 0.2),
    ];
    cases.extend(MEASURED.map(lafortune));
    cases
}

fn all_cases() -> Vec<Bsdf> {
    let mut cases = smooth_cases();
    cases.extend([plastic(0.1, 1.0, 0.002), substrate(0.1, 0.5, 0.01, 0.001)]);
    cases
}

/// Each sample's f and pdf are eval's and pdf's, and f(wo, wi) = f(wi, wo): the three models
/// are symmetric in wo and wi (the Blinn lobe's G and F(wi . h) = F(wo . h), FresnelBlend's
/// max(cos_i, cos_o), the Lafortune lobes' products wo.x wi.x ...).
#[test]
fn samples_match_eval_and_pdf_and_f_is_reciprocal() {
    for (i, bsdf) in all_cases().iter().enumerate() {
        assert_samples_match_eval(bsdf, 1.5, 1 + i as u64, 5_000);
    }
}

/// Pearson's chi-square of the sampled directions against the pdf over the sphere.
#[test]
fn sampling_histogram_matches_pdf() {
    for (i, bsdf) in smooth_cases().iter().enumerate() {
        assert_sampling_follows_pdf(bsdf, wo(0.8), 10 + i as u64, &format!("{bsdf:?}"));
    }
}

/// The importance-sampled albedo equals the quadrature of eval within 5 standard errors of the
/// sampled mean (measured from the samples) plus 0.5% for the quadrature.
#[test]
fn sampled_albedo_matches_quadrature_of_eval() {
    for (i, bsdf) in smooth_cases().into_iter().enumerate() {
        for theta in [0.2f32, 0.9, 1.3] {
            let w = wo(theta);
            let expected = quadrature(&bsdf, w, 0.0);
            let (albedo, error) = sampled_albedo(&bsdf, w, 100 + i as u64);
            let bound = 5.0 * error + 0.005 * expected + Vec3::splat(1e-4);
            assert!(
                ((albedo - expected).abs() - bound).max_element() <= 0.0,
                "{bsdf:?} theta {theta}: sampled {albedo} quadrature {expected} bound {bound}"
            );
        }
    }
}

/// Energy. FresnelBlend is built to conserve it (Ashikhmin and Shirley's diffuse term is the
/// remainder of the glossy one's): a white base under any Rs reflects at most what it
/// receives, and nearly all of it at normal incidence. `plastic` sums its two lobes, so it
/// conserves energy when Kd + Ks <= 1, and reflects more than it receives for Kd = Ks = 1, as
/// pbrt-v1's does. Bounds: 5 standard errors of the sampled mean.
#[test]
fn white_furnace() {
    for (i, bsdf) in [
        substrate(1.0, 0.05, 0.1, 0.1),
        substrate(1.0, 0.5, 0.05, 0.3),
        plastic(0.5, 0.5, 0.1),
        plastic(0.3, 0.7, 0.02),
    ]
    .iter()
    .enumerate()
    {
        for theta in [0.0f32, 0.7, 1.2, 1.45] {
            let (albedo, error) = sampled_albedo(bsdf, wo(theta), 300 + i as u64);
            println!("{i} theta {theta}: {albedo} +- {error}");
            assert!(
                (albedo - 5.0 * error).max_element() <= 1.0,
                "{bsdf:?} theta {theta}: {albedo} +- {error}"
            );
        }
    }
    let (normal, error) = sampled_albedo(&substrate(1.0, 0.05, 0.1, 0.1), Vec3::Z, 399);
    assert!(normal.x + 5.0 * error.x > 0.9, "{normal} +- {error}");
    let (over, error) = sampled_albedo(&plastic(1.0, 1.0, 0.1), wo(0.2), 398);
    assert!(
        over.x - 5.0 * error.x > 1.0,
        "Kd = Ks = 1: {over} +- {error}"
    );
}

/// The measured fits: their albedo stays below 1 at every angle tested (they are fits of
/// real, passive materials).
#[test]
fn measured_fits_reflect_less_than_they_receive() {
    for (i, kind) in MEASURED.iter().enumerate() {
        let bsdf = lafortune(kind);
        for theta in [0.0f32, 0.5, 1.0, 1.3, 1.5] {
            let (albedo, error) = sampled_albedo(&bsdf, wo(theta), 400 + i as u64);
            println!("{kind} theta {theta}: {albedo} +- {error}");
            assert!(
                (albedo - 5.0 * error).max_element() <= 1.0,
                "{kind} theta {theta}: {albedo} +- {error}"
            );
        }
    }
}

/// One value of each measured BRDF by hand. With wo = (sin 45, 0, cos 45) and wi its mirror
/// image (-sin 45, 0, cos 45), wo.x wi.x = -1/2 and wo.z wi.z = 1/2, so each lobe's base is
/// (Cz - Cxy) / 2 and f = R / pi + sum_k max(0, (Cz_k - Cxy_k) / 2)^n_k. The expected values
/// below are that sum of the sources' coefficients, evaluated in double precision apart from
/// foton (e.g. clay's red: 0.383626 / pi + 0 (lobe 1's base -0.1325) + 0.7047445^8.219745 +
/// 0.9606655^152.912795).
#[test]
fn measured_fits_known_values_at_the_mirror_direction() {
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let (o, i) = (Vec3::new(s, 0.0, s), Vec3::new(-s, 0.0, s));
    let expected = [
        ("primer", [0.0883009, 0.0900608, 0.0917821]),
        ("felt", [0.0097565, 0.0097565, 0.0097565]),
        ("clay", [0.1806205, 0.1461292, 0.1548173]),
        ("bluepaint", [0.1170239, 0.1446172, 0.2472612]),
        ("skin", [0.2036042, 0.1610486, 0.1654669]),
    ];
    for (kind, rgb) in expected {
        let f = lafortune(kind).eval(o, i);
        let want = Vec3::from(rgb);
        assert!(
            ((f - want).abs() - 1e-4 * want).max_element() <= 1e-6,
            "{kind}: {f} against {want}"
        );
    }
}

/// `plastic` by hand. Along the normal (wo = wi = n): h = n, D = (e + 2) / (2 pi), G = 1 and
/// F = ((1.5 - 1) / (1.5 + 1))^2 = 0.04, so f = Kd / pi + Ks (e + 2) / (2 pi) 0.04 / 4. At 60
/// degrees in the mirror configuration h = n again but wi . h = 1/2: from the 1.5 side
/// sin = 1.5 x 0.866 > 1, total internal reflection, F = 1 (pbrt-v1's `FresnelDielectric(1.5,
/// 1)`), G = min(1, 2 x 1 x 1/2 / (1/2)) = 1, so f = Kd / pi + Ks (e + 2) / (2 pi) / (4 / 4).
/// At 30 degrees (wi . h = cos 30), F is the internal reflectance 0.0552 (Fresnel's
/// equations for sin_t = 1.5 / 2 by hand).
#[test]
fn plastic_known_values() {
    let (kd, ks, e) = (0.5f32, 0.8f32, 10.0f32);
    let bsdf = Bsdf::BlinnPlastic(BlinnPlastic {
        diffuse: Vec3::splat(kd),
        specular: Vec3::splat(ks),
        distribution: PhongDistribution::from_roughness(1.0 / e, 1.0 / e),
    });
    let d = (e + 2.0) / (2.0 * PI);
    let at = |theta: f32| {
        let (sin, cos) = theta.sin_cos();
        bsdf.eval(Vec3::new(sin, 0.0, cos), Vec3::new(-sin, 0.0, cos))
            .x
    };
    let normal = kd / PI + ks * d * 0.04 / 4.0;
    assert!((at(0.0) - normal).abs() < 1e-5 * normal, "{}", at(0.0));
    let cos60 = 0.5f32;
    let total = kd / PI + ks * d / (4.0 * cos60 * cos60);
    assert!(
        (at(PI / 3.0) - total).abs() < 1e-5 * total,
        "{}",
        at(PI / 3.0)
    );
    // Fresnel from inside glass at 30 degrees: cos_i = 0.8660254, sin_t = 0.75, cos_t =
    // 0.6614378; r_s = (1.5 cos_i - cos_t) / (1.5 cos_i + cos_t) = 0.3252273,
    // r_p = (cos_i - 1.5 cos_t) / (cos_i + 1.5 cos_t) = -0.0678789 (pbrt's FrDiel with
    // etai = 1.5, etat = 1), F = (r_s^2 + r_p^2) / 2 = 0.0551902.
    let cos30 = 0.866_025_4f32;
    let thirty = kd / PI + ks * d * 0.055_190_2 / (4.0 * cos30 * cos30);
    assert!(
        (at(PI / 6.0) - thirty).abs() < 1e-4 * thirty,
        "{}",
        at(PI / 6.0)
    );
}

/// `substrate` by hand along the normal: h = n, so the Phong lobe is
/// D(n) = sqrt((ex + 2)(ey + 2)) / (2 pi), F = Rs, and
/// f = 28 / (23 pi) Rd (1 - Rs) (1 - 0.5^5)^2 + D(n) Rs / 4.
/// Anisotropy: at equal tilts of h along x and y the lobe is larger along the axis of the
/// smaller exponent, the rougher one, by cos_h^(ex - ey).
#[test]
fn substrate_known_values() {
    let (rd, rs, u, v) = (0.6f32, 0.2f32, 0.05f32, 0.2f32);
    let bsdf = substrate(rd, rs, u, v);
    let (ex, ey) = (1.0 / u, 1.0 / v);
    let d = ((ex + 2.0) * (ey + 2.0)).sqrt() / (2.0 * PI);
    let expected =
        28.0 / (23.0 * PI) * rd * (1.0 - rs) * (1.0 - 0.5f32.powi(5)).powi(2) + d * rs / 4.0;
    let f = bsdf.eval(Vec3::Z, Vec3::Z).x;
    assert!(
        (f - expected).abs() < 1e-5 * expected,
        "{f} against {expected}"
    );
    // wo = n, wi tilted by 2 t along x or y: h tilted by t, cos_h = cos t.
    let t = 0.2f32;
    let along = |axis: Vec3| {
        let wi = Vec3::Z * (2.0 * t).cos() + axis * (2.0 * t).sin();
        let diffuse = 28.0 / (23.0 * PI)
            * rd
            * (1.0 - rs)
            * (1.0 - (1.0 - 0.5 * wi.z).powi(5))
            * (1.0 - 0.5f32.powi(5));
        bsdf.eval(Vec3::Z, wi).x - diffuse
    };
    let ratio = along(Vec3::Y) / along(Vec3::X);
    let expected = t.cos().powf(ey - ex);
    assert!(
        (ratio - expected).abs() < 1e-3 * expected,
        "{ratio} against {expected}"
    );
}

/// A fit whose lobes vanish (no sampling axis) under huge exponents.
const FLAT_FIT: LafortuneFit = LafortuneFit {
    diffuse: Vec3::ONE,
    lobes: [LafortuneLobe {
        xy: Vec3::ZERO,
        z: Vec3::ZERO,
        exponent: Vec3::splat(1e4),
    }; 3],
};

/// Degenerate directions and samples give finite, non-negative outputs.
#[test]
fn outputs_are_finite() {
    let dirs = [
        Vec3::Z,
        -Vec3::Z,
        Vec3::X,
        Vec3::new(1.0, 0.0, 1e-8),
        Vec3::new(0.0, 1e-8, 1.0),
        Vec3::ZERO,
        Vec3::splat(f32::NAN),
        Vec3::splat(f32::INFINITY),
    ];
    let us = [
        (Vec2::ZERO, 0.0),
        (Vec2::ONE, 1.0),
        (Vec2::new(0.999_999, 0.0), 0.5),
        (Vec2::splat(f32::NAN), f32::NAN),
        (Vec2::new(-1.0, 2.0), 0.3),
    ];
    let mut cases = all_cases();
    cases.extend([
        plastic(1.0, 1.0, 0.0),
        plastic(1.0, 1.0, -1.0),
        substrate(1.0, 1.0, 0.0, f32::NAN),
        Bsdf::Lafortune(Lafortune { fit: &FLAT_FIT }),
    ]);
    for bsdf in &cases {
        for &w in &dirs {
            assert_finite_outputs(bsdf, w, &dirs, &us);
        }
    }
}
