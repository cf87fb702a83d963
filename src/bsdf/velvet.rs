//! LuxRender's `velvet` (`materials/velvet.cpp`, `core/reflection/bxdf/asperity.cpp`): asperity
//! scattering after Koenderink and Pont 2002 ("The Secret of Velvety Skin"), a thin layer of
//! sparse scatterers over the surface. Single scattering in a layer of optical thickness
//! delta, seen from wo and lit from wi, gives
//!
//!   f(wo, wi) = R p(cos_s) delta / (cos_o cos_i),  clamped to [0, 1] (the paper's page 7),
//!
//! with cos_s = -wo . wi the cosine of the scattering angle and the phase function p a
//! Legendre series of four terms, the first 1 (`p1`, `p2`, `p3` the others):
//!
//!   p(x) = (1 + A1 P1(x) + A2 P2(x) + A3 P3(x)) / (4 pi),
//!   P1 = x, P2 = (3 x^2 - 1) / 2, P3 = (5 x^3 - 3 x) / 2.
//!
//! f is symmetric in wo and wi, so reciprocal; it is sampled as LuxRender's BxDFs are by
//! default, cosine-weighted on wo's side. Its albedo is not bounded by 1 (the clamp keeps f
//! below 1 but the layer grows bright at grazing angles, as the model intends).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::BsdfSample;
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};

#[derive(Clone, Copy, Debug)]
pub struct Velvet {
    pub reflectance: Vec3,
    /// The phase function's Legendre coefficients A1, A2, A3.
    pub legendre: [f32; 3],
    /// The layer's optical thickness delta.
    pub thickness: f32,
}

impl Velvet {
    /// f, on one side of the surface (velvet reflects only).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z * wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let x = -wo.dot(wi);
        let [a1, a2, a3] = self.legendre;
        let phase = (1.0
            + a1 * x
            + a2 * 0.5 * (3.0 * x * x - 1.0)
            + a3 * 0.5 * (5.0 * x * x * x - 3.0 * x))
            / (4.0 * PI);
        let p = phase * self.thickness / (wo.z * wi.z);
        self.reflectance * p.clamp(0.0, 1.0)
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z * wi.z <= 0.0 {
            return 0.0;
        }
        cosine_hemisphere_pdf(wi.z.abs())
    }

    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let mut wi = cosine_hemisphere(u);
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }
}
