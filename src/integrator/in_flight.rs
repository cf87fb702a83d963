//! Chunks in flight: with several threads, the renderer traces as many chunks at once, each in a
//! world of its own on a thread of its own. Thread k traces in world k, taking the next chunk
//! of the render as soon as it is done with its last, so a chunk's batches stay with one core
//! from its camera rays to its last bounce; a thread left without chunks at the render's end
//! shares the stages' parallel loops of the chunks still in flight. The threads meet only where
//! a traced chunk waits for the film: the first thread gives the film the waiting chunks, in
//! chunk order, after each of its own, so the film too stays with one core.
//!
//! Before (stop 37), the chunks went in groups, one per world, each group ending when its
//! slowest chunk did, and the threads shared each other's stages in between, so the stages'
//! batches crossed between the cores (docs/speed.md, stop 38: two threads 1.93x-1.95x one
//! against 1.79x-1.89x in the same rounds).
//!
//! The worlds share the scene's geometry and lights ([`Shared`]), copy the small tables and
//! the camera entity, and run schedules of their own (a system keeps state for the world it
//! runs in). The film takes the chunks' samples in chunk order whichever finishes first, so
//! the image is the same at any number of chunks in flight and threads.

use std::collections::BTreeMap;
use std::ops::Range;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use bevy_ecs::prelude::*;

use super::batch::{FinishedSamples, PathBatch};
use super::start_pass::CameraSampling;
use super::{
    Progress, RenderStats, Stage, StageTime, WorldStages, bounce_stages, chunk_schedule,
    insert_chunk_state, trace_chunk,
};
use crate::camera::copy_camera;
use crate::film::Film;
use crate::light::LightTable;
use crate::material::MaterialTable;
use crate::material::texture::TextureTable;
use crate::settings::{RenderSettings, Techniques};
use crate::shape::geometry::SceneGeometry;
use crate::shared::Shared;

/// The most chunks traced at once, whatever the threads: each holds its batches (a few
/// megabytes at the default chunk size).
pub const MAX_IN_FLIGHT: usize = 8;

/// A world that traces one chunk at a time, beside the main world.
pub(super) struct ChunkWorld {
    pub world: World,
    /// Its chunk start: fresh paths and the camera's rays.
    pub chunk: Schedule,
    /// Its bounce stages.
    pub bounce: Vec<Stage>,
    /// Time and items of its stages, laid out as the main world's, when stages are timed.
    pub times: Option<Vec<StageTime>>,
}

impl ChunkWorld {
    /// A world with what the stages read of `main` (the render's world, after its startup
    /// systems), batches and schedules of its own.
    pub fn new(main: &World) -> Self {
        let mut world = World::new();
        copy_camera(main, &mut world);
        world.insert_resource(main.resource::<CameraSampling>().clone());
        world.insert_resource(main.resource::<Shared<SceneGeometry>>().clone());
        world.insert_resource(main.resource::<Shared<LightTable>>().clone());
        world.insert_resource(main.resource::<MaterialTable>().clone());
        if let Some(textures) = main.get_resource::<TextureTable>() {
            world.insert_resource(textures.clone());
        }
        world.insert_resource(main.resource::<RenderSettings>().clone());
        world.insert_resource(*main.resource::<Techniques>());
        insert_chunk_state(&mut world);
        let chunk = chunk_schedule(&mut world);
        let bounce = bounce_stages(world.resource::<RenderSettings>().integrator);
        Self {
            world,
            chunk,
            bounce,
            times: None,
        }
    }

    /// The world with its schedules and stage times, as a chunk is traced.
    pub fn stages(&mut self) -> WorldStages<'_> {
        (
            &mut self.world,
            &mut self.chunk,
            &mut self.bounce,
            self.times.as_deref_mut(),
        )
    }
}

/// A chunk of a pass: its pixels `first..first + count`.
#[derive(Clone, Copy, Debug)]
pub(super) struct ChunkJob {
    pub pass: u32,
    pub first: usize,
    pub count: usize,
}

/// A render's passes cut into chunks of consecutive pixels, numbered pass after pass: the
/// order in which the film takes them.
pub(super) struct ChunkPlan {
    pixels: usize,
    chunk: usize,
    passes: Range<u32>,
    chunks_per_pass: usize,
}

impl ChunkPlan {
    /// The passes `passes` of `pixels` paths each, in chunks of `chunk_paths` (the last of a
    /// pass shorter).
    pub fn new(pixels: usize, chunk_paths: usize, passes: Range<u32>) -> Self {
        let chunk = chunk_paths.clamp(1, pixels.max(1));
        Self {
            pixels,
            chunk,
            chunks_per_pass: pixels.div_ceil(chunk),
            passes,
        }
    }

    fn len(&self) -> usize {
        self.passes.len() * self.chunks_per_pass
    }

    fn job(&self, index: usize) -> ChunkJob {
        let first = index % self.chunks_per_pass * self.chunk;
        ChunkJob {
            pass: self.passes.start + (index / self.chunks_per_pass) as u32,
            first,
            count: self.chunk.min(self.pixels - first),
        }
    }
}

/// Where the chunks' results go, in chunk order: the film, and the caller's progress, which
/// may stop the render.
pub(super) struct Intake<'a, P> {
    pub film: Film,
    /// The splat's time, when stages are timed.
    pub splat_time: Option<&'a mut StageTime>,
    /// The render's start and time limit, checked at the end of each pass.
    pub time_limit: Option<(Instant, Duration)>,
    pub on_progress: P,
}

/// Traces `plan`'s chunks in `worlds` (the main world's first), world k on thread k of the
/// pool, each taking the next chunk when done with its last; `intake` takes them in order.
/// Returns the film and what went into it (elapsed time left at zero).
pub(super) fn trace_in_flight<P: FnMut(Progress) -> bool + Send>(
    plan: &ChunkPlan,
    worlds: Vec<WorldStages>,
    intake: Intake<P>,
) -> (Film, RenderStats) {
    let worlds: Vec<Mutex<Option<WorldStages>>> =
        worlds.into_iter().map(|w| Mutex::new(Some(w))).collect();
    let film_order = Mutex::new(FilmOrder::new(plan, intake));
    let waiting = Mutex::new(Waiting::default());
    let next_chunk = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    rayon::broadcast(|context| {
        let world = (worlds.get(context.index())).and_then(|world| world.lock().ok()?.take());
        let Some(mut world) = world else { return };
        // The first thread gives the film its chunks: the film stays with one core.
        let gives = context.index() == 0;
        while !stop.load(Ordering::Relaxed) {
            let index = next_chunk.fetch_add(1, Ordering::Relaxed);
            if index >= plan.len() {
                break;
            }
            let job = plan.job(index);
            let rays = trace_chunk(&mut world, &job);
            let mut samples = lock(&waiting).spares.pop().unwrap_or_default();
            (world.0.resource_mut::<PathBatch>()).take_finished(&mut samples);
            let done = TracedChunk { samples, job, rays };
            lock(&waiting).chunks.insert(index, done);
            if gives && give_in_order(plan, &mut lock(&film_order), &waiting) {
                stop.store(true, Ordering::Relaxed);
            }
        }
    });
    let mut order = film_order.into_inner().expect("no panic holds the lock");
    // The chunks the other threads finished after the first thread's last.
    give_in_order(plan, &mut order, &waiting);
    (order.intake.film, order.stats)
}

/// A traced chunk: its job, film samples and rays.
struct TracedChunk {
    samples: FinishedSamples,
    job: ChunkJob,
    rays: u64,
}

/// Chunks traced and waiting for the film to reach them, and sample buffers to reuse.
#[derive(Default)]
struct Waiting {
    /// By chunk index.
    chunks: BTreeMap<usize, TracedChunk>,
    spares: Vec<FinishedSamples>,
}

/// The film's side: the next chunk it takes, and what the chunks taken did.
struct FilmOrder<'a, P> {
    stats: RenderStats,
    next: usize,
    /// Whether the render stopped: the later chunks are dropped.
    stopped: bool,
    intake: Intake<'a, P>,
}

impl<'a, P: FnMut(Progress) -> bool> FilmOrder<'a, P> {
    /// Before `plan`'s first chunk.
    fn new(plan: &ChunkPlan, intake: Intake<'a, P>) -> Self {
        Self {
            stats: RenderStats::empty(plan.passes.start),
            next: 0,
            stopped: false,
            intake,
        }
    }

    /// Splats `chunk` (the next in order) and tells the progress, which may stop the render.
    fn take(&mut self, plan: &ChunkPlan, chunk: &TracedChunk) {
        let intake = &mut self.intake;
        let timer = Instant::now();
        let samples = chunk.samples.samples();
        if !samples.is_empty() {
            intake.film.begin_pass(chunk.job.pass);
            intake.film.add_samples(samples);
        }
        if let Some(time) = intake.splat_time.as_deref_mut() {
            time.time += timer.elapsed();
            time.items += samples.len() as u64;
        }
        self.next += 1;
        let stats = &mut self.stats;
        stats.rays += chunk.rays;
        stats.paths += chunk.job.count as u64;
        let pass_done = chunk.job.first + chunk.job.count == plan.pixels;
        stats.passes += u32::from(pass_done);
        let pixels = plan.pixels as u64;
        let go_on = (intake.on_progress)(Progress {
            paths_done: u64::from(plan.passes.start) * pixels + stats.paths,
            paths_total: u64::from(plan.passes.end) * pixels,
            passes_done: stats.passes,
        });
        stats.complete_passes = go_on || pass_done;
        let time_up =
            pass_done && (intake.time_limit).is_some_and(|(start, limit)| start.elapsed() >= limit);
        self.stopped = !go_on || time_up;
    }
}

/// Gives the film the waiting chunks that are next in order; returns whether the render
/// stopped.
fn give_in_order<P: FnMut(Progress) -> bool>(
    plan: &ChunkPlan,
    order: &mut FilmOrder<P>,
    waiting: &Mutex<Waiting>,
) -> bool {
    while !order.stopped {
        let Some(chunk) = lock(waiting).chunks.remove(&order.next) else {
            break;
        };
        order.take(plan, &chunk);
        let mut samples = chunk.samples;
        samples.clear();
        lock(waiting).spares.push(samples);
    }
    order.stopped
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex.lock().expect("no panic holds the lock")
}

#[cfg(test)]
mod tests {
    use std::cell::RefCell;

    use super::*;

    /// A pass of 10 pixels in chunks of 4 is three chunks (4, 4, 2), numbered pass after pass.
    #[test]
    fn a_plan_numbers_its_chunks_pass_after_pass() {
        let plan = ChunkPlan::new(10, 4, 1..3);
        let jobs: Vec<_> = (0..plan.len())
            .map(|index| plan.job(index))
            .map(|job| (job.pass, job.first, job.count))
            .collect();
        let pass = |p| [(p, 0, 4), (p, 4, 4), (p, 8, 2)];
        assert_eq!(jobs, [pass(1), pass(2)].concat());
        assert_eq!(ChunkPlan::new(10, 64, 0..1).len(), 1);
        assert_eq!(ChunkPlan::new(0, 64, 0..4).len(), 0);
    }

    /// The film takes the chunks in chunk order whatever order they are traced in, and once
    /// the progress says stop, takes no later chunk.
    #[test]
    fn the_film_takes_chunks_in_order_and_none_after_a_stop() {
        let plan = ChunkPlan::new(10, 4, 1..3);
        let told = RefCell::new(Vec::new());
        let intake = Intake {
            film: Film::new(10, 1),
            splat_time: None,
            time_limit: None,
            // Stops after the pass's second chunk (18 paths done, counting pass 0's).
            on_progress: |progress: Progress| {
                told.borrow_mut().push(progress.paths_done);
                progress.paths_done < 18
            },
        };
        let mut order = FilmOrder::new(&plan, intake);
        let waiting = Mutex::new(Waiting::default());
        let arrive = |index: usize| {
            let chunk = TracedChunk {
                samples: FinishedSamples::default(),
                job: plan.job(index),
                rays: 1 << index,
            };
            lock(&waiting).chunks.insert(index, chunk);
        };
        arrive(2);
        arrive(1);
        assert!(!give_in_order(&plan, &mut order, &waiting));
        assert!(told.borrow().is_empty(), "chunk 0 is not there yet");
        arrive(0);
        assert!(give_in_order(&plan, &mut order, &waiting));
        arrive(3);
        assert!(give_in_order(&plan, &mut order, &waiting));
        assert_eq!(*told.borrow(), [14, 18]);
        let stats = order.stats;
        assert_eq!((stats.passes, stats.paths, stats.rays), (1, 8, 0b11));
        assert!(!stats.complete_passes);
    }
}
