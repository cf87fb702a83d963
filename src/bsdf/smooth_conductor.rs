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
    /// The mirror direction, reflecting R F(cos) of the incident light.
    pub fn sample(&self, wo: Vec3) -> Option<BsdfSample> {
        BsdfSample::mirror(wo, self.reflectance * fr_conductor(wo.z, self.eta, self.k))
    }
}
