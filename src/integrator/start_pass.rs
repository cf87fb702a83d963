//! The first stage of a chunk: one fresh path per pixel of the chunk, with its film sample.

use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::batch::{HitBatch, PathBatch};
use crate::film::PixelFilter;
use crate::sampling::{
    DimensionLanes, DimensionSampler, Divisor, FirstDraws, PADDED_DRAWS, PassStreams, PathRng,
    PixelSampler, SampleLanes,
};
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
#[derive(Resource, Clone)]
pub struct CameraSampling {
    pub sampler: PixelSampler,
    pub filter: PixelFilter,
}

/// The chunk's paths' padded draws, by their slot at the chunk's start (see
/// `sampling::PathDraws`): computed many paths at a time at the chunk's first bounce
/// ([`compute_first_draws`]) rather than one at a time where shading makes them. Sized to the
/// chunk; left stale for the plain samplers, whose paths make no padded draw.
#[derive(Resource)]
pub struct FirstDrawsTable {
    /// How many of a path's first draws are read from the table (1 to [`PADDED_DRAWS`]): those
    /// its integrator's first vertex makes for every path (see `insert_chunk_state`); the
    /// others are made where drawn.
    pub draws: u32,
    /// Those of them that are computed (bit `d` for draw `d`): the others' values go unused in
    /// the scene (see `sampling::FirstDraws::compute`).
    pub computed: u32,
    pub rows: Vec<FirstDraws>,
}

impl FirstDrawsTable {
    /// An empty table for paths whose first `draws` draws are read from it, those in `unused`
    /// (a set of draws) left uncomputed.
    pub fn new(draws: u32, unused: u32) -> Self {
        assert!((1..=PADDED_DRAWS).contains(&draws), "{draws} first draws");
        Self {
            draws,
            computed: ((1 << draws) - 1) & !unused,
            rows: Vec::new(),
        }
    }
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
    let streams = PassStreams::new(settings.seed, pass, settings.sampler.padded_draws());
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
                let filter = &sampling.filter;
                match pixels {
                    // Path `first + k` of the pass is pixel `first + k`.
                    None => {
                        let run = (pixel, film, rng);
                        match sampler.lanes() {
                            DimensionLanes::Sobol(lanes) => {
                                start_run(&lanes, filter, width, streams, first, run)
                            }
                            DimensionLanes::Plain(lanes) => {
                                start_run(&lanes, filter, width, streams, first, run)
                            }
                        }
                    }
                    // A crop: the pixel list's entry.
                    Some(pixels) => {
                        let paths = pixel.iter_mut().zip(film).zip(rng.iter_mut());
                        for (&i, slots) in pixels[first..].iter().zip(paths) {
                            let column_row = (width.remainder(i), width.quotient(i));
                            start_path(filter, &sampler, streams, i, column_row, slots);
                        }
                    }
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

/// The chunk's first bounce, after its closest hits: its paths' padded draws
/// ([`FirstDrawsTable`]), those of [`BLOCK`] paths to a task, `sampling::FirstDraws`' lanes at
/// a time, but for groups of lanes whose camera rays all escaped: such a path makes no draw (a
/// sky's lookup takes none). The first bounce's slots are still the camera paths', in order.
pub fn compute_first_draws(
    settings: Res<RenderSettings>,
    batch: Res<PathBatch>,
    hits: Res<HitBatch>,
    mut table: ResMut<FirstDrawsTable>,
) {
    let n = batch.len;
    table.rows.resize(n, FirstDraws::default());
    // None computed: the ray caster's one draw, the mix's choice, where no material mixes (its
    // stale values go unread); none for the plain samplers, whose draws are hashed.
    let draws = table.computed;
    if settings.sampler.padded_draws() == 0 || draws == 0 {
        return;
    }
    (
        batch.rng[..n].par_chunks(BLOCK),
        hits.hit[..n].par_chunks(BLOCK),
        table.rows.par_chunks_mut(BLOCK),
    )
        .into_par_iter()
        .for_each(|(rng, hits, rows)| {
            FirstDraws::compute(rng, rows, draws, |k| hits[k].is_some());
        });
}

/// Samples the fields of the paths of pixels `first..` (a run of the film's pixels, as many as
/// `pixel` holds): their pixels, film positions (`lanes`' samples) and random streams. Their
/// column and row are counted along, one division per run rather than per path; the samples
/// and streams are hashed [`LANES`] at a time (the last group's lanes past the run are computed
/// and dropped). Generic over the sampler's kind, matched once per run (see
/// `DimensionSampler::lanes`).
#[inline(always)]
fn start_run<S: SampleLanes>(
    lanes: &S,
    filter: &PixelFilter,
    width: Divisor,
    streams: PassStreams,
    first: usize,
    (pixel, film, rng): (&mut [u32], &mut [Vec2], &mut [PathRng]),
) {
    let mut column = width.remainder(first as u32);
    let mut row = width.quotient(first as u32);
    let groups = pixel.chunks_mut(LANES).zip(film.chunks_mut(LANES));
    for (group, ((pixel, film), rng)) in groups.zip(rng.chunks_mut(LANES)).enumerate() {
        let first = (first + group * LANES) as u32;
        let pixels: [u32; LANES] = std::array::from_fn(|k| first + k as u32);
        let offsets = lanes.sample_lanes(pixels);
        let slots = pixel.iter_mut().zip(film).zip(rng);
        let lanes = pixels.iter().zip(offsets).zip(streams.paths(pixels));
        for (((pixel, film), rng), ((&i, u), stream)) in slots.zip(lanes) {
            *pixel = i;
            *film = film_position(filter, (column, row), u);
            *rng = stream;
            column += 1;
            if column == width.get() {
                (column, row) = (0, row + 1);
            }
        }
    }
}

/// Samples path slots' fields for pixel `i`, at (column, row) of the film: its pixel, its film
/// position and its random stream (for a crop's pixels, one at a time).
#[inline(always)]
fn start_path(
    filter: &PixelFilter,
    sampler: &DimensionSampler,
    streams: PassStreams,
    i: u32,
    column_row: (u32, u32),
    ((pixel, film), rng): PathSlots,
) {
    *pixel = i;
    *film = film_position(filter, column_row, sampler.sample(i));
    *rng = streams.path(i);
}

/// The raster position of a camera sample: the centre of the pixel at (x, y) plus the filter's
/// offset for the unit-square sample `u`.
#[inline(always)]
fn film_position(filter: &PixelFilter, (x, y): (u32, u32), u: Vec2) -> Vec2 {
    Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + filter.sample(u)
}

/// A path's slots that [`start_pass`] samples: its pixel, film position and random stream.
type PathSlots<'a> = ((&'a mut u32, &'a mut Vec2), &'a mut PathRng);

/// Paths per task of [`start_pass`].
const BLOCK: usize = 1024;
/// Pixels whose samples and streams are hashed together: eight 32-bit lanes of AVX2.
const LANES: usize = 8;
