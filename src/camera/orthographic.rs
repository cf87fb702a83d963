//! The orthographic camera: parallel rays along the view axis, starting across the screen
//! window (in camera-space units).

use bevy_ecs::prelude::*;
use glam::Vec3;
use rayon::prelude::*;

use super::{CameraStage, raster_to_screen, world_has};
use crate::integrator::batch::PathBatch;
use crate::settings::RenderSettings;

#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Orthographic {
    /// [xmin, xmax, ymin, ymax] in camera-space units.
    pub screen_window: [f32; 4],
}

pub fn register(pass: &mut Schedule, world: &mut World) {
    if world_has::<Orthographic>(world) {
        pass.add_systems(
            generate_orthographic_rays
                .run_if(any_with_component::<Orthographic>)
                .in_set(CameraStage::Generate),
        );
    }
}

fn generate_orthographic_rays(
    camera: Single<&Orthographic>,
    settings: Res<RenderSettings>,
    mut batch: ResMut<PathBatch>,
) {
    let window = camera.screen_window;
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
            *origin = raster_to_screen(*film, width, height, window).extend(0.0);
            // z = 1: the focal plane, for a lens, is at the focal distance.
            *direction = Vec3::Z;
        });
}
