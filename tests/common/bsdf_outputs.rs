//! Robustness of a BSDF on degenerate input: whatever the directions and sample coordinates,
//! its outputs stay finite and non-negative.

use foton::bsdf::Bsdf;
use glam::{Vec2, Vec3};

/// Asserts, for outgoing `wo`, that eval and pdf towards each of `dirs` are finite and
/// non-negative, and that each sample drawn with `us` has a finite unit `wi`, a finite
/// non-negative f and a finite positive pdf. Returns how many of the samples succeeded.
pub fn assert_finite_outputs(bsdf: &Bsdf, wo: Vec3, dirs: &[Vec3], us: &[(Vec2, f32)]) -> usize {
    for &wi in dirs {
        let (f, pdf) = (bsdf.eval(wo, wi), bsdf.pdf(wo, wi));
        assert!(
            f.is_finite() && f.min_element() >= 0.0,
            "{bsdf:?} {wo} {wi}: {f}"
        );
        assert!(pdf.is_finite() && pdf >= 0.0, "{bsdf:?} {wo} {wi}: {pdf}");
    }
    let mut count = 0;
    for &(u, uc) in us {
        if let Some(s) = bsdf.sample(wo, u, uc) {
            count += 1;
            assert!(
                s.wi.is_finite() && s.f.is_finite(),
                "{bsdf:?} {wo} {u}: {s:?}"
            );
            assert!(s.pdf.is_finite() && s.pdf > 0.0, "{bsdf:?} {wo} {u}: {s:?}");
            assert!(s.f.min_element() >= 0.0, "{bsdf:?} {wo} {u}: {s:?}");
            assert!((s.wi.length() - 1.0).abs() < 1e-4, "unit wi: {s:?}");
        }
    }
    count
}
