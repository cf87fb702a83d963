//! Checks of a BSDF's sampling against its eval and pdf: one sample's consistency and
//! reciprocity, the directional albedo by importance sampling and by quadrature.

use std::f32::consts::PI;

use foton::bsdf::{Bsdf, BsdfSample};

use super::chi_square::DirectionGrid;
use glam::{Vec2, Vec3};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::{Rng, SeedableRng};

/// A uniform number in [0, 1) from the top 24 bits.
pub fn uniform(r: &mut Xoshiro256PlusPlus) -> f32 {
    (r.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// A (non-delta) sample's f and pdf are eval's and pdf's towards its wi, and f(wo, wi) =
/// f(wi, wo). The dispatch renormalises wi: at grazing angles the half vector of the sharpest
/// lobes then moves by enough rounding for a relative 1e-4 in Z, hence the 1e-3 tolerances.
pub fn assert_sample_matches_eval_and_is_reciprocal(bsdf: &Bsdf, wo: Vec3, s: &BsdfSample) {
    let (f, pdf) = (bsdf.eval(wo, s.wi), bsdf.pdf(wo, s.wi));
    assert!(
        (s.pdf - pdf).abs() <= 1e-3 * pdf.max(1.0),
        "{bsdf:?}: {s:?} {pdf}"
    );
    assert!((s.f - f).abs().max_element() <= 1e-3 * f.max_element().max(1.0));
    let back = bsdf.eval(s.wi, wo);
    assert!(
        (f - back).abs().max_element() <= 1e-4 * f.max_element().max(1e-3),
        "{bsdf:?} {wo} {}: {f} vs {back}",
        s.wi
    );
}

/// The integral of f |cos_i| over the directions with z in [`z_min`, 1], by the midpoint rule
/// in (cos_i, phi), where dω = d cos dφ (600 bands of z per unit of z).
pub fn quadrature(bsdf: &Bsdf, w: Vec3, z_min: f32) -> Vec3 {
    let (nz, nphi) = ((600.0 * (1.0 - z_min)) as usize, 1200);
    let dz = (1.0 - z_min) / nz as f32;
    let mut sum = Vec3::ZERO;
    for iz in 0..nz {
        let z = z_min + (iz as f32 + 0.5) * dz;
        let r = (1.0 - z * z).sqrt();
        for ip in 0..nphi {
            let phi = 2.0 * PI * (ip as f32 + 0.5) / nphi as f32;
            let wi = Vec3::new(r * phi.cos(), r * phi.sin(), z);
            sum += bsdf.eval(w, wi) * z.abs();
        }
    }
    sum * (2.0 * PI * dz / nphi as f32)
}

/// The directional albedo, the mean of f |cos| / pdf over 200,000 samples, and its standard
/// error.
pub fn sampled_albedo(bsdf: &Bsdf, w: Vec3, seed: u64) -> (Vec3, Vec3) {
    const N: usize = 200_000;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let (mut sum, mut sum2) = (Vec3::ZERO, Vec3::ZERO);
    for _ in 0..N {
        let u = Vec2::new(uniform(&mut rng), uniform(&mut rng));
        if let Some(s) = bsdf.sample(w, u, uniform(&mut rng)) {
            let x = s.f * s.wi.z.abs() / s.pdf;
            sum += x;
            sum2 += x * x;
        }
    }
    let mean = sum / N as f32;
    let variance = (sum2 / N as f32 - mean * mean).max(Vec3::ZERO);
    (mean, (variance / N as f32).powf(0.5))
}

/// The outgoing direction of polar angle `theta` the BSDF tests use (azimuth atan(4 / 3), off
/// the frame's axes).
pub fn outgoing(theta: f32) -> Vec3 {
    Vec3::new(theta.sin() * 0.6, theta.sin() * 0.8, theta.cos())
}

/// 20,000 samples at outgoing directions of polar angle uniform in [0, `max_theta`): every
/// non-delta one is consistent with eval and pdf and reciprocal
/// ([`assert_sample_matches_eval_and_is_reciprocal`]), and there are more than `min_samples`.
pub fn assert_samples_match_eval(bsdf: &Bsdf, max_theta: f32, seed: u64, min_samples: usize) {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut count = 0;
    for _ in 0..20_000 {
        let w = outgoing(uniform(&mut rng) * max_theta);
        let u = Vec2::new(uniform(&mut rng), uniform(&mut rng));
        let Some(s) = bsdf.sample(w, u, uniform(&mut rng)) else {
            continue;
        };
        if s.delta {
            continue;
        }
        count += 1;
        assert_sample_matches_eval_and_is_reciprocal(bsdf, w, &s);
    }
    assert!(count > min_samples, "{bsdf:?}: {count} non-delta samples");
}

/// Pearson's chi-square of 400,000 sampled (non-delta) directions for `wo` against the pdf over
/// the sphere (`DirectionGrid`: 24 x 24 cells of equal solid angle, p = 1e-4).
pub fn assert_sampling_follows_pdf(bsdf: &Bsdf, wo: Vec3, seed: u64, label: &str) {
    let grid = DirectionGrid {
        z_min: -1.0,
        nz: 24,
        nphi: 24,
        sub: 16,
    };
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let sample = || {
        let u = Vec2::new(uniform(&mut rng), uniform(&mut rng));
        bsdf.sample(wo, u, uniform(&mut rng))
            .filter(|s| !s.delta)
            .map(|s| s.wi)
    };
    grid.assert_follows_pdf(label, 400_000, sample, |d| bsdf.pdf(wo, d));
}
