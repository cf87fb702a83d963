//! LuxRender 0.x's `substrate` (`materials/substrate.cpp`, pbrt-v1's `FresnelBlend`): Ashikhmin
//! and Shirley's coupled diffuse and glossy BRDF (2000, "An Anisotropic Phong BRDF Model",
//! eq. 2 and 5), the model LuxRender 1.x's `glossy` later replaced by Schlick's (foton's
//! [`super::CoatedGlossy`], a different function):
//!
//!   f = 28 / (23 pi) Rd (1 - Rs) (1 - (1 - cos_i / 2)^5) (1 - (1 - cos_o / 2)^5)
//!     + D(h) F(wi . h) / (4 (wi . h) max(cos_i, cos_o)),
//!
//! with F = Rs + (1 - Rs)(1 - wi . h)^5 Schlick's Fresnel term and D the anisotropic Phong
//! distribution of exponents 1 / `uroughness` and 1 / `vroughness` ([`PhongDistribution`];
//! Blinn's for u = v, as `substrate.cpp` picks). The diffuse term is the one that makes the sum
//! conserve energy for Rd = 1 (the paper's derivation); sampled as pbrt-v1's
//! `FresnelBlend::Sample_f`: half the samples cosine-weighted, half by the half-vector lobe.

use crate::math::try_normalize;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

use super::BsdfSample;
use super::fresnel::schlick;
use super::phong_distribution::PhongDistribution;

#[derive(Clone, Copy, Debug)]
pub struct FresnelBlend {
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub distribution: PhongDistribution,
}

impl FresnelBlend {
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let grazing = |cos: f32| 1.0 - (1.0 - 0.5 * cos).powi(5);
        let diffuse = self.diffuse
            * (Vec3::ONE - self.specular)
            * (28.0 / (23.0 * PI) * grazing(wi.z) * grazing(wo.z));
        let Some(h) = try_normalize(wo + wi) else {
            return diffuse;
        };
        let cos_ih = wi.dot(h);
        diffuse
            + schlick(self.specular, cos_ih) * self.distribution.d(h)
                / (4.0 * cos_ih * wi.z.max(wo.z))
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.distribution.pdf_with_diffuse(wo, wi)
    }

    pub fn sample(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        let wi = self.distribution.sample_with_diffuse(wo, u, uc)?;
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// Rs at normal incidence plus the diffuse part under it.
    pub fn albedo(&self) -> Vec3 {
        self.specular + (Vec3::ONE - self.specular) * self.diffuse
    }
}
