//! Lambertian (ideal diffuse) reflection: f = R / pi on the upper hemisphere.

use super::BsdfSample;
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug)]
pub struct Lambertian {
    pub reflectance: Vec3,
}

impl Lambertian {
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z > 0.0 && wi.z > 0.0 {
            self.reflectance * FRAC_1_PI
        } else {
            Vec3::ZERO
        }
    }

    /// Cosine-weighted hemisphere sampling: pdf = cos(theta_i) / pi.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        cosine_lobe_pdf(wo, wi)
    }

    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        sample_cosine_lobe(wo, u, |wi| self.eval(wo, wi))
    }
}

/// The pdf of [`sample_cosine_lobe`]: cos(theta_i) / pi on the upper hemisphere, for `wo` above.
#[inline]
pub fn cosine_lobe_pdf(wo: Vec3, wi: Vec3) -> f32 {
    if wo.z > 0.0 && wi.z > 0.0 {
        cosine_hemisphere_pdf(wi.z)
    } else {
        0.0
    }
}

/// Samples a reflection lobe by the cosine (Lambert, Oren-Nayar); `eval` gives f(wo, wi).
#[inline]
pub fn sample_cosine_lobe(wo: Vec3, u: Vec2, eval: impl Fn(Vec3) -> Vec3) -> Option<BsdfSample> {
    if wo.z <= 0.0 {
        return None;
    }
    let wi = cosine_hemisphere(u);
    BsdfSample::glossy(wi, eval(wi), cosine_lobe_pdf(wo, wi))
}
