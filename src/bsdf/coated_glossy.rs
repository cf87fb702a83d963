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
//! LuxRender's `uroughness` u and `vroughness` v give r = u v and Schlick's anisotropy
//! (Z times A(h), [`super::schlick_distribution`]); foton samples its own way (below), with a
//! pdf that matches its sampling exactly.

use super::BsdfSample;
use super::schlick_distribution::{SchlickLobe, half_vector};
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug)]
pub struct CoatedGlossy {
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// Absorption coefficient of the coating (Ka) and its depth (d).
    pub absorption: Vec3,
    pub depth: f32,
    /// Schlick's r, in (0, 1].
    pub roughness: f32,
    /// Schlick's anisotropy a (0: isotropic; positive: the lobe wider along the local y axis).
    pub anisotropy: f32,
}

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

impl CoatedGlossy {
    fn lobe(&self) -> SchlickLobe {
        SchlickLobe::anisotropic(self.roughness, self.anisotropy)
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
        diffuse + s * self.lobe().eval(wo, wi, h)
    }

    /// Half the samples cosine-weighted, half from the Schlick lobe
    /// ([`super::schlick_distribution`]).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let Some((h, cos_wh)) = half_vector(wo, wi) else {
            return 0.0;
        };
        0.5 * cosine_hemisphere_pdf(wi.z) + 0.5 * self.lobe().pdf(h, cos_wh)
    }

    /// `u.x` < 1/2 picks the lobe and is rescaled to [0, 1).
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = if u.x < 0.5 {
            cosine_hemisphere(Vec2::new(2.0 * u.x, u.y))
        } else {
            self.lobe()
                .sample(wo, Vec2::new((2.0 * u.x - 1.0).min(1.0), u.y))
        };
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }
}
