//! A smooth conductor (Mitsuba 3's `conductor`, `src/bsdfs/conductor.cpp`): mirror reflection
//! whose reflected fraction is the exact Fresnel reflectance of the complex index eta + i k at
//! the angle of incidence ([`fr_conductor`]), times `reflectance` (Mitsuba's
//! `specular_reflectance`, 1 for a physical conductor).

use super::BsdfSample;
use super::fresnel::fr_conductor;
use glam::Vec3;

#[derive(Clone, Copy, Debug)]
pub struct SmoothConductor {
    pub reflectance: Vec3,
    /// The complex index of refraction, relative to the outside.
    pub eta: Vec3,
    pub k: Vec3,
}

impl SmoothConductor {
    /// The mirror direction (-x, -y, z) with probability 1; f = R F(cos) / cos(theta_i) so that
    /// f |cos| / pdf = R F(cos).
    pub fn sample(&self, wo: Vec3) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = Vec3::new(-wo.x, -wo.y, wo.z);
        Some(BsdfSample {
            wi,
            f: self.reflectance * fr_conductor(wo.z, self.eta, self.k) / wi.z,
            pdf: 1.0,
            delta: true,
        })
    }
}
