//! The first stage of a chunk: one fresh path per pixel of the chunk, with its film sample.

use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};
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
    let pass_sampler = sampling.sampler.pass(pass);
    let sampler = pass_sampler.dimension(FILM_DIMENSION);
    let pixels = settings.pixels.as_deref();
    let batch = &mut *batch;
    batch.resize(chunk.count as usize);
    // Blocks of paths, each a plain loop over its slices: the sampled fields path by path,
    // the constant ones filled (vector stores), rather than rayon zipping nine fields per path.
    (
        batch.pixel.par_chunks_mut(BLOCK),
        batch.film_position.par_chunks_mut(BLOCK),
        batch.rng.par_chunks_mut(BLOCK),
        batch.throughput.par_chunks_mut(BLOCK),
        batch.radiance.par_chunks_mut(BLOCK),
        batch.depth.par_chunks_mut(BLOCK),
        batch.pass_through.par_chunks_mut(BLOCK),
        batch.scatter_pdf.par_chunks_mut(BLOCK),
        batch.alive.par_chunks_mut(BLOCK),
    )
        .into_par_iter()
        .enumerate()
        .for_each(
            |(block, (pixel, film, rng, throughput, radiance, depth, through, pdf, alive))| {
                let first = first as usize + block * BLOCK;
                for (path, ((pixel, film), rng)) in
                    (first..).zip(pixel.iter_mut().zip(film).zip(rng))
                {
                    // Path `first + i` of the pass: its pixel, or the crop's pixel list's entry.
                    let i = pixels.map_or(path as u32, |p| p[path]);
                    let centre = Vec2::new(
                        width.remainder(i) as f32 + 0.5,
                        width.quotient(i) as f32 + 0.5,
                    );
                    *pixel = i;
                    *film = centre + sampling.filter.sample(sampler.sample(i));
                    *rng = streams.path(i);
                }
                throughput.fill(Vec3::ONE);
                radiance.fill(Vec3::ZERO);
                depth.fill(0);
                through.fill(0);
                pdf.fill(0.0);
                alive.fill(true);
            },
        );
}

/// Paths per task of [`start_pass`].
const BLOCK: usize = 1024;
