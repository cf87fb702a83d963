//! Smooth plastic (Mitsuba 3's `plastic`, `src/bsdfs/plastic.cpp`; Weidlich and Wilkie 2007,
//! "Arbitrarily Layered Micro-Facet Surfaces"): a diffuse base of reflectance Kd under a
//! smooth dielectric coating of relative index eta (coating over outside).
//!
//! Light meets the coating first: a share F(cos_o) is reflected as by a mirror (times Ks), the
//! rest enters, is scattered by the base, and bounces between base and coating; of the
//! diffuse light reaching the coating from inside, the share Fdr_int (the coating's internal
//! reflectance averaged over the cosine-weighted hemisphere, [`internal_reflectance`]) goes
//! back down. Summing the bounces, Kd (1 + Fdr Kd + (Fdr Kd)^2 + ...) = Kd / (1 - Fdr Kd);
//! Mitsuba uses this (`nonlinear`) or, by default, Kd / (1 - Fdr), which keeps the colour of
//! a texture unchanged. Radiance crossing into the coating and back is scaled by 1 / eta^2
//! (the solid angle spreads on the way out), and each crossing passes 1 - F, so
//!
//!   f(wo, wi) = Kd' (1 - F(cos_o)) (1 - F(cos_i)) / (pi eta^2)   (+ the specular delta lobe)
//!
//! with Kd' the summed base. Sampling picks the mirror lobe with probability proportional to
//! F(cos_o) Ks_mean and the diffuse one to (1 - F(cos_o)) (1 - Ks_mean) as Mitsuba does (its
//! weights use the texture means; foton uses the colours at the hit), then a cosine lobe.

use super::BsdfSample;
use super::dielectric::clamp_eta;
use super::fresnel::fr_dielectric;
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug)]
pub struct Plastic {
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// Coating index over outside index.
    pub eta: f32,
    /// [`internal_reflectance`] of `eta`, computed once per material.
    pub internal_reflectance: f32,
    /// Kd / (1 - Fdr Kd) (true) or Kd / (1 - Fdr) (false).
    pub nonlinear: bool,
}

/// The share of light diffusely incident on the coating from inside that it reflects back:
/// Fdr = integral over the hemisphere of F(cos) cos / pi = 2 integral_0^1 F(mu) mu dmu, with F
/// seen from inside (relative index 1 / eta). Midpoint rule, 4096 steps (Mitsuba fits the same
/// integral: `fresnel_diffuse_reflectance(1 / eta)`, Egan and Hilgeman 1973, within 0.1%).
pub fn internal_reflectance(eta: f32) -> f32 {
    const STEPS: usize = 4096;
    let eta = clamp_eta(eta);
    let h = 1.0 / STEPS as f64;
    let sum: f64 = (0..STEPS)
        .map(|i| {
            let mu = (i as f64 + 0.5) * h;
            2.0 * fr_dielectric(mu as f32, 1.0 / eta) as f64 * mu * h
        })
        .sum();
    sum as f32
}

/// The base's reflectance with its interreflections under the coating (see the module doc).
pub fn summed_base(diffuse: Vec3, internal_reflectance: f32, nonlinear: bool) -> Vec3 {
    let back = if nonlinear {
        diffuse * internal_reflectance
    } else {
        Vec3::splat(internal_reflectance)
    };
    diffuse / (Vec3::ONE - back)
}

/// The probability of sampling the specular lobe when the coating reflects `reflected` of the
/// light: Mitsuba's `prob_specular`, with weight Ks_mean / (Kd_mean + Ks_mean).
pub fn specular_probability(diffuse: Vec3, specular: Vec3, reflected: f32) -> f32 {
    let (d, s) = (mean(diffuse), mean(specular));
    let weight = if d + s > 0.0 { s / (d + s) } else { 0.5 };
    let p_specular = reflected * weight;
    let p_diffuse = (1.0 - reflected) * (1.0 - weight);
    if p_specular + p_diffuse > 0.0 {
        p_specular / (p_specular + p_diffuse)
    } else {
        0.0
    }
}

fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

impl Plastic {
    fn eta(&self) -> f32 {
        clamp_eta(self.eta)
    }

    fn fresnel(&self, cos: f32) -> f32 {
        fr_dielectric(cos, self.eta())
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let base = summed_base(self.diffuse, self.internal_reflectance, self.nonlinear);
        let crossings = (1.0 - self.fresnel(wo.z)) * (1.0 - self.fresnel(wi.z));
        base * (crossings * FRAC_1_PI / (self.eta() * self.eta()))
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let p_specular = specular_probability(self.diffuse, self.specular, self.fresnel(wo.z));
        (1.0 - p_specular) * cosine_hemisphere_pdf(wi.z)
    }

    pub fn sample(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let f = self.fresnel(wo.z);
        let p_specular = specular_probability(self.diffuse, self.specular, f);
        if uc < p_specular {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return Some(BsdfSample {
                wi,
                f: self.specular * (f / wi.z),
                pdf: p_specular,
                delta: true,
            });
        }
        let wi = cosine_hemisphere(u);
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// The coating's reflectance at normal incidence, and the base through the rest.
    pub fn albedo(&self) -> Vec3 {
        let f = self.fresnel(1.0);
        self.specular * f + self.diffuse * (1.0 - f)
    }
}
