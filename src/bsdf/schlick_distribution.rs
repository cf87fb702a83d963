//! Schlick's microfacet distribution and shadowing (Schlick 1994, "An Inexpensive BRDF Model
//! for Physically-based Rendering", §5; LuxRender's
//! `core/reflection/microfacetdistribution/schlickdistribution.h`), isotropic (its A(phi) = 1),
//! and the Cook-Torrance reflection lobe LuxRender builds on it (`MicrofacetReflection`):
//!
//!   D(h) = Z(cos_h) / pi,  Z(t) = r / (1 + (r - 1) t^2)^2,
//!   G(wo, wi) = G1(cos_o) G1(cos_i),  G1(c) = c / (c (1 - r) + r),
//!   f(wo, wi) = F(wi . h) D(h) G(wo, wi) / (4 cos_o cos_i),
//!
//! with r the roughness. Z / pi is the GGX distribution of alpha^2 = r (Walter et al. 2007,
//! eq. 33: D = alpha^2 / (pi (1 + (alpha^2 - 1) cos^2)^2)), normalised: the integral of
//! D cos_h over the hemisphere is 1, so h is sampled with density D(h) cos_h by inverting the
//! CDF in cos^2, u / (r (1 - u) + u); the reflection about h has the Jacobian 1 / (4 wo . h)
//! (Walter et al. 2007, eq. 14).

use std::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

/// The smallest roughness: keeps Z's peak, 1 / r, finite.
const ROUGHNESS_MIN: f32 = 1e-4;

/// Schlick's roughness r clamped to [1e-4, 1]; NaN becomes the minimum.
fn clamp_roughness(roughness: f32) -> f32 {
    if roughness >= ROUGHNESS_MIN {
        roughness.min(1.0)
    } else {
        ROUGHNESS_MIN
    }
}

/// Schlick's Z of roughness r at the unit half vector h: pi D(h). The denominator's
/// 1 + (r - 1) cos^2 is written sin^2 + r cos^2 from h's components, which keeps its relative
/// precision near the peak, where it is about r and 1 - cos^2 would cancel.
fn schlick_z(r: f32, h: Vec3) -> f32 {
    let d = h.x * h.x + h.y * h.y + r * h.z * h.z;
    r / (d * d)
}

/// Schlick's shadowing G1(c) = c / (c (1 - r) + r) of one direction.
pub(super) fn schlick_g(r: f32, c: f32) -> f32 {
    c / (c * (1.0 - r) + r)
}

/// A half vector drawn with density Z(cos_h) cos_h / pi per solid angle.
fn sample_schlick_half(r: f32, u: Vec2) -> Vec3 {
    let cos2 = u.x / (r * (1.0 - u.x) + u.x);
    let (cos_t, sin_t) = (cos2.sqrt(), (1.0 - cos2).max(0.0).sqrt());
    let phi = 2.0 * PI * u.y;
    Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

/// The half vector h of two unit vectors and wo . h = wi . h. The cosine is |wo + wi| / 2
/// ((wo + wi) . wo = 1 + wo . wi = |wo + wi|^2 / 2), which stays accurate when wo and wi are
/// nearly opposite, where 1 + wo . wi cancels.
pub(super) fn half_vector(wo: Vec3, wi: Vec3) -> Option<(Vec3, f32)> {
    let sum = wo + wi;
    let length = sum.length();
    (length > 0.0 && length.is_finite()).then(|| (sum / length, 0.5 * length))
}

/// The Cook-Torrance lobe of Schlick's distribution, without its Fresnel term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SchlickLobe {
    r: f32,
}

impl SchlickLobe {
    /// The lobe of roughness r (clamped).
    pub(super) fn new(roughness: f32) -> Self {
        Self {
            r: clamp_roughness(roughness),
        }
    }

    /// D(h) G(wo, wi) / (4 cos_o cos_i) for wo, wi above the surface and h their half vector.
    pub(super) fn eval(&self, wo: Vec3, wi: Vec3, h: Vec3) -> f32 {
        let g = schlick_g(self.r, wo.z) * schlick_g(self.r, wi.z);
        schlick_z(self.r, h) * FRAC_1_PI * g / (4.0 * wo.z * wi.z)
    }

    /// The density of [`SchlickLobe::sample`] at the direction whose half vector is `h`, with
    /// `cos_wh` = wo . h.
    pub(super) fn pdf(&self, h: Vec3, cos_wh: f32) -> f32 {
        schlick_z(self.r, h) * h.z * FRAC_1_PI / (4.0 * cos_wh.max(1e-7))
    }

    /// wo reflected about a sampled half vector (it may fall below the surface).
    pub(super) fn sample(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let h = sample_schlick_half(self.r, u);
        2.0 * wo.dot(h) * h - wo
    }
}
