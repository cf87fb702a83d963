//! Rough plastic (Mitsuba 3's `roughplastic`, `src/bsdfs/roughplastic.cpp`): the smooth
//! plastic of `plastic.rs` with a rough (GGX) coating. The coating reflects as a microfacet
//! dielectric,
//!
//!   f_s(wo, wi) = Ks F(wo . h; eta) D(h) G1(wo) G1(wi) / (4 cos_o cos_i),
//!
//! and the light it lets through is the rough interface's directional transmittance
//! t(cos) = integral of G1(wt) (1 - F) over the normals visible from the direction, wt the
//! refracted direction (the albedo of the transmitted lobe of `rough_dielectric.rs`). So
//!
//!   f_d(wo, wi) = Kd' t(cos_o) t(cos_i) / (pi eta^2),
//!
//! with Kd' the base summed over its interreflections (`plastic::summed_base`) with the rough
//! coating's internal reflectance. Both follow Mitsuba: t tabulated at 64 cosines
//! mu_j = max(1e-6, j / 63) and interpolated linearly, and the internal reflectance
//! 2 mean_j(R(mu_j; 1 / eta) mu_j) over the same cosines, R the reflected lobe's albedo seen
//! from inside (Mitsuba's own quadrature, kept so that the base's brightness is the same).
//! foton integrates each albedo over the visible normals on a 48 x 48 midpoint grid.
//! Sampling: the specular lobe (visible normals) with probability from 1 - t(cos_o) and Ks,
//! as in `plastic.rs`, else a cosine lobe; the pdf is the mixture of both densities.

use std::sync::{Mutex, OnceLock};

use super::BsdfSample;
use super::dielectric::{clamp_eta, refract};
use super::fresnel::fr_dielectric;
use super::microfacet::TrowbridgeReitz;
use super::plastic::{specular_probability, summed_base};
use crate::math::try_normalize;
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// The number of tabulated cosines (Mitsuba's `MI_ROUGH_TRANSMITTANCE_RES`).
const TABLE_SIZE: usize = 64;
/// The quadrature grid over the visible normals, per axis.
const GRID: usize = 48;

/// What a rough coating of one (alpha, eta) lets through, computed once per pair.
#[derive(Debug, PartialEq)]
pub struct CoatingTables {
    /// t(mu_j), mu_j = max(1e-6, j / 63).
    transmittance: [f32; TABLE_SIZE],
    /// The coating's reflectance of diffuse light from inside.
    internal_reflectance: f32,
}

/// The coating's albedo for the direction `w` (w.z > 0) and relative index `eta`, split into
/// the reflected and the transmitted parts: the mean of G1(w') F (reflected w') and of
/// G1(w') (1 - F) (refracted w') over normals drawn from D_w (Mitsuba's `eval_reflectance`,
/// `eval_transmittance`; f cos / pdf of visible-normal sampling is G1(w') times the lobe's
/// Fresnel weight).
fn coating_albedo(distribution: &TrowbridgeReitz, w: Vec3, eta: f32) -> (f32, f32) {
    let (mut reflected, mut transmitted) = (0.0f64, 0.0f64);
    for i in 0..GRID * GRID {
        let u = Vec2::new(
            ((i % GRID) as f32 + 0.5) / GRID as f32,
            ((i / GRID) as f32 + 0.5) / GRID as f32,
        );
        let wm = distribution.sample_wm(w, u);
        let f = fr_dielectric(w.dot(wm), eta);
        let wr = 2.0 * w.dot(wm) * wm - w;
        if wr.z > 0.0 && wr.dot(wm) > 0.0 {
            reflected += (distribution.g1(wr) * f) as f64;
        }
        if let Some((wt, _)) = refract(w, wm, eta)
            && wt.z < 0.0
            && wt.dot(wm) < 0.0
        {
            transmitted += (distribution.g1(wt) * (1.0 - f)) as f64;
        }
    }
    let n = (GRID * GRID) as f64;
    ((reflected / n) as f32, (transmitted / n) as f32)
}

impl CoatingTables {
    fn compute(alpha: f32, eta: f32) -> Self {
        let distribution = TrowbridgeReitz::new(alpha, alpha);
        let mut transmittance = [0.0; TABLE_SIZE];
        let mut internal = 0.0;
        for (j, t) in transmittance.iter_mut().enumerate() {
            let mu = (j as f32 / (TABLE_SIZE - 1) as f32).max(1e-6);
            let w = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
            *t = coating_albedo(&distribution, w, eta).1;
            internal += coating_albedo(&distribution, w, 1.0 / eta).0 * mu;
        }
        Self {
            transmittance,
            internal_reflectance: 2.0 * internal / TABLE_SIZE as f32,
        }
    }

    /// The tables of a coating, computed on first use and kept for the process (interned by
    /// the bits of alpha and eta, so that a scene loaded again reuses them).
    pub fn of(alpha: f32, eta: f32) -> &'static CoatingTables {
        type Interned = Vec<((u32, u32), &'static CoatingTables)>;
        static TABLES: OnceLock<Mutex<Interned>> = OnceLock::new();
        let (alpha, eta) = (alpha, clamp_eta(eta));
        let key = (alpha.to_bits(), eta.to_bits());
        let mut tables = TABLES
            .get_or_init(Default::default)
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some((_, t)) = tables.iter().find(|(k, _)| *k == key) {
            return t;
        }
        let t: &'static CoatingTables = Box::leak(Box::new(Self::compute(alpha, eta)));
        tables.push((key, t));
        t
    }

    /// t(cos), linearly interpolated as Mitsuba's `lerp_gather`.
    pub fn transmittance(&self, cos: f32) -> f32 {
        let x = cos.clamp(0.0, 1.0) * (TABLE_SIZE - 1) as f32;
        let j = (x as usize).min(TABLE_SIZE - 2);
        let w = x - j as f32;
        self.transmittance[j] * (1.0 - w) + self.transmittance[j + 1] * w
    }

    pub fn internal_reflectance(&self) -> f32 {
        self.internal_reflectance
    }
}

#[derive(Clone, Copy, Debug)]
pub struct RoughPlastic {
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// Coating index over outside index.
    pub eta: f32,
    pub distribution: TrowbridgeReitz,
    pub nonlinear: bool,
    /// [`CoatingTables::of`] this coating's alpha and eta.
    pub tables: &'static CoatingTables,
}

impl RoughPlastic {
    fn eta(&self) -> f32 {
        clamp_eta(self.eta)
    }

    fn specular_probability(&self, wo: Vec3) -> f32 {
        let reflected = 1.0 - self.tables.transmittance(wo.z);
        specular_probability(self.diffuse, self.specular, reflected)
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let Some(h) = try_normalize(wo + wi) else {
            return Vec3::ZERO;
        };
        let d = &self.distribution;
        let f = fr_dielectric(wo.dot(h), self.eta());
        let specular = self.specular * (f * d.d(h) * d.g1(wo) * d.g1(wi) / (4.0 * wo.z * wi.z));
        let base = summed_base(
            self.diffuse,
            self.tables.internal_reflectance,
            self.nonlinear,
        );
        let crossings = self.tables.transmittance(wo.z) * self.tables.transmittance(wi.z);
        specular + base * (crossings * FRAC_1_PI / (self.eta() * self.eta()))
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let Some(h) = try_normalize(wo + wi) else {
            return 0.0;
        };
        let p_specular = self.specular_probability(wo);
        let specular = self.distribution.d_visible(wo, h) / (4.0 * wo.dot(h));
        p_specular * specular + (1.0 - p_specular) * cosine_hemisphere_pdf(wi.z)
    }

    pub fn sample(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = if uc < self.specular_probability(wo) {
            let wm = self.distribution.sample_wm(wo, u);
            2.0 * wo.dot(wm) * wm - wo
        } else {
            cosine_hemisphere(u)
        };
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// The coating's reflectance at normal incidence, and the base through the rest.
    pub fn albedo(&self) -> Vec3 {
        let t = self.tables.transmittance(1.0);
        self.specular * (1.0 - t) + self.diffuse * t
    }
}
