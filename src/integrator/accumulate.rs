//! The last stages of a bounce: unoccluded light reaches its path, finished paths leave the batch
//! with their film samples, and the live ones are compacted for the next bounce.

use bevy_ecs::prelude::*;
use glam::Vec3;
use rayon::prelude::*;

use super::batch::{PathBatch, ShadowBatch};

pub fn gather_unoccluded_light(mut batch: ResMut<PathBatch>, shadows: Res<ShadowBatch>) {
    let k = shadows.rays_per_path;
    let n = batch.len;
    if k == 0 || shadows.t_max.len() < n * k {
        return;
    }
    // Tasks of PATHS_PER_TASK paths, each one plain loop over its paths' slots (a loop of its
    // own, which rustc compiles the same whichever codegen unit rayon's loop lands in).
    batch.radiance[..n]
        .par_chunks_mut(PATHS_PER_TASK)
        .enumerate()
        .for_each(|(task, radiance)| {
            let slots = task * PATHS_PER_TASK * k..(task * PATHS_PER_TASK + radiance.len()) * k;
            add_unoccluded(
                radiance,
                &shadows.t_max[slots.clone()],
                &shadows.occluded[slots.clone()],
                &shadows.contribution[slots],
            );
        });
}

const PATHS_PER_TASK: usize = 1024;

/// Adds to each path's radiance the contributions of its slots (`t_max.len() / radiance.len()`
/// each, in slot order) that hold a ray (t_max > 0) found unoccluded.
fn add_unoccluded(radiance: &mut [Vec3], t_max: &[f32], occluded: &[bool], contribution: &[Vec3]) {
    let k = t_max.len() / radiance.len();
    let paths = (t_max.chunks_exact(k))
        .zip(occluded.chunks_exact(k))
        .zip(contribution.chunks_exact(k));
    for (radiance, ((t_max, occluded), contribution)) in radiance.iter_mut().zip(paths) {
        for ((&t_max, &occluded), &contribution) in t_max.iter().zip(occluded).zip(contribution) {
            if t_max > 0.0 && !occluded {
                *radiance += contribution;
            }
        }
    }
}

/// Finished paths leave the batch, their film samples kept for the chunk's end (see
/// `Renderer::trace_chunk`, which splats them); the rest move to the front of the batch.
pub fn retire_finished_paths(mut batch: ResMut<PathBatch>) {
    batch.retire();
}
