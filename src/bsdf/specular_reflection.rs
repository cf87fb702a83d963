//! Perfect specular reflection (LuxRender's `mirror`: no Fresnel term, the
//! reflected fraction is the colour `Kr`).

use super::BsdfSample;
use glam::Vec3;

#[derive(Clone, Copy, Debug)]
pub struct SpecularReflection {
    pub reflectance: Vec3,
}

impl SpecularReflection {
    /// The mirror direction about the normal: (-x, -y, z). Delta lobe with
    /// probability 1; f = R / |cos(theta_i)| so that f |cos| / pdf = R.
    pub fn sample(&self, wo: Vec3) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = Vec3::new(-wo.x, -wo.y, wo.z);
        Some(BsdfSample {
            wi,
            f: self.reflectance / wi.z,
            pdf: 1.0,
            delta: true,
        })
    }
}
