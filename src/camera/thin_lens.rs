//! The thin lens: depth of field for any projection.
//!
//! A ray through the lens centre reaches its point of sharp focus at `origin + f * direction`
//! (see the module notes in `camera`); every other ray of that pixel sample starts on the lens
//! disk and passes through the same point (pbrt-v4 §5.2.3, the thin lens model).

use bevy_ecs::prelude::*;
use rayon::prelude::*;

use super::{CameraStage, register_for};
use crate::integrator::batch::PathBatch;
use crate::sampling::warp::concentric_disk;

#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ThinLens {
    pub lens_radius: f32,
    pub focal_distance: f32,
}

pub fn register(pass: &mut Schedule, world: &mut World) {
    register_for::<ThinLens, _>(pass, world, CameraStage::Lens, focus_through_thin_lens);
}

fn focus_through_thin_lens(lens: Single<&ThinLens>, mut batch: ResMut<PathBatch>) {
    let lens = **lens;
    let batch = &mut *batch;
    let n = batch.len;
    (
        &batch.lens_sample[..n],
        &mut batch.origin[..n],
        &mut batch.direction[..n],
    )
        .into_par_iter()
        .with_min_len(1024)
        .for_each(|(sample, origin, direction)| {
            let focus = *origin + *direction * lens.focal_distance;
            // Shirley-Chiu's concentric map keeps the sampler's stratification on the disk.
            let on_lens = concentric_disk(*sample) * lens.lens_radius;
            *origin += on_lens.extend(0.0);
            *direction = focus - *origin;
        });
}
