//! BVH build time and closest-hit throughput on a procedurally tessellated torus of 1M
//! triangles, and the accel's bytes per triangle.
//!
//! `cargo bench --bench bvh -- --quick`; `cargo bench --bench bvh -- flat` alone prints the
//! crossover between testing a few primitives flat and the tree (`Accel::build_with_flat_limit`). The mesh and the rays are also written to
//! `target/bvh-peer/` (raw little-endian f32: 9 per triangle, 6 per ray: origin, direction),
//! which `scripts/peers/embree_compare.py` traces with Embree.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use foton::accel::{Accel, Primitives};
use glam::Vec3;
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::{Rng, SeedableRng};

const RAYS: usize = 1 << 16;

/// A torus (major radius 1, minor 0.3) of `2 · rings · sides` triangles.
fn torus(rings: usize, sides: usize) -> Vec<[Vec3; 3]> {
    use std::f32::consts::TAU;
    let point = |i: usize, j: usize| {
        let (u, v) = (TAU * i as f32 / rings as f32, TAU * j as f32 / sides as f32);
        let r = 1.0 + 0.3 * v.cos();
        Vec3::new(r * u.cos(), r * u.sin(), 0.3 * v.sin())
    };
    let mut tris = Vec::with_capacity(2 * rings * sides);
    for i in 0..rings {
        for j in 0..sides {
            let (a, b) = (point(i, j), point(i + 1, j));
            let (c, d) = (point(i + 1, j + 1), point(i, j + 1));
            tris.push([a, b, c]);
            tris.push([a, c, d]);
        }
    }
    tris
}

/// Rays from a sphere of radius 3 around the torus towards random points in its bounds:
/// roughly half hit, as in a camera's view of an object.
fn rays() -> (Vec<Vec3>, Vec<Vec3>) {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
    let mut uniform = || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0;
    (0..RAYS)
        .map(|_| {
            let origin = 3.0 * Vec3::new(uniform(), uniform(), uniform()).normalize_or(Vec3::X);
            let target = Vec3::new(1.3 * uniform(), 1.3 * uniform(), 0.3 * uniform());
            (origin, target - origin)
        })
        .unzip()
}

/// CPU time of the calling thread in seconds (Linux's `/proc/thread-self/schedstat`): on a
/// shared machine it counts only the time this thread ran, unlike wall time.
fn thread_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    Some(stat.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
}

/// CPU time of the whole process (all threads) in seconds, from `/proc/self/stat`'s utime and
/// stime (in clock ticks of 1/100 s on Linux).
fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15.
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// The median of `values`.
fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Writes `values` as raw little-endian f32 to `target/bvh-peer/name`.
fn write_f32(name: &str, values: impl Iterator<Item = f32>) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bvh-peer");
    std::fs::create_dir_all(&dir).expect("create target/bvh-peer");
    let bytes: Vec<u8> = values.flat_map(f32::to_le_bytes).collect();
    std::fs::write(dir.join(name), bytes).expect("write the peer files");
}

fn bench(c: &mut Criterion) {
    if std::env::args().any(|a| a == "flat") {
        return;
    }
    let primitives = Primitives {
        triangles: torus(1000, 500),
        ..Default::default()
    };
    let (origins, dirs) = rays();
    write_f32(
        "mesh.f32",
        primitives
            .triangles
            .iter()
            .flatten()
            .flat_map(|v| v.to_array()),
    );
    write_f32(
        "rays.f32",
        (origins.iter().zip(&dirs)).flat_map(|(o, d)| [o.to_array(), d.to_array()].concat()),
    );
    let mut group = c.benchmark_group("bvh");
    group.sample_size(10);
    group.throughput(Throughput::Elements(primitives.triangles.len() as u64));
    group.bench_function("build_torus_1m", |b| {
        b.iter(|| Accel::build(black_box(&primitives)))
    });

    let accel = Accel::build(&primitives);
    let t_maxs = vec![f32::INFINITY; RAYS];
    group.throughput(Throughput::Elements(RAYS as u64));
    group.bench_function("closest_hit_1_thread", |b| {
        b.iter(|| {
            origins
                .iter()
                .zip(&dirs)
                .filter(|&(&o, &d)| accel.closest_hit(o, d, 0.0, f32::INFINITY).is_some())
                .count()
        })
    });
    let mut hits = vec![None; RAYS];
    group.bench_function("closest_hits_batch", |b| {
        b.iter(|| accel.closest_hits(&origins, &dirs, 0.0, &t_maxs, &mut hits))
    });
    let mut occluded = vec![false; RAYS];
    group.bench_function("any_hits_batch", |b| {
        b.iter(|| accel.any_hits(&origins, &dirs, 0.0, &t_maxs, None, &mut occluded))
    });
    group.finish();
    let s = accel.stats();
    // Counted here: the batch benchmarks above may be filtered out, leaving `hits` unset.
    let hit_count = (origins.iter().zip(&dirs))
        .filter(|&(&o, &d)| accel.closest_hit(o, d, 0.0, f32::INFINITY).is_some())
        .count();
    // CPU-time measurements, less sensitive to other processes than criterion's wall time:
    // the build's wall and process CPU time, and one-thread closest hits per CPU second.
    let builds: Vec<(f64, f64)> = (0..5)
        .map(|_| {
            let (wall, cpu) = (std::time::Instant::now(), process_cpu_seconds());
            black_box(Accel::build(&primitives));
            let cpu = cpu
                .zip(process_cpu_seconds())
                .map_or(f64::NAN, |(a, b)| b - a);
            (wall.elapsed().as_secs_f64(), cpu)
        })
        .collect();
    println!(
        "build of 1M triangles: median wall {:.3} s, median process CPU {:.3} s",
        median(builds.iter().map(|b| b.0).collect()),
        median(builds.iter().map(|b| b.1).collect())
    );
    let passes: Vec<f64> = (0..5)
        .filter_map(|_| {
            let start = thread_cpu_seconds()?;
            for (&o, &d) in origins.iter().zip(&dirs) {
                black_box(accel.closest_hit(o, d, 0.0, f32::INFINITY));
            }
            Some(thread_cpu_seconds()? - start)
        })
        .collect();
    if !passes.is_empty() {
        println!(
            "closest hit, one thread: {:.3} M rays per CPU second (median of {} passes)",
            RAYS as f64 / median(passes) / 1e6,
            5
        );
    }
    println!(
        "torus: {} triangles, {} nodes, {} leaves, max depth {}, max leaf {}, {:.1} bytes per triangle, {hit_count}/{RAYS} rays hit",
        primitives.triangles.len(),
        s.nodes,
        s.leaves,
        s.max_depth,
        s.max_leaf_size,
        s.bytes as f64 / primitives.triangles.len() as f64,
    );
}

/// A scene of `n` primitives in the unit cube around the origin: one sphere in eight, the
/// rest triangles of edges up to 0.4 (small enough that a tree culls).
fn random_scene(n: usize) -> Primitives {
    use foton::accel::SphereInstance;
    use glam::Affine3A;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(n as u64);
    let mut uniform = || (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32 - 0.5;
    let mut point = || Vec3::new(uniform(), uniform(), uniform());
    let spheres = n / 8;
    Primitives {
        triangles: (0..n - spheres)
            .map(|_| {
                let c = point();
                [c, c + 0.8 * point(), c + 0.8 * point()]
            })
            .collect(),
        spheres: (0..spheres)
            .map(|_| SphereInstance {
                object_to_world: Affine3A::from_translation(point()),
                radius: 0.1,
            })
            .collect(),
        ..Default::default()
    }
}

/// Closest-hit and any-hit batches on scenes of a few primitives, flat against the tree, on
/// a one-thread pool: the pool thread's CPU nanoseconds per ray (median of 7 runs of passes
/// over 64k rays) for each size, where the two cross.
fn flat_crossover(_: &mut Criterion) {
    if !std::env::args().any(|a| a == "flat") {
        return;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let (origins, dirs) = rays();
    let t_maxs = vec![f32::INFINITY; RAYS];
    let (mut hits, mut occluded) = (vec![None; RAYS], vec![false; RAYS]);
    let nanos_per_ray = |pass: &mut dyn FnMut()| {
        // Passes repeated for at least 0.1 s of CPU time: the kernel counts it in ticks.
        let times = (0..7)
            .filter_map(|_| {
                let (start, mut passes) = (thread_cpu_seconds()?, 0);
                while thread_cpu_seconds()? - start < 0.1 {
                    pass();
                    passes += 1;
                }
                Some((thread_cpu_seconds()? - start) / passes as f64)
            })
            .collect();
        median(times) * 1e9 / RAYS as f64
    };
    println!("primitives  closest flat / tree ns  any flat / tree ns");
    for n in [4, 8, 16, 24, 32, 48, 64, 96, 128, 192, 256] {
        let scene = random_scene(n);
        let [flat, tree] = [n, 0].map(|limit| Accel::build_with_flat_limit(&scene, limit));
        let mut row = Vec::new();
        pool.install(|| {
            for accel in [&flat, &tree] {
                row.push(nanos_per_ray(&mut || {
                    accel.closest_hits(&origins, &dirs, 0.0, &t_maxs, &mut hits)
                }));
            }
            for accel in [&flat, &tree] {
                row.push(nanos_per_ray(&mut || {
                    accel.any_hits(&origins, &dirs, 0.0, &t_maxs, None, &mut occluded)
                }));
            }
        });
        println!(
            "{n:10}  {:8.1} / {:8.1}  {:8.1} / {:8.1}",
            row[0], row[1], row[2], row[3]
        );
    }
}

criterion_group!(benches, bench, flat_crossover);
criterion_main!(benches);
