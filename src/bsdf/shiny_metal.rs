//! LuxRender's `shinymetal` (`materials/shinymetal.cpp`, pbrt-v1 heritage): the sum of a mirror
//! and a glossy microfacet lobe, each weighted by pbrt-v1's approximate conductor Fresnel term.
//!
//! Each lobe's Fresnel term is `FresnelConductor(FresnelApproxEta(R), k = 0)`: the index
//! eta = (1 + sqrt(R)) / (1 - sqrt(R)) whose normal-incidence reflectance ((eta - 1) /
//! (eta + 1))^2 is R (clamped to [0, 0.999] so that eta stays finite), in pbrt-v1's conductor
//! formula ([`fr_conductor_approx`]), with R = `Kr` for the mirror and R = `Ks` for the glossy
//! lobe. The glossy lobe is pbrt-v1's Torrance-Sparrow `Microfacet`:
//!
//!   f = F(wi . h) D(h) G(wo, wi) / (4 cos_o cos_i),
//!   G = min(1, 2 cos_h cos_o / (wo . h), 2 cos_h cos_i / (wo . h)),
//!
//! with Blinn's distribution of exponent e = 1 / roughness (`Blinn(1 / u)`) or, for
//! `uroughness` != `vroughness`, Ashikhmin and Shirley's anisotropic one
//! (`Anisotropic(1 / u, 1 / v)`); Blinn is its case e_x = e_y:
//!
//!   D(h) = sqrt((e_x + 2)(e_y + 2)) / (2 pi) cos_h^(e_x cos^2 phi + e_y sin^2 phi).
//!
//! Sampling picks either lobe with probability 1/2 (LuxRender's BSDF picks a component
//! uniformly); the glossy one draws h with density sqrt((e_x + 1)(e_y + 1)) / (2 pi)
//! cos_h^e(phi) (pbrt-v1 `Anisotropic::Sample_f`, quadrant by quadrant) and reflects wo about it
//! (Jacobian 1 / (4 wo . h), Walter et al. 2007, eq. 14).
//!
//! Both lobes can reflect up to their R, so with LuxRender's defaults (`Ks` = `Kr` = 1) the
//! albedo approaches 2: LuxRender's material is not energy conserving, and foton keeps it so.

use std::f32::consts::{FRAC_PI_2, PI};

use glam::{Vec2, Vec3};

use super::BsdfSample;
use super::fresnel::{approx_eta, fr_conductor_approx};

#[derive(Clone, Copy, Debug)]
pub struct ShinyMetal {
    /// Normal-incidence reflectance of the glossy lobe (`Ks`).
    pub glossy: Vec3,
    /// Normal-incidence reflectance of the mirror lobe (`Kr`).
    pub mirror: Vec3,
    /// Blinn exponents along the local x and y axes (1 / roughness).
    pub exponent_x: f32,
    pub exponent_y: f32,
}

/// Exponents beyond this make cos^e underflow everywhere but at the pole: a mirror in effect.
const EXPONENT_MAX: f32 = 1e5;

/// The probability of each lobe.
const LOBE_PROBABILITY: f32 = 0.5;

impl ShinyMetal {
    fn exponents(&self) -> (f32, f32) {
        let clamp = |e: f32| {
            if e >= 0.0 {
                e.min(EXPONENT_MAX)
            } else {
                0.0
            }
        };
        (clamp(self.exponent_x), clamp(self.exponent_y))
    }

    /// The exponent e(phi) of a half vector: e_x cos^2 phi + e_y sin^2 phi.
    fn exponent_at(&self, h: Vec3) -> f32 {
        let (ex, ey) = self.exponents();
        let sin2 = h.x * h.x + h.y * h.y;
        if sin2 > 0.0 {
            (ex * h.x * h.x + ey * h.y * h.y) / sin2
        } else {
            ex
        }
    }

    fn d(&self, h: Vec3) -> f32 {
        let (ex, ey) = self.exponents();
        ((ex + 2.0) * (ey + 2.0)).sqrt() / (2.0 * PI) * h.z.powf(self.exponent_at(h))
    }

    /// The density of the sampled half vector per solid angle.
    fn pdf_h(&self, h: Vec3) -> f32 {
        let (ex, ey) = self.exponents();
        ((ex + 1.0) * (ey + 1.0)).sqrt() / (2.0 * PI) * h.z.powf(self.exponent_at(h))
    }

    fn fresnel(reflectance: Vec3, cos: f32) -> Vec3 {
        let eta = approx_eta(reflectance);
        Vec3::new(
            fr_conductor_approx(cos, eta.x),
            fr_conductor_approx(cos, eta.y),
            fr_conductor_approx(cos, eta.z),
        )
    }

    /// The glossy lobe (the mirror is a delta, not part of eval).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let Some(h) = (wo + wi).try_normalize() else {
            return Vec3::ZERO;
        };
        let cos_oh = wo.dot(h);
        if cos_oh <= 0.0 {
            return Vec3::ZERO;
        }
        let g = (2.0 * h.z * wo.z.min(wi.z) / cos_oh).min(1.0);
        Self::fresnel(self.glossy, wi.dot(h)) * (self.d(h) * g / (4.0 * wo.z * wi.z))
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let Some(h) = (wo + wi).try_normalize() else {
            return 0.0;
        };
        let cos_oh = wo.dot(h);
        if cos_oh <= 0.0 {
            return 0.0;
        }
        (1.0 - LOBE_PROBABILITY) * self.pdf_h(h) / (4.0 * cos_oh)
    }

    /// A half vector in the first quadrant of azimuth (pbrt-v1 `sampleFirstQuadrant`): phi with
    /// tan phi = sqrt((e_x + 1) / (e_y + 1)) tan(pi u1 / 2), then cos_h = u2^(1 / (e(phi) + 1)).
    fn sample_first_quadrant(&self, u1: f32, u2: f32) -> (f32, f32) {
        let (ex, ey) = self.exponents();
        let phi = if ex == ey {
            FRAC_PI_2 * u1
        } else {
            (((ex + 1.0) / (ey + 1.0)).sqrt() * (FRAC_PI_2 * u1).tan()).atan()
        };
        let (sin_phi, cos_phi) = phi.sin_cos();
        let e = ex * cos_phi * cos_phi + ey * sin_phi * sin_phi;
        (phi, u2.powf(1.0 / (e + 1.0)))
    }

    /// `uc` picks the lobe: the mirror below 1/2.
    pub fn sample(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        if uc < LOBE_PROBABILITY {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return Some(BsdfSample {
                wi,
                f: Self::fresnel(self.mirror, wo.z) / (LOBE_PROBABILITY * wi.z),
                pdf: LOBE_PROBABILITY,
                delta: true,
            });
        }
        // The four quadrants of azimuth, each mirrored from the first.
        let (phi, cos_h) = match (4.0 * u.x) as u32 {
            0 => self.sample_first_quadrant(4.0 * u.x, u.y),
            1 => {
                let (phi, c) = self.sample_first_quadrant(4.0 * (0.5 - u.x), u.y);
                (PI - phi, c)
            }
            2 => {
                let (phi, c) = self.sample_first_quadrant(4.0 * (u.x - 0.5), u.y);
                (PI + phi, c)
            }
            _ => {
                let (phi, c) = self.sample_first_quadrant(4.0 * (1.0 - u.x), u.y);
                (2.0 * PI - phi, c)
            }
        };
        let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
        let h = Vec3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
        let wi = 2.0 * wo.dot(h) * h - wo;
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// Both lobes at normal incidence.
    pub fn albedo(&self) -> Vec3 {
        (Self::fresnel(self.mirror, 1.0) + Self::fresnel(self.glossy, 1.0)).min(Vec3::ONE)
    }
}
