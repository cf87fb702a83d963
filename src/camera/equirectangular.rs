//! The equirectangular (latitude-longitude) panorama: 360 degrees across the image, 180 down it.
//! The image centre looks along the view axis, image right turns towards camera +x, image up
//! towards camera +y.

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::Vec3;
use rayon::prelude::*;

use super::{CameraStage, world_has};
use crate::integrator::batch::PathBatch;
use crate::settings::RenderSettings;

#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Equirectangular;

pub fn register(pass: &mut Schedule, world: &mut World) {
    if world_has::<Equirectangular>(world) {
        pass.add_systems(
            generate_equirectangular_rays
                .run_if(any_with_component::<Equirectangular>)
                .in_set(CameraStage::Generate),
        );
    }
}

/// The camera-space unit direction for longitude `longitude` (0 ahead, positive to the right)
/// and latitude `latitude` (0 at the horizon, positive up).
pub fn equirectangular_direction(longitude: f32, latitude: f32) -> Vec3 {
    let (sin_lon, cos_lon) = longitude.sin_cos();
    let (sin_lat, cos_lat) = latitude.sin_cos();
    Vec3::new(cos_lat * sin_lon, sin_lat, cos_lat * cos_lon)
}

fn generate_equirectangular_rays(settings: Res<RenderSettings>, mut batch: ResMut<PathBatch>) {
    let (width, height) = (settings.width as f32, settings.height as f32);
    let batch = &mut *batch;
    let n = batch.len;
    (
        &batch.film_position[..n],
        &mut batch.origin[..n],
        &mut batch.direction[..n],
    )
        .into_par_iter()
        .with_min_len(1024)
        .for_each(|(film, origin, direction)| {
            let longitude = (film.x / width - 0.5) * 2.0 * PI;
            let latitude = (0.5 - film.y / height) * PI;
            *origin = Vec3::ZERO;
            *direction = equirectangular_direction(longitude, latitude);
        });
}
