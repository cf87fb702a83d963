//! The pinhole perspective camera.

use bevy_ecs::prelude::*;
use glam::Vec3;
use rayon::prelude::*;

use super::{CameraStage, raster_to_screen, world_has};
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
    if world_has::<Pinhole>(world) {
        pass.add_systems(
            generate_pinhole_rays
                .run_if(any_with_component::<Pinhole>)
                .in_set(CameraStage::Generate),
        );
    }
}

fn generate_pinhole_rays(
    camera: Single<&Pinhole>,
    settings: Res<RenderSettings>,
    mut batch: ResMut<PathBatch>,
) {
    let camera = **camera;
    let tan_half_fov = (camera.fov_degrees.to_radians() * 0.5).tan();
    let (width, height) = (settings.width, settings.height);
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
            let screen = raster_to_screen(*film, width, height, camera.screen_window);
            *origin = Vec3::ZERO;
            *direction = (screen * tan_half_fov).extend(1.0);
        });
}
