//! Thin dielectric sheet (Mitsuba 3's `thindielectric`, `src/bsdfs/thindielectric.cpp`): a
//! slab so thin that light leaving it continues along its incoming line (the two refractions
//! cancel) and the interreflections inside add up.
//!
//! With R the Fresnel reflectance of one interface at the incident angle (the same from
//! either side, Mitsuba evaluates it at |cos theta| with eta) and T = 1 - R, a ray reflects
//! off the front face (R), or enters and leaves after an even number of internal bounces:
//!
//!   R' = R + T R T + T R^3 T + ... = R + T^2 R / (1 - R^2) = 2 R / (1 + R),
//!   T' = 1 - R' = T^2 (1 + R^2 + R^4 + ...) = (1 - R) / (1 + R).
//!
//! Both lobes are deltas: mirror reflection with weight R', and straight transmission
//! (wi = -wo) with weight T', chosen with those probabilities.

use super::BsdfSample;
use super::dielectric::clamp_eta;
use super::fresnel::fr_dielectric;
use glam::Vec3;

#[derive(Clone, Copy, Debug)]
pub struct ThinDielectric {
    pub reflectance: Vec3,
    pub transmittance: Vec3,
    /// Index of the sheet over that of its surroundings.
    pub eta: f32,
}

impl ThinDielectric {
    /// R' = 2 R / (1 + R) for a direction whose cosine with the normal is `cos`.
    pub fn sheet_reflectance(&self, cos: f32) -> f32 {
        let r = fr_dielectric(cos.abs(), clamp_eta(self.eta));
        2.0 * r / (1.0 + r)
    }

    pub fn sample(&self, wo: Vec3, uc: f32) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let r = self.sheet_reflectance(wo.z);
        let (wi, weight, pdf) = if uc < r {
            (Vec3::new(-wo.x, -wo.y, wo.z), self.reflectance, r)
        } else {
            (-wo, self.transmittance, 1.0 - r)
        };
        Some(BsdfSample {
            wi,
            f: weight * (pdf / wi.z.abs()),
            pdf,
            delta: true,
        })
    }

    /// Kr and Kt blended by the sheet's reflectance at normal incidence.
    pub fn albedo(&self) -> Vec3 {
        let r = self.sheet_reflectance(1.0);
        self.reflectance * r + self.transmittance * (1.0 - r)
    }
}
