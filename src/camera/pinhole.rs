//! The pinhole perspective camera.

use bevy_ecs::prelude::*;
use glam::Vec3;

use super::{CameraStage, generate_camera_rays, raster_to_screen, register_for};
use crate::integrator::batch::PathBatch;
use crate::settings::RenderSettings;

/// A perspective projection: screen coordinate 1 is at `tan(fov / 2)` on the plane z = 1.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Pinhole {
    pub fov_degrees: f32,
    /// [xmin, xmax, ymin, ymax] in screen coordinates.
    pub screen_window: [f32; 4],
}

pub fn register(pass: &mut Schedule, world: &mut World) {
    register_for::<Pinhole, _>(pass, world, CameraStage::Generate, generate_pinhole_rays);
}

fn generate_pinhole_rays(
    camera: Single<&Pinhole>,
    settings: Res<RenderSettings>,
    mut batch: ResMut<PathBatch>,
) {
    let camera = **camera;
    let tan_half_fov = (camera.fov_degrees.to_radians() * 0.5).tan();
    let (width, height) = (settings.width, settings.height);
    generate_camera_rays(&mut batch, |film| {
        let screen = raster_to_screen(film, width, height, camera.screen_window);
        Some((Vec3::ZERO, (screen * tan_half_fov).extend(1.0)))
    });
}
