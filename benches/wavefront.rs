//! Wavefront throughput: camera paths per second through the whole schedule (ray generation,
//! traversal, shading, shadow rays, accumulation) on the project's Cornell box, for both
//! integrators. `cargo bench --bench wavefront`; compare ratios measured in one run.

use std::path::Path;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use foton::integrator::Renderer;
use foton::scene::build::{RenderOptions, build_world};
use foton::settings::IntegratorKind;

fn wavefront(c: &mut Criterion) {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell.lxs");
    let desc = foton::scene::load(&scene).expect("scenes/cornell.lxs loads");
    let (width, height, spp) = (160, 160, 4);
    let mut group = c.benchmark_group("wavefront");
    group.sample_size(10);
    group.throughput(Throughput::Elements((width * height * spp) as u64));
    for (name, integrator) in [
        ("path_tracer", IntegratorKind::PathTracer),
        ("ray_caster", IntegratorKind::RayCaster),
    ] {
        let options = RenderOptions {
            samples_per_pixel: Some(spp),
            resolution: Some((width, height)),
            integrator: Some(integrator),
            ..RenderOptions::default()
        };
        group.bench_function(name, |b| {
            b.iter_batched(
                || Renderer::new(build_world(desc.clone(), &options).0),
                |mut renderer| renderer.render(|_| true),
                criterion::BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, wavefront);
criterion_main!(benches);
