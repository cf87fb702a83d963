//! Lafortune et al.'s generalized cosine lobes (1997, "Non-Linear Approximation of Reflectance
//! Functions"), the BRDF of LuxRender 0.x's measured materials `primer`, `felt`, `clay`,
//! `bluepaint` and `skin` (pbrt-v1's `Lafortune`, `core/reflection.cpp`):
//!
//!   f = R / pi + sum_k max(0, Cxy_k (wo.x wi.x + wo.y wi.y) + Cz_k wo.z wi.z)^n_k,
//!
//! per colour channel, with the fitted coefficients of [`LafortuneFit`] (x and y share one
//! coefficient in every LuxRender fit: isotropic lobes). A negative Cxy near -1 with Cz near 1
//! makes a lobe about the mirror direction, a positive Cxy one about the retro-reflection,
//! Cz < 0 with Cxy < 0 one towards grazing angles. f is symmetric in wo and wi.
//!
//! Sampling follows LuxRender's choice of lobe and shape, with the density the samples have:
//! the cosine or one lobe, each with probability 1 / (lobes + 1); a lobe's direction is drawn
//! about its axis a = normalize(Cxy wo.x, Cxy wo.y, Cz wo.z) (coefficients and exponents taken
//! at their luminance) with the density (m + 1) / (2 pi) (a . wi)^m of the cosine power
//! m = 0.8 n (LuxRender's `.8f * exponent`: a little wider than the lobe). Directions below
//! the surface are rejected, so a lobe whose axis points down is never sampled from (f there
//! is still reached through the cosine).

use std::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

use super::BsdfSample;
use super::frame::Frame;
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};

/// One generalized cosine lobe: its coefficients (RGB) and exponent (RGB).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LafortuneLobe {
    pub xy: Vec3,
    pub z: Vec3,
    pub exponent: Vec3,
}

/// A measured BRDF: the diffuse albedo R and three lobes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LafortuneFit {
    pub diffuse: Vec3,
    pub lobes: [LafortuneLobe; 3],
}

/// The Y of linear RGB with pbrt-v1's weights (`Spectrum::y()`), by which LuxRender samples.
fn luminance(c: Vec3) -> f32 {
    0.212671 * c.x + 0.715160 * c.y + 0.072169 * c.z
}

/// LuxRender's widening of a lobe's exponent for sampling.
const SAMPLING_EXPONENT_SCALE: f32 = 0.8;

impl LafortuneLobe {
    /// The lobe's value, each channel's base raised to its exponent where the base is positive
    /// (`SWCSpectrum::Pow`: 0 elsewhere).
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let base = self.xy * (wo.x * wi.x + wo.y * wi.y) + self.z * (wo.z * wi.z);
        let pow = |b: f32, e: f32| if b > 0.0 { b.powf(e) } else { 0.0 };
        Vec3::new(
            pow(base.x, self.exponent.x),
            pow(base.y, self.exponent.y),
            pow(base.z, self.exponent.z),
        )
    }

    /// The sampling axis for `wo` and the cosine power m; None where the axis vanishes.
    fn sampling_lobe(&self, wo: Vec3) -> Option<(Vec3, f32)> {
        let (xy, z) = (luminance(self.xy), luminance(self.z));
        let axis = Vec3::new(xy * wo.x, xy * wo.y, z * wo.z).try_normalize()?;
        Some((axis, SAMPLING_EXPONENT_SCALE * luminance(self.exponent)))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some((axis, m)) = self.sampling_lobe(wo) else {
            return 0.0;
        };
        let cos = axis.dot(wi);
        if cos <= 0.0 {
            return 0.0;
        }
        (m + 1.0) * 0.5 * FRAC_1_PI * cos.powf(m)
    }

    fn sample(&self, wo: Vec3, u: Vec2) -> Option<Vec3> {
        let (axis, m) = self.sampling_lobe(wo)?;
        let cos = u.x.powf(1.0 / (m + 1.0));
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let (sin_phi, cos_phi) = (2.0 * PI * u.y).sin_cos();
        let frame = Frame::from_z(axis);
        Some(frame.x * (sin * cos_phi) + frame.y * (sin * sin_phi) + axis * cos)
    }
}

#[derive(Clone, Copy, Debug)]
pub struct Lafortune {
    pub fit: &'static LafortuneFit,
}

impl Lafortune {
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let lobes = self.fit.lobes.iter().map(|lobe| lobe.eval(wo, wi));
        self.fit.diffuse * FRAC_1_PI + lobes.sum::<Vec3>()
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let lobes: f32 = self.fit.lobes.iter().map(|lobe| lobe.pdf(wo, wi)).sum();
        (cosine_hemisphere_pdf(wi.z) + lobes) / (self.fit.lobes.len() + 1) as f32
    }

    /// `uc` picks the cosine or a lobe, each with the same probability.
    pub fn sample(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let choices = self.fit.lobes.len() + 1;
        let choice = ((uc * choices as f32) as usize).min(choices - 1);
        let wi = match self.fit.lobes.get(choice) {
            Some(lobe) => lobe.sample(wo, u)?,
            None => cosine_hemisphere(u),
        };
        if wi.z <= 0.0 {
            return None;
        }
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// The diffuse albedo (the lobes add a fitted, angle-dependent part).
    pub fn albedo(&self) -> Vec3 {
        self.fit.diffuse
    }
}
