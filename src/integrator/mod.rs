//! The wavefront integrator: schedules of small systems over a batch of live paths.
//!
//! ```text
//! startup:  build_scene_geometry → build_light_table
//! chunk:    start_pass → camera (generate → lens → to world)
//! bounce:   trace_closest_hits → shade (path or raycast) → trace_shadow_rays
//!           → gather_unoccluded_light → retire_finished_paths   (repeated while paths live)
//! film:     the chunk's samples splatted, beside the next chunk's stages
//! ```
//!
//! A pass (one sample per pixel) runs as chunks of consecutive pixels, each traced through all
//! its bounces before the next, so that a chunk's batches stay in the caches between stages
//! rather than streaming the whole image through memory at every stage. A path's result depends
//! only on its pixel, pass and seed, and every pixel takes one sample per pass, so the image is
//! the same whatever the chunk size and thread count.

pub mod accumulate;
pub mod batch;
mod conductor_lanes;
mod diffuse_lanes;
mod escaped_lanes;
mod glass_lanes;
pub(crate) mod lanes;
pub mod shade_path;
pub mod shade_raycast;
pub mod shading;
pub mod start_pass;
pub mod trace;

use std::time::{Duration, Instant};

use bevy_ecs::prelude::*;

use crate::camera::{CameraStage, register_cameras};
use crate::film::{Film, PixelFilter, Reconstruction};
use crate::light::{LightTable, build_light_table};
use crate::material::MaterialTable;
use crate::material::texture::TextureTable;
use crate::sampling::PADDED_DRAWS;
use crate::settings::{IntegratorKind, RenderSettings, Techniques};
use crate::shape::geometry::{SceneGeometry, build_scene_geometry};
use accumulate::{gather_unoccluded_light, retire_finished_paths};
use batch::{FinishedSamples, HitBatch, PathBatch, ShadowBatch};
use shade_path::shade_path_vertices;
use shade_raycast::{shade_raycast_hits, shadow_rays_per_path};
use start_pass::{CameraSampling, ChunkRange, FirstDrawsTable, PassIndex, start_pass};
use trace::{trace_closest_hits, trace_shadow_rays};

/// Camera paths per chunk unless [`Renderer::set_chunk_paths`] says otherwise. At ~100 bytes of
/// batch state per path (twice, with the compaction's spare columns), plus its hit and shadow
/// ray, a chunk of 16k keeps its batches within about 4 MB. Measured (docs/speed.md) from 4k to
/// 64k on the three peer scenes: callgrind's cache simulation has 4k and 8k miss a 512 KB L2
/// 12 % to 38 % less than 16k for the same instructions, but on a quiet machine at 2 threads
/// 16k was faster than 8k in all six scene-rounds (more work per stage to share between the
/// threads), and 32k no faster than 16k.
pub const DEFAULT_CHUNK_PATHS: usize = 16 * 1024;

/// The world and the schedules that render it.
pub struct Renderer {
    pub world: World,
    /// Starts a chunk: fresh paths and their camera rays.
    chunk: Schedule,
    /// One bounce, stage by stage.
    bounce: Vec<Stage>,
    chunk_paths: usize,
    /// Time and work per stage, when asked for: the chunk start first, then the bounce stages.
    stage_times: Option<Vec<StageTime>>,
    /// Passes already in the film (from a checkpoint): rendering goes on from there.
    passes_done: u32,
    /// The pass rendering stops before (`--passes A..B`: B); all of them when `None`.
    end_pass: Option<u32>,
    /// The last chunk traced's film samples: splatted beside the next chunk's stages, or when
    /// the render returns.
    unsplatted: ChunkSamples,
}

/// A bounce stage: one system in a schedule of its own, so it can be timed on its own.
struct Stage {
    name: &'static str,
    schedule: Schedule,
    works_on: StageItems,
}

/// What a bounce stage works on, and so what its work is counted in.
#[derive(Clone, Copy, PartialEq, Eq)]
enum StageItems {
    LivePaths,
    /// The shadow rays the shading stage made: skipped in a bounce that made none (a scene lit
    /// only by light the paths hit, such as the furnace's sky), which saves its parallel loop.
    ShadowRays,
    /// The live paths, once their shadow rays are traced: skipped as well when there are none.
    ShadowResults,
}

impl Stage {
    fn new<M, S: IntoScheduleConfigs<bevy_ecs::system::ScheduleSystem, M>>(system: S) -> Self {
        let name = std::any::type_name::<S>();
        let mut schedule = Schedule::default();
        schedule.add_systems(system);
        Self {
            name: name.rsplit("::").next().unwrap_or(name),
            schedule,
            works_on: StageItems::LivePaths,
        }
    }
}

/// Where a stage's time went: its wall-clock time over the render and the items (camera paths,
/// rays or paths) it processed.
#[derive(Clone, Debug)]
pub struct StageTime {
    pub name: &'static str,
    pub time: Duration,
    pub items: u64,
}

/// How far a render is, told after every chunk.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Camera paths traced so far, over all passes.
    pub paths_done: u64,
    /// Camera paths of the whole render (pixels times samples per pixel).
    pub paths_total: u64,
    /// Passes completed.
    pub passes_done: u32,
}

/// What a render did.
#[derive(Clone, Copy, Debug)]
pub struct RenderStats {
    /// Passes completed: samples per pixel.
    pub passes: u32,
    /// Camera paths traced, including those of a pass stopped part way.
    pub paths: u64,
    /// Whether the render stopped at the end of a pass, every pixel with `passes` samples; if not,
    /// the pixels of the stopped pass's finished chunks have one sample more.
    pub complete_passes: bool,
    /// Rays traced: path segments plus shadow rays.
    pub rays: u64,
    pub elapsed: Duration,
}

impl RenderStats {
    pub fn paths_per_second(&self) -> f64 {
        self.paths as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }
}

impl Renderer {
    /// Runs the startup systems on a populated world and builds the render schedules.
    pub fn new(mut world: World) -> Self {
        world.init_resource::<Techniques>();
        if world.resource::<Techniques>().film == Reconstruction::Splat {
            // Splatting: positions uniform in the pixel, the filter's weights on the film.
            let filter = std::mem::replace(
                &mut world.resource_mut::<CameraSampling>().filter,
                PixelFilter::pixel_box(),
            );
            world.resource_mut::<Film>().splat_with(filter);
        }
        let mut startup = Schedule::default();
        startup.add_systems((build_scene_geometry, build_light_table).chain());
        startup.run(&mut world);

        let settings = world.resource::<RenderSettings>().clone();
        world.init_resource::<PassIndex>();
        world.init_resource::<ChunkRange>();
        world.init_resource::<PathBatch>();
        world.init_resource::<HitBatch>();
        // The path tracer: one ray to a light drawn at random, and all its first vertex's
        // padded draws computed ahead; the ray caster: one ray per light, and its BSDF choice.
        let (rays_per_path, slot_per_light, draws_ahead) = match settings.integrator {
            IntegratorKind::PathTracer => (1, false, PADDED_DRAWS),
            IntegratorKind::RayCaster => (
                shadow_rays_per_path(world.resource::<LightTable>()),
                true,
                shade_raycast::DRAWS_AHEAD,
            ),
        };
        world.insert_resource(ShadowBatch::new(rays_per_path, slot_per_light));
        world.insert_resource(FirstDrawsTable::new(draws_ahead));

        let mut chunk = Schedule::default();
        register_cameras(&mut chunk, &mut world);
        chunk.add_systems(start_pass.before(CameraStage::Generate));

        // The integrator is the choice of shading stage; every other stage is shared.
        let shade = match settings.integrator {
            IntegratorKind::PathTracer => Stage::new(shade_path_vertices),
            IntegratorKind::RayCaster => Stage::new(shade_raycast_hits),
        };
        let bounce = vec![
            Stage::new(trace_closest_hits),
            shade,
            Stage {
                works_on: StageItems::ShadowRays,
                ..Stage::new(trace_shadow_rays)
            },
            Stage {
                works_on: StageItems::ShadowResults,
                ..Stage::new(gather_unoccluded_light)
            },
            Stage::new(retire_finished_paths),
        ];
        Self {
            world,
            chunk,
            bounce,
            chunk_paths: DEFAULT_CHUNK_PATHS,
            stage_times: None,
            passes_done: 0,
            end_pass: None,
            unsplatted: Default::default(),
        }
    }

    /// Sets the camera paths per chunk (at least 1); the image does not depend on it.
    pub fn set_chunk_paths(&mut self, paths: usize) {
        self.chunk_paths = paths.max(1);
    }

    /// Times every stage of the renders that follow (see [`Renderer::stage_times`]).
    pub fn time_stages(&mut self) {
        let names = std::iter::once("start_pass + camera")
            .chain(self.bounce.iter().map(|s| s.name))
            .chain([SPLAT_STAGE]);
        self.stage_times = Some(
            names
                .map(|name| StageTime {
                    name,
                    time: Duration::ZERO,
                    items: 0,
                })
                .collect(),
        );
    }

    /// Time and items per stage so far, if [`Renderer::time_stages`] was called.
    pub fn stage_times(&self) -> Option<&[StageTime]> {
        self.stage_times.as_deref()
    }

    /// The film's current estimate: mean radiance per pixel, rows from the top.
    pub fn image(&self) -> Vec<glam::Vec3> {
        self.world.resource::<crate::film::Film>().mean()
    }

    pub fn samples_per_pixel(&self) -> u32 {
        self.world.resource::<RenderSettings>().samples_per_pixel
    }

    /// What was built for this scene, for `--verbose`.
    pub fn describe(&mut self) -> String {
        let world = &mut self.world;
        let settings = world.resource::<RenderSettings>().clone();
        let geometry = world.resource::<SceneGeometry>();
        let stats = geometry.accel.stats();
        let mut lines = vec![
            format!(
                "render: {}x{}, {} spp, max depth {}, {:?}, {:?} sampler, seed {}",
                settings.width,
                settings.height,
                settings.samples_per_pixel,
                settings.max_depth,
                settings.integrator,
                settings.sampler,
                settings.seed
            ),
            format!(
                "geometry: {} triangles, {} spheres, {} planes, {} disks; {} emissive shapes; uvs {}, shading normals {}",
                geometry.triangles.len(),
                geometry.spheres.len(),
                geometry.planes.len(),
                geometry.disks.len(),
                geometry.emissive_shapes.len(),
                if geometry.triangle_uvs.is_empty() {
                    "not kept"
                } else {
                    "kept"
                },
                if geometry.triangle_normals.is_empty() {
                    "none"
                } else {
                    "kept"
                },
            ),
            format!(
                "bvh: {} nodes, {} leaves, depth {}, largest leaf {}, built in {:.1} ms",
                stats.nodes,
                stats.leaves,
                stats.max_depth,
                stats.max_leaf_size,
                stats.build_time.as_secs_f64() * 1e3
            ),
        ];
        let lights = world.resource::<LightTable>();
        lines.push(format!(
            "lights: {} ({}); MIS {}",
            lights.lights.len(),
            lights.kinds(),
            if lights.has_hittable_lights() {
                "on"
            } else {
                "off: only delta lights"
            }
        ));
        lines.push(format!(
            "materials: {}; textures: {}",
            world.resource::<MaterialTable>().materials.len(),
            world
                .get_resource::<TextureTable>()
                .map_or("none loaded".to_string(), |t| t.textures.len().to_string())
        ));
        let mut camera = world.query::<EntityRef>();
        for entity in camera.iter(world) {
            if entity.contains::<crate::camera::CameraPose>() {
                let names: Vec<String> = entity
                    .archetype()
                    .components()
                    .iter()
                    .filter_map(|id| world.components().get_name(*id))
                    .map(|name| name.shortname().to_string())
                    .collect();
                lines.push(format!("camera entity: {}", names.join(" + ")));
            }
        }
        // Building the schedule's graph here is the same work its first run would do.
        let _ = self.chunk.initialize(world);
        let systems: Vec<String> = self
            .chunk
            .systems()
            .map(|systems| {
                systems
                    .map(|(_, system)| system.name().shortname().to_string())
                    .collect()
            })
            .unwrap_or_default();
        lines.push(format!(
            "chunk schedule ({} paths): {}",
            self.chunk_paths,
            systems.join(", ")
        ));
        let stages: Vec<&str> = self.bounce.iter().map(|stage| stage.name).collect();
        lines.push(format!("bounce stages: {}", stages.join(", ")));
        lines.join("\n")
    }

    /// Continues from a film holding `passes` completed passes (a checkpoint of this scene with
    /// the same settings): the passes rendered next draw the same random streams (seeded by seed,
    /// pixel and pass) as an uninterrupted render, so the image is the same to the bit.
    /// Returns false, and changes nothing, if the film's size is not this render's.
    pub fn resume(&mut self, film: crate::film::Film, passes: u32) -> bool {
        let restored = self.world.resource_mut::<crate::film::Film>().restore(film);
        if restored {
            self.passes_done = passes;
        }
        restored
    }

    /// Renders only the passes `first..end` (a part, `foton render --passes`), into an empty
    /// film: each pass draws the random streams it has in a full render (seeded by seed, pixel
    /// and pass), so the parts' films sum to the full render's.
    pub fn render_only_passes(&mut self, first: u32, end: u32) {
        self.passes_done = first;
        self.end_pass = Some(end);
    }

    /// The pass the render stops before: the samples per pixel, or the end of a part's passes.
    pub fn end_pass(&self) -> u32 {
        let spp = self.samples_per_pixel();
        self.end_pass.map_or(spp, |end| end.min(spp))
    }

    /// Renders passes until the samples per pixel or the time limit (checked at the end of each
    /// pass) are reached, or until `on_progress`, told after each chunk how far the render is,
    /// returns false.
    pub fn render(&mut self, mut on_progress: impl FnMut(Progress) -> bool) -> RenderStats {
        let settings = self.world.resource::<RenderSettings>().clone();
        let pixels = settings.path_count();
        let chunk = self.chunk_paths.min(pixels.max(1));
        let end_pass = self.end_pass();
        let paths_total = u64::from(end_pass) * pixels as u64;
        let start = Instant::now();
        let (mut rays, mut paths) = (0u64, 0u64);
        let mut passes = self.passes_done;
        let resumed_paths = u64::from(passes) * pixels as u64;
        let mut complete_passes = true;
        'passes: while passes < end_pass {
            self.world.resource_mut::<PassIndex>().0 = passes;
            for first in (0..pixels).step_by(chunk) {
                let count = chunk.min(pixels - first);
                *self.world.resource_mut::<ChunkRange>() = ChunkRange {
                    first: first as u32,
                    count: count as u32,
                };
                // On a worker of the thread pool, the stages' parallel loops hand their halves to
                // the other workers directly; from outside it, each loop would be injected into
                // the pool and this thread put to sleep until it ends (two wake-ups per loop,
                // about ten loops per bounce).
                rays += rayon::scope(|_| self.trace_chunk(count, passes));
                paths += count as u64;
                let pass_done = first + count == pixels;
                passes += u32::from(pass_done);
                let progress = Progress {
                    paths_done: resumed_paths + paths,
                    paths_total,
                    passes_done: passes,
                };
                if !on_progress(progress) {
                    complete_passes = pass_done;
                    self.passes_done = passes;
                    break 'passes;
                }
            }
            self.passes_done = passes;
            if settings
                .time_limit
                .is_some_and(|limit| start.elapsed() >= limit)
            {
                break;
            }
        }
        let world = &mut self.world;
        let time = (self.stage_times.as_deref_mut()).and_then(|times| times.last_mut());
        splat_timed(&mut world.resource_mut::<Film>(), &self.unsplatted, time);
        self.unsplatted.samples.clear();
        RenderStats {
            passes,
            paths,
            complete_passes,
            rays,
            elapsed: start.elapsed(),
        }
    }

    /// Traces the chunk of `count` camera paths of pass `pass` set in [`ChunkRange`] through
    /// all its bounces, while the last chunk's samples are splatted; keeps this chunk's samples
    /// for the next. Returns the rays traced.
    ///
    /// The splat is one task, which another thread takes while this one starts the stages (it
    /// is the oldest task in this thread's queue), and the stages' parallel loops share the
    /// rest: the film's sums take their samples in one order, chunk after chunk, each in
    /// (bounce, slot) order, so the image is the same at any thread count. Splatted in parallel
    /// over bands of rows instead, a sample near a band's edge had its weights computed by both
    /// bands, and the splat scaled 1.05x-1.18x from one thread to two (docs/speed.md, stop 34).
    /// On one thread the splat follows the stages.
    fn trace_chunk(&mut self, count: usize, pass: u32) -> u64 {
        let world = &mut self.world;
        // The splat's time is the last entry, the stages' the others.
        let (splat_time, times) = match self.stage_times.as_deref_mut() {
            Some(times) => times
                .split_last_mut()
                .map(|(last, rest)| (Some(last), Some(rest))),
            None => None,
        }
        .unwrap_or((None, None));
        let mut film = world
            .remove_resource::<Film>()
            .expect("a renderer's world has a film");
        let unsplatted = &self.unsplatted;
        let (chunk, bounce) = (&mut self.chunk, &mut self.bounce);
        let (rays, ()) = rayon::join(
            || trace_stages(chunk, bounce, world, times, count),
            || splat_timed(&mut film, unsplatted, splat_time),
        );
        world.insert_resource(film);
        (world.resource_mut::<PathBatch>()).take_finished(&mut self.unsplatted.samples);
        self.unsplatted.pass = pass;
        rays
    }
}

/// Name of the film's splat in the stage times (it runs beside the stages, see
/// [`Renderer::trace_chunk`]).
const SPLAT_STAGE: &str = "film splat (beside them)";

/// A chunk's film samples and the pass they belong to.
#[derive(Default)]
struct ChunkSamples {
    samples: FinishedSamples,
    pass: u32,
}

/// Splats a chunk's samples on `film`, adding the time taken to `time` when stages are timed.
fn splat_timed(
    film: &mut Film,
    ChunkSamples { samples, pass }: &ChunkSamples,
    time: Option<&mut StageTime>,
) {
    let start = Instant::now();
    if !samples.samples().is_empty() {
        film.begin_pass(*pass);
        film.add_samples(samples.samples());
    }
    if let Some(time) = time {
        time.time += start.elapsed();
        time.items += samples.samples().len() as u64;
    }
}

/// Runs the chunk's start and its bounces for `count` camera paths, each stage timed into its
/// entry of `times` (the start first, then the bounce stages) when stages are timed; returns
/// the rays traced.
fn trace_stages(
    chunk: &mut Schedule,
    bounce: &mut [Stage],
    world: &mut World,
    mut times: Option<&mut [StageTime]>,
    count: usize,
) -> u64 {
    run_timed(chunk, world, times.as_deref_mut().map(|t| &mut t[0]), count);
    let mut rays = 0;
    loop {
        let live = world.resource::<PathBatch>().len;
        if live == 0 {
            return rays;
        }
        rays += live as u64;
        let mut shadow_rays = 0;
        for (i, stage) in bounce.iter_mut().enumerate() {
            let items = match stage.works_on {
                StageItems::LivePaths => live,
                StageItems::ShadowRays => {
                    shadow_rays = world.resource::<ShadowBatch>().rays;
                    rays += shadow_rays as u64;
                    shadow_rays
                }
                StageItems::ShadowResults => live,
            };
            if stage.works_on != StageItems::LivePaths && shadow_rays == 0 {
                continue;
            }
            let time = times.as_deref_mut().map(|t| &mut t[i + 1]);
            run_timed(&mut stage.schedule, world, time, items);
        }
    }
}

/// Runs `schedule`, adding its time and `items` to `time` when stages are timed.
fn run_timed(
    schedule: &mut Schedule,
    world: &mut World,
    time: Option<&mut StageTime>,
    items: usize,
) {
    match time {
        Some(time) => {
            let start = Instant::now();
            schedule.run(world);
            time.time += start.elapsed();
            time.items += items as u64;
        }
        None => schedule.run(world),
    }
}
