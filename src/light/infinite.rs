//! The infinite (environment) light: radiance arriving from every direction, constant or from a
//! latitude-longitude map, importance-sampled by the map's luminance (pbrt-v3 §14.2.4).

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::{Mat3, Vec2, Vec3};

use super::LightSample;
use crate::film::luminance;
use crate::material::texture::{ImageTexture, sample_bilinear};
use crate::sampling::Distribution2D;
use crate::sampling::warp::{uniform_sphere, uniform_sphere_pdf};

/// The entity's component, as the scene gives it.
#[derive(Component, Clone, Debug)]
pub struct InfiniteLight {
    pub radiance: Vec3,
    pub map: Option<ImageTexture>,
    pub light_to_world: Mat3,
}

/// The light, ready for sampling.
#[derive(Clone, Debug)]
pub struct Environment {
    radiance: Vec3,
    map: Option<EnvironmentMap>,
}

#[derive(Clone, Debug)]
struct EnvironmentMap {
    image: ImageTexture,
    distribution: Distribution2D,
    light_to_world: Mat3,
    world_to_light: Mat3,
}

impl Environment {
    pub fn new(light: &InfiniteLight) -> Self {
        let map = light.map.as_ref().map(|image| {
            let (w, h) = (image.width as usize, image.height as usize);
            // Weight each texel by sin(theta): rows near the poles cover less solid angle.
            let weights: Vec<f32> = (0..w * h)
                .map(|i| {
                    let theta = PI * ((i / w) as f32 + 0.5) / h as f32;
                    luminance(image.texels[i]) * theta.sin()
                })
                .collect();
            EnvironmentMap {
                image: image.clone(),
                distribution: Distribution2D::new(&weights, w, h),
                light_to_world: light.light_to_world,
                world_to_light: light.light_to_world.inverse(),
            }
        });
        Self {
            radiance: light.radiance,
            map,
        }
    }

    /// Radiance arriving along `-direction` (from `direction`).
    pub fn radiance(&self, direction: Vec3) -> Vec3 {
        match &self.map {
            None => self.radiance,
            Some(map) => {
                let uv = direction_to_uv((map.world_to_light * direction).normalize_or(Vec3::Z));
                self.radiance * sample_bilinear(&map.image, uv)
            }
        }
    }

    pub fn sample(&self, u: Vec2) -> Option<LightSample> {
        let (wi, pdf) = match &self.map {
            None => (uniform_sphere(u), uniform_sphere_pdf()),
            Some(map) => {
                let (uv, map_pdf) = map.distribution.sample_continuous(u);
                let (local, sin_theta) = uv_to_direction(uv);
                if map_pdf <= 0.0 || sin_theta <= 0.0 {
                    return None;
                }
                // The (u, v) -> direction map has Jacobian 2 pi^2 sin(theta).
                (
                    (map.light_to_world * local).normalize_or(Vec3::Z),
                    map_pdf / (2.0 * PI * PI * sin_theta),
                )
            }
        };
        Some(LightSample {
            wi,
            distance: f32::INFINITY,
            radiance: self.radiance(wi),
            pdf,
            delta: false,
        })
    }

    /// Solid-angle density of `sample` choosing `direction`.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        match &self.map {
            None => uniform_sphere_pdf(),
            Some(map) => {
                let local = (map.world_to_light * direction).normalize_or(Vec3::Z);
                let sin_theta = (1.0 - local.z * local.z).max(0.0).sqrt();
                if sin_theta <= 0.0 {
                    return 0.0;
                }
                map.distribution.pdf(direction_to_uv(local)) / (2.0 * PI * PI * sin_theta)
            }
        }
    }

    /// pbrt-v4's estimate for the light sampler: 4 pi^2 r^2 times the mean radiance.
    pub fn power(&self, scene_radius: f32) -> f32 {
        let mean = match &self.map {
            None => luminance(self.radiance),
            Some(map) => {
                let texels = &map.image.texels;
                let total: f32 = texels.iter().map(|t| luminance(*t)).sum();
                total / texels.len().max(1) as f32 * luminance(self.radiance)
            }
        };
        4.0 * PI * PI * scene_radius * scene_radius * mean
    }
}

/// Latitude-longitude: u = phi / 2pi around +z, v = theta / pi from +z.
fn direction_to_uv(d: Vec3) -> Vec2 {
    let phi = d.y.atan2(d.x);
    let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
    Vec2::new(phi / (2.0 * PI), d.z.clamp(-1.0, 1.0).acos() / PI)
}

fn uv_to_direction(uv: Vec2) -> (Vec3, f32) {
    let (phi, theta) = (uv.x * 2.0 * PI, uv.y * PI);
    let (sin_theta, cos_theta) = theta.sin_cos();
    (
        Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta),
        sin_theta,
    )
}
