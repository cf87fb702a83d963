//! The wavefront batches: structure-of-arrays state of every live path, allocated once per
//! render and reused by every pass and bounce. Slot `i` of each array belongs to path `i`;
//! live paths are kept contiguous in `0..len` by [`PathBatch::compact`].

use bevy_ecs::prelude::Resource;
use glam::{Vec2, Vec3};

use crate::accel::Hit;
use crate::sampling::PathRng;

/// One path per slot.
#[derive(Resource, Default)]
pub struct PathBatch {
    /// Live paths are `0..len`.
    pub len: usize,
    pub pixel: Vec<u32>,
    /// Raster position of the camera sample (pixel centre plus the filter offset).
    pub film_position: Vec<Vec2>,
    /// The ray the path follows next (camera space between ray generation and the lens stages).
    pub origin: Vec<Vec3>,
    pub direction: Vec<Vec3>,
    /// The last scattering vertex, where the current ray's direction was sampled (a pass through
    /// a null surface moves `origin`, not this): the point light sampling would have sampled
    /// from, for the MIS weight of an emitter the ray hits. Set by the first scattering.
    pub vertex: Vec<Vec3>,
    /// Product of f |cos| / pdf along the path.
    pub throughput: Vec<Vec3>,
    /// Radiance gathered so far.
    pub radiance: Vec<Vec3>,
    /// Bounces taken.
    pub depth: Vec<u32>,
    /// Surfaces passed through without scattering (null material), to bound such chains.
    pub pass_through: Vec<u32>,
    pub rng: Vec<PathRng>,
    /// Solid-angle pdf of the BSDF sample that made the current ray; 0 for the camera ray and delta
    /// lobes (their emitter hits take no MIS weight).
    pub scatter_pdf: Vec<f32>,
    /// Cleared by a stage when the path ends; `compact` removes it.
    pub alive: Vec<bool>,
}

impl PathBatch {
    /// Sizes the batch for a pass of `count` paths, reusing the allocations; the pass's first
    /// stage then sets every field of every slot.
    pub fn resize(&mut self, count: usize) {
        self.len = count;
        resize(&mut self.pixel, count, 0);
        resize(&mut self.film_position, count, Vec2::ZERO);
        resize(&mut self.origin, count, Vec3::ZERO);
        resize(&mut self.direction, count, Vec3::Z);
        resize(&mut self.vertex, count, Vec3::ZERO);
        resize(&mut self.throughput, count, Vec3::ONE);
        resize(&mut self.radiance, count, Vec3::ZERO);
        resize(&mut self.depth, count, 0);
        resize(&mut self.pass_through, count, 0);
        resize(&mut self.rng, count, PathRng::new(0, 0, 0));
        resize(&mut self.scatter_pdf, count, 0.0);
        resize(&mut self.alive, count, true);
    }

    /// Moves the live paths to the front, keeping their order (so results do not depend on
    /// scheduling), and returns how many there are.
    pub fn compact(&mut self) -> usize {
        let mut kept = 0;
        for i in 0..self.len {
            if !self.alive[i] {
                continue;
            }
            if kept != i {
                self.pixel[kept] = self.pixel[i];
                self.film_position[kept] = self.film_position[i];
                self.origin[kept] = self.origin[i];
                self.direction[kept] = self.direction[i];
                self.vertex[kept] = self.vertex[i];
                self.throughput[kept] = self.throughput[i];
                self.radiance[kept] = self.radiance[i];
                self.depth[kept] = self.depth[i];
                self.pass_through[kept] = self.pass_through[i];
                self.rng[kept] = self.rng[i].clone();
                self.scatter_pdf[kept] = self.scatter_pdf[i];
                self.alive[kept] = true;
            }
            kept += 1;
        }
        self.len = kept;
        kept
    }
}

/// Closest hits of the path rays, slot for slot.
#[derive(Resource, Default)]
pub struct HitBatch {
    pub hit: Vec<Option<Hit>>,
    /// Ray extents for the trace: infinite for a live path, 0 for one that ended.
    pub t_max: Vec<f32>,
}

/// Shadow rays: `rays_per_path` slots for each path, path `i` owning
/// `i * rays_per_path .. (i + 1) * rays_per_path`. A slot with zero contribution is empty.
#[derive(Resource, Default)]
pub struct ShadowBatch {
    pub rays_per_path: usize,
    pub origin: Vec<Vec3>,
    pub direction: Vec<Vec3>,
    /// The last scattering vertex, where the current ray's direction was sampled (a pass through
    /// a null surface moves `origin`, not this): the point light sampling would have sampled
    /// from, for the MIS weight of an emitter the ray hits. Set by the first scattering.
    pub vertex: Vec<Vec3>,
    /// The ray is tested on (t_min, t_max); 0 marks an empty slot.
    pub t_max: Vec<f32>,
    /// Radiance the path gains when the ray is unoccluded.
    pub contribution: Vec<Vec3>,
    pub occluded: Vec<bool>,
}

impl ShadowBatch {
    pub fn new(rays_per_path: usize) -> Self {
        Self {
            rays_per_path,
            ..Default::default()
        }
    }

    /// Sizes the batch for `paths` paths and empties every slot.
    pub fn clear(&mut self, paths: usize) {
        let count = paths * self.rays_per_path;
        resize(&mut self.origin, count, Vec3::ZERO);
        resize(&mut self.direction, count, Vec3::Z);
        resize(&mut self.contribution, count, Vec3::ZERO);
        resize(&mut self.occluded, count, false);
        self.t_max.clear();
        self.t_max.resize(count, 0.0);
    }
}

/// Sets the length to `count`, reusing the allocation; new slots take `value`, old ones keep theirs.
fn resize<T: Clone>(values: &mut Vec<T>, count: usize, value: T) {
    values.truncate(count);
    values.resize(count, value);
}
