//! Rough conductor: the Cook-Torrance microfacet BRDF (Cook and Torrance 1982,
//! "A Reflectance Model for Computer Graphics"; in the form of Walter et al.
//! 2007, eq. 20):
//!
//!   f(wo, wi) = D(wh) G(wo, wi) F(wo . wh) / (4 |cos theta_o| |cos theta_i|)
//!
//! with wh = normalize(wo + wi), D the GGX or Beckmann distribution, G Smith's term
//! (height-correlated for LuxRender's metals, separable as Mitsuba 3's `roughconductor`; see
//! `microfacet_distribution.rs`), and F either Schlick's approximation with F0 = Kr, the
//! colour the scene gives (LuxRender's metal2 takes a Fresnel texture; the course's scenes give
//! a colour), or the exact conductor Fresnel of a complex index (LuxRender's `metal`, Mitsuba's
//! conductors), times a `reflectance` factor (Mitsuba's `specular_reflectance`).
//! Sampling draws visible normals for GGX (Heitz 2018), so the estimator weight
//! f |cos theta_i| / pdf = F G / G1(wo); all normals for Beckmann.

use super::BsdfSample;
use super::fresnel::{fr_conductor, schlick};
use super::microfacet_distribution::{Masking, Microfacet};
use crate::math::try_normalize;
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct RoughConductor {
    /// A factor on the whole lobe (1 for a physical conductor).
    pub reflectance: Vec3,
    pub fresnel: ConductorFresnel,
    pub distribution: Microfacet,
    pub masking: Masking,
}

/// A conductor's reflectance against the angle to the microfacet normal.
#[derive(Clone, Copy, Debug)]
pub enum ConductorFresnel {
    /// Schlick's approximation from the reflectance at normal incidence.
    Schlick(Vec3),
    /// The complex index eta + i k, per channel.
    Complex { eta: Vec3, k: Vec3 },
}

impl ConductorFresnel {
    pub fn eval(&self, cos: f32) -> Vec3 {
        match *self {
            ConductorFresnel::Schlick(f0) => schlick(f0, cos),
            ConductorFresnel::Complex { eta, k } => fr_conductor(cos, eta, k),
        }
    }
}

/// The half vector, if wo and wi are both in the upper hemisphere.
fn half_vector(wo: Vec3, wi: Vec3) -> Option<Vec3> {
    if wo.z > 0.0 && wi.z > 0.0 {
        try_normalize(wo + wi)
    } else {
        None
    }
}

impl RoughConductor {
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        self.eval_and_pdf(wo, wi).0
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.eval_and_pdf(wo, wi).1
    }

    /// f(wo, wi) and the density with which [`RoughConductor::sample`] returns `wi`, sharing the
    /// half vector, D(wh) and Smith's term for `wo` ([`Microfacet::d_g_pdf_wm`]). The density
    /// is that of the sampled normals mapped through reflection, whose Jacobian is
    /// d(wh)/d(wi) = 1 / (4 |wo . wh|) (Walter et al. 2007, eq. 14).
    pub fn eval_and_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let Some(wh) = half_vector(wo, wi) else {
            return (Vec3::ZERO, 0.0);
        };
        let (d, g, pdf_wm) = self.distribution.d_g_pdf_wm(wo, wi, wh, self.masking);
        let cos_oh = wo.dot(wh);
        let denom = 4.0 * wo.z * wi.z;
        let f = if denom <= 0.0 {
            Vec3::ZERO
        } else {
            self.reflectance * self.fresnel.eval(cos_oh) * (d * g / denom)
        };
        let pdf = if cos_oh <= 0.0 {
            0.0
        } else {
            pdf_wm / (4.0 * cos_oh)
        };
        (f, pdf)
    }

    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wh = self.distribution.sample_wm(wo, u);
        // Reflect wo about the sampled microfacet normal.
        let wi = 2.0 * wo.dot(wh) * wh - wo;
        let (f, pdf) = self.eval_and_pdf(wo, wi);
        BsdfSample::glossy(wi, f, pdf)
    }
}
