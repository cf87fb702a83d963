//! The wavefront integrator: schedules of small systems over a batch of live paths.
//!
//! ```text
//! startup:  build_scene_geometry → build_light_table
//! chunk:    start_pass → camera (generate → lens → to world)
//! bounce:   trace_closest_hits → compute_first_draws (the first bounce only)
//!           → shade (path or raycast) → trace_shadow_rays → gather_unoccluded_light
//!           → retire_finished_paths   (repeated while paths live)
//! film:     the chunks' samples splatted in chunk order, beside other chunks' stages
//! ```
//!
//! A pass (one sample per pixel) runs as chunks of consecutive pixels, each traced through all
//! its bounces in one world, so that a chunk's batches stay in the caches between stages
//! rather than streaming the whole image through memory at every stage; with several threads,
//! as many chunks are traced at once, each in a world of its own ([`in_flight`]). A path's
//! result depends only on its pixel, pass and seed, every pixel takes one sample per pass, and
//! the film takes the chunks in order, so the image is the same at any thread count. The chunk
//! size changes only the order in which a splatting filter's sums take the samples of
//! neighbouring chunks, near a chunk's first and last rows: their last bits (8k against 16k
//! paths: about 850 pixels of 49,152, at most 2.3e-7 relative, on dof-sky, envmap and
//! textured).

pub mod accumulate;
pub mod batch;
mod conductor_lanes;
mod diffuse_lanes;
mod escaped_lanes;
mod glass_lanes;
mod in_flight;
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
use crate::sampling::{
    LIGHT_CHOICE_DRAW, LIGHT_POINT_DRAW, LOBE_DRAW, MATERIAL_CHOICE_DRAW, PADDED_DRAWS,
};
use crate::settings::{IntegratorKind, RenderSettings, Techniques};
use crate::shape::geometry::{SceneGeometry, build_scene_geometry};
use crate::shared::Shared;
use accumulate::{gather_unoccluded_light, retire_finished_paths};
use batch::{HitBatch, PathBatch, ShadowBatch};
use in_flight::{ChunkJob, ChunkPlan, ChunkWorld, Intake, MAX_IN_FLIGHT, trace_in_flight};
use shade_path::{draws_no_lobe, shade_path_vertices};
use shade_raycast::{shade_raycast_hits, shadow_rays_per_path};
use start_pass::{
    CameraSampling, ChunkRange, FirstDrawsTable, PassIndex, compute_first_draws, start_pass,
};
use trace::{trace_closest_hits, trace_shadow_rays};

/// Camera paths per chunk unless [`Renderer::set_chunk_paths`] says otherwise. At ~100 bytes of
/// batch state per path (twice, with the compaction's spare columns), plus its hit and shadow
/// ray, a chunk of 8k keeps its batches within about 2 MB, and a chunk in flight per thread
/// (`in_flight.rs`) about as much per core. Measured with chunks in flight (docs/speed.md, stop
/// 37), `foton bench --spp 64 --threads 2`, ten rounds: 8k against 16k 1.04x-1.06x on dof-sky
/// and the furnace, 0.98x on the Cornell box; 4k slower than 8k on the furnace; at one thread
/// 8k and 16k within 3 %. (With one chunk at a time, 16k had been faster than 8k at two
/// threads: more work in each stage to share.)
pub const DEFAULT_CHUNK_PATHS: usize = 8 * 1024;

/// The world and the schedules that render it.
pub struct Renderer {
    pub world: World,
    /// Starts a chunk: fresh paths and their camera rays.
    chunk: Schedule,
    /// One bounce, stage by stage.
    bounce: Vec<Stage>,
    /// The worlds tracing the other chunks in flight beside the main world's (one fewer than
    /// the threads, up to [`MAX_IN_FLIGHT`]); made at the first render, for its thread pool.
    others: Vec<ChunkWorld>,
    chunk_paths: usize,
    /// Time and work per stage, when asked for: the chunk start first, then the bounce stages.
    stage_times: Option<Vec<StageTime>>,
    /// Passes already in the film (from a checkpoint): rendering goes on from there.
    passes_done: u32,
    /// The pass rendering stops before (`--passes A..B`: B); all of them when `None`.
    end_pass: Option<u32>,
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
    /// The camera paths, at the chunk's first bounce alone.
    FirstBounce,
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
    /// What a render has done before it traces anything, its film holding `passes` passes.
    pub fn empty(passes: u32) -> Self {
        Self {
            passes,
            paths: 0,
            complete_passes: true,
            rays: 0,
            elapsed: Duration::ZERO,
        }
    }

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
        insert_chunk_state(&mut world);
        let chunk = chunk_schedule(&mut world);
        let bounce = bounce_stages(settings.integrator);
        Self {
            world,
            chunk,
            bounce,
            others: Vec::new(),
            chunk_paths: DEFAULT_CHUNK_PATHS,
            stage_times: None,
            passes_done: 0,
            end_pass: None,
        }
    }

    /// Sets the camera paths per chunk (at least 1); the image depends on it only in its last
    /// bits (see the module's notes).
    pub fn set_chunk_paths(&mut self, paths: usize) {
        self.chunk_paths = paths.max(1);
    }

    /// Times every stage of the renders that follow (see [`Renderer::stage_times`]).
    pub fn time_stages(&mut self) {
        for other in &mut self.others {
            other.times = Some(empty_stage_times(&self.bounce));
        }
        self.stage_times = Some(empty_stage_times(&self.bounce));
    }

    /// Time and items per stage so far, if [`Renderer::time_stages`] was called: summed over
    /// the worlds in flight, whose stages overlap in time.
    pub fn stage_times(&self) -> Option<Vec<StageTime>> {
        let mut sums = self.stage_times.clone()?;
        for times in self.others.iter().filter_map(|other| other.times.as_ref()) {
            for (sum, time) in sums.iter_mut().zip(times) {
                sum.time += time.time;
                sum.items += time.items;
            }
        }
        Some(sums)
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
        let geometry = world.resource::<Shared<SceneGeometry>>();
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
                "geometry: {} triangles, {} spheres, {} planes, {} disks; {} emissive shapes; \
                 uvs {}, shading normals {}",
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
        let lights = world.resource::<Shared<LightTable>>();
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
            "chunk schedule ({} paths a chunk, {} in flight): {}",
            self.chunk_paths,
            worlds_in_flight(),
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
    ///
    /// Each world in flight takes the next chunk as soon as it is done with its last, on a
    /// thread of its own, and the film takes the chunks in order (see
    /// [`in_flight`](self::in_flight)). Chunks traced past the one after which the render
    /// stops are dropped, so the film holds what a render one chunk at a time would hold.
    pub fn render(&mut self, on_progress: impl FnMut(Progress) -> bool + Send) -> RenderStats {
        self.fit_worlds_in_flight();
        let settings = self.world.resource::<RenderSettings>().clone();
        let plan = ChunkPlan::new(
            settings.path_count(),
            self.chunk_paths,
            self.passes_done..self.end_pass(),
        );
        let start = Instant::now();
        // The splat's time is the last entry, the stages' the others.
        let (splat_time, times) = match self.stage_times.as_deref_mut() {
            Some(times) => times
                .split_last_mut()
                .map(|(last, rest)| (Some(last), Some(rest))),
            None => None,
        }
        .unwrap_or((None, None));
        let film = (self.world)
            .remove_resource::<Film>()
            .expect("a renderer's world has a film");
        let main = (
            &mut self.world,
            &mut self.chunk,
            &mut self.bounce[..],
            times,
        );
        let worlds = std::iter::once(main).chain(self.others.iter_mut().map(ChunkWorld::stages));
        let intake = Intake {
            film,
            splat_time,
            time_limit: settings.time_limit.map(|limit| (start, limit)),
            on_progress,
        };
        let (film, mut stats) = trace_in_flight(&plan, worlds.collect(), intake);
        self.world.insert_resource(film);
        self.passes_done = stats.passes;
        stats.elapsed = start.elapsed();
        stats
    }

    /// Makes one world in flight per thread of the pool the render runs in (up to
    /// [`MAX_IN_FLIGHT`]): the main world and the others.
    fn fit_worlds_in_flight(&mut self) {
        let others = worlds_in_flight() - 1;
        self.others.truncate(others);
        while self.others.len() < others {
            let mut other = ChunkWorld::new(&self.world);
            if self.stage_times.is_some() {
                other.times = Some(empty_stage_times(&self.bounce));
            }
            self.others.push(other);
        }
    }
}

/// The worlds in flight in the thread pool a render runs in: one per thread, up to
/// [`MAX_IN_FLIGHT`].
fn worlds_in_flight() -> usize {
    rayon::current_num_threads().clamp(1, MAX_IN_FLIGHT)
}

/// Gives `world` (holding the settings, the light table and the materials) the state of a
/// chunk in flight: which pass and pixels, and its batches.
fn insert_chunk_state(world: &mut World) {
    world.init_resource::<PassIndex>();
    world.init_resource::<ChunkRange>();
    world.init_resource::<PathBatch>();
    world.init_resource::<HitBatch>();
    // The path tracer: one ray to a light drawn at random, and its first vertex's padded draws
    // read from the table (those the scene uses computed ahead); the ray caster: one ray per
    // light, and its BSDF choice.
    let (rays_per_path, slot_per_light, draws_ahead) =
        match world.resource::<RenderSettings>().integrator {
            IntegratorKind::PathTracer => (1, false, PADDED_DRAWS),
            IntegratorKind::RayCaster => (
                shadow_rays_per_path(world.resource::<Shared<LightTable>>()),
                true,
                shade_raycast::DRAWS_AHEAD,
            ),
        };
    world.insert_resource(ShadowBatch::new(rays_per_path, slot_per_light));
    let unused = unused_first_draws(world.resource(), world.resource::<Shared<LightTable>>());
    world.insert_resource(FirstDrawsTable::new(draws_ahead, unused));
}

/// The first draws whose values nothing in the scene uses (see `sampling::FirstDraws`): the
/// material's choice where no material mixes; where every path's first surface scatters it
/// with a light sample (a delta BSDF draws its lobe and direction in the light's places, and a
/// null surface leaves them to the next one), the light's choice where there is one light or
/// none, the point on a light where there is none to sample, and the lobe where no BSDF draws
/// one ([`draws_no_lobe`]: Lambertian or a GGX conductor).
fn unused_first_draws(materials: &MaterialTable, lights: &LightTable) -> u32 {
    let draw = |unused: bool, draw: u32| u32::from(unused) << draw;
    let alike = materials.every_bsdf(|bsdf| !bsdf.is_delta());
    let one_lobe = materials.every_bsdf(draws_no_lobe);
    draw(!materials.has_mix(), MATERIAL_CHOICE_DRAW)
        | draw(alike && !lights.has_choice(), LIGHT_CHOICE_DRAW)
        | draw(alike && !lights.can_choose(), LIGHT_POINT_DRAW)
        | draw(one_lobe, LOBE_DRAW)
}

/// The chunk's start in `world`: fresh paths and the camera's rays.
fn chunk_schedule(world: &mut World) -> Schedule {
    let mut chunk = Schedule::default();
    register_cameras(&mut chunk, world);
    chunk.add_systems(start_pass.before(CameraStage::Generate));
    chunk
}

/// The bounce stages of `integrator`: the integrator is the choice of shading stage; every
/// other stage is shared.
fn bounce_stages(integrator: IntegratorKind) -> Vec<Stage> {
    let shade = match integrator {
        IntegratorKind::PathTracer => Stage::new(shade_path_vertices),
        IntegratorKind::RayCaster => Stage::new(shade_raycast_hits),
    };
    vec![
        Stage::new(trace_closest_hits),
        Stage {
            works_on: StageItems::FirstBounce,
            ..Stage::new(compute_first_draws)
        },
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
    ]
}

/// A world with its chunk start and bounce stages and, when stages are timed, their times (the
/// chunk start's first).
type WorldStages<'a> = (
    &'a mut World,
    &'a mut Schedule,
    &'a mut [Stage],
    Option<&'a mut [StageTime]>,
);

/// Starts `job`'s chunk in `world` and runs its bounces until no path lives, each stage timed
/// into its entry of `times` when stages are timed; returns the rays traced.
fn trace_chunk((world, chunk, bounce, times): &mut WorldStages, job: &ChunkJob) -> u64 {
    world.resource_mut::<PassIndex>().0 = job.pass;
    *world.resource_mut::<ChunkRange>() = ChunkRange {
        first: job.first as u32,
        count: job.count as u32,
    };
    let time = times.as_deref_mut().map(|t| &mut t[0]);
    run_timed(chunk, world, time, job.count);
    trace_bounces(bounce, world, times.as_deref_mut())
}

/// A world's stage times before any render: the chunk start, the `bounce` stages, the splat.
fn empty_stage_times(bounce: &[Stage]) -> Vec<StageTime> {
    let names = std::iter::once("start_pass + camera")
        .chain(bounce.iter().map(|s| s.name))
        .chain([SPLAT_STAGE]);
    names
        .map(|name| StageTime {
            name,
            time: Duration::ZERO,
            items: 0,
        })
        .collect()
}

/// Name of the film's splat in the stage times (it runs beside other worlds' stages, see
/// [`in_flight`]).
const SPLAT_STAGE: &str = "film splat (beside them)";

/// Runs the bounces of the chunk started in `world` until no path lives, each stage timed into
/// its entry of `times` (after the chunk start's) when stages are timed; returns the rays traced.
fn trace_bounces(
    bounce: &mut [Stage],
    world: &mut World,
    mut times: Option<&mut [StageTime]>,
) -> u64 {
    let mut rays = 0;
    for bounce_index in 0.. {
        let live = world.resource::<PathBatch>().len;
        if live == 0 {
            break;
        }
        rays += live as u64;
        let mut shadow_rays = 0;
        for (i, stage) in bounce.iter_mut().enumerate() {
            let items = match stage.works_on {
                StageItems::LivePaths => live,
                StageItems::FirstBounce if bounce_index > 0 => continue,
                StageItems::FirstBounce => live,
                StageItems::ShadowRays => {
                    shadow_rays = world.resource::<ShadowBatch>().rays;
                    rays += shadow_rays as u64;
                    shadow_rays
                }
                StageItems::ShadowResults => live,
            };
            let on_shadow_rays = matches!(
                stage.works_on,
                StageItems::ShadowRays | StageItems::ShadowResults
            );
            if on_shadow_rays && shadow_rays == 0 {
                continue;
            }
            let time = times.as_deref_mut().map(|t| &mut t[i + 1]);
            run_timed(&mut stage.schedule, world, time, items);
        }
    }
    rays
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

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};

    use glam::Vec3;

    use super::*;
    use crate::scene::build::{RenderOptions, build_world};

    /// `scene` (a path under the repository's root, or absolute) rendered at 40 x 30, 2 spp, on
    /// one thread, with the first draws its scene leaves out, or with every one computed; and
    /// the set of those computed.
    fn render_small(scene: &Path, every_draw: bool) -> (Vec<Vec3>, u32) {
        let desc = crate::scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join(scene))
            .expect("the scene loads");
        let options = RenderOptions {
            samples_per_pixel: Some(2),
            resolution: Some((40, 30)),
            ..RenderOptions::default()
        };
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build();
        pool.expect("a thread pool").install(|| {
            let mut renderer = Renderer::new(build_world(desc, &options).0);
            let mut table = renderer.world.resource_mut::<FirstDrawsTable>();
            if every_draw {
                table.computed = (1 << PADDED_DRAWS) - 1;
            }
            let computed = table.computed;
            renderer.render(|_| true);
            (renderer.image(), computed)
        })
    }

    /// A furnace (a unit sphere under a uniform sky) whose sphere's material is `material`
    /// (LuxRender's directives, which may name materials made before), written to a
    /// temporary file named after `name`.
    fn furnace_of(name: &str, material: &str) -> PathBuf {
        let path = std::env::temp_dir().join(format!("foton-{name}-{}.lxs", std::process::id()));
        let scene = format!(
            "LookAt 0 -4 0  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" [30]\n\
             WorldBegin\nLightSource \"infinite\" \"color L\" [1 1 1]\n{material}\n\
             Shape \"sphere\" \"float radius\" [1]\nWorldEnd\n"
        );
        std::fs::write(&path, scene).expect("a temporary file");
        path
    }

    /// The first draws a scene leaves uncomputed go unused: its image is the same to the bit
    /// with every first draw computed. The scenes make their first draws in each way: a matte
    /// sphere under a sky (all but the direction left out), matte walls lit through a null
    /// lamp, metal and glass (cornell.lxs), a thin lens, glass and a sky (dof-sky.lxs), lights
    /// to choose among (many-lights.lxs), a mix of two mattes and a shiny metal (written here:
    /// two lobes). Each fails with the mix's choice, a glass or null surface's lobe, or the
    /// metal's, taken for a draw nothing uses (checked).
    #[test]
    fn first_draws_left_out_go_unused() {
        let mix = furnace_of(
            "mix",
            "MakeNamedMaterial \"white\" \"string type\" [\"matte\"] \"color Kd\" [0.5 0.5 0.5]\n\
             MakeNamedMaterial \"red\" \"string type\" [\"matte\"] \"color Kd\" [0.8 0.1 0.1]\n\
             MakeNamedMaterial \"both\" \"string type\" [\"mix\"] \"string namedmaterial1\" \
             [\"white\"] \"string namedmaterial2\" [\"red\"] \"float amount\" [0.5]\n\
             NamedMaterial \"both\"",
        );
        let shiny = furnace_of(
            "shiny",
            "Material \"shinymetal\" \"color Kr\" [0.5 0.5 0.5] \"color Ks\" [0.5 0.5 0.5] \
             \"float uroughness\" [0.1] \"float vroughness\" [0.1]",
        );
        let scenes: [PathBuf; 6] = [
            "scenes/furnace.lxs".into(),
            "scenes/cornell.lxs".into(),
            "scenes/dof-sky.lxs".into(),
            "scenes/many-lights.lxs".into(),
            mix.clone(),
            shiny.clone(),
        ];
        let mut computed = Vec::new();
        for scene in &scenes {
            let (image, draws) = render_small(scene, false);
            assert!(image == render_small(scene, true).0, "{}", scene.display());
            computed.push(draws);
        }
        std::fs::remove_file(&mix).ok();
        std::fs::remove_file(&shiny).ok();
        // Left out: all but the furnace's direction, the material's choice in the box, none
        // with a mix, the lights' draws but not the lobe of a shiny metal.
        assert_eq!(
            (computed[0], computed[1], computed[4], computed[5]),
            (0b10000, 0b11110, 0b11111, 0b11000)
        );
    }
}
