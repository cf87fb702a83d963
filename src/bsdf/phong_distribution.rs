//! The microfacet distribution of LuxRender 0.x's `plastic`, `substrate` and `shinymetal`
//! (inherited from pbrt-v1's `Blinn` and `Anisotropic`, `core/reflection.h`): Ashikhmin and
//! Shirley's anisotropic Phong distribution of half vectors (2000, "An Anisotropic Phong BRDF
//! Model", eq. 4 and 9),
//!
//!   D(h) = sqrt((ex + 2)(ey + 2)) / (2 pi) cos_h^e(h),   e(h) = (ex h.x^2 + ey h.y^2) / (1 - cos_h^2),
//!
//! so e(h) = ex cos^2 phi + ey sin^2 phi. For ex = ey = e it is Blinn's (e + 2) / (2 pi) cos_h^e;
//! either way D(h) cos_h integrates to 1 over the hemisphere. LuxRender 0.x gives each exponent
//! as the inverse of a roughness, e = 1 / r, and pbrt-v1's constructors clamp it to 10,000.
//!
//! Half vectors are sampled as Ashikhmin and Shirley do (pbrt-v1 `sampleFirstQuadrant`): in the
//! first quadrant phi = atan(sqrt((ex + 1) / (ey + 1)) tan(pi u / 2)), mirrored to the other
//! three, and cos_h = u'^(1 / (e(phi) + 1)). The density per solid angle of h is then
//!
//!   p(h) = sqrt((ex + 1)(ey + 1)) / (2 pi) cos_h^e(h),
//!
//! and the reflected direction wi = 2 (wo . h) h - wo has p(h) / (4 wo . h).

use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, PI};

use crate::math::try_normalize;
use glam::{Vec2, Vec3};

use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};

/// pbrt-v1's bound on a Blinn or Ashikhmin-Shirley exponent (`Blinn(e)`, `Anisotropic(x, y)`).
const MAX_EXPONENT: f32 = 10_000.0;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongDistribution {
    /// The exponent along the local x axis (dp/du) and along y.
    pub ex: f32,
    pub ey: f32,
}

impl PhongDistribution {
    /// LuxRender 0.x's exponents 1 / `u` and 1 / `v` of roughnesses, clamped as pbrt-v1 does (a
    /// zero roughness is the largest exponent; a negative one, meaningless, the smallest).
    pub fn from_roughness(u: f32, v: f32) -> Self {
        let exponent = |r: f32| {
            let e = 1.0 / r;
            if e.is_nan() {
                MAX_EXPONENT
            } else {
                e.clamp(0.0, MAX_EXPONENT)
            }
        };
        Self {
            ex: exponent(u),
            ey: exponent(v),
        }
    }

    /// e(h) = ex cos^2 phi + ey sin^2 phi of a unit half vector (any value along the normal,
    /// where cos_h^e = 1).
    fn exponent(&self, h: Vec3) -> f32 {
        let sin2 = h.x * h.x + h.y * h.y;
        if sin2 > 0.0 {
            (self.ex * h.x * h.x + self.ey * h.y * h.y) / sin2
        } else {
            self.ex
        }
    }

    /// D(h) for a unit half vector on the upper side.
    pub fn d(&self, h: Vec3) -> f32 {
        if h.z <= 0.0 {
            return 0.0;
        }
        ((self.ex + 2.0) * (self.ey + 2.0)).sqrt() * 0.5 * FRAC_1_PI * h.z.powf(self.exponent(h))
    }

    /// The density per solid angle of a half vector drawn by [`Self::sample_h`].
    fn pdf_h(&self, h: Vec3) -> f32 {
        if h.z <= 0.0 {
            return 0.0;
        }
        ((self.ex + 1.0) * (self.ey + 1.0)).sqrt() * 0.5 * FRAC_1_PI * h.z.powf(self.exponent(h))
    }

    /// A half vector on the upper side for a canonical `u`.
    fn sample_h(&self, u: Vec2) -> Vec3 {
        let quarter = (4.0 * u.x).min(3.999_999_8);
        let quadrant = quarter as u32;
        let angle = FRAC_PI_2 * (quarter - quadrant as f32);
        let first = if self.ex == self.ey {
            angle
        } else {
            (((self.ex + 1.0) / (self.ey + 1.0)).sqrt() * angle.tan()).atan()
        };
        let phi = match quadrant {
            0 => first,
            1 => PI - first,
            2 => PI + first,
            _ => 2.0 * PI - first,
        };
        let (sin_phi, cos_phi) = phi.sin_cos();
        let e = self.ex * cos_phi * cos_phi + self.ey * sin_phi * sin_phi;
        let cos_h = u.y.powf(1.0 / (e + 1.0));
        let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
        Vec3::new(sin_h * cos_phi, sin_h * sin_phi, cos_h)
    }

    /// The density of `wi` reflected about a sampled half vector, for `wo` and `wi` above.
    pub fn reflection_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some(h) = try_normalize(wo + wi) else {
            return 0.0;
        };
        let cos_oh = wo.dot(h);
        if cos_oh <= 0.0 {
            return 0.0;
        }
        self.pdf_h(h) / (4.0 * cos_oh)
    }

    /// The density of [`Self::sample_with_diffuse`]: half cosine-weighted, half reflected about
    /// a sampled half vector (pbrt-v1's `FresnelBlend::Pdf`, and its `BSDF` averaging the
    /// densities of a Lambertian and a microfacet lobe).
    pub fn pdf_with_diffuse(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        0.5 * (cosine_hemisphere_pdf(wi.z) + self.reflection_pdf(wo, wi))
    }

    /// A direction above the surface for `wo` above: cosine-weighted for `choice` < 1/2, else
    /// reflected about a half vector sampled for `u`; None when `wo` is behind that half
    /// vector or the reflection goes below (directions [`Self::reflection_pdf`] does not count).
    pub fn sample_with_diffuse(&self, wo: Vec3, u: Vec2, choice: f32) -> Option<Vec3> {
        if wo.z <= 0.0 {
            return None;
        }
        if choice < 0.5 {
            return Some(cosine_hemisphere(u));
        }
        let h = self.sample_h(u);
        let cos_oh = wo.dot(h);
        let wi = 2.0 * cos_oh * h - wo;
        (cos_oh > 0.0 && wi.z > 0.0).then_some(wi)
    }
}
