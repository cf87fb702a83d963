//! Spot lights: a point light limited to a cone, with a smooth falloff at its rim.

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::Vec3;

use super::LightSample;
use super::bvh::LightBounds;
use super::point::PointLight;
use crate::film::luminance;

/// How a spot's intensity falls from full, inside its beam, to zero at its cone's edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpotFalloff {
    /// pbrt v1 and LuxRender (`lights/spot.cpp`): ((cos theta - cos theta_cone) /
    /// (cos theta_beam - cos theta_cone))^4.
    SmoothCosine,
    /// Mitsuba 3 (`emitters/spot.cpp`, `falloff_curve`): linear in the angle,
    /// (theta_cone - theta) / (theta_cone - theta_beam).
    LinearAngle,
}

#[derive(Component, Clone, Copy, Debug)]
pub struct SpotLight {
    pub position: Vec3,
    /// Unit axis of the cone.
    pub direction: Vec3,
    pub intensity: Vec3,
    /// The cone's half-angle and where its falloff starts (the beam's), in radians, and their
    /// cosines.
    pub cone: f32,
    pub beam: f32,
    pub cos_total: f32,
    pub cos_falloff_start: f32,
    pub falloff: SpotFalloff,
}

impl SpotLight {
    /// A spot with a cone of half-angle `cone` degrees whose falloff spans its outer `delta`
    /// degrees.
    pub fn new(
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        (cone, delta): (f32, f32),
        falloff: SpotFalloff,
    ) -> Self {
        let cone = cone.clamp(0.0, 180.0);
        let beam = cone - delta.clamp(0.0, cone);
        Self {
            position,
            direction: direction.normalize_or(Vec3::NEG_Z),
            intensity,
            cone: cone.to_radians(),
            beam: beam.to_radians(),
            cos_total: cone.to_radians().cos(),
            cos_falloff_start: beam.to_radians().cos(),
            falloff,
        }
    }

    /// 1 inside the beam, 0 outside the cone, and the [`SpotFalloff`] curve between.
    fn falloff(&self, cos_theta: f32) -> f32 {
        if cos_theta < self.cos_total {
            0.0
        } else if cos_theta >= self.cos_falloff_start {
            1.0
        } else {
            match self.falloff {
                SpotFalloff::SmoothCosine => {
                    let delta = (cos_theta - self.cos_total)
                        / (self.cos_falloff_start - self.cos_total).max(1e-6);
                    delta.powi(4)
                }
                SpotFalloff::LinearAngle => ((self.cone - cos_theta.clamp(-1.0, 1.0).acos())
                    / (self.cone - self.beam).max(1e-6))
                .clamp(0.0, 1.0),
            }
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

    /// For the light BVH: a point emitting within the beam's cone about the axis and, past
    /// it, over the falloff's angle (pbrt-v4's `SpotLight::Bounds`: theta_o the beam,
    /// theta_e the falloff's width).
    pub fn bounds(&self) -> LightBounds {
        LightBounds {
            axis: self.direction,
            cos_normals: self.cos_falloff_start,
            cos_emission: (self.cone - self.beam).cos(),
            ..LightBounds::point(self.position, self.power())
        }
    }

    /// pbrt-v3's estimate: the intensity over the cone up to the middle of the falloff.
    pub fn power(&self) -> f32 {
        2.0 * PI
            * (1.0 - 0.5 * (self.cos_total + self.cos_falloff_start))
            * luminance(self.intensity)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The intensity reaching a point 1 away at `degrees` off the axis of a spot with a cone of
    /// 20 degrees and a beam of 10.
    fn intensity(falloff: SpotFalloff, degrees: f32) -> f32 {
        let spot = SpotLight::new(Vec3::ZERO, Vec3::Z, Vec3::ONE, (20.0, 10.0), falloff);
        let (sin, cos) = degrees.to_radians().sin_cos();
        spot.sample(Vec3::new(sin, 0.0, cos)).unwrap().radiance.x
    }

    #[test]
    fn mitsubas_falloff_is_linear_in_the_angle_and_luxrenders_quartic_in_the_cosine() {
        for falloff in [SpotFalloff::LinearAngle, SpotFalloff::SmoothCosine] {
            assert!((intensity(falloff, 5.0) - 1.0).abs() < 1e-5);
            assert_eq!(intensity(falloff, 21.0), 0.0);
        }
        // Mitsuba's `falloff_curve`: (20 - 15) / (20 - 10) halfway through the band.
        assert!((intensity(SpotFalloff::LinearAngle, 15.0) - 0.5).abs() < 1e-4);
        assert!((intensity(SpotFalloff::LinearAngle, 18.0) - 0.2).abs() < 1e-4);
        let cos = |d: f32| d.to_radians().cos();
        let smooth = ((cos(15.0) - cos(20.0)) / (cos(10.0) - cos(20.0))).powi(4);
        assert!((intensity(SpotFalloff::SmoothCosine, 15.0) - smooth).abs() < 1e-4);
    }
}
