//! The last stages of a bounce: unoccluded light reaches its path, finished paths leave the batch
//! with their film samples, and the live ones are compacted for the next bounce.

use bevy_ecs::prelude::*;
use glam::{BVec3, Vec3};
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
/// each, in slot order) that hold a ray (t_max > 0) found unoccluded. The path tracer's one
/// slot a path is compiled apart, the count known: LLVM then vectorises the loop (the Cornell
/// box's stage about 24 -> 6 ms, one thread, 32 spp).
fn add_unoccluded(radiance: &mut [Vec3], t_max: &[f32], occluded: &[bool], contribution: &[Vec3]) {
    let slots = (t_max, occluded, contribution);
    match t_max.len() / radiance.len() {
        1 => add_unoccluded_slots(1, radiance, slots),
        k => add_unoccluded_slots(k, radiance, slots),
    }
}

#[inline(always)]
fn add_unoccluded_slots(
    k: usize,
    radiance: &mut [Vec3],
    (t_max, occluded, contribution): (&[f32], &[bool], &[Vec3]),
) {
    let paths = (t_max.chunks_exact(k))
        .zip(occluded.chunks_exact(k))
        .zip(contribution.chunks_exact(k));
    for (radiance, ((t_max, occluded), contribution)) in radiance.iter_mut().zip(paths) {
        for ((&t_max, &occluded), &contribution) in t_max.iter().zip(occluded).zip(contribution) {
            // A select, not a branch: whether a shadow ray was blocked is a coin toss (the
            // branch was a sixth of the Cornell box's mispredictions in cachegrind's model;
            // the stage 52 -> 24 ms). Adding zero leaves the sum's bits as they were (a
            // radiance starts at +0 and is never -0).
            let unoccluded = (t_max > 0.0) & !occluded;
            *radiance += Vec3::select(BVec3::splat(unoccluded), contribution, Vec3::ZERO);
        }
    }
}

/// Finished paths leave the batch, their film samples kept for the chunk's end (see
/// `Renderer::trace_chunk`, which splats them); the rest move to the front of the batch.
pub fn retire_finished_paths(mut batch: ResMut<PathBatch>) {
    batch.retire();
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One and two slots a path (the loop compiled for one slot apart): each path gains the
    /// contributions of its filled, unoccluded slots only, and an empty or occluded slot's
    /// contribution, even a NaN left from an earlier bounce, changes no bit of its radiance.
    #[test]
    fn only_filled_unoccluded_slots_add_light() {
        let slot = |j: usize| Vec3::splat(2f32.powi(j as i32));
        for k in [1, 2] {
            // Path p's slot j: filled unless (p + j) % 3 == 0, occluded where (p + j) % 4 == 1.
            let paths = 12;
            let (mut t_max, mut occluded, mut contribution) = (vec![], vec![], vec![]);
            for p in 0..paths {
                for j in 0..k {
                    let filled = (p + j) % 3 != 0;
                    let blocked = (p + j) % 4 == 1;
                    t_max.push(if filled { 1.0 } else { 0.0 });
                    occluded.push(blocked);
                    let counted = filled && !blocked;
                    contribution.push(if counted { slot(j) } else { Vec3::NAN });
                }
            }
            let mut radiance = vec![Vec3::splat(0.25); paths];
            add_unoccluded(&mut radiance, &t_max, &occluded, &contribution);
            for (p, radiance) in radiance.iter().enumerate() {
                let expected = (0..k)
                    .filter(|&j| (p + j) % 3 != 0 && (p + j) % 4 != 1)
                    .fold(Vec3::splat(0.25), |sum, j| sum + slot(j));
                assert_eq!(
                    radiance.to_array(),
                    expected.to_array(),
                    "{k} slots, path {p}"
                );
            }
        }
    }
}
