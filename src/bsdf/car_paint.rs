//! LuxRender's `carpaint` (`materials/carpaint.cpp`, after Günther et al. 2005, "Efficient
//! Acquisition and Realistic Rendering of Car Paint"): three Schlick microfacet lobes over a
//! diffuse base, summed (LuxRender's `MultiBSDF`).
//!
//! Lobe k (added only when its Ks_k and M_k are positive) is a Cook-Torrance reflection of
//! Schlick's distribution of roughness r = M_k^2 (`SchlickDistribution(m * m, 0)`, isotropic):
//!
//!   f_k = Ks_k F_k(wi . h) Z(cos_h) / pi G(cos_o) G(cos_i) / (4 cos_o cos_i),
//!
//! with F_k(c) = R_k + (1 - R_k)(1 - c)^5 Schlick's Fresnel of normal reflectance R_k
//! (`FresnelSlick(r, 0)`), Z and G Schlick's ([`super::schlick_distribution`]). The base is
//! LuxRender's `SchlickBRDF(Kd, Ks = 0, Ka, d, roughness 1)`: foton's [`CoatedGlossy`] with
//! a coating of zero reflectance at normal incidence and roughness 1, whose Fresnel term still
//! rises towards grazing angles.
//!
//! Sampling picks one of the present components uniformly (as `MultiBSDF` does) and the pdf
//! is their mean; a lobe draws h with density Z(cos_h) cos_h / pi and reflects wo about it.

use glam::{Vec2, Vec3};

use super::BsdfSample;
use super::coated_glossy::CoatedGlossy;
use super::fresnel::schlick;
use super::schlick_distribution::{SchlickLobe, half_vector};
use crate::sampling::ONE_MINUS_EPSILON;

/// One of the three specular lobes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CarPaintLobe {
    /// Ks_k, the lobe's colour.
    pub specular: Vec3,
    /// R_k, its Fresnel reflectance at normal incidence.
    pub f0: f32,
    /// M_k, its roughness (Schlick's r = M_k^2).
    pub roughness: f32,
}

#[derive(Clone, Copy, Debug)]
pub struct CarPaint {
    /// The diffuse base (its `specular` 0 and `roughness` 1, see the module doc).
    pub base: CoatedGlossy,
    pub lobes: [CarPaintLobe; 3],
}

impl CarPaintLobe {
    fn is_present(&self) -> bool {
        self.specular.max_element() > 0.0 && self.roughness > 0.0
    }

    fn lobe(&self) -> SchlickLobe {
        SchlickLobe::new(self.roughness * self.roughness)
    }

    fn eval(&self, wo: Vec3, wi: Vec3, h: Vec3, cos_wh: f32) -> Vec3 {
        let fresnel = schlick(Vec3::splat(self.f0.clamp(0.0, 1.0)), cos_wh);
        self.specular * fresnel * self.lobe().eval(wo, wi, h)
    }
}

impl CarPaint {
    fn present_lobes(&self) -> impl Iterator<Item = &CarPaintLobe> {
        self.lobes.iter().filter(|l| l.is_present())
    }

    /// The number of components: the present lobes and the base.
    fn components(&self) -> usize {
        self.present_lobes().count() + 1
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let Some((h, cos_wh)) = half_vector(wo, wi) else {
            return Vec3::ZERO;
        };
        self.present_lobes()
            .map(|l| l.eval(wo, wi, h, cos_wh))
            .sum::<Vec3>()
            + self.base.eval(wo, wi)
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let Some((h, cos_wh)) = half_vector(wo, wi) else {
            return 0.0;
        };
        let lobes: f32 = self.present_lobes().map(|l| l.lobe().pdf(h, cos_wh)).sum();
        (lobes + self.base.pdf(wo, wi)) / self.components() as f32
    }

    /// `u.x` picks the component and is rescaled to [0, 1) for it.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let n = self.components();
        let scaled = u.x * n as f32;
        let pick = (scaled as usize).min(n - 1);
        let u = Vec2::new((scaled - pick as f32).min(ONE_MINUS_EPSILON), u.y);
        let wi = match self.present_lobes().nth(pick) {
            Some(lobe) => lobe.lobe().sample(wo, u),
            None => self.base.sample(wo, u)?.wi,
        };
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// The lobes' normal-incidence reflectance over the base's.
    pub fn albedo(&self) -> Vec3 {
        let lobes: Vec3 = self.present_lobes().map(|l| l.specular * l.f0).sum();
        (lobes + self.base.diffuse).min(Vec3::ONE)
    }
}
