//! Spot lights: a point light limited to a cone, with a smooth falloff at its rim.

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::Vec3;

use super::LightSample;
use super::point::PointLight;
use crate::film::luminance;

#[derive(Component, Clone, Copy, Debug)]
pub struct SpotLight {
    pub position: Vec3,
    /// Unit axis of the cone.
    pub direction: Vec3,
    pub intensity: Vec3,
    /// Cosines of the cone's half-angle and of where its falloff starts.
    pub cos_total: f32,
    pub cos_falloff_start: f32,
}

impl SpotLight {
    pub fn new(position: Vec3, direction: Vec3, intensity: Vec3, cone: f32, delta: f32) -> Self {
        let cone = cone.clamp(0.0, 180.0);
        Self {
            position,
            direction: direction.normalize_or(Vec3::NEG_Z),
            intensity,
            cos_total: cone.to_radians().cos(),
            cos_falloff_start: (cone - delta.clamp(0.0, cone)).to_radians().cos(),
        }
    }

    /// The falloff of pbrt v1 / LuxRender: 1 inside the inner cone, 0 outside the outer one,
    /// and ((cos - cos_total) / (cos_falloff_start - cos_total))^4 between.
    fn falloff(&self, cos_theta: f32) -> f32 {
        if cos_theta < self.cos_total {
            0.0
        } else if cos_theta >= self.cos_falloff_start {
            1.0
        } else {
            let delta =
                (cos_theta - self.cos_total) / (self.cos_falloff_start - self.cos_total).max(1e-6);
            delta.powi(4)
        }
    }

    pub fn sample(&self, p: Vec3) -> Option<LightSample> {
        let mut sample = PointLight {
            position: self.position,
            intensity: self.intensity,
        }
        .sample(p)?;
        sample.radiance *= self.falloff((-sample.wi).dot(self.direction));
        Some(sample)
    }

    /// pbrt-v3's estimate: the intensity over the cone up to the middle of the falloff.
    pub fn power(&self) -> f32 {
        2.0 * PI
            * (1.0 - 0.5 * (self.cos_total + self.cos_falloff_start))
            * luminance(self.intensity)
    }
}
