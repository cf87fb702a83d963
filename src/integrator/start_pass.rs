//! The first stage of a chunk: one fresh path per pixel of the chunk, with its film sample.

use bevy_ecs::prelude::*;
use glam::Vec2;
use rayon::prelude::*;

use super::batch::PathBatch;
use crate::film::PixelFilter;
use crate::sampling::{Divisor, PassStreams, PixelSampler};
use crate::settings::RenderSettings;

/// Which pass (sample index per pixel) is running.
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct PassIndex(pub u32);

/// The pixels of the running pass that the chunk traces: `first..first + count`.
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct ChunkRange {
    pub first: u32,
    pub count: u32,
}

/// The pixel and lens sample patterns and the pixel filter they are warped by.
#[derive(Resource)]
pub struct CameraSampling {
    pub sampler: PixelSampler,
    pub filter: PixelFilter,
}

/// Sampler dimensions: the film position, then the lens (drawn by the lens stage, if any).
pub const FILM_DIMENSION: u32 = 0;
pub const LENS_DIMENSION: u32 = 1;

pub fn start_pass(
    settings: Res<RenderSettings>,
    pass: Res<PassIndex>,
    chunk: Res<ChunkRange>,
    sampling: Res<CameraSampling>,
    mut batch: ResMut<PathBatch>,
) {
    let width = Divisor::new(settings.width);
    let pass = pass.0;
    let streams = PassStreams::new(settings.seed, pass);
    let first = chunk.first;
    let sampler = sampling.sampler.pass(pass);
    let pixels = settings.pixels.as_deref();
    let batch = &mut *batch;
    batch.resize(chunk.count as usize);
    (
        &mut batch.pixel[..],
        &mut batch.film_position[..],
        &mut batch.rng[..],
        &mut batch.throughput[..],
        &mut batch.radiance[..],
        &mut batch.depth[..],
        &mut batch.pass_through[..],
        &mut batch.scatter_pdf[..],
        &mut batch.alive[..],
    )
        .into_par_iter()
        .enumerate()
        .with_min_len(1024)
        .for_each(
            |(i, (pixel, film, rng, throughput, radiance, depth, through, pdf, alive))| {
                // Path `first + i` of the pass: its pixel, or the crop's pixel list's entry.
                let path = first as usize + i;
                let i = pixels.map_or(path as u32, |p| p[path]);
                let centre = Vec2::new(
                    width.remainder(i) as f32 + 0.5,
                    width.quotient(i) as f32 + 0.5,
                );
                *pixel = i;
                *film = centre + sampling.filter.sample(sampler.sample_2d(i, FILM_DIMENSION));
                *rng = streams.path(i);
                *throughput = glam::Vec3::ONE;
                *radiance = glam::Vec3::ZERO;
                *depth = 0;
                *through = 0;
                *pdf = 0.0;
                *alive = true;
            },
        );
}
