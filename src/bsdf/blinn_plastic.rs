//! LuxRender 0.x's `plastic` (`materials/plastic.cpp`, pbrt-v1's): a Lambertian base plus a
//! Cook-Torrance microfacet lobe, summed (no layering: the two are not energy-coupled),
//!
//!   f = Kd / pi + Ks D(h) G F(wi . h) / (4 cos_i cos_o),
//!
//! with D Blinn's distribution of exponent 1 / roughness ([`PhongDistribution`]), G the
//! V-cavity shadowing of Torrance and Sparrow as pbrt-v1 writes it (`Microfacet::G`),
//!
//!   G = min(1, 2 cos_h cos_o / (wo . h), 2 cos_h cos_i / (wo . h)),
//!
//! and F pbrt-v1's `FresnelDielectric(1.5, 1)`: incidence from the index-1.5 side into index 1
//! (the order of pbrt's arguments is eta_i, eta_t), so F is the reflectance of glass seen from
//! inside and is 1 (total internal reflection) beyond asin(1 / 1.5) = 41.8 degrees between wi
//! and h. That is what pbrt-v1, and so LuxRender 0.x, render; foton keeps it.
//!
//! Sampled as pbrt-v1's `BSDF` samples two components: each with probability 1/2 (the cosine
//! or a Blinn half vector), the density the average of both.

use crate::math::try_normalize;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

use super::BsdfSample;
use super::fresnel::fr_dielectric;
use super::phong_distribution::PhongDistribution;

/// The index of `plastic`'s coating: pbrt-v1's `FresnelDielectric(1.5, 1)` lights it from the
/// 1.5 side, so the relative index seen by the incident light is 1 / 1.5.
const INCIDENT_SIDE_INDEX: f32 = 1.5;

#[derive(Clone, Copy, Debug)]
pub struct BlinnPlastic {
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub distribution: PhongDistribution,
}

impl BlinnPlastic {
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let diffuse = self.diffuse * FRAC_1_PI;
        let Some(h) = try_normalize(wo + wi) else {
            return diffuse;
        };
        // wo . h = wi . h; their mean keeps f exactly reciprocal in floating point (F is steep
        // near its critical angle).
        let cos_oh = 0.5 * (wo.dot(h) + wi.dot(h));
        let g = (2.0 * h.z * wo.z.min(wi.z) / cos_oh).min(1.0);
        let fresnel = fr_dielectric(cos_oh, 1.0 / INCIDENT_SIDE_INDEX);
        diffuse + self.specular * (self.distribution.d(h) * g * fresnel / (4.0 * wi.z * wo.z))
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.distribution.pdf_with_diffuse(wo, wi)
    }

    pub fn sample(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        let wi = self.distribution.sample_with_diffuse(wo, u, uc)?;
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// Diffuse plus the lobe's specular colour: the estimate Russian roulette needs.
    pub fn albedo(&self) -> Vec3 {
        (self.diffuse + self.specular).min(Vec3::ONE)
    }
}
