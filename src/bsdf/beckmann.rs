//! The anisotropic Beckmann microfacet distribution, as Mitsuba 3 defines it
//! (`include/mitsuba/render/microfacet.h`, after Walter et al. 2007, "Microfacet Models for
//! Refraction through Rough Surfaces", eqs. 25-27). All directions are in the local frame
//! (z = macro normal); alpha is the RMS slope along the local x and y axes.
//!
//! Sampling draws normals from the whole distribution, D(wm) cos(theta_m) (Walter eq. 28, with
//! Mitsuba's anisotropic azimuth), not only those visible from wo as Mitsuba does by default:
//! both are unbiased, this one is noisier at grazing angles (its reflections below the horizon
//! are lost samples).

use super::microfacet::Alphas;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Beckmann {
    pub(super) alpha: Alphas,
}

impl Beckmann {
    /// The alphas are clamped as GGX's ([`Alphas::new`]).
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        Self {
            alpha: Alphas::new(alpha_x, alpha_y),
        }
    }

    /// D(wm) = exp(-tan^2(theta_m) (cos^2 phi / ax^2 + sin^2 phi / ay^2)) / (pi ax ay cos^4 theta_m),
    /// written with the unit vector's coordinates: tan^2 cos^2 phi = x^2 / z^2 (and y likewise).
    /// Its projected area, the integral of D cos(theta_m), is 1.
    pub fn d(&self, wm: Vec3) -> f32 {
        if wm.z <= 0.0 {
            return 0.0;
        }
        let z2 = wm.z * wm.z;
        let exponent = ((wm.x / self.alpha.x).powi(2) + (wm.y / self.alpha.y).powi(2)) / z2;
        (-exponent).exp() / (PI * self.alpha.x * self.alpha.y * z2 * z2)
    }

    /// Smith's masking G1(w) by the rational approximation Mitsuba uses (Walter et al. 2007,
    /// eq. 27; below 0.35 % relative error): with a = 1 / (alpha(phi) tan theta),
    /// G1 = (3.535 a + 2.181 a^2) / (1 + 2.276 a + 2.577 a^2) for a < 1.6, else 1.
    pub fn g1(&self, w: Vec3) -> f32 {
        let xy = (self.alpha.x * w.x).powi(2) + (self.alpha.y * w.y).powi(2);
        if xy == 0.0 {
            return 1.0;
        }
        let a = w.z.abs() / xy.sqrt();
        if a >= 1.6 {
            1.0
        } else {
            (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
        }
    }

    /// Smith's Lambda(w), from G1 = 1 / (1 + Lambda) (infinite where G1 is 0, on the horizon).
    pub fn lambda(&self, w: Vec3) -> f32 {
        1.0 / self.g1(w) - 1.0
    }

    /// A normal drawn with density D(wm) cos(theta_m) (Mitsuba's `sample` without visible
    /// normals). The azimuth: uniform when isotropic, else phi = atan(ay / ax tan(2 pi u.y)) on
    /// the quadrant of 2 pi u.y, whose alpha along phi is 1 / (cos^2 phi / ax^2 + sin^2 phi / ay^2);
    /// the elevation inverts the marginal CDF 1 - exp(-tan^2 theta / alpha^2):
    /// tan^2 theta = -alpha^2 ln(1 - u.x).
    pub fn sample_wm(&self, u: Vec2) -> Vec3 {
        let (ax, ay) = (self.alpha.x, self.alpha.y);
        let (sin_phi, cos_phi, alpha2) = if ax == ay {
            let (s, c) = (2.0 * PI * u.y).sin_cos();
            (s, c, ax * ax)
        } else {
            let tan = ay / ax * (2.0 * PI * u.y).tan();
            // The sign puts phi in the quadrant of 2 pi u.y: cos < 0 for u.y in (1/4, 3/4).
            let cos = (1.0 / (tan * tan + 1.0).sqrt()).copysign((u.y - 0.5).abs() - 0.25);
            let sin = cos * tan;
            (sin, cos, 1.0 / ((cos / ax).powi(2) + (sin / ay).powi(2)))
        };
        let tan2 = -alpha2 * (1.0 - u.x).ln();
        let cos_theta = 1.0 / (1.0 + tan2).sqrt();
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        Vec3::new(cos_phi * sin_theta, sin_phi * sin_theta, cos_theta)
    }

    /// The density of [`Beckmann::sample_wm`]: D(wm) cos(theta_m).
    pub fn pdf_wm(&self, wm: Vec3) -> f32 {
        self.d(wm) * wm.z.max(0.0)
    }
}
