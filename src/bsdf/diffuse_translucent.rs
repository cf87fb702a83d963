//! Diffuse reflection plus diffuse transmission (LuxRender's `mattetranslucent`,
//! `materials/mattetranslucent.cpp`: a Lambertian lobe of `Kr` and, through `BRDFToBTDF`, a
//! Lambertian lobe of `Kt` mirrored to the other side of the surface):
//!
//!   f(wo, wi) = R / pi  when wo and wi are on the same side,  T / pi  otherwise.
//!
//! With `sigma` > 0 LuxRender makes both lobes Oren-Nayar (`OrenNayar(R, sigma)` and
//! `BRDFToBTDF(OrenNayar(T, sigma))`, which evaluates the reflection lobe at wi mirrored
//! through the surface): here each lobe is [`OrenNayar`] of its colour at wo and wi brought to
//! the same side, (A, B) = (1, 0) the Lambertian case. The A term keeps the albedo formula
//! below only for the Lambertian; the lobes stay symmetric in wo and wi, so f stays
//! reciprocal.
//!
//! Each lobe integrates, against |cos theta_i|, to its colour, so the albedo is R + T: energy is
//! conserved when R + T <= 1 (what LuxRender's `energyconserving` ensures, see the loader).
//! The lobes are symmetric in wo and wi, so f is reciprocal. Sampling picks a lobe with
//! probability proportional to its largest channel, then a cosine-weighted direction on that
//! lobe's side: pdf = P(lobe) |cos theta_i| / pi.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::BsdfSample;
use super::oren_nayar::OrenNayar;
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};

#[derive(Clone, Copy, Debug)]
pub struct DiffuseTranslucent {
    pub reflectance: Vec3,
    pub transmittance: Vec3,
    /// Oren-Nayar's A and B ([`super::oren_nayar::oren_nayar_ab`]); (1, 0) is Lambertian.
    pub a: f32,
    pub b: f32,
}

impl DiffuseTranslucent {
    /// The probability of sampling the reflection lobe.
    fn reflection_probability(&self) -> f32 {
        let (r, t) = (
            self.reflectance.max_element().max(0.0),
            self.transmittance.max_element().max(0.0),
        );
        if r + t > 0.0 { r / (r + t) } else { 0.0 }
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let side = wo.z * wi.z;
        let colour = if side > 0.0 {
            self.reflectance
        } else if side < 0.0 {
            self.transmittance
        } else {
            return Vec3::ZERO;
        };
        if self.b == 0.0 {
            return colour * (self.a * FRAC_1_PI);
        }
        let above = |w: Vec3| Vec3::new(w.x, w.y, w.z.abs());
        OrenNayar {
            reflectance: colour,
            a: self.a,
            b: self.b,
        }
        .eval(above(wo), above(wi))
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let side = wo.z * wi.z;
        let p_reflect = self.reflection_probability();
        let lobe = if side > 0.0 {
            p_reflect
        } else if side < 0.0 {
            1.0 - p_reflect
        } else {
            0.0
        };
        lobe * cosine_hemisphere_pdf(wi.z.abs())
    }

    /// `uc` chooses the lobe, `u` the direction in it.
    pub fn sample(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        if wo.z == 0.0
            || (self.reflectance.max_element() <= 0.0 && self.transmittance.max_element() <= 0.0)
        {
            return None;
        }
        let mut wi = cosine_hemisphere(u);
        // On wo's side for reflection, the other side for transmission.
        let reflect = uc < self.reflection_probability();
        if (wo.z > 0.0) != reflect {
            wi.z = -wi.z;
        }
        let pdf = self.pdf(wo, wi);
        (pdf > 0.0).then(|| BsdfSample {
            wi,
            f: self.eval(wo, wi),
            pdf,
            delta: false,
        })
    }

    /// The hemispherical albedo R + T.
    pub fn albedo(&self) -> Vec3 {
        self.reflectance + self.transmittance
    }
}
