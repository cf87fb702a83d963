//! Schlick's microfacet distribution and shadowing (Schlick 1994, "An Inexpensive BRDF Model
//! for Physically-based Rendering", §5; LuxRender's
//! `core/reflection/microfacetdistribution/schlickdistribution.h` and `.cpp`), and the
//! Cook-Torrance reflection lobe LuxRender builds on it (`MicrofacetReflection`):
//!
//!   D(h) = Z(cos_h) A(h) / pi,  Z(t) = r / (1 + (r - 1) t^2)^2,
//!   G(wo, wi) = G1(cos_o) G1(cos_i),  G1(c) = c / (c (1 - r) + r),
//!   f(wo, wi) = F(wi . h) D(h) G(wo, wi) / (4 cos_o cos_i),
//!
//! with r the roughness. The anisotropy a in (-1, 1) (LuxRender's from `uroughness` u and
//! `vroughness` v: 1 - u^2 / v^2 when u < v, else v^2 / u^2 - 1) gives Schlick's azimuthal
//! factor, with p = 1 - |a| and w the cosine of h's azimuth from the x axis for a > 0, from
//! the y axis for a < 0 (h's x or y over |h_xy|):
//!
//!   A(h) = sqrt(p / (p^2 + w^2 (1 - p^2))),
//!
//! 1 for a = 0; for a > 0 (u < v) A is largest for h along y: the lobe is wider along the
//! tangent of larger roughness. A is normalised only approximately (its mean over the azimuth
//! is 0.99 at p = 0.7, 0.92 at p = 0.3, 0.62 at p = 0.05), so LuxRender's anisotropic lobe
//! reflects less than its isotropic one; foton keeps it as it is.
//!
//! Isotropic, Z / pi is the GGX distribution of alpha^2 = r (Walter et al. 2007,
//! eq. 33: D = alpha^2 / (pi (1 + (alpha^2 - 1) cos^2)^2)), normalised: the integral of
//! D cos_h over the hemisphere is 1, so h is sampled with density D(h) cos_h by inverting the
//! CDF in cos^2, u / (r (1 - u) + u); the reflection about h has the Jacobian 1 / (4 wo . h)
//! (Walter et al. 2007, eq. 14).
//!
//! LuxRender samples the azimuth by Schlick's approximate inversion (`SampleH`): u2 picks one of
//! the four quadrants and, with u its fraction there, the angle from the quadrant's axis is
//! G = (pi / 2) sqrt(u^2 p^2 / (1 - u^2 (1 - p^2))), measured from x for a < 0 and from y for
//! a > 0 (LuxRender adds pi / 2). Its true density is not A / 2 pi (LuxRender weighs its samples
//! with D as if it were, which biases them); foton uses the true one. Inverting, u^2 = t /
//! (p^2 + t (1 - p^2)) with t = (2 G / pi)^2, and du / dG divided by 4 quadrants gives
//!
//!   pdf(phi) = B / 2 pi,  B = p^2 / (p^2 + t (1 - p^2))^(3/2),
//!
//! which integrates to 1 over the circle (B = 1 for p = 1); h's density per solid angle is then
//! Z(cos_h) cos_h B / pi.

use std::f32::consts::{FRAC_1_PI, FRAC_2_PI, FRAC_PI_2, PI};

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

/// The smallest p = 1 - |a|: keeps A and B finite off their axis (u or v 0 would make the lobe
/// a line).
const P_MIN: f32 = 1e-4;

/// Schlick's azimuthal factor A(h) for p = 1 - |a| and the sign of a.
fn schlick_a(p: f32, along_x: bool, h: Vec3) -> f32 {
    let h2 = h.x * h.x + h.y * h.y;
    if h2 <= 0.0 {
        return 1.0;
    }
    let w2 = if along_x { h.x * h.x } else { h.y * h.y } / h2;
    (p / (p * p + w2 * (1.0 - p * p))).sqrt()
}

/// The azimuthal density's B(h) (module doc): G is h's angle from the sampled axis (y when
/// `along_x`, as LuxRender turns its angle by pi / 2 for a > 0), folded into [0, pi / 2].
fn azimuth_weight(p: f32, along_x: bool, h: Vec3) -> f32 {
    let (from_axis, across) = if along_x {
        (h.y.abs(), h.x.abs())
    } else {
        (h.x.abs(), h.y.abs())
    };
    let t = (across.atan2(from_axis) * FRAC_2_PI).powi(2);
    p * p / (p * p + t * (1.0 - p * p)).powf(1.5)
}

/// Schlick's approximate inverse of the azimuth's distribution, G of the module doc for the
/// quadrant's fraction `u` in [0, 1].
fn schlick_azimuth(u: f32, p: f32) -> f32 {
    let a = u * u;
    let b = p * p;
    FRAC_PI_2 * (a * b / (1.0 - a * (1.0 - b))).sqrt()
}

/// A half vector drawn with density Z(cos_h) cos_h B / pi per solid angle.
fn sample_schlick_half(r: f32, anisotropy: f32, u: Vec2) -> Vec3 {
    let cos2 = u.x / (r * (1.0 - u.x) + u.x);
    let (cos_t, sin_t) = (cos2.sqrt(), (1.0 - cos2).max(0.0).sqrt());
    let phi = if anisotropy == 0.0 {
        2.0 * PI * u.y
    } else {
        let p = (1.0 - anisotropy.abs()).max(P_MIN);
        let quadrant = u.y * 4.0;
        let (q, fraction) = (quadrant as u32, quadrant.fract());
        let g = |f: f32| schlick_azimuth(f, p);
        let phi = match q {
            0 => g(fraction),
            1 => PI - g(1.0 - fraction),
            2 => PI + g(fraction),
            _ => 2.0 * PI - g(1.0 - fraction),
        };
        if anisotropy > 0.0 {
            phi + FRAC_PI_2
        } else {
            phi
        }
    };
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
    /// Schlick's anisotropy a (0: isotropic).
    anisotropy: f32,
}

impl SchlickLobe {
    /// The isotropic lobe of roughness r (clamped).
    pub(super) fn new(roughness: f32) -> Self {
        Self::anisotropic(roughness, 0.0)
    }

    /// The lobe of roughness r (clamped) and anisotropy a (clamped to [-1, 1]).
    pub(super) fn anisotropic(roughness: f32, anisotropy: f32) -> Self {
        Self {
            r: clamp_roughness(roughness),
            anisotropy: if anisotropy.is_finite() {
                anisotropy.clamp(-1.0, 1.0)
            } else {
                0.0
            },
        }
    }

    /// p = 1 - |a| (clamped) and whether A's cosine is taken from the x axis (a > 0).
    fn shape(&self) -> (f32, bool) {
        (
            (1.0 - self.anisotropy.abs()).max(P_MIN),
            self.anisotropy > 0.0,
        )
    }

    /// D(h) G(wo, wi) / (4 cos_o cos_i) for wo, wi above the surface and h their half vector.
    pub(super) fn eval(&self, wo: Vec3, wi: Vec3, h: Vec3) -> f32 {
        let g = schlick_g(self.r, wo.z) * schlick_g(self.r, wi.z);
        let d = schlick_z(self.r, h) * FRAC_1_PI * g / (4.0 * wo.z * wi.z);
        if self.anisotropy == 0.0 {
            return d;
        }
        let (p, along_x) = self.shape();
        d * schlick_a(p, along_x, h)
    }

    /// The density of [`SchlickLobe::sample`] at the direction whose half vector is `h`, with
    /// `cos_wh` = wo . h.
    pub(super) fn pdf(&self, h: Vec3, cos_wh: f32) -> f32 {
        let pdf = schlick_z(self.r, h) * h.z * FRAC_1_PI / (4.0 * cos_wh.max(1e-7));
        if self.anisotropy == 0.0 {
            return pdf;
        }
        let (p, along_x) = self.shape();
        pdf * azimuth_weight(p, along_x, h)
    }

    /// wo reflected about a sampled half vector (it may fall below the surface).
    pub(super) fn sample(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let h = sample_schlick_half(self.r, self.anisotropy, u);
        2.0 * wo.dot(h) * h - wo
    }
}
