//! LuxRender's `glossytranslucent` BSDF: sampling against eval and pdf, reciprocity, the
//! sampled albedo against a quadrature of eval over the sphere, closed forms at normal
//! incidence, the back coating on the back, finite outputs.

use std::f32::consts::PI;

use foton::bsdf::glossy_translucent::{Coating, GlossyTranslucent};
use foton::bsdf::{Bsdf, CoatedGlossy};
use glam::{Vec2, Vec3};

use crate::common::bsdf_estimates::{
    assert_samples_match_eval, assert_sampling_follows_pdf, quadrature, sampled_albedo,
};
use crate::common::bsdf_outputs::assert_finite_outputs;

/// A direction at `theta` from the normal (below the surface for theta > pi / 2).
fn wo(theta: f32) -> Vec3 {
    Vec3::new(theta.sin(), 0.0, theta.cos())
}

/// A coating: Ks, Ka, d, Schlick's r, multibounce.
fn coating(kd: f32, ks: f32, ka: f32, d: f32, r: f32, multibounce: bool) -> Coating {
    Coating {
        lobe: CoatedGlossy {
            diffuse: Vec3::splat(kd),
            specular: Vec3::splat(ks),
            absorption: Vec3::new(ka, 0.5 * ka, 0.0),
            depth: d,
            roughness: r,
            anisotropy: 0.0,
        },
        multibounce,
    }
}

/// `coating` with Schlick's anisotropy `a`.
fn anisotropic(coating: Coating, a: f32) -> Coating {
    Coating {
        lobe: CoatedGlossy {
            anisotropy: a,
            ..coating.lobe
        },
        ..coating
    }
}

fn sheet(kd: f32, kt: Vec3, front: Coating, back: Coating) -> Bsdf {
    Bsdf::GlossyTranslucent(GlossyTranslucent {
        front: Coating {
            lobe: CoatedGlossy {
                diffuse: Vec3::splat(kd),
                ..front.lobe
            },
            ..front
        },
        back: Coating {
            lobe: CoatedGlossy {
                diffuse: Vec3::splat(kd),
                ..back.lobe
            },
            ..back
        },
        transmittance: kt,
    })
}

fn cases() -> Vec<Bsdf> {
    let default_front = coating(0.5, 0.04, 0.0, 0.0, 0.01, false);
    vec![
        // LuxRender's defaults but Kd (index 1.5: Ks 0.04), one-sided.
        sheet(0.5, Vec3::ONE, default_front, default_front),
        // Two different coatings, absorbing, multibounce on the front.
        sheet(
            0.3,
            Vec3::new(0.9, 0.6, 0.3),
            coating(0.3, 0.1, 1.0, 0.2, 0.05, true),
            coating(0.3, 0.3, 0.5, 0.4, 0.3, false),
        ),
        // Anisotropic coatings (LuxRender's u 0.1, v 0.2 in front, u 0.3, v 0.1 behind).
        sheet(
            0.4,
            Vec3::new(0.7, 0.8, 0.9),
            anisotropic(coating(0.4, 0.1, 0.0, 0.0, 0.02, true), 0.75),
            anisotropic(coating(0.4, 0.2, 0.0, 0.0, 0.03, false), 1.0 / 9.0 - 1.0),
        ),
        // No transmission: reflection only, on either side.
        sheet(
            0.8,
            Vec3::ZERO,
            default_front,
            coating(0.8, 0.2, 0.0, 0.0, 0.2, true),
        ),
    ]
}

/// Each sample's f and pdf are eval's and pdf's, seen from either side, and
/// f(wo, wi) = f(wi, wo).
#[test]
fn samples_match_eval_and_pdf_and_f_is_reciprocal() {
    for (i, bsdf) in cases().iter().enumerate() {
        assert_samples_match_eval(bsdf, PI, 1 + i as u64, 10_000);
    }
}

/// Pearson's chi-square of the sampled directions against the pdf over the whole sphere, seen
/// from the front and from the back.
#[test]
fn sampling_histogram_matches_pdf() {
    for (i, bsdf) in cases().iter().enumerate() {
        for theta in [0.8, PI - 0.5] {
            let label = format!("{bsdf:?} theta {theta}");
            assert_sampling_follows_pdf(bsdf, wo(theta), 10 + i as u64, &label);
        }
    }
}

/// The importance-sampled albedo equals the quadrature of eval within 5 standard errors of the
/// sampled mean (measured from the samples) plus 0.5% for the quadrature, from both sides.
#[test]
fn sampled_albedo_matches_quadrature_of_eval() {
    for (i, bsdf) in cases().into_iter().enumerate() {
        for theta in [0.2f32, 0.9, 1.3, PI - 0.4] {
            let w = wo(theta);
            let expected = quadrature(&bsdf, w, -1.0);
            let (albedo, error) = sampled_albedo(&bsdf, w, 100 + i as u64);
            let bound = 5.0 * error + 0.005 * expected + Vec3::splat(1e-4);
            eprintln!("case {i} theta {theta}: albedo {albedo} quadrature {expected}");
            assert!(
                ((albedo - expected).abs() - bound).max_element() <= 0.0,
                "{bsdf:?} theta {theta}: sampled {albedo} quadrature {expected} bound {bound}"
            );
        }
    }
}

/// At normal incidence h = n, Schlick's Z = 1 / r, G = 1 and S = Ks, so reflection on a side
/// is Kd (1 - Ks) exp(-2 Ka d) / pi + Ks / (4 pi r) of that side's coating (multibounce adds
/// (1 - G) = 0); straight through, h' = -n, u = 1, and transmission is
/// Kt (1 - Kd) / pi (1 - Ks1)(1 - Ks2) / (1 - (Ks1 + Ks2) / 2) exp(-Ka1 d1 - Ka2 d2).
#[test]
fn known_values_at_normal_incidence() {
    let (kd, kt) = (0.3, Vec3::new(0.9, 0.6, 0.3));
    let (front, back) = (
        coating(kd, 0.1, 1.0, 0.2, 0.05, true),
        coating(kd, 0.3, 0.5, 0.4, 0.3, false),
    );
    let bsdf = sheet(kd, kt, front, back);
    let reflection = |c: &Coating| {
        let l = &c.lobe;
        l.diffuse * (Vec3::ONE - l.specular) * (-2.0 * l.absorption * l.depth).exp() / PI
            + l.specular / (4.0 * PI * l.roughness)
    };
    let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() <= 1e-4 * b.max_element();
    let f = bsdf.eval(Vec3::Z, Vec3::Z);
    assert!(close(f, reflection(&front)), "{f} {}", reflection(&front));
    let f = bsdf.eval(-Vec3::Z, -Vec3::Z);
    assert!(close(f, reflection(&back)), "{f} {}", reflection(&back));
    let (s1, s2) = (front.lobe.specular, back.lobe.specular);
    let absorption =
        (-front.lobe.absorption * front.lobe.depth - back.lobe.absorption * back.lobe.depth).exp();
    let expected = kt * (1.0 - kd) / PI * (Vec3::ONE - s1) * (Vec3::ONE - s2)
        / (Vec3::ONE - (s1 + s2) * 0.5)
        * absorption;
    for (a, b) in [(Vec3::Z, -Vec3::Z), (-Vec3::Z, Vec3::Z)] {
        let f = bsdf.eval(a, b);
        assert!(close(f, expected), "{f} {expected}");
    }
}

/// Degenerate directions and samples give finite, non-negative outputs.
#[test]
fn outputs_are_finite() {
    let dirs = [
        Vec3::Z,
        -Vec3::Z,
        Vec3::X,
        Vec3::new(1.0, 0.0, 1e-8),
        Vec3::new(0.0, 1e-8, -1.0),
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
    let mut all = cases();
    let extreme = coating(1.0, 1.0, 100.0, 1.0, 1e-6, true);
    all.push(sheet(1.0, Vec3::ONE, extreme, extreme));
    for bsdf in &all {
        for &w in &dirs {
            assert_finite_outputs(bsdf, w, &dirs, &us);
        }
    }
}
