//! Rough dielectric interface: microfacet reflection and refraction (Walter et al. 2007,
//! "Microfacet Models for Refraction through Rough Surfaces"), as Mitsuba 3's
//! `roughdielectric` (`src/bsdfs/roughdielectric.cpp`) and pbrt-v4's `DielectricBxDF` (§9.7)
//! define it, with the GGX distribution and visible-normal sampling (Heitz 2018), or Beckmann's
//! sampled over all normals (`beckmann.rs`).
//!
//! With wo the direction towards the viewer, wi the one towards the light, and eta' the index
//! of wi's side over wo's (1 for reflection), the generalised half vector is
//! wm = ±normalize(eta' wi + wo) (Walter eq. 16, oriented to +z). Then
//!
//!   reflection:   f = Kr D(wm) G F(wo . wm) / (4 |cos_o cos_i|)                   (eq. 20)
//!   transmission: f = Kt D(wm) G (1 - F) |wi . wm| |wo . wm|
//!                     / (|cos_o cos_i| (wi . wm + wo . wm / eta')^2) / eta'^2       (eq. 21)
//!
//! where the last 1 / eta'^2 is radiance transport (pbrt-v4 §9.5.2; importance transport
//! drops it). G is Smith's separable G1(wo) G1(wi) (Walter eq. 23), as Mitsuba uses it (pbrt-v4
//! uses the height-correlated form). Sampling draws wm from the normals visible from wo (wo
//! flipped to the upper hemisphere), then reflects with probability F, else refracts; the
//! density is D_wo(wm) times the Jacobian of wm -> wi: 1 / (4 |wo . wm|) for reflection
//! (eq. 14), |wi . wm| / (wi . wm + wo . wm / eta')^2 for refraction (eq. 17).
//! Microfacets seen from behind by either direction contribute nothing.

use super::BsdfSample;
use super::dielectric::{blend_by_normal_fresnel, clamp_eta, refract};
use super::fresnel::fr_dielectric;
use super::microfacet_distribution::{Masking, Microfacet};
use crate::math::try_normalize;
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct RoughDielectric {
    pub reflectance: Vec3,
    pub transmittance: Vec3,
    /// Index inside / index outside; the normal (+z) points outside.
    pub eta: f32,
    pub distribution: Microfacet,
}

/// The geometry of a pair of directions: the oriented half vector, eta', and whether wi is
/// reflected (on wo's side).
struct HalfVector {
    wm: Vec3,
    etap: f32,
    reflect: bool,
}

impl RoughDielectric {
    fn eta(&self) -> f32 {
        clamp_eta(self.eta)
    }

    /// The half vector of (wo, wi), None where it is undefined or a direction sees the
    /// microfacet from behind.
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<HalfVector> {
        if wo.z == 0.0 || wi.z == 0.0 {
            return None;
        }
        let reflect = wo.z * wi.z > 0.0;
        let etap = match (reflect, wo.z > 0.0) {
            (true, _) => 1.0,
            (false, true) => self.eta(),
            (false, false) => 1.0 / self.eta(),
        };
        let wm = try_normalize(wi * etap + wo)?;
        let wm = if wm.z < 0.0 { -wm } else { wm };
        if wm.dot(wi) * wi.z <= 0.0 || wm.dot(wo) * wo.z <= 0.0 {
            return None;
        }
        Some(HalfVector { wm, etap, reflect })
    }

    /// Smith's separable masking-shadowing G1(wo) G1(wi).
    fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.distribution.g(wo, wi, Masking::Separable)
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let Some(HalfVector { wm, etap, reflect }) = self.half_vector(wo, wi) else {
            return Vec3::ZERO;
        };
        let f = fr_dielectric(wo.dot(wm), self.eta());
        let dg = self.distribution.d(wm) * self.g(wo, wi);
        let cos = (wo.z * wi.z).abs();
        if reflect {
            self.reflectance * (dg * f / (4.0 * cos))
        } else {
            let (cos_im, cos_om) = (wi.dot(wm), wo.dot(wm));
            let denom = (cos_im + cos_om / etap).powi(2) * cos;
            self.transmittance * (dg * (1.0 - f) * (cos_im * cos_om).abs() / denom / (etap * etap))
        }
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some(HalfVector { wm, etap, reflect }) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let f = fr_dielectric(wo.dot(wm), self.eta());
        let wo_up = wo * wo.z.signum();
        let visible = self.distribution.pdf_wm(wo_up, wm);
        if reflect {
            visible / (4.0 * wo.dot(wm).abs()) * f
        } else {
            let cos_im = wi.dot(wm);
            let denom = (cos_im + wo.dot(wm) / etap).powi(2);
            visible * cos_im.abs() / denom * (1.0 - f)
        }
    }

    pub fn sample(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let wm = self.distribution.sample_wm(wo * wo.z.signum(), u);
        let f = fr_dielectric(wo.dot(wm), self.eta());
        let wi = if uc < f {
            let wi = 2.0 * wo.dot(wm) * wm - wo;
            (wi.z * wo.z > 0.0).then_some(wi)?
        } else {
            let (wi, _) = refract(wo, wm, self.eta())?;
            (wi.z * wo.z < 0.0).then_some(wi)?
        };
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// Kr and Kt blended by the Fresnel reflectance at normal incidence, as for smooth glass.
    pub fn albedo(&self) -> Vec3 {
        blend_by_normal_fresnel(self.reflectance, self.transmittance, self.eta())
    }
}
