//! The equidistant fisheye: the angle from the view axis grows linearly with the distance from
//! the image centre (Paul Bourke, "Computer generated angular fisheye projections", 2001; the
//! seed report's §3). Aperture 0 to 360 degrees.

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};

use super::{CameraRays, CameraStage, CameraType, FovRange, register_for};
use crate::settings::RenderSettings;

#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Fisheye {
    /// The full aperture, 0 to 360 degrees.
    pub fov_degrees: f32,
    pub fit: FisheyeFit,
}

/// How the image circle sits in the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FisheyeFit {
    /// Each axis normalised to [-1, 1] on its own: on a non-square image an ellipse touching all
    /// four borders (the original renderer and Blender Cycles' `FISHEYE_EQUIDISTANT`).
    Ellipse,
    /// The shorter axis normalised to [-1, 1]: a circle inscribed in the frame.
    Circle,
}

/// The aperture is `--fisheye-fov`, else the scene's if its camera is a fisheye, else 180
/// degrees; the fit is `--fisheye-fit`.
pub static CAMERA: CameraType = CameraType {
    names: &["fisheye"],
    fov: Some(FovRange {
        default: 180.0,
        max: 360.0,
    }),
    build: |setup, entity, _| {
        let scene_fov = setup.scene_names_it.then_some(setup.scene.fov_degrees);
        entity.insert(Fisheye {
            fov_degrees: setup.options.fisheye_fov.or(scene_fov).unwrap_or(180.0),
            fit: setup.options.fisheye_fit,
        });
    },
    register,
};

fn register(pass: &mut Schedule, world: &mut World) {
    register_for::<Fisheye, _>(pass, world, CameraStage::Generate, generate_fisheye_rays);
}

/// The camera-space unit direction for a film point normalised to [-1, 1] (y up), or `None`
/// outside the image circle (r > 1).
pub fn fisheye_direction(normalized: Vec2, fov_radians: f32) -> Option<Vec3> {
    let r = normalized.length();
    if r > 1.0 {
        return None;
    }
    let phi = normalized.y.atan2(normalized.x);
    let theta = r * fov_radians * 0.5;
    let (sin_theta, cos_theta) = theta.sin_cos();
    Some(Vec3::new(
        sin_theta * phi.cos(),
        sin_theta * phi.sin(),
        cos_theta,
    ))
}

fn generate_fisheye_rays(
    camera: Single<&Fisheye>,
    settings: Res<RenderSettings>,
    mut rays: CameraRays,
) {
    let fov = camera.fov_degrees.clamp(0.0, 360.0) * PI / 180.0;
    let size = Vec2::new(settings.width as f32, settings.height as f32);
    let half_extent = match camera.fit {
        FisheyeFit::Ellipse => size * 0.5,
        FisheyeFit::Circle => Vec2::splat(size.min_element() * 0.5),
    };
    // Outside the image circle: a black sample that costs no ray.
    rays.generate(|film| {
        let centred = (film - size * 0.5) / half_extent;
        fisheye_direction(Vec2::new(centred.x, -centred.y), fov).map(|d| (Vec3::ZERO, d))
    });
}
