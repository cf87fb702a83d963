//! The last stages of a bounce: unoccluded light reaches its path, finished paths go to the film,
//! and the live ones are compacted for the next bounce.

use bevy_ecs::prelude::*;
use rayon::prelude::*;

use super::batch::{PathBatch, ShadowBatch};
use super::start_pass::PassIndex;
use crate::film::Film;

pub fn gather_unoccluded_light(mut batch: ResMut<PathBatch>, shadows: Res<ShadowBatch>) {
    let k = shadows.rays_per_path;
    let n = batch.len;
    if k == 0 || shadows.t_max.len() < n * k {
        return;
    }
    batch.radiance[..n]
        .par_iter_mut()
        .enumerate()
        .with_min_len(1024)
        .for_each(|(i, radiance)| {
            for slot in i * k..(i + 1) * k {
                if shadows.t_max[slot] > 0.0 && !shadows.occluded[slot] {
                    *radiance += shadows.contribution[slot];
                }
            }
        });
}

/// Finished paths add their radiance to the film (one sample at their film position, in
/// (bounce, slot) order, so the sums do not depend on the thread count; the film splats a
/// chunk's samples at once, when its last path ends, in parallel over bands of rows: see
/// [`PathBatch::retire`]), into the sums of their pass; the rest move to the front of the batch.
pub fn retire_finished_paths(
    mut batch: ResMut<PathBatch>,
    mut film: ResMut<Film>,
    pass: Res<PassIndex>,
) {
    // A chunk's last retire hands over all its samples, so every sample of earlier passes is
    // in the film by now.
    film.begin_pass(pass.0);
    batch.retire(|samples, run_ends| film.add_sample_runs(samples, run_ends));
}
