//! Oren-Nayar rough diffuse reflection (Oren and Nayar 1994, "Generalization of Lambert's
//! Reflectance Model"), the qualitative model of pbrt-v1 §9.3 that LuxRender's `matte` uses
//! when `sigma` > 0 (`materials/matte.cpp`, `core/reflection/bxdf/orennayar.cpp`):
//!
//!   f = R / pi (A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta)),
//!   A = 1 - sigma^2 / (2 (sigma^2 + 0.33)),  B = 0.45 sigma^2 / (sigma^2 + 0.09),
//!
//! with sigma the standard deviation of the facet slope angle in radians, alpha the larger and
//! beta the smaller of theta_i and theta_o. Symmetric in wi and wo; sampled like Lambertian.

use super::BsdfSample;
use super::lambertian::{cosine_lobe_pdf, sample_cosine_lobe};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug)]
pub struct OrenNayar {
    pub reflectance: Vec3,
    pub a: f32,
    pub b: f32,
}

/// (A, B) for a slope deviation of `sigma_degrees` (LuxRender's `sigma` is in degrees);
/// sigma = 0 gives (1, 0), the Lambertian.
pub fn oren_nayar_ab(sigma_degrees: f32) -> (f32, f32) {
    let s = sigma_degrees.to_radians();
    let s2 = if s.is_finite() { s * s } else { 0.0 };
    (1.0 - s2 / (2.0 * (s2 + 0.33)), 0.45 * s2 / (s2 + 0.09))
}

impl OrenNayar {
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let sin_i = (1.0 - wi.z * wi.z).max(0.0).sqrt();
        let sin_o = (1.0 - wo.z * wo.z).max(0.0).sqrt();
        // cos(phi_i - phi_o) = (wi_xy . wo_xy) / (sin_i sin_o).
        let max_cos = if sin_i > 1e-4 && sin_o > 1e-4 {
            ((wi.x * wo.x + wi.y * wo.y) / (sin_i * sin_o)).max(0.0)
        } else {
            0.0
        };
        // alpha = max(theta_i, theta_o): sin(alpha) is that of the smaller cosine; beta the
        // other, tan(beta) = sin / cos.
        let (sin_alpha, tan_beta) = if wi.z > wo.z {
            (sin_o, sin_i / wi.z)
        } else {
            (sin_i, sin_o / wo.z)
        };
        self.reflectance * (FRAC_1_PI * (self.a + self.b * max_cos * sin_alpha * tan_beta))
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        cosine_lobe_pdf(wo, wi)
    }

    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        sample_cosine_lobe(wo, u, |wi| self.eval(wo, wi))
    }
}
