//! Point lights: radiant intensity from one point.

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::Vec3;

use super::LightSample;
use crate::film::luminance;

#[derive(Component, Clone, Copy, Debug)]
pub struct PointLight {
    pub position: Vec3,
    pub intensity: Vec3,
}

impl PointLight {
    /// Incident radiance at `p` falls off with the squared distance (a delta light).
    pub fn sample(&self, p: Vec3) -> Option<LightSample> {
        let to_light = self.position - p;
        let distance_squared = to_light.length_squared();
        if distance_squared == 0.0 {
            return None;
        }
        let distance = distance_squared.sqrt();
        Some(LightSample {
            wi: to_light / distance,
            distance,
            radiance: self.intensity / distance_squared,
            pdf: 1.0,
            delta: true,
        })
    }

    pub fn power(&self) -> f32 {
        4.0 * PI * luminance(self.intensity)
    }
}
