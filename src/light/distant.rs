//! Distant (directional) lights: parallel light from one direction.

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::Vec3;

use super::LightSample;
use crate::film::luminance;

#[derive(Component, Clone, Copy, Debug)]
pub struct DistantLight {
    /// Unit vector from the scene towards the light.
    pub direction_to_light: Vec3,
    pub radiance: Vec3,
}

impl DistantLight {
    pub fn sample(&self) -> LightSample {
        LightSample {
            wi: self.direction_to_light,
            distance: f32::INFINITY,
            radiance: self.radiance,
            pdf: 1.0,
            delta: true,
        }
    }

    /// The flux through a disk the size of the scene (pbrt-v4 §12.4).
    pub fn power(&self, scene_radius: f32) -> f32 {
        PI * scene_radius * scene_radius * luminance(self.radiance)
    }
}
