//! Tests of the rough dielectric, thin dielectric, plastic and rough plastic BSDFs (Mitsuba 3's
//! `roughdielectric`, `thindielectric`, `plastic`, `roughplastic`): energy where it is
//! conserved, known reflectances, sampling against eval and pdf (also by chi-square, with the
//! lobe choice random), reciprocity (generalised for refraction), and robustness.

use foton::bsdf::fresnel::fr_dielectric;
use foton::bsdf::microfacet::TrowbridgeReitz;
use foton::bsdf::microfacet_distribution::{DistributionKind, Microfacet};
use foton::bsdf::plastic::internal_reflectance;
use foton::bsdf::rough_plastic::CoatingTables;
use foton::bsdf::{Bsdf, Plastic, RoughDielectric, RoughPlastic, ThinDielectric};
use glam::{Vec2, Vec3};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::{Rng, SeedableRng};
use std::f32::consts::PI;

use crate::common::bsdf_outputs::assert_finite_outputs;
use crate::common::chi_square::DirectionGrid;

const N: usize = 200_000;

struct Sampler(Xoshiro256PlusPlus);

impl Sampler {
    fn new(seed: u64) -> Self {
        Self(Xoshiro256PlusPlus::seed_from_u64(seed))
    }
    fn next(&mut self) -> f32 {
        (self.0.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }
    fn next2(&mut self) -> Vec2 {
        Vec2::new(self.next(), self.next())
    }
    /// A uniform direction on the sphere.
    fn direction(&mut self) -> Vec3 {
        let z = 1.0 - 2.0 * self.next();
        let s = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * self.next();
        Vec3::new(s * phi.cos(), s * phi.sin(), z)
    }
}

/// A unit direction at polar angle `theta` (azimuth 0.7 rad).
fn dir(theta: f32) -> Vec3 {
    Vec3::new(
        theta.sin() * 0.7f32.cos(),
        theta.sin() * 0.7f32.sin(),
        theta.cos(),
    )
}

/// The mean and standard error of f |cos| / pdf (times `weight(wi)`) over N samples.
fn albedo(bsdf: &Bsdf, wo: Vec3, seed: u64, weight: impl Fn(Vec3) -> f32) -> (f64, f64) {
    let mut s = Sampler::new(seed);
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..N {
        let (u, uc) = (s.next2(), s.next());
        if let Some(b) = bsdf.sample(wo, u, uc) {
            let v = (b.f.x * b.wi.z.abs() / b.pdf * weight(b.wi)) as f64;
            sum += v;
            sum2 += v * v;
        }
    }
    let mean = sum / N as f64;
    let var = (sum2 / N as f64 - mean * mean).max(0.0);
    (mean, (var / N as f64).sqrt())
}

fn rough_glass(eta: f32, ax: f32, ay: f32) -> Bsdf {
    Bsdf::RoughDielectric(RoughDielectric {
        reflectance: Vec3::ONE,
        transmittance: Vec3::ONE,
        eta,
        distribution: Microfacet::TrowbridgeReitz(TrowbridgeReitz::new(ax, ay)),
    })
}

/// Mitsuba's rough dielectric with the Beckmann distribution (sampled over all normals).
fn beckmann_glass(eta: f32, ax: f32, ay: f32) -> Bsdf {
    Bsdf::RoughDielectric(RoughDielectric {
        reflectance: Vec3::ONE,
        transmittance: Vec3::ONE,
        eta,
        distribution: Microfacet::new(DistributionKind::Beckmann, ax, ay),
    })
}

fn thin(eta: f32) -> Bsdf {
    Bsdf::ThinDielectric(ThinDielectric {
        reflectance: Vec3::ONE,
        transmittance: Vec3::ONE,
        eta,
    })
}

fn plastic(diffuse: Vec3, eta: f32, nonlinear: bool) -> Bsdf {
    Bsdf::Plastic(Plastic {
        diffuse,
        specular: Vec3::ONE,
        eta,
        internal_reflectance: internal_reflectance(eta),
        nonlinear,
    })
}

fn rough_plastic(diffuse: Vec3, eta: f32, alpha: f32) -> Bsdf {
    Bsdf::RoughPlastic(RoughPlastic {
        diffuse,
        specular: Vec3::ONE,
        eta,
        distribution: TrowbridgeReitz::new(alpha, alpha),
        nonlinear: false,
        tables: CoatingTables::of(alpha, eta),
    })
}

/// The non-delta BSDFs under test, and whether wo may lie below the surface.
fn glossy_cases() -> Vec<(Bsdf, bool)> {
    vec![
        (rough_glass(1.5, 0.3, 0.3), true),
        (rough_glass(1.33, 0.1, 0.1), true),
        (rough_glass(1.0 / 1.5, 0.5, 0.5), true),
        (rough_glass(1.5, 0.1, 0.5), true),
        (beckmann_glass(1.5, 0.3, 0.3), true),
        (beckmann_glass(1.0 / 1.33, 0.1, 0.4), true),
        (rough_plastic(Vec3::new(0.7, 0.3, 0.1), 1.49, 0.1), false),
        (rough_plastic(Vec3::splat(0.5), 1.5, 0.5), false),
    ]
}

/// A rough dielectric with tiny alpha is the smooth one: in radiance, R + T / eta'^2 with the
/// smooth Fresnel R (eta' the index of wi's side over wo's); and with the 1 / eta'^2 undone,
/// all energy is kept (R + T = 1). Both sides, several angles; bounds: 5 standard errors.
#[test]
fn rough_dielectric_tends_to_the_smooth_one() {
    for eta in [1.5f32, 1.0 / 1.33] {
        let bsdf = rough_glass(eta, 1e-3, 1e-3);
        for theta in [0.0f32, 0.5, 1.0] {
            for wo in [dir(theta), -dir(theta)] {
                let etap = if wo.z > 0.0 { eta } else { 1.0 / eta };
                let r = fr_dielectric(wo.z, eta) as f64;
                let expected = r + (1.0 - r) / (etap * etap) as f64;
                let (a, se) = albedo(&bsdf, wo, 1, |_| 1.0);
                assert!(
                    (a - expected).abs() < 5.0 * se + 1e-3,
                    "eta {eta} cos {}: {a} vs {expected} (se {se})",
                    wo.z
                );
                let (e, se) = albedo(&bsdf, wo, 2, |wi| {
                    if wi.z * wo.z < 0.0 { etap * etap } else { 1.0 }
                });
                assert!((e - 1.0).abs() < 5.0 * se + 2e-3, "energy {e} (se {se})");
            }
        }
    }
}

/// A rough dielectric loses energy only to single-scattering's missing interreflections: R + T
/// (the 1 / eta'^2 undone) is at most 1, and above 0.9 up to 1.2 rad at these alphas (the loss
/// grows toward grazing angles: 0.922 measured at alpha 0.3, 1.2 rad).
#[test]
fn rough_dielectric_energy_is_bounded() {
    for (eta, alpha) in [(1.5f32, 0.3f32), (1.5, 0.1), (1.33, 0.3)] {
        let bsdf = rough_glass(eta, alpha, alpha);
        for theta in [0.0f32, 0.6, 1.2] {
            let wo = dir(theta);
            let (e, se) = albedo(&bsdf, wo, 3, |wi| if wi.z < 0.0 { eta * eta } else { 1.0 });
            println!("eta {eta} alpha {alpha} theta {theta}: {e} (se {se})");
            assert!(e < 1.0 + 5.0 * se, "{e}");
            assert!(e > 0.9, "{e}");
        }
    }
}

/// Radiance transport through an interface: f(wo, wi) eta_i^2 = f(wi, wo) eta_o^2 (Veach 1997,
/// eq. 5.14), with eta_i, eta_o the indices of wi's and wo's sides; plain reciprocity for
/// reflection and for the plastics.
#[test]
fn generalised_reciprocity() {
    let mut s = Sampler::new(4);
    for (bsdf, _) in glossy_cases() {
        let eta = match bsdf {
            Bsdf::RoughDielectric(d) => d.eta,
            _ => 1.0,
        };
        let index = |w: Vec3| if w.z > 0.0 { 1.0 } else { eta };
        for _ in 0..20_000 {
            let (a, b) = (s.direction(), s.direction());
            let fab = bsdf.eval(a, b).x * index(b).powi(2);
            let fba = bsdf.eval(b, a).x * index(a).powi(2);
            assert!(
                (fab - fba).abs() <= 1e-3 * fab.max(fba).max(1.0),
                "{bsdf:?} {a} {b}: {fab} vs {fba}"
            );
        }
    }
}

#[test]
fn sample_matches_eval_and_pdf() {
    let mut s = Sampler::new(5);
    for (bsdf, both_sides) in glossy_cases() {
        let mut found = 0;
        for _ in 0..20_000 {
            let mut wo = s.direction();
            if !both_sides {
                wo.z = wo.z.abs();
            }
            let Some(b) = bsdf.sample(wo, s.next2(), s.next()) else {
                continue;
            };
            found += 1;
            // From a grazing wo, Beckmann's sampling of all normals draws directions whose
            // half vector nearly cancels (eta' wi + wo ~ 0): ill-conditioned in f32, a rounding
            // of wi moves it by more than the tolerance.
            if wo.z.abs() < 0.01 {
                continue;
            }
            assert!(!b.delta);
            let (pdf, f) = (bsdf.pdf(wo, b.wi), bsdf.eval(wo, b.wi));
            assert!((b.pdf - pdf).abs() <= 1e-3 * pdf.max(1.0), "{bsdf:?} {wo}");
            assert!((b.f - f).abs().max_element() <= 1e-3 * f.max_element().max(1.0));
        }
        assert!(found > 15_000, "{bsdf:?}: {found}");
    }
}

/// Pearson's chi-square test of sampled directions (lobe choice random) against the pdf
/// integrated over cells of equal solid angle on the whole sphere; the critical value at
/// p = 1e-4 from the Wilson-Hilferty approximation.
#[test]
fn sampling_histogram_matches_pdf() {
    const SAMPLES: usize = 400_000;
    let mut cases: Vec<(Bsdf, Vec3)> = glossy_cases()
        .into_iter()
        .map(|(b, _)| (b, dir(0.8)))
        .collect();
    cases.push((rough_glass(1.5, 0.4, 0.4), -dir(0.5)));
    cases.push((plastic(Vec3::splat(0.5), 1.5, false), dir(0.8)));
    let grid = DirectionGrid {
        z_min: -1.0,
        nz: 24,
        nphi: 32,
        sub: 12,
    };
    for (bsdf, wo) in cases {
        let mut s = Sampler::new(6);
        let sample = || {
            (bsdf.sample(wo, s.next2(), s.next()))
                .filter(|b| !b.delta)
                .map(|b| b.wi)
        };
        grid.assert_follows_pdf(&format!("{bsdf:?}"), SAMPLES, sample, |wi| bsdf.pdf(wo, wi));
    }
}

/// A thin sheet keeps all energy (R' + T' = 1), reflects 2R / (1 + R) of it (R the single
/// interface's Fresnel reflectance: 0.04 at normal incidence for eta 1.5, so 0.0769), and
/// transmits straight through.
#[test]
fn thin_dielectric_interreflections() {
    let bsdf = thin(1.5);
    assert!(bsdf.is_delta());
    for theta in [0.0f32, 0.7, 1.3] {
        for wo in [dir(theta), -dir(theta)] {
            let r = fr_dielectric(wo.z.abs(), 1.5);
            let expected = 2.0 * r / (1.0 + r);
            let (total, _) = albedo(&bsdf, wo, 7, |_| 1.0);
            assert!((total - 1.0).abs() < 1e-5, "{total}");
            let (reflected, se) = albedo(&bsdf, wo, 8, |wi| f32::from(wi.z * wo.z > 0.0));
            assert!(
                (reflected - expected as f64).abs() < 5.0 * se + 1e-6,
                "{reflected} vs {expected}"
            );
            let t = bsdf.sample(wo, Vec2::ZERO, 0.999).unwrap();
            assert!(t.wi.distance(-wo) < 1e-6 && t.delta);
        }
    }
    let r0 = fr_dielectric(1.0, 1.5);
    assert!((r0 - 0.04).abs() < 1e-6);
}

/// Fdr, the coating's internal diffuse reflectance, obeys 1 - Fdr_int = (1 - Fdr_ext) / eta^2
/// (each an independent integral; the interface's reciprocity), and agrees with Egan and
/// Hilgeman's fit that Mitsuba uses (within 0.2% for eta in [1.3, 1.5]; 0.5% off at 1.1).
#[test]
fn internal_reflectance_of_the_coating() {
    for eta in [1.1f32, 1.33, 1.49, 1.5, 2.0] {
        let fdr_int = internal_reflectance(eta) as f64;
        let steps = 20_000;
        let fdr_ext: f64 = (0..steps)
            .map(|i| {
                let mu = (i as f64 + 0.5) / steps as f64;
                2.0 * fr_dielectric(mu as f32, eta) as f64 * mu / steps as f64
            })
            .sum();
        let via_ext = 1.0 - (1.0 - fdr_ext) / (eta * eta) as f64;
        assert!(
            (fdr_int - via_ext).abs() < 1e-4,
            "eta {eta}: {fdr_int} vs {via_ext}"
        );
        let n = eta as f64;
        let fit = -1.4399 / (n * n) + 0.7099 / n + 0.6681 + 0.0636 * n;
        if (1.3..=1.5).contains(&eta) {
            assert!(
                (fdr_int - fit).abs() < 2e-3 * fit,
                "eta {eta}: {fdr_int} vs fit {fit}"
            );
        }
    }
}

/// A white plastic (Kd = 1, linear) keeps all energy: the coating reflects F(cos_o), and the
/// base under it, summed over its interreflections, returns the rest, since
/// (1 - Fdr_ext) / (eta^2 (1 - Fdr_int)) = 1. With Kd = 0 only the coating's F(cos_o) is left.
#[test]
fn white_furnace_plastic() {
    for eta in [1.3f32, 1.5] {
        for theta in [0.0f32, 0.6, 1.2, 1.5] {
            let wo = dir(theta);
            let (a, se) = albedo(&plastic(Vec3::ONE, eta, false), wo, 9, |_| 1.0);
            assert!(
                (a - 1.0).abs() < 5.0 * se + 2e-3,
                "eta {eta} theta {theta}: {a}"
            );
            let (a, se) = albedo(&plastic(Vec3::ZERO, eta, false), wo, 10, |_| 1.0);
            let f = fr_dielectric(wo.z, eta) as f64;
            assert!((a - f).abs() < 5.0 * se + 1e-5, "coat {a} vs {f}");
        }
    }
    // Nonlinear: Kd / (1 - Fdr Kd) darkens a grey base against Kd / (1 - Fdr).
    let wo = dir(0.3);
    let (linear, _) = albedo(&plastic(Vec3::splat(0.5), 1.5, false), wo, 11, |_| 1.0);
    let (nonlinear, _) = albedo(&plastic(Vec3::splat(0.5), 1.5, true), wo, 11, |_| 1.0);
    assert!(nonlinear < linear - 0.05, "{nonlinear} vs {linear}");
}

/// A rough plastic of tiny alpha is the smooth plastic with the rough one's internal
/// reflectance (Mitsuba's 64-point mean, which lies within 2% of the integral); at alpha 0.2 a
/// white one stays within 1 and loses about a fifth to single scattering and the coarse
/// quadrature (Mitsuba 3.9's own `roughplastic` sampled at normal incidence: 0.795; foton 0.793).
#[test]
fn rough_plastic_tends_to_plastic_and_is_bounded() {
    let tables = CoatingTables::of(1e-3, 1.5);
    let exact = internal_reflectance(1.5);
    assert!((tables.internal_reflectance() - exact).abs() < 0.02 * exact);
    let smooth_bsdf = Bsdf::Plastic(Plastic {
        diffuse: Vec3::splat(0.5),
        specular: Vec3::ONE,
        eta: 1.5,
        internal_reflectance: tables.internal_reflectance(),
        nonlinear: false,
    });
    for theta in [0.0f32, 0.6, 1.2] {
        let wo = dir(theta);
        let (smooth, se_s) = albedo(&smooth_bsdf, wo, 12, |_| 1.0);
        let (rough, se_r) = albedo(&rough_plastic(Vec3::splat(0.5), 1.5, 1e-3), wo, 13, |_| 1.0);
        let tol = 5.0 * (se_s * se_s + se_r * se_r).sqrt() + 0.01 * smooth;
        assert!(
            (rough - smooth).abs() < tol,
            "theta {theta}: {rough} vs {smooth}"
        );
        let (white, se) = albedo(&rough_plastic(Vec3::ONE, 1.5, 0.2), wo, 14, |_| 1.0);
        assert!(
            white < 1.0 + 5.0 * se && white > 0.75,
            "white rough plastic, theta {theta}: {white}"
        );
    }
}

#[test]
fn outputs_are_finite_for_degenerate_inputs() {
    let values = [
        0.0f32,
        -1.0,
        1e-7,
        0.5,
        1.0,
        1.5,
        1e30,
        f32::NAN,
        f32::INFINITY,
    ];
    let mut bsdfs = Vec::new();
    for &a in &values {
        bsdfs.push(rough_glass(a, a, 0.2));
        bsdfs.push(rough_glass(1.5, a, a));
        bsdfs.push(thin(a));
        bsdfs.push(plastic(Vec3::splat(0.5), a, a > 1.0));
        bsdfs.push(rough_plastic(Vec3::splat(0.5), a, a));
    }
    let mut s = Sampler::new(15);
    let mut dirs = vec![
        Vec3::Z,
        -Vec3::Z,
        Vec3::X,
        Vec3::new(1.0, 0.0, 1e-7),
        Vec3::ZERO,
    ];
    dirs.extend((0..20).map(|_| s.direction()));
    for bsdf in &bsdfs {
        assert!(bsdf.albedo().is_finite(), "{bsdf:?}");
        for &wo in &dirs {
            let us: Vec<(Vec2, f32)> = (0..20).map(|_| (s.next2(), s.next())).collect();
            assert_finite_outputs(bsdf, wo, &dirs, &us);
        }
    }
}
