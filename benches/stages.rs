//! Each wavefront stage on its own, on a fixed chunk of paths of the project's Cornell box
//! (128x128 pixels, one chunk of 16,384 camera paths): camera rays, closest hits of coherent
//! (camera) and incoherent (first diffuse bounce) rays, shadow rays, path shading, and
//! accumulation (gathering unoccluded light, retiring finished paths to the film).
//! `cargo bench --bench stages`; compare ratios measured in one run.

use std::path::Path;
use std::time::{Duration, Instant};

use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemId;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use foton::camera::{CameraStage, register_cameras};
use foton::integrator::Renderer;
use foton::integrator::accumulate::{gather_unoccluded_light, retire_finished_paths};
use foton::integrator::batch::{PathBatch, ShadowBatch};
use foton::integrator::shade_path::shade_path_vertices;
use foton::integrator::start_pass::{ChunkRange, compute_first_draws, start_pass};
use foton::integrator::trace::{trace_closest_hits, trace_shadow_rays};
use foton::scene::build::{RenderOptions, build_world};
use foton::scene::lxs;

const SIDE: u32 = 128;
const PATHS: u32 = SIDE * SIDE;

/// The Cornell box's world with one chunk of the whole image, and its stages as systems.
struct Stages {
    world: World,
    camera: Schedule,
    trace: SystemId,
    first_draws: SystemId,
    shade: SystemId,
    shadow: SystemId,
    gather: SystemId,
    retire: SystemId,
}

impl Stages {
    fn new() -> Self {
        let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell.lxs");
        let desc = lxs::load(&scene).expect("scenes/cornell.lxs loads");
        let options = RenderOptions {
            samples_per_pixel: Some(4),
            resolution: Some((SIDE, SIDE)),
            ..RenderOptions::default()
        };
        let mut world = Renderer::new(build_world(desc, &options).0).world;
        *world.resource_mut::<ChunkRange>() = ChunkRange {
            first: 0,
            count: PATHS,
        };
        let mut camera = Schedule::default();
        register_cameras(&mut camera, &mut world);
        camera.add_systems(start_pass.before(CameraStage::Generate));
        Self {
            trace: world.register_system(trace_closest_hits),
            first_draws: world.register_system(compute_first_draws),
            shade: world.register_system(shade_path_vertices),
            shadow: world.register_system(trace_shadow_rays),
            gather: world.register_system(gather_unoccluded_light),
            retire: world.register_system(retire_finished_paths),
            world,
            camera,
        }
    }

    fn run(&mut self, system: SystemId) {
        self.world.run_system(system).expect("stage runs");
    }

    /// Fresh camera paths, then each of `stages` in turn.
    fn prepare(&mut self, stages: &[SystemId]) {
        self.camera.run(&mut self.world);
        for &stage in stages {
            self.run(stage);
        }
    }

    /// Times `stage` alone, each time after `prepare(before)`.
    fn time(&mut self, iters: u64, before: &[SystemId], stage: &[SystemId]) -> Duration {
        let mut total = Duration::ZERO;
        for _ in 0..iters {
            self.prepare(before);
            let start = Instant::now();
            for &s in stage {
                self.run(s);
            }
            total += start.elapsed();
        }
        total
    }
}

fn stages(c: &mut Criterion) {
    let mut s = Stages::new();
    let (trace, first, shade) = (s.trace, s.first_draws, s.shade);
    let (shadow, gather, retire) = (s.shadow, s.gather, s.retire);
    let mut group = c.benchmark_group("stages");
    group.sample_size(20);
    group.throughput(Throughput::Elements(u64::from(PATHS)));
    group.bench_function("camera_rays", |b| {
        b.iter(|| s.camera.run(&mut s.world));
    });
    group.bench_function("closest_hit_coherent", |b| {
        b.iter_custom(|iters| s.time(iters, &[], &[trace]));
    });
    // After one diffuse bounce the live paths' rays leave the walls in all directions.
    let bounced = [trace, first, shade, shadow, gather, retire];
    s.prepare(&bounced);
    group.throughput(Throughput::Elements(
        s.world.resource::<PathBatch>().len as u64,
    ));
    group.bench_function("closest_hit_incoherent", |b| {
        b.iter_custom(|iters| s.time(iters, &bounced, &[trace]));
    });
    group.throughput(Throughput::Elements(u64::from(PATHS)));
    group.bench_function("shade_path_vertices", |b| {
        b.iter_custom(|iters| s.time(iters, &[trace, first], &[shade]));
    });
    s.prepare(&[trace, first, shade]);
    let shadow_rays = s.world.resource::<ShadowBatch>().rays;
    group.throughput(Throughput::Elements(shadow_rays as u64));
    group.bench_function("shadow_rays", |b| {
        b.iter_custom(|iters| s.time(iters, &[trace, first, shade], &[shadow]));
    });
    group.throughput(Throughput::Elements(u64::from(PATHS)));
    group.bench_function("accumulate", |b| {
        b.iter_custom(|iters| s.time(iters, &[trace, first, shade, shadow], &[gather, retire]));
    });
    group.finish();
}

criterion_group!(benches, stages);
criterion_main!(benches);
