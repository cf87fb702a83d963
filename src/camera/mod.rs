//! Cameras as components. Each camera file holds its component and the system that turns the
//! batch's film positions into camera-space rays; the system runs only when its component exists.
//! The stages after ray generation (the lens, the move to world space) do not know which camera
//! made the rays, and nothing after them does either.
//!
//! Ray generation writes directions whose length places the focus surface: a point at distance
//! `f` in focus lies at `origin + f * direction`. Planar projections write `z = 1` (a focal plane),
//! spherical ones unit vectors (a focal sphere). The thin lens relies only on that.

pub mod equirectangular;
pub mod fisheye;
pub mod orthographic;
pub mod pinhole;
pub mod thin_lens;

use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;
use glam::{Affine3A, Vec2, Vec3};
use rayon::prelude::*;

use crate::integrator::batch::PathBatch;

/// Camera space to world space (x right, y up, z forward in camera space).
#[derive(Component, Clone, Copy, Debug)]
pub struct CameraPose(pub Affine3A);

/// The order of the camera stages within a pass.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CameraStage {
    /// One projection's ray generation.
    Generate,
    /// Optional optics applied to any projection's rays.
    Lens,
    ToWorld,
}

/// Registers the camera systems in the pass schedule: one line per camera. Each camera adds its
/// system only when the world has its component, so the schedule holds only what the scene uses.
pub fn register_cameras(pass: &mut Schedule, world: &mut World) {
    pass.configure_sets(
        (
            CameraStage::Generate,
            CameraStage::Lens,
            CameraStage::ToWorld,
        )
            .chain(),
    );
    pass.add_systems(move_camera_rays_to_world.in_set(CameraStage::ToWorld));
    pinhole::register(pass, world);
    thin_lens::register(pass, world);
    fisheye::register(pass, world);
    orthographic::register(pass, world);
    equirectangular::register(pass, world);
}

/// Adds `system` to `stage` when the world has a camera component `C`, to run while it does.
pub fn register_for<C: Component, M>(
    pass: &mut Schedule,
    world: &mut World,
    stage: CameraStage,
    system: impl IntoScheduleConfigs<ScheduleSystem, M>,
) {
    if world
        .query_filtered::<(), With<C>>()
        .iter(world)
        .next()
        .is_some()
    {
        let configs: ScheduleConfigs<ScheduleSystem> =
            system.run_if(any_with_component::<C>).in_set(stage);
        pass.add_systems(configs);
    }
}

/// Fills every path's camera-space ray from its film position: `project` maps a raster position
/// to (origin, direction), or to `None` where the camera sees nothing (a black sample that costs
/// no ray).
pub fn generate_camera_rays(
    batch: &mut PathBatch,
    project: impl Fn(Vec2) -> Option<(Vec3, Vec3)> + Sync,
) {
    let n = batch.len;
    (
        &batch.film_position[..n],
        &mut batch.origin[..n],
        &mut batch.direction[..n],
        &mut batch.alive[..n],
    )
        .into_par_iter()
        .with_min_len(1024)
        .for_each(|(film, origin, direction, alive)| match project(*film) {
            Some((o, d)) => {
                *origin = o;
                *direction = d;
            }
            None => *alive = false,
        });
}

/// Maps a raster position (pixels, y down) to the screen window [xmin, xmax, ymin, ymax] (y up).
pub fn raster_to_screen(raster: Vec2, width: u32, height: u32, window: [f32; 4]) -> Vec2 {
    let [x_min, x_max, y_min, y_max] = window;
    Vec2::new(
        x_min + raster.x / width as f32 * (x_max - x_min),
        y_max - raster.y / height as f32 * (y_max - y_min),
    )
}

/// The default screen window: the shorter image axis spans [-1, 1].
pub fn default_screen_window(width: u32, height: u32) -> [f32; 4] {
    let aspect = width as f32 / height as f32;
    if aspect >= 1.0 {
        [-aspect, aspect, -1.0, 1.0]
    } else {
        [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]
    }
}

fn move_camera_rays_to_world(camera: Single<&CameraPose>, mut batch: ResMut<PathBatch>) {
    let pose = camera.0;
    let batch = &mut *batch;
    let n = batch.len;
    (&mut batch.origin[..n], &mut batch.direction[..n])
        .into_par_iter()
        .with_min_len(1024)
        .for_each(|(origin, direction)| {
            *origin = pose.transform_point3(*origin);
            *direction = pose.transform_vector3(*direction).normalize_or_zero();
        });
}
