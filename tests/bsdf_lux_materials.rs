//! LuxRender's `shinymetal`, `velvet` and `carpaint` BSDFs, and LuxRender 0.x's own (pbrt-v1's)
//! `plastic` (a Blinn lobe), `substrate` (Ashikhmin-Shirley) and measured Lafortune fits
//! (`primer`, `felt`, `clay`, `bluepaint`, `skin`): sampling against eval and pdf (values and a
//! chi-square histogram), reciprocity, the directional albedo by importance sampling against a
//! quadrature of eval, energy conservation where the model has it, known values by hand (the
//! fitted conductor Fresnel term, the measured fits, plastic, substrate), and finite outputs
//! on degenerate input.

use std::f32::consts::PI;

use foton::bsdf::fresnel::{approx_eta, approx_k, fr_dielectric, fr_general};
use foton::bsdf::lafortune::{LafortuneFit, LafortuneLobe};
use foton::bsdf::phong_distribution::PhongDistribution;
use foton::bsdf::thin_film::ThinFilm;
use foton::bsdf::{
    BlinnPlastic, Bsdf, CarPaint, CarPaintLobe, CoatedGlossy, FresnelBlend, Lafortune, ShinyMetal,
    Velvet,
};
use foton::scene::desc::MaterialDesc;
use foton::texture::blackbody::{XYZ_TO_SRGB, cie_xyz};
use glam::{Vec2, Vec3};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

use crate::common::bsdf_estimates::{
    assert_samples_match_eval, assert_sampling_follows_pdf, quadrature, sampled_albedo, uniform,
};
use crate::common::bsdf_outputs::assert_finite_outputs;

/// Energy conservation: at each `wo(theta)` the sampled albedo is at most 1, allowing five
/// standard errors of its estimate (seed `seed`).
fn assert_albedo_at_most_one(bsdf: &Bsdf, thetas: &[f32], seed: u64, label: &str) {
    for &theta in thetas {
        let (albedo, error) = sampled_albedo(bsdf, wo(theta), seed);
        println!("{label} theta {theta}: {albedo} +- {error}");
        assert!(
            (albedo - 5.0 * error).max_element() <= 1.0,
            "{label} {bsdf:?} theta {theta}: {albedo} +- {error}"
        );
    }
}

fn wo(theta: f32) -> Vec3 {
    Vec3::new(theta.sin() * 0.6, theta.sin() * 0.8, theta.cos())
}

fn shiny(glossy: f32, mirror: f32, roughness: f32) -> Bsdf {
    anisotropic_shiny(glossy, mirror, roughness, 0.0)
}

/// shinymetal of roughness r = u v and Schlick's anisotropy a.
fn anisotropic_shiny(glossy: f32, mirror: f32, roughness: f32, anisotropy: f32) -> Bsdf {
    Bsdf::ShinyMetal(ShinyMetal {
        glossy: Vec3::new(glossy, glossy * 0.8, glossy * 0.5),
        mirror: Vec3::splat(mirror),
        roughness,
        anisotropy,
        film: None,
    })
}

/// LuxRender's anisotropy of `uroughness` u and `vroughness` v (`shinymetal.cpp`).
fn schlick_anisotropy(u: f32, v: f32) -> f32 {
    let (u2, v2) = (u * u, v * v);
    if u2 < v2 {
        1.0 - u2 / v2
    } else {
        v2 / u2 - 1.0
    }
}

fn velvet(legendre: [f32; 3], thickness: f32) -> Bsdf {
    Bsdf::Velvet(Velvet {
        reflectance: Vec3::new(0.3, 0.5, 0.9),
        legendre,
        thickness,
    })
}

/// Car paint with lobes (Ks, R, M) over a base of `kd` (absorption `ka` over depth `d`).
fn paint(kd: Vec3, lobes: [(f32, f32, f32); 3], ka: f32, d: f32) -> Bsdf {
    Bsdf::CarPaint(CarPaint {
        base: CoatedGlossy {
            diffuse: kd,
            specular: Vec3::ZERO,
            absorption: Vec3::splat(ka),
            depth: d,
            roughness: 1.0,
            anisotropy: 0.0,
        },
        lobes: lobes.map(|(ks, f0, roughness)| CarPaintLobe {
            specular: Vec3::splat(ks),
            f0,
            roughness,
        }),
    })
}

/// LuxRender's "ford f8" and "white" presets (`materials/carpaint.h`).
fn ford_f8() -> Bsdf {
    Bsdf::CarPaint(CarPaint {
        base: CoatedGlossy {
            diffuse: Vec3::new(0.0012, 0.0015, 0.0018),
            specular: Vec3::ZERO,
            absorption: Vec3::ZERO,
            depth: 0.0,
            roughness: 1.0,
            anisotropy: 0.0,
        },
        lobes: [
            (Vec3::new(0.0049, 0.0076, 0.0120), 0.15, 0.32),
            (Vec3::new(0.0100, 0.0130, 0.0180), 0.087, 0.11),
            (Vec3::new(0.0070, 0.0065, 0.0077), 0.9, 0.013),
        ]
        .map(|(specular, f0, roughness)| CarPaintLobe {
            specular,
            f0,
            roughness,
        }),
    })
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
        shiny(0.8, 0.6, 0.3 * 0.3),
        shiny(1.0, 1.0, 0.6),
        anisotropic_shiny(0.8, 0.6, 0.5 * 0.2, schlick_anisotropy(0.5, 0.2)),
        anisotropic_shiny(0.9, 0.3, 0.3 * 0.6, schlick_anisotropy(0.3, 0.6)),
        velvet([-2.0, 20.0, 2.0], 0.1),
        velvet([1.0, 0.5, -0.3], 0.8),
        paint(
            Vec3::splat(0.5),
            [(0.3, 0.5, 0.5), (0.2, 0.9, 0.35), (0.1, 1.0, 0.3)],
            0.0,
            0.0,
        ),
        paint(
            Vec3::splat(0.9),
            [(0.0, 0.5, 0.5), (1.0, 0.2, 0.4), (0.0, 1.0, 0.3)],
            0.5,
            0.3,
        ),
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
    cases.extend([
        shiny(0.9, 0.9, 0.01 * 0.02),
        anisotropic_shiny(0.9, 0.9, 0.1 * 0.3, schlick_anisotropy(0.1, 0.3)),
        ford_f8(),
        plastic(0.1, 1.0, 0.002),
        substrate(0.1, 0.5, 0.01, 0.001),
    ]);
    cases
}

/// Each sample's f and pdf are eval's and pdf's (non-delta samples), and f(wo, wi) =
/// f(wi, wo): the three models are symmetric in wo and wi (Schlick's lobes depend on wi . h =
/// wo . h and on cos_o cos_i symmetrically; the velvet phase function on wo . wi).
#[test]
fn samples_match_eval_and_pdf_and_f_is_reciprocal() {
    for (i, bsdf) in all_cases().iter().enumerate() {
        assert_samples_match_eval(bsdf, 1.5, 1 + i as u64, 5_000);
    }
}

/// Pearson's chi-square of the sampled (non-delta) directions against the pdf over the
/// sphere (`DirectionGrid`: cells of equal solid angle, p = 1e-4); shinymetal's mirror
/// samples are not counted, and its pdf integrates to the glossy lobe's probability, 1/2.
#[test]
fn sampling_histogram_matches_pdf() {
    for (i, bsdf) in all_cases().iter().enumerate() {
        assert_sampling_follows_pdf(bsdf, wo(0.8), 10 + i as u64, &format!("{bsdf:?}"));
    }
}

/// The importance-sampled albedo equals the quadrature of eval (plus, for shinymetal, the
/// mirror's Fresnel reflectance F(cos_o), its known delta part) within 5 standard errors of
/// the sampled mean (measured from the samples) plus 0.5% for the quadrature.
#[test]
fn sampled_albedo_matches_quadrature_of_eval() {
    for (i, bsdf) in smooth_cases().into_iter().enumerate() {
        for theta in [0.2f32, 0.9, 1.3] {
            let w = wo(theta);
            let mut expected = quadrature(&bsdf, w, 0.0);
            if let Bsdf::ShinyMetal(m) = bsdf {
                expected += fr_general(w.z, approx_eta(m.mirror), approx_k(m.mirror));
            }
            let (albedo, error) = sampled_albedo(&bsdf, w, 100 + i as u64);
            let bound = 5.0 * error + 0.005 * expected + Vec3::splat(1e-4);
            assert!(
                ((albedo - expected).abs() - bound).max_element() <= 0.0,
                "{bsdf:?} theta {theta}: sampled {albedo} quadrature {expected} bound {bound}"
            );
        }
    }
}

/// Car paint is a sum of lobes, so it conserves energy only when they are weak, as in the
/// measured presets: with them (and with a white base under the same lobes) its albedo is
/// at most 1 within 5 standard errors; three full lobes (Ks = 1, R = 1) reflect more than
/// they receive, as LuxRender's model does.
#[test]
fn car_paint_conserves_energy_with_measured_lobes() {
    let white = paint(
        Vec3::new(0.61, 0.63, 0.55),
        [
            (0.00031, 0.049, 1.0),
            (0.013, 0.45, 0.15),
            (0.049, 0.17, 0.015),
        ],
        0.0,
        0.0,
    );
    let white_base = paint(
        Vec3::ONE,
        [
            (0.0120, 0.15, 0.32),
            (0.0180, 0.087, 0.11),
            (0.0077, 0.9, 0.013),
        ],
        0.0,
        0.0,
    );
    let full = paint(
        Vec3::ONE,
        [(1.0, 1.0, 0.5), (1.0, 1.0, 0.2), (1.0, 1.0, 0.05)],
        0.0,
        0.0,
    );
    let (over, _) = sampled_albedo(&full, wo(0.0), 199);
    assert!(over.x > 1.5, "three full lobes: {over}");
    let cases = [ford_f8(), white, white_base];
    for (i, bsdf) in cases.iter().enumerate() {
        assert_albedo_at_most_one(bsdf, &[0.0, 0.7, 1.4], 200 + i as u64, &i.to_string());
    }
}

/// shinymetal's Fresnel term (`FresnelGeneral` of `FresnelApproxEta`/`FresnelApproxK`): at
/// normal incidence ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2), which for k = 0 is the R the
/// index was fitted to; 1 at grazing incidence; with k = 0 and eta > 1 the dielectric Fresnel
/// reflectance at every angle.
#[test]
fn fitted_conductor_fresnel_known_values() {
    for r in [0.0f32, 0.04, 0.3, 0.9, 0.999] {
        let (eta, k) = (approx_eta(Vec3::splat(r)), approx_k(Vec3::splat(r)));
        let normal = fr_general(1.0, eta, k).x;
        let expected = ((eta.x - 1.0).powi(2) + k.x * k.x) / ((eta.x + 1.0).powi(2) + k.x * k.x);
        assert!(
            (normal - expected).abs() < 1e-5,
            "R {r}: {normal} vs {expected}"
        );
        assert!(
            (fr_general(1.0, eta, Vec3::ZERO).x - r).abs() < 1e-5,
            "R {r}"
        );
        assert!(
            (fr_general(0.0, eta, k).x - 1.0).abs() < 1e-5,
            "R {r} grazing"
        );
    }
    for cos in [0.05f32, 0.3, 0.7, 1.0] {
        let f = fr_general(cos, Vec3::splat(1.5), Vec3::ZERO).x;
        assert!((f - fr_dielectric(cos, 1.5)).abs() < 1e-5, "cos {cos}: {f}");
    }
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
        shiny(1.0, 1.0, 0.0),
        anisotropic_shiny(1.0, 1.0, 0.0, schlick_anisotropy(0.0, 0.3)),
        anisotropic_shiny(1.0, 1.0, 0.1, -1.0),
        velvet([100.0, -100.0, 100.0], 1.0),
        paint(
            Vec3::ONE,
            [(1.0, 1.0, 0.0), (1.0, 0.0, 1e-6), (1.0, 2.0, 1.0)],
            1.0,
            1.0,
        ),
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

/// Closed forms. Velvet: seen and lit along the normal the scattering angle is back
/// (x = -1: P1 = -1, P2 = 1, P3 = -1), so f = R (1 - A1 + A2 - A3) delta / (4 pi); seen and
/// lit from opposite azimuths at 45 degrees, x = 0 (P1 = P3 = 0, P2 = -1/2) and
/// f = R (1 - A2 / 2) delta / (4 pi cos^2 45). A Schlick lobe at normal incidence has h = n,
/// Z = 1 / r and G = 1, so f = F(1) / (4 pi r): car paint adds Ks_k R_k / (4 pi M_k^2) over the
/// base's Kd / pi (its Fresnel term S is 0 at normal incidence); shinymetal's glossy lobe is
/// F(1) / (4 pi u v) and its mirror reflects F(cos_o).
#[test]
fn known_values_at_normal_incidence() {
    let close = |a: Vec3, b: Vec3, what: &str| {
        assert!(
            (a - b).abs().max_element() <= 1e-5 * b.max_element().max(1.0),
            "{what}: {a} vs {b}"
        );
    };
    let (a, thickness) = ([0.7f32, 0.8, -1.5], 0.2);
    let v = velvet(a, thickness);
    let Bsdf::Velvet(Velvet { reflectance, .. }) = v else {
        unreachable!()
    };
    let back = reflectance * ((1.0 - a[0] + a[1] - a[2]) * thickness / (4.0 * PI));
    close(v.eval(Vec3::Z, Vec3::Z), back, "velvet backscatter");
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let side = reflectance * ((1.0 - a[1] / 2.0) * thickness / (4.0 * PI * 0.5));
    close(
        v.eval(Vec3::new(s, 0.0, s), Vec3::new(-s, 0.0, s)),
        side,
        "velvet at x = 0",
    );

    let lobes = [(0.3f32, 0.5f32, 0.5f32), (0.2, 0.9, 0.35), (0.1, 1.0, 0.3)];
    let kd = Vec3::new(0.2, 0.4, 0.6);
    let expected = kd / PI
        + Vec3::splat(
            lobes
                .iter()
                .map(|&(ks, r, m)| ks * r / (4.0 * PI * m * m))
                .sum::<f32>(),
        );
    close(
        paint(kd, lobes, 0.0, 0.0).eval(Vec3::Z, Vec3::Z),
        expected,
        "car paint",
    );

    let metal = shiny(0.8, 0.6, 0.3 * 0.2);
    let Bsdf::ShinyMetal(m) = metal else {
        unreachable!()
    };
    let fit = |r: Vec3, cos: f32| fr_general(cos, approx_eta(r), approx_k(r));
    close(
        metal.eval(Vec3::Z, Vec3::Z),
        fit(m.glossy, 1.0) / (4.0 * PI * m.roughness),
        "shinymetal glossy lobe",
    );
    let w = wo(0.6);
    let mirror = metal.sample(w, Vec2::ZERO, 0.0).unwrap();
    assert!(mirror.delta);
    // A delta lobe's f |cos| is the fraction it reflects; pdf the probability of picking it.
    close(
        mirror.f * mirror.wi.z,
        fit(m.mirror, w.z),
        "shinymetal mirror",
    );
    assert_eq!(mirror.pdf, 0.5);
}

/// shinymetal's anisotropic lobe is wider along the tangent of larger roughness. Seen and lit
/// along the normal, a direction tilted by the same angle towards x or towards y has the same
/// Z and G; only Schlick's A differs: with u < v, a = 1 - u^2 / v^2 > 0, p = 1 - a = u^2 / v^2
/// and w the cosine of h's azimuth from x, A = sqrt(p) along x (w = 1) and 1 / sqrt(p) along y
/// (w = 0): the ratio of f along y to f along x is 1 / p = v^2 / u^2. Swapping u and v turns
/// the lobe by 90 degrees; u = v is isotropic.
#[test]
fn anisotropic_lobe_is_wider_along_the_rougher_tangent() {
    let tilt = 0.3f32;
    let along_x = Vec3::new(tilt.sin(), 0.0, tilt.cos());
    let along_y = Vec3::new(0.0, tilt.sin(), tilt.cos());
    let ratio = |u: f32, v: f32| {
        let metal = anisotropic_shiny(0.8, 0.6, u * v, schlick_anisotropy(u, v));
        metal.eval(Vec3::Z, along_y).y / metal.eval(Vec3::Z, along_x).y
    };
    for (u, v) in [(0.1f32, 0.4f32), (0.2, 0.25), (0.4, 0.1), (0.3, 0.3)] {
        let expected = (v * v) / (u * u);
        let measured = ratio(u, v);
        assert!(
            (measured / expected - 1.0).abs() < 1e-4,
            "u {u}, v {v}: f along y / f along x {measured}, expected {expected}"
        );
    }
    // The sampled directions spread the same way: the mean squared y of the glossy samples
    // exceeds that of x when u < v.
    let metal = anisotropic_shiny(0.8, 0.6, 0.1 * 0.4, schlick_anisotropy(0.1, 0.4));
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    let (mut x2, mut y2) = (0.0, 0.0);
    for _ in 0..20_000 {
        let u = Vec2::new(uniform(&mut rng), uniform(&mut rng));
        if let Some(s) = metal.sample(Vec3::Z, u, 0.9) {
            x2 += s.wi.x * s.wi.x;
            y2 += s.wi.y * s.wi.y;
        }
    }
    assert!(y2 > 4.0 * x2, "mean x^2 {x2}, y^2 {y2}");
}

/// The thin film's weight, LuxRender's cos^2(4 pi d s / lambda + pi) with s = sqrt(n^2 -
/// sin^2 theta_o), by hand for d = 100 nm, n = 1.5: along the normal s = 1.5 and 4 pi d s =
/// 600 pi nm, so the phase is 2 pi at 600 nm (weight 1), 2.5 pi at 400 nm (0) and 2.25 pi at
/// 480 nm (1/2); at 45 degrees s = sqrt(2.25 - 0.5) = 1.3229 and the phase is 2 pi at
/// 4 d s = 529.15 nm. Projected to RGB the film is warm (its peak at 600 nm, its zero at
/// 400 nm) and equals the CIE-weighted mean of the weight (a 1 nm sum in the test against
/// foton's 5 nm one), and the mirror's reflectance is the fitted Fresnel term times it.
#[test]
fn thin_film_weights_the_mirror_by_hand_derived_values() {
    let film = ThinFilm {
        thickness: 100.0,
        index: 1.5,
    };
    for (cos_o, nm, expected) in [
        (1.0f32, 600.0f32, 1.0f32),
        (1.0, 400.0, 0.0),
        (1.0, 480.0, 0.5),
        (std::f32::consts::FRAC_1_SQRT_2, 529.15, 1.0),
    ] {
        let weight = film.spectral_weight(cos_o, nm);
        assert!(
            (weight - expected).abs() < 1e-3,
            "cos {cos_o}, {nm} nm: {weight} against {expected}"
        );
    }
    for cos_o in [1.0f32, 0.6, 0.2] {
        let rgb = film.rgb_weight(cos_o);
        let (mut sum, mut white) = (Vec3::ZERO, Vec3::ZERO);
        for i in 0..335 {
            let nm = 383.0 + i as f32;
            let cmf = XYZ_TO_SRGB * cie_xyz(nm);
            sum += film.spectral_weight(cos_o, nm) * cmf;
            white += cmf;
        }
        let reference = sum / white;
        assert!(
            (rgb - reference).abs().max_element() < 0.01,
            "cos {cos_o}: {rgb} against {reference}"
        );
    }
    let normal = film.rgb_weight(1.0);
    assert!(normal.x > normal.z + 0.2, "{normal}");

    let metal = ShinyMetal {
        glossy: Vec3::splat(0.8),
        mirror: Vec3::new(0.9, 0.7, 0.5),
        roughness: 0.01,
        anisotropy: 0.0,
        film: Some(film),
    };
    let w = wo(0.6);
    let sample = Bsdf::ShinyMetal(metal).sample(w, Vec2::ZERO, 0.0).unwrap();
    let expected =
        fr_general(w.z, approx_eta(metal.mirror), approx_k(metal.mirror)) * film.rgb_weight(w.z);
    assert!(
        (sample.f * sample.wi.z - expected).abs().max_element() < 1e-5,
        "{} against {expected}",
        sample.f * sample.wi.z
    );
}

/// Energy. FresnelBlend is built to conserve it (Ashikhmin and Shirley's diffuse term is the
/// remainder of the glossy one's): a white base under any Rs reflects at most what it
/// receives, and nearly all of it at normal incidence. `plastic` sums its two lobes, so it
/// conserves energy when Kd + Ks <= 1, and reflects more than it receives for Kd = Ks = 1, as
/// pbrt-v1's does. Bounds: 5 standard errors of the sampled mean.
#[test]
fn substrate_and_plastic_white_furnace() {
    for (i, bsdf) in [
        substrate(1.0, 0.05, 0.1, 0.1),
        substrate(1.0, 0.5, 0.05, 0.3),
        plastic(0.5, 0.5, 0.1),
        plastic(0.3, 0.7, 0.02),
    ]
    .iter()
    .enumerate()
    {
        assert_albedo_at_most_one(bsdf, &[0.0, 0.7, 1.2, 1.45], 300 + i as u64, &i.to_string());
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
        let thetas = [0.0, 0.5, 1.0, 1.3, 1.5];
        assert_albedo_at_most_one(&lafortune(kind), &thetas, 400 + i as u64, kind);
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
