//! LuxRender's `glossy` (`materials/glossy2.cpp`, `core/reflection/bxdf/schlickbrdf.cpp`): a
//! diffuse base under a glossy coating, after Schlick 1994 ("An Inexpensive BRDF Model for
//! Physically-based Rendering", §5 and eq. 15):
//!
//!   f = a Kd / pi (1 - S) + S G(cos_i) G(cos_o) Z(cos_h) / (4 pi cos_i cos_o),
//!
//! with h the half vector, S = Ks + (1 - Ks)(1 - |wi . h|)^5 the coating's Fresnel term,
//! Z(t) = r / (1 + (r - 1) t^2)^2 Schlick's facet distribution (r the roughness),
//! G(c) = c / (c (1 - r) + r) Schlick's shadowing, and a = exp(-Ka d (1 / cos_i + 1 / cos_o))
//! the absorption of a coating of depth d crossed twice. LuxRender's `index`, when positive,
//! scales Ks by ((n - 1) / (n + 1))^2 (see [`coating_f0`]).
//!
//! foton's version is isotropic (LuxRender's `uroughness` x `vroughness` gives r; the
//! anisotropy term A(phi) is left at 1) and samples its own way (below), with a pdf that
//! matches its sampling exactly.

use super::BsdfSample;
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

#[derive(Clone, Copy, Debug)]
pub struct CoatedGlossy {
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// Absorption coefficient of the coating (Ka) and its depth (d).
    pub absorption: Vec3,
    pub depth: f32,
    /// Schlick's r, in (0, 1].
    pub roughness: f32,
}

/// The smallest roughness: keeps Z's peak, 1 / r, finite.
const ROUGHNESS_MIN: f32 = 1e-4;

/// The coating's reflectance at normal incidence: Ks, times ((n - 1) / (n + 1))^2 for an
/// index n > 0 (`glossy2.cpp`: `if (i > 0) s *= ((i - 1) / (i + 1))^2`), clamped to [0, 1].
pub fn coating_f0(ks: Vec3, index: f32) -> Vec3 {
    let f0 = if index > 0.0 && index.is_finite() {
        ks * ((index - 1.0) / (index + 1.0)).powi(2)
    } else {
        ks
    };
    f0.clamp(Vec3::ZERO, Vec3::ONE)
}

/// The half vector h of two unit vectors and wo . h = wi . h. The cosine is |wo + wi| / 2
/// ((wo + wi) . wo = 1 + wo . wi = |wo + wi|^2 / 2), which stays accurate when wo and wi are
/// nearly opposite, where 1 + wo . wi cancels.
pub(super) fn half_vector(wo: Vec3, wi: Vec3) -> Option<(Vec3, f32)> {
    let sum = wo + wi;
    let length = sum.length();
    (length > 0.0 && length.is_finite()).then(|| (sum / length, 0.5 * length))
}

/// Schlick's roughness r clamped to [`ROUGHNESS_MIN`], 1]; NaN becomes the minimum.
pub(super) fn clamp_roughness(roughness: f32) -> f32 {
    if roughness >= ROUGHNESS_MIN {
        roughness.min(1.0)
    } else {
        ROUGHNESS_MIN
    }
}

/// Schlick's Z of roughness r, which is pi times the GGX distribution with alpha^2 = r
/// (Walter et al. 2007, eq. 33: D = alpha^2 / (pi (1 + (alpha^2 - 1) cos^2)^2)).
pub(super) fn schlick_z(r: f32, cos_h: f32) -> f32 {
    let d = 1.0 + (r - 1.0) * cos_h * cos_h;
    r / (d * d)
}

/// Schlick's shadowing G(c) = c / (c (1 - r) + r) of one direction.
pub(super) fn schlick_g(r: f32, c: f32) -> f32 {
    c / (c * (1.0 - r) + r)
}

/// A half vector drawn with density Z(cos_h) cos_h / pi per solid angle (its inverse CDF in
/// cos^2 is u / (r (1 - u) + u)).
pub(super) fn sample_schlick_half(r: f32, u: Vec2) -> Vec3 {
    let cos2 = u.x / (r * (1.0 - u.x) + u.x);
    let (cos_t, sin_t) = (cos2.sqrt(), (1.0 - cos2).max(0.0).sqrt());
    let phi = 2.0 * PI * u.y;
    Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

impl CoatedGlossy {
    fn r(&self) -> f32 {
        clamp_roughness(self.roughness)
    }

    fn z(&self, cos_h: f32) -> f32 {
        schlick_z(self.r(), cos_h)
    }

    fn g(&self, c: f32) -> f32 {
        schlick_g(self.r(), c)
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let Some((h, cos_wh)) = half_vector(wo, wi) else {
            return Vec3::ZERO;
        };
        let s = self.specular + (Vec3::ONE - self.specular) * (1.0 - cos_wh).powi(5);
        let a = if self.depth > 0.0 {
            (-self.absorption * self.depth * (1.0 / wi.z + 1.0 / wo.z)).exp()
        } else {
            Vec3::ONE
        };
        let diffuse = a * self.diffuse * FRAC_1_PI * (Vec3::ONE - s);
        let spec = self.g(wi.z) * self.g(wo.z) * self.z(h.z) / (4.0 * PI * wi.z * wo.z);
        diffuse + s * spec
    }

    /// Half the samples cosine-weighted, half reflected about a normal drawn from
    /// D(h) cos(theta_h) = Z cos / pi (whose inverse CDF in cos^2 is u / (r (1 - u) + u));
    /// the reflection's Jacobian is 1 / (4 |wo . h|) (Walter et al. 2007, eq. 14).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let Some((h, cos_wh)) = half_vector(wo, wi) else {
            return 0.0;
        };
        let spec = self.z(h.z) * h.z * FRAC_1_PI / (4.0 * cos_wh.max(1e-7));
        0.5 * cosine_hemisphere_pdf(wi.z) + 0.5 * spec
    }

    /// `u.x` < 1/2 picks the lobe and is rescaled to [0, 1).
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = if u.x < 0.5 {
            cosine_hemisphere(Vec2::new(2.0 * u.x, u.y))
        } else {
            let u1 = (2.0 * u.x - 1.0).min(1.0);
            let h = sample_schlick_half(self.r(), Vec2::new(u1, u.y));
            2.0 * wo.dot(h) * h - wo
        };
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }
}
