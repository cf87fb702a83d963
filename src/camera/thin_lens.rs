//! The thin lens: depth of field for any projection.
//!
//! A ray through the lens centre reaches its point of sharp focus at `origin + f * direction`
//! (see the module notes in `camera`); every other ray of that pixel sample starts on the lens
//! disk and passes through the same point (pbrt-v4 §5.2.3, the thin lens model).

use bevy_ecs::prelude::*;
use rayon::prelude::*;

use super::{CameraStage, register_for};
use crate::integrator::batch::PathBatch;
use crate::integrator::start_pass::{CameraSampling, LENS_DIMENSION, PassIndex};
use crate::sampling::warp::concentric_disk;

#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ThinLens {
    pub lens_radius: f32,
    pub focal_distance: f32,
}

pub fn register(pass: &mut Schedule, world: &mut World) {
    register_for::<ThinLens, _>(pass, world, CameraStage::Lens, focus_through_thin_lens);
}

fn focus_through_thin_lens(
    lens: Single<&ThinLens>,
    pass: Res<PassIndex>,
    sampling: Res<CameraSampling>,
    mut batch: ResMut<PathBatch>,
) {
    let lens = **lens;
    let batch = &mut *batch;
    let n = batch.len;
    (
        &batch.pixel[..n],
        &mut batch.origin[..n],
        &mut batch.direction[..n],
    )
        .into_par_iter()
        .with_min_len(1024)
        .for_each(|(pixel, origin, direction)| {
            let focus = *origin + *direction * lens.focal_distance;
            let sample = sampling.sampler.sample_2d(*pixel, pass.0, LENS_DIMENSION);
            // Shirley-Chiu's concentric map keeps the sampler's stratification on the disk.
            let on_lens = concentric_disk(sample) * lens.lens_radius;
            *origin += on_lens.extend(0.0);
            *direction = focus - *origin;
        });
}
