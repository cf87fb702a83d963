//! LuxRender's `shinymetal` (1.x, `materials/shinymetal.cpp`): the sum (a `MultiBSDF`) of a
//! mirror and a glossy microfacet lobe, each weighted by a conductor Fresnel term fitted to a
//! reflectance.
//!
//! Each lobe's Fresnel term is `FresnelGeneral(FresnelApproxEta(R), FresnelApproxK(R))`
//! ([`fr_general`] of [`approx_eta`] and [`approx_k`]), with R = `Kr` for the mirror and
//! R = `Ks` for the glossy lobe; the mirror reflects F(cos_o), the glossy lobe is
//! `MicrofacetReflection` of Schlick's distribution of roughness r = u v and anisotropy a
//! from u and v ([`super::schlick_distribution`]): f = F(wi . h) D(h) G(wo, wi) / (4 cos_o
//! cos_i). A film (`film` thickness > 0, `filmindex`) weighs the mirror's Fresnel term by
//! LuxRender's thin-film interference ([`ThinFilm`]; `SpecularReflection` with `film`, which
//! `shinymetal` gives only its mirror). Sampling picks either lobe with probability 1/2, as
//! LuxRender's BSDF picks a component uniformly.
//!
//! Each lobe can reflect up to about its R, so with LuxRender's defaults (`Ks` = `Kr` = 1) the
//! albedo approaches 2: LuxRender's material is not energy conserving, and foton keeps it so.

use glam::{Vec2, Vec3};

use super::BsdfSample;
use super::fresnel::{approx_eta, approx_k, fr_general};
use super::schlick_distribution::{SchlickLobe, half_vector};
use super::thin_film::ThinFilm;

#[derive(Clone, Copy, Debug)]
pub struct ShinyMetal {
    /// The reflectance the glossy lobe's Fresnel term is fitted to (`Ks`).
    pub glossy: Vec3,
    /// The reflectance the mirror's Fresnel term is fitted to (`Kr`).
    pub mirror: Vec3,
    /// Schlick's roughness r (LuxRender's `uroughness` x `vroughness`).
    pub roughness: f32,
    /// Schlick's anisotropy a (0: isotropic; positive: the lobe wider along the local y axis).
    pub anisotropy: f32,
    /// Thin-film interference on the mirror, if any.
    pub film: Option<ThinFilm>,
}

/// The probability of each lobe.
const LOBE_PROBABILITY: f32 = 0.5;

impl ShinyMetal {
    fn fresnel(reflectance: Vec3, cos: f32) -> Vec3 {
        fr_general(cos, approx_eta(reflectance), approx_k(reflectance))
    }

    fn lobe(&self) -> SchlickLobe {
        SchlickLobe::anisotropic(self.roughness, self.anisotropy)
    }

    /// Whether the glossy lobe depends on the azimuth (the frame must follow dp/du).
    pub fn is_anisotropic(&self) -> bool {
        self.anisotropy != 0.0
    }

    /// The mirror's reflectance at `cos_o`: its Fresnel term times the film's weight.
    pub fn mirror_reflectance(&self, cos_o: f32) -> Vec3 {
        let fresnel = Self::fresnel(self.mirror, cos_o);
        match self.film {
            Some(film) => fresnel * film.rgb_weight(cos_o),
            None => fresnel,
        }
    }

    /// The glossy lobe (the mirror is a delta, not part of eval).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let Some((h, cos_wh)) = half_vector(wo, wi) else {
            return Vec3::ZERO;
        };
        Self::fresnel(self.glossy, cos_wh) * self.lobe().eval(wo, wi, h)
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let Some((h, cos_wh)) = half_vector(wo, wi) else {
            return 0.0;
        };
        (1.0 - LOBE_PROBABILITY) * self.lobe().pdf(h, cos_wh)
    }

    /// `uc` picks the lobe: the mirror below 1/2.
    pub fn sample(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        if uc < LOBE_PROBABILITY {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return Some(BsdfSample {
                wi,
                f: self.mirror_reflectance(wo.z) / wi.z,
                pdf: LOBE_PROBABILITY,
                delta: true,
            });
        }
        let wi = self.lobe().sample(wo, u);
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// Both lobes at normal incidence, at most 1.
    pub fn albedo(&self) -> Vec3 {
        (self.mirror_reflectance(1.0) + Self::fresnel(self.glossy, 1.0)).min(Vec3::ONE)
    }
}
