//! Perfect specular reflection (LuxRender's `mirror`: no Fresnel term, the
//! reflected fraction is the colour `Kr`).

use super::BsdfSample;
use glam::Vec3;

#[derive(Clone, Copy, Debug)]
pub struct SpecularReflection {
    pub reflectance: Vec3,
}

impl SpecularReflection {
    /// The mirror direction, reflecting the fraction R (no Fresnel term).
    pub fn sample(&self, wo: Vec3) -> Option<BsdfSample> {
        BsdfSample::mirror(wo, self.reflectance)
    }
}
