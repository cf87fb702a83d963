//! The first stage of a pass: one fresh path per pixel, with its film sample.

use bevy_ecs::prelude::*;
use glam::Vec2;
use rayon::prelude::*;

use super::batch::PathBatch;
use crate::film::PixelFilter;
use crate::sampling::{PathRng, PixelSampler};
use crate::settings::RenderSettings;

/// Which pass (sample index per pixel) is running.
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct PassIndex(pub u32);

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
    sampling: Res<CameraSampling>,
    mut batch: ResMut<PathBatch>,
) {
    let width = settings.width;
    let seed = settings.seed;
    let pass = pass.0;
    let n = settings.path_count();
    let pixels = settings.pixels.as_deref();
    let batch = &mut *batch;
    batch.resize(n);
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
                let i = pixels.map_or(i as u32, |p| p[i]);
                let centre = Vec2::new((i % width) as f32 + 0.5, (i / width) as f32 + 0.5);
                *pixel = i;
                *film = centre
                    + sampling
                        .filter
                        .sample(sampling.sampler.sample_2d(i, pass, FILM_DIMENSION));
                *rng = PathRng::new(seed, i, pass);
                *throughput = glam::Vec3::ONE;
                *radiance = glam::Vec3::ZERO;
                *depth = 0;
                *through = 0;
                *pdf = 0.0;
                *alive = true;
            },
        );
}
