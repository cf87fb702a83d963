//! The anisotropic Trowbridge-Reitz (GGX) microfacet distribution.
//!
//! Sources: Trowbridge and Reitz 1975; Walter et al. 2007, "Microfacet Models
//! for Refraction through Rough Surfaces" (GGX); Heitz 2014, "Understanding
//! the Masking-Shadowing Function in Microfacet-Based BRDFs" (Smith Lambda,
//! height-correlated G); Heitz 2018, "Sampling the GGX Distribution of Visible
//! Normals" (JCGT 7(4)); pbrt-v4 §9.6. All directions are in the local frame
//! (z = macro normal).

use crate::sampling::warp::concentric_disk;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The smallest alpha: keeps D's peak, 1 / (pi alpha^2), finite in f32.
pub const ALPHA_MIN: f32 = 1e-3;
/// The largest alpha: beyond 1 the GGX lobe is wider than a diffuse one.
pub const ALPHA_MAX: f32 = 1.0;

/// GGX with roughness `alpha_x` along the local x axis and `alpha_y` along y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitz {
    pub(super) alpha: Alphas,
}

/// A microfacet distribution's roughness along the local x and y axes, each clamped by
/// [`clamp_alpha`]: GGX's and Beckmann's alike.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Alphas {
    pub x: f32,
    pub y: f32,
}

impl Alphas {
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        Self {
            x: clamp_alpha(alpha_x),
            y: clamp_alpha(alpha_y),
        }
    }

    /// Whether the roughness differs along x and y.
    pub fn is_anisotropic(&self) -> bool {
        self.x != self.y
    }
}

/// Clamps alpha to [ALPHA_MIN, ALPHA_MAX]; NaN becomes ALPHA_MIN.
pub fn clamp_alpha(alpha: f32) -> f32 {
    if alpha >= ALPHA_MIN {
        alpha.min(ALPHA_MAX)
    } else {
        ALPHA_MIN
    }
}

impl TrowbridgeReitz {
    /// The alphas are clamped by [`clamp_alpha`].
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        Self {
            alpha: Alphas::new(alpha_x, alpha_y),
        }
    }

    /// D(wm), the density of microfacet normals per solid angle, normalised
    /// so that the projected area is 1: the integral of D(wm) cos(theta_m)
    /// over the hemisphere is 1. For a unit wm, Walter's
    /// 1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2)
    /// equals 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2), whose denominator
    /// is at least pi ax ay since alpha <= 1: finite at every angle.
    pub fn d(&self, wm: Vec3) -> f32 {
        if wm.z <= 0.0 {
            return 0.0;
        }
        let (ax, ay) = (self.alpha.x, self.alpha.y);
        let s = (wm.x / ax).powi(2) + (wm.y / ay).powi(2) + wm.z * wm.z;
        1.0 / (PI * ax * ay * s * s)
    }

    /// Smith's Lambda(w) for GGX (Heitz 2014, eq. 72 with the anisotropic
    /// alpha of eq. 80): (sqrt(1 + alpha(phi)^2 tan^2 theta) - 1) / 2.
    /// Infinite for w on the horizon (then G1 = G = 0).
    pub fn lambda(&self, w: Vec3) -> f32 {
        let z2 = w.z * w.z;
        if z2 == 0.0 {
            return f32::INFINITY;
        }
        let a2_tan2 = ((self.alpha.x * w.x).powi(2) + (self.alpha.y * w.y).powi(2)) / z2;
        // (sqrt(1 + t) - 1) / 2 rewritten as t / (2 (sqrt(1 + t) + 1)) to avoid
        // cancellation for small t.
        a2_tan2 / (2.0 * ((1.0 + a2_tan2).sqrt() + 1.0))
    }

    /// Smith masking G1(w) = 1 / (1 + Lambda(w)).
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated Smith masking-shadowing (Heitz 2014, eq. 99):
    /// G(wo, wi) = 1 / (1 + Lambda(wo) + Lambda(wi)).
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// The density of normals visible from `w` (Heitz 2014, eq. 38):
    /// D_w(wm) = G1(w) max(0, w . wm) D(wm) / cos(theta_w), for w.z > 0.
    pub fn d_visible(&self, w: Vec3, wm: Vec3) -> f32 {
        if w.z <= 0.0 {
            return 0.0;
        }
        self.g1(w) * w.dot(wm).max(0.0) * self.d(wm) / w.z
    }

    /// Samples a normal wm from D_w (Heitz 2018, Listing 1) for w.z > 0: in
    /// the stretched configuration where the distribution is the hemisphere
    /// of unit roughness, the visible projected area of the hemisphere is a
    /// disk with half of it foreshortened by cos(theta); sample it, lift the
    /// point to the hemisphere, and unstretch.
    pub fn sample_wm(&self, w: Vec3, u: Vec2) -> Vec3 {
        // The view direction in the hemisphere configuration.
        let wh = Vec3::new(self.alpha.x * w.x, self.alpha.y * w.y, w.z).normalize();
        // An orthonormal basis around wh (T1 horizontal).
        let t1 = if wh.z < 0.99999 {
            Vec3::Z.cross(wh).normalize()
        } else {
            Vec3::X
        };
        let t2 = wh.cross(t1);
        // A uniform point on the projected disk, squeezed vertically on the
        // half that the hemisphere's cap hides partly.
        let mut p = concentric_disk(u);
        let h = (1.0 - p.x * p.x).max(0.0).sqrt();
        let s = 0.5 * (1.0 + wh.z);
        p.y = (1.0 - s) * h + s * p.y;
        // Project onto the hemisphere and back to the ellipsoid configuration.
        let pz = (1.0 - p.length_squared()).max(0.0).sqrt();
        let nh = p.x * t1 + p.y * t2 + pz * wh;
        Vec3::new(self.alpha.x * nh.x, self.alpha.y * nh.y, nh.z.max(0.0)).normalize()
    }
}
