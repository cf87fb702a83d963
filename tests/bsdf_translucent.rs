//! The diffuse reflection + transmission BSDF (LuxRender's `mattetranslucent`): energy, its
//! sampling against its pdf and eval over the whole sphere, reciprocity.

use std::f32::consts::PI;

use foton::bsdf::oren_nayar::oren_nayar_ab;
use foton::bsdf::{Bsdf, DiffuseTranslucent};
use glam::{Vec2, Vec3};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

use crate::common::bsdf_estimates::uniform;
use crate::common::chi_square::DirectionGrid;

fn translucent(reflectance: Vec3, transmittance: Vec3) -> Bsdf {
    Bsdf::DiffuseTranslucent(DiffuseTranslucent {
        reflectance,
        transmittance,
        a: 1.0,
        b: 0.0,
    })
}

fn cases() -> [Bsdf; 3] {
    [
        translucent(Vec3::new(0.3, 0.5, 0.1), Vec3::new(0.6, 0.2, 0.9)),
        translucent(Vec3::splat(0.8), Vec3::ZERO),
        translucent(Vec3::ZERO, Vec3::new(0.2, 0.4, 0.6)),
    ]
}

fn wo(theta: f32) -> Vec3 {
    Vec3::new(theta.sin(), 0.0, theta.cos())
}

/// The directional albedo by importance sampling is R + T (each Lambertian lobe integrates
/// to its colour), for wo on either side; with R + T = 1 (a white furnace) it is 1. Each
/// sample's weight f |cos| / pdf is bounded by max(R) + max(T), so the standard error of the
/// mean of N = 100k is below 1 / sqrt(N) = 0.003: the bound is 5 of those.
#[test]
fn albedo_is_r_plus_t() {
    const N: usize = 100_000;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
    let furnace = translucent(Vec3::splat(0.35), Vec3::splat(0.65));
    for bsdf in cases().into_iter().chain([furnace]) {
        let Bsdf::DiffuseTranslucent(d) = bsdf else {
            unreachable!()
        };
        for theta in [0.1f32, 1.0, 1.5, 2.5] {
            let mut sum = Vec3::ZERO;
            for _ in 0..N {
                let u = Vec2::new(uniform(&mut rng), uniform(&mut rng));
                if let Some(s) = bsdf.sample(wo(theta), u, uniform(&mut rng)) {
                    sum += s.f * s.wi.z.abs() / s.pdf;
                }
            }
            let albedo = sum / N as f32;
            let expected = d.reflectance + d.transmittance;
            assert!(
                (albedo - expected).abs().max_element() < 0.015,
                "{bsdf:?} theta {theta}: {albedo} vs {expected}"
            );
            assert!((bsdf.albedo() - expected).abs().max_element() < 1e-6);
        }
    }
}

/// The cases and one with Oren-Nayar lobes (LuxRender's `sigma`, here 30 degrees).
fn cases_with_rough_lobes() -> Vec<Bsdf> {
    let (a, b) = oren_nayar_ab(30.0);
    let mut all = cases().to_vec();
    all.push(Bsdf::DiffuseTranslucent(DiffuseTranslucent {
        reflectance: Vec3::new(0.3, 0.5, 0.1),
        transmittance: Vec3::new(0.6, 0.2, 0.9),
        a,
        b,
    }));
    all
}

/// Sampled values agree with eval and pdf; f is reciprocal (with Oren-Nayar lobes too).
#[test]
fn sample_matches_eval_pdf_and_is_reciprocal() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(2);
    for bsdf in cases_with_rough_lobes() {
        for _ in 0..20_000 {
            let w = wo(uniform(&mut rng) * PI);
            let u = Vec2::new(uniform(&mut rng), uniform(&mut rng));
            let Some(s) = bsdf.sample(w, u, uniform(&mut rng)) else {
                continue;
            };
            assert!((s.pdf - bsdf.pdf(w, s.wi)).abs() <= 1e-4 * s.pdf.max(1.0));
            assert!((s.f - bsdf.eval(w, s.wi)).abs().max_element() <= 1e-6);
            assert!(
                (bsdf.eval(w, s.wi) - bsdf.eval(s.wi, w))
                    .abs()
                    .max_element()
                    <= 1e-6
            );
        }
    }
}

/// Pearson's chi-square of sampled directions against the pdf over the whole sphere
/// (`DirectionGrid`: cells of equal solid angle, p = 1e-4).
#[test]
fn sampling_histogram_matches_pdf_over_the_sphere() {
    let grid = DirectionGrid {
        z_min: -1.0,
        nz: 20,
        nphi: 16,
        sub: 16,
    };
    for bsdf in cases_with_rough_lobes() {
        let w = wo(0.8);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let sample = || {
            let u = Vec2::new(uniform(&mut rng), uniform(&mut rng));
            bsdf.sample(w, u, uniform(&mut rng)).map(|s| s.wi)
        };
        grid.assert_follows_pdf(&format!("{bsdf:?}"), 400_000, sample, |d| bsdf.pdf(w, d));
    }
}
