//! The wavefront integrator: schedules of small systems over the whole batch of live paths.
//!
//! ```text
//! startup:  build_scene_geometry → build_light_table
//! pass:     start_pass → camera (generate → lens → to world)
//! bounce:   trace_closest_hits → shade (path or raycast) → trace_shadow_rays
//!           → gather_unoccluded_light → retire_finished_paths   (repeated while paths live)
//! ```

pub mod accumulate;
pub mod batch;
pub mod shade_path;
pub mod shade_raycast;
pub mod shading;
pub mod start_pass;
pub mod trace;

use std::time::{Duration, Instant};

use bevy_ecs::prelude::*;

use crate::camera::{CameraStage, register_cameras};
use crate::light::{LightTable, build_light_table};
use crate::material::MaterialTable;
use crate::material::texture::TextureTable;
use crate::settings::{IntegratorKind, RenderSettings};
use crate::shape::geometry::{SceneGeometry, build_scene_geometry};
use accumulate::{gather_unoccluded_light, retire_finished_paths};
use batch::{HitBatch, PathBatch, ShadowBatch};
use shade_path::shade_path_vertices;
use shade_raycast::{shade_raycast_hits, shadow_rays_per_path};
use start_pass::{PassIndex, start_pass};
use trace::{trace_closest_hits, trace_shadow_rays};

/// The world and the schedules that render it.
pub struct Renderer {
    pub world: World,
    pass: Schedule,
    bounce: Schedule,
    /// Passes already in the film (from a checkpoint): rendering goes on from there.
    passes_done: u32,
}

/// What a render did.
#[derive(Clone, Copy, Debug)]
pub struct RenderStats {
    /// Passes completed: samples per pixel.
    pub passes: u32,
    /// Camera paths traced (pixels times passes).
    pub paths: u64,
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
        let mut startup = Schedule::default();
        startup.add_systems((build_scene_geometry, build_light_table).chain());
        startup.run(&mut world);

        let settings = world.resource::<RenderSettings>().clone();
        world.init_resource::<PassIndex>();
        world.init_resource::<PathBatch>();
        world.init_resource::<HitBatch>();
        let rays_per_path = match settings.integrator {
            IntegratorKind::PathTracer => 1,
            IntegratorKind::RayCaster => shadow_rays_per_path(world.resource::<LightTable>()),
        };
        world.insert_resource(ShadowBatch::new(rays_per_path));

        let mut pass = Schedule::default();
        register_cameras(&mut pass, &mut world);
        pass.add_systems(start_pass.before(CameraStage::Generate));

        // The integrator is the choice of shading stage; every other stage is shared.
        let mut bounce = Schedule::default();
        let stages = match settings.integrator {
            IntegratorKind::PathTracer => (
                trace_closest_hits,
                shade_path_vertices,
                trace_shadow_rays,
                gather_unoccluded_light,
                retire_finished_paths,
            )
                .chain(),
            IntegratorKind::RayCaster => (
                trace_closest_hits,
                shade_raycast_hits,
                trace_shadow_rays,
                gather_unoccluded_light,
                retire_finished_paths,
            )
                .chain(),
        };
        bounce.add_systems(stages);
        Self {
            world,
            pass,
            bounce,
            passes_done: 0,
        }
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
                "geometry: {} triangles, {} spheres, {} planes; {} emissive shapes; uvs {}, shading normals {}",
                geometry.triangles.len(),
                geometry.spheres.len(),
                geometry.planes.len(),
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
        for (name, schedule) in [("pass", &mut self.pass), ("bounce", &mut self.bounce)] {
            // Building the schedule's graph here is the same work its first run would do.
            let _ = schedule.initialize(world);
            let systems: Vec<String> = schedule
                .systems()
                .map(|systems| {
                    systems
                        .map(|(_, system)| system.name().shortname().to_string())
                        .collect()
                })
                .unwrap_or_default();
            lines.push(format!("{name} schedule: {}", systems.join(", ")));
        }
        lines.join("\n")
    }

    /// Continues from a film holding `passes` completed passes (a checkpoint of this scene with
    /// the same settings): the passes rendered next draw the same random streams (seeded by seed,
    /// pixel and pass) as an uninterrupted render, so the image is the same to the bit.
    pub fn resume(&mut self, film: crate::film::Film, passes: u32) {
        self.world.insert_resource(film);
        self.passes_done = passes;
    }

    /// Renders passes until the samples per pixel or the time limit are reached, or until
    /// `on_pass` (told after each pass how many are done) returns false.
    pub fn render(&mut self, mut on_pass: impl FnMut(u32) -> bool) -> RenderStats {
        let settings = self.world.resource::<RenderSettings>().clone();
        let start = Instant::now();
        let mut rays = 0u64;
        let first = self.passes_done;
        let mut passes = first;
        while passes < settings.samples_per_pixel {
            self.world.resource_mut::<PassIndex>().0 = passes;
            self.pass.run(&mut self.world);
            while self.world.resource::<PathBatch>().len > 0 {
                rays += self.world.resource::<PathBatch>().len as u64;
                self.bounce.run(&mut self.world);
                let shadows = self.world.resource::<ShadowBatch>();
                rays += shadows.t_max.iter().filter(|t| **t > 0.0).count() as u64;
            }
            passes += 1;
            self.passes_done = passes;
            let go_on = on_pass(passes);
            if !go_on
                || settings
                    .time_limit
                    .is_some_and(|limit| start.elapsed() >= limit)
            {
                break;
            }
        }
        RenderStats {
            passes,
            paths: u64::from(passes - first) * settings.path_count() as u64,
            rays,
            elapsed: start.elapsed(),
        }
    }
}
