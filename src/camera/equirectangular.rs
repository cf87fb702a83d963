//! The equirectangular (latitude-longitude) panorama: 360 degrees across the image, 180 down it.
//! The image centre looks along the view axis, image right turns towards camera +x, image up
//! towards camera +y.

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::Vec3;

use super::{CameraRays, CameraStage, CameraType, register_for};
use crate::settings::RenderSettings;

#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Equirectangular;

/// LuxRender calls it `environment`.
pub static CAMERA: CameraType = CameraType {
    names: &["equirectangular", "environment"],
    fov: None,
    build: |_, entity, _| {
        entity.insert(Equirectangular);
    },
    register,
};

fn register(pass: &mut Schedule, world: &mut World) {
    register_for::<Equirectangular, _>(
        pass,
        world,
        CameraStage::Generate,
        generate_equirectangular_rays,
    );
}

/// The camera-space unit direction for longitude `longitude` (0 ahead, positive to the right)
/// and latitude `latitude` (0 at the horizon, positive up).
pub fn equirectangular_direction(longitude: f32, latitude: f32) -> Vec3 {
    let (sin_lon, cos_lon) = longitude.sin_cos();
    let (sin_lat, cos_lat) = latitude.sin_cos();
    Vec3::new(cos_lat * sin_lon, sin_lat, cos_lat * cos_lon)
}

fn generate_equirectangular_rays(settings: Res<RenderSettings>, mut rays: CameraRays) {
    let (width, height) = (settings.width as f32, settings.height as f32);
    rays.generate(|film| {
        let longitude = (film.x / width - 0.5) * 2.0 * PI;
        let latitude = (0.5 - film.y / height) * PI;
        Some((Vec3::ZERO, equirectangular_direction(longitude, latitude)))
    });
}
