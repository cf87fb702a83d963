//! The sun as a disc: light of uniform radiance from every direction inside a cone of
//! half-angle theta_max around the direction to the sun, none outside (LuxRender 1.x,
//! `lights/sun.cpp`: sin theta_max = relsize x the sun's radius over its distance).
//!
//! Next-event estimation samples the cone uniformly (pbrt-v4's `SampleUniformCone`): cos theta
//! uniform in [cos theta_max, 1] and phi uniform, so the density per solid angle is the
//! constant 1 / Omega with Omega = 2 pi (1 - cos theta_max) the cone's solid angle. Escaped
//! rays inside the cone see the disc (a mirror shows the sun; BSDF sampling is weighted by MIS
//! against this density).
//!
//! Precision: the real sun's cone has 1 - cos theta_max = 1.08e-5, where a `f32` cos theta_max
//! keeps only two digits (its spacing near 1 is 6e-8). So the light keeps
//! 1 - cos theta_max = sin^2 / (1 + cos) and sin^2 theta_max, samples 1 - cos theta = u (1 -
//! cos theta_max) (the same uniform law for cos theta), with sin^2 theta = (1 - cos)(1 + cos),
//! and tests a direction w against the cone by its squared distance from the axis,
//! |w - (w . a) a|^2 = sin^2 theta <= sin^2 theta_max with w . a > 0 (as `SunLight::Le` does).

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};

use super::LightSample;
use crate::bsdf::frame::Frame;
use crate::film::luminance;

#[derive(Component, Clone, Copy, Debug)]
pub struct SunDiscLight {
    /// The frame whose z axis is the unit vector from the scene towards the disc's centre.
    frame: Frame,
    /// Radiance seen inside the cone.
    radiance: Vec3,
    /// sin^2 theta_max and 1 - cos theta_max of the cone's half-angle.
    sin2_max: f32,
    one_minus_cos_max: f32,
}

impl SunDiscLight {
    /// The disc around `direction_to_light` (normalised here) whose half-angle has sine
    /// `sin_theta_max` in (0, 1], of uniform `radiance`.
    pub fn new(direction_to_light: Vec3, radiance: Vec3, sin_theta_max: f32) -> Self {
        let sin2_max = (sin_theta_max * sin_theta_max).min(1.0);
        Self {
            frame: Frame::from_z(direction_to_light.normalize_or(Vec3::Z)),
            radiance,
            sin2_max,
            one_minus_cos_max: sin2_max / (1.0 + (1.0 - sin2_max).sqrt()),
        }
    }

    /// The cone's solid angle, 2 pi (1 - cos theta_max).
    pub fn solid_angle(&self) -> f32 {
        2.0 * PI * self.one_minus_cos_max
    }

    /// The density of [`SunDiscLight::sample`] per solid angle inside the cone.
    pub fn pdf(&self) -> f32 {
        1.0 / self.solid_angle()
    }

    /// A direction uniform in the cone.
    pub fn sample(&self, u: Vec2) -> LightSample {
        let one_minus_cos = u.x * self.one_minus_cos_max;
        let sin_theta = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let local = Vec3::new(
            sin_theta * phi.cos(),
            sin_theta * phi.sin(),
            1.0 - one_minus_cos,
        );
        LightSample {
            wi: self.frame.to_world(local),
            distance: f32::INFINITY,
            radiance: self.radiance,
            pdf: self.pdf(),
            delta: false,
        }
    }

    /// Whether the unit direction `w` lies inside the cone.
    pub fn contains(&self, w: Vec3) -> bool {
        let along = w.dot(self.frame.z);
        along > 0.0 && (w - along * self.frame.z).length_squared() <= self.sin2_max
    }

    /// The radiance an escaped ray of unit direction `w` sees: the disc's inside the cone.
    pub fn radiance_towards(&self, w: Vec3) -> Vec3 {
        if self.contains(w) {
            self.radiance
        } else {
            Vec3::ZERO
        }
    }

    /// The flux through a disk the size of the scene of the irradiance the disc gives a
    /// surface facing it, radiance times solid angle (pbrt-v4 §12.4's distant light).
    pub fn power(&self, scene_radius: f32) -> f32 {
        PI * scene_radius * scene_radius * luminance(self.radiance) * self.solid_angle()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The solid angle keeps its digits for the real sun's cone (sin theta_max = 695500 /
    /// 149.6e6): 2 pi (1 - sqrt(1 - s^2)) = 6.7906e-5 sr evaluated in double precision.
    #[test]
    fn solid_angle_of_the_real_sun() {
        let sun = SunDiscLight::new(Vec3::Z, Vec3::ONE, 695_500.0 / 149.6e6);
        let exact =
            2.0 * std::f64::consts::PI * (1.0 - (1.0 - (695_500.0f64 / 149.6e6).powi(2)).sqrt());
        assert!(
            (sun.solid_angle() as f64 / exact - 1.0).abs() < 1e-5,
            "{}",
            sun.solid_angle()
        );
    }

    /// Every sampled direction is a unit vector inside the cone, and the cone's rim is reached.
    #[test]
    fn samples_stay_in_the_cone() {
        let axis = Vec3::new(0.3, -0.5, 0.8).normalize();
        for sin_theta_max in [4.6e-3, 0.2, 1.0] {
            let sun = SunDiscLight::new(axis, Vec3::ONE, sin_theta_max);
            for i in 0..64 {
                for j in 0..8 {
                    let u = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 8.0);
                    let w = sun.sample(u).wi;
                    assert!((w.length() - 1.0).abs() < 1e-5, "{w}");
                    assert!(sun.contains(w), "{sin_theta_max}: {w}");
                }
            }
            let rim = sun.sample(Vec2::new(0.999, 0.3)).wi;
            let sin_theta = rim.cross(axis).length();
            assert!(
                (sin_theta / sin_theta_max - 1.0).abs() < 0.01,
                "{sin_theta}"
            );
        }
    }
}
