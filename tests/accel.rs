//! The BVH against an independent brute-force reference in f64, plus edge cases.

use foton::accel::{
    Accel, Hit, MeshInstance, PlaneInstance, PrimitiveIds, PrimitiveRef, Primitives, SphereInstance,
};
use glam::{Affine3A, DAffine3, DVec3, Quat, Vec3};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::{Rng, SeedableRng};

fn rng(seed: u64) -> Xoshiro256PlusPlus {
    Xoshiro256PlusPlus::seed_from_u64(seed)
}

/// Uniform in [0, 1).
fn uniform(rng: &mut impl Rng) -> f32 {
    (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32
}

fn range(rng: &mut impl Rng, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * uniform(rng)
}

fn vec_in(rng: &mut impl Rng, lo: f32, hi: f32) -> Vec3 {
    Vec3::new(range(rng, lo, hi), range(rng, lo, hi), range(rng, lo, hi))
}

fn triangle_soup(rng: &mut impl Rng, n: usize) -> Vec<[Vec3; 3]> {
    (0..n)
        .map(|_| {
            let c = vec_in(rng, -10.0, 10.0);
            [
                c + vec_in(rng, -1.0, 1.0),
                c + vec_in(rng, -1.0, 1.0),
                c + vec_in(rng, -1.0, 1.0),
            ]
        })
        .collect()
}

/// Spheres under random rotations, translations and (often non-uniform) scales.
fn random_spheres(rng: &mut impl Rng, n: usize) -> Vec<SphereInstance> {
    (0..n)
        .map(|_| {
            let axis = vec_in(rng, -1.0, 1.0).normalize_or(Vec3::X);
            let rotation = Quat::from_axis_angle(axis, range(rng, 0.0, std::f32::consts::TAU));
            let scale = match rng.next_u32() % 3 {
                0 => Vec3::ONE,
                1 => Vec3::splat(range(rng, 0.3, 2.0)),
                _ => vec_in(rng, 0.2, 2.0),
            };
            SphereInstance {
                object_to_world: Affine3A::from_scale_rotation_translation(
                    scale,
                    rotation,
                    vec_in(rng, -10.0, 10.0),
                ),
                radius: range(rng, 0.2, 1.5),
            }
        })
        .collect()
}

fn random_planes(rng: &mut impl Rng, n: usize) -> Vec<PlaneInstance> {
    (0..n)
        .map(|_| PlaneInstance {
            point: vec_in(rng, -15.0, 15.0),
            normal: vec_in(rng, -1.0, 1.0),
        })
        .collect()
}

struct TestRay {
    origin: Vec3,
    dir: Vec3,
    t_min: f32,
    t_max: f32,
}

/// Origins around and inside the scene, unnormalised directions, varied ranges.
fn random_rays(rng: &mut impl Rng, n: usize) -> Vec<TestRay> {
    (0..n)
        .map(|_| TestRay {
            origin: vec_in(rng, -14.0, 14.0),
            dir: vec_in(rng, -1.0, 1.0) * range(rng, 0.1, 3.0),
            t_min: if rng.next_u32().is_multiple_of(2) {
                0.0
            } else {
                range(rng, 0.0, 2.0)
            },
            t_max: if rng.next_u32().is_multiple_of(2) {
                f32::INFINITY
            } else {
                range(rng, 2.0, 30.0)
            },
        })
        .collect()
}

/// A reference hit: t and primitive, and whether an f32 computation could reasonably decide
/// differently (a near-grazing hit or miss).
#[derive(Default)]
struct Reference {
    closest: Option<(f64, u32)>,
    /// |cos| of the angle between the ray and the normal of the closest triangle or plane (1
    /// for a sphere).
    cos: f64,
    ambiguous: bool,
}

const GRAZE: f64 = 1e-4;

/// Brute force over every primitive in f64, written independently of the crate: Möller-Trumbore
/// with unprecomputed edges, the textbook quadratic for the sphere, the plane equation.
fn reference(p: &Primitives, ray: &TestRay) -> Reference {
    let o = ray.origin.as_dvec3();
    let d = ray.dir.as_dvec3();
    let (t_min, t_max) = (ray.t_min as f64, ray.t_max as f64);
    let mut r = Reference::default();
    let mut hits: Vec<(f64, u32)> = Vec::new();
    let mut cosines = std::collections::HashMap::new();
    let near_range = |t: f64| {
        ((t - t_min).abs() <= GRAZE * t.abs().max(1.0))
            || ((t - t_max).abs() <= GRAZE * t.abs().max(1.0))
    };
    for (i, tri) in p.triangles.iter().enumerate() {
        let [v0, v1, v2] = tri.map(|v| v.as_dvec3());
        let (e1, e2) = (v1 - v0, v2 - v0);
        let n = e1.cross(e2);
        if n.length_squared() == 0.0 {
            continue;
        }
        let pv = d.cross(e2);
        let det = e1.dot(pv);
        if det.abs() < 1e-12 * e1.length() * pv.length() {
            r.ambiguous |= det != 0.0;
            continue;
        }
        let s = o - v0;
        let u = s.dot(pv) / det;
        let q = s.cross(e1);
        let v = d.dot(q) / det;
        let t = e2.dot(q) / det;
        let margin = u.min(v).min(1.0 - u - v);
        if margin.abs() < GRAZE && t > t_min - 1.0 && t < t_max + 1.0 {
            r.ambiguous = true;
        }
        if margin >= 0.0 && t > t_min && t < t_max {
            r.ambiguous |= near_range(t);
            hits.push((t, i as u32));
            cosines.insert(i as u32, n.normalize().dot(d.normalize()).abs());
        }
    }
    let n_tri = p.triangles.len();
    for (i, s) in p.spheres.iter().enumerate() {
        let m: DAffine3 = s.object_to_world.as_daffine3();
        if m.matrix3.determinant() == 0.0 || s.radius <= 0.0 {
            continue;
        }
        let inv = m.inverse();
        let (oo, od) = (inv.transform_point3(o), inv.transform_vector3(d));
        let (a, b, c) = (
            od.dot(od),
            2.0 * oo.dot(od),
            oo.dot(oo) - (s.radius as f64).powi(2),
        );
        let disc = b * b - 4.0 * a * c;
        // Relative size of the discriminant: near zero means a grazing ray.
        if disc.abs() < GRAZE * b * b.max(a * c).max(1e-30) / b.abs().max(1e-30) {
            r.ambiguous = true;
        }
        if disc < 0.0 {
            continue;
        }
        for t in [
            (-b - disc.sqrt()) / (2.0 * a),
            (-b + disc.sqrt()) / (2.0 * a),
        ] {
            if t > t_min && t < t_max {
                r.ambiguous |= near_range(t);
                hits.push((t, (n_tri + i) as u32));
                break;
            }
        }
    }
    let n_sph = p.spheres.len();
    for (i, pl) in p.planes.iter().enumerate() {
        let n: DVec3 = pl.normal.as_dvec3();
        let t = (pl.point.as_dvec3() - o).dot(n) / d.dot(n);
        if t > t_min && t < t_max {
            r.ambiguous |= near_range(t);
            let id = (n_tri + n_sph + i) as u32;
            hits.push((t, id));
            cosines.insert(id, n.normalize().dot(d.normalize()).abs());
        }
    }
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    if hits.len() >= 2 && (hits[1].0 - hits[0].0) <= GRAZE * hits[0].0.abs().max(1.0) {
        r.ambiguous = true;
    }
    r.closest = hits.first().copied();
    r.cos = r
        .closest
        .map_or(1.0, |(_, i)| *cosines.get(&i).unwrap_or(&1.0));
    r
}

/// Checks closest_hit and any_hit on `n` random rays; ambiguous rays (grazing, near a range end,
/// or two hits at nearly the same t) are skipped, and must be rare.
fn check_against_reference(p: &Primitives, seed: u64, n: usize) {
    check_against_flat(p, p, |id| id, seed, n);
}

/// As [`check_against_reference`] for `p`, whose brute-force twin is `flat` (instances
/// flattened into world-space triangles); `to_p` maps an id of `flat` to the id in `p`.
///
/// A shift of a ray by δ (the rounding of its origin, and where `p` has instances, of its
/// carrying into object space) moves its hit on a flat surface along the ray by δ / cos θ (θ
/// the angle of incidence), so the tolerance on `t` is divided by cos θ.
fn check_against_flat(
    p: &Primitives,
    flat: &Primitives,
    to_p: impl Fn(u32) -> u32,
    seed: u64,
    n: usize,
) {
    let accel = Accel::build(p);
    let mut rng = rng(seed);
    let (mut skipped, mut hits) = (0, 0);
    for (k, ray) in random_rays(&mut rng, n).iter().enumerate() {
        let mut expected = reference(flat, ray);
        expected.closest = expected.closest.map(|(t, prim)| (t, to_p(prim)));
        let d_len = ray.dir.as_dvec3().length();
        if expected.ambiguous {
            skipped += 1;
            continue;
        }
        let got = accel.closest_hit(ray.origin, ray.dir, ray.t_min, ray.t_max);
        let any = accel.any_hit(ray.origin, ray.dir, ray.t_min, ray.t_max);
        match (expected.closest, got) {
            (None, None) => {}
            (Some((t, prim)), Some(hit)) => {
                hits += 1;
                assert_eq!(
                    hit.prim, prim,
                    "ray {k}: wrong primitive (expected t {t}, got {hit:?})"
                );
                // Relative 1e-4, with a floor for hits very near the origin: there the f32
                // rounding of the origin's coordinates (~1e-6 at 14) dominates the error in t.
                let dist = d_len * t;
                let incidence = expected.cos;
                assert!(
                    (hit.t as f64 - t).abs() * d_len <= 1e-4 * dist.max(0.1) / incidence,
                    "ray {k}: t {} vs reference {t} (|d| {d_len}, cos {incidence})",
                    hit.t
                );
            }
            (e, g) => panic!("ray {k}: expected {e:?}, got {g:?}"),
        }
        assert_eq!(
            any,
            expected.closest.is_some(),
            "ray {k}: any_hit disagrees"
        );
    }
    assert!(skipped * 100 < n, "{skipped} of {n} rays were ambiguous");
    assert!(
        hits * 10 > n,
        "only {hits} of {n} rays hit: the test says little"
    );
}

#[test]
fn triangle_soup_matches_brute_force() {
    let p = Primitives {
        triangles: triangle_soup(&mut rng(1), 3000),
        ..Default::default()
    };
    check_against_reference(&p, 2, 4000);
}

#[test]
fn transformed_spheres_match_brute_force() {
    let p = Primitives {
        spheres: random_spheres(&mut rng(3), 200),
        ..Default::default()
    };
    check_against_reference(&p, 4, 4000);
}

#[test]
fn mixed_scene_with_planes_and_degenerates_matches_brute_force() {
    let mut r = rng(5);
    let mut triangles = triangle_soup(&mut r, 1500);
    // Degenerate triangles in the middle of the id range: a point, and a collinear sliver.
    triangles[10] = [Vec3::ONE; 3];
    triangles[700] = [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X];
    let mut spheres = random_spheres(&mut r, 100);
    spheres[5].object_to_world = Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0)); // singular
    spheres[6].radius = 0.0;
    let p = Primitives {
        triangles,
        spheres,
        planes: random_planes(&mut r, 3),
        ..Default::default()
    };
    check_against_reference(&p, 6, 4000);
}

#[test]
fn planes_only_match_brute_force() {
    let p = Primitives {
        planes: random_planes(&mut rng(7), 4),
        ..Default::default()
    };
    check_against_reference(&p, 8, 2000);
}

#[test]
fn ray_inside_sphere_hits_far_side() {
    let object_to_world = Affine3A::from_scale_rotation_translation(
        Vec3::new(3.0, 1.0, 0.5),
        Quat::from_rotation_z(0.7),
        Vec3::new(1.0, 2.0, 3.0),
    );
    let p = Primitives {
        spheres: vec![SphereInstance {
            object_to_world,
            radius: 2.0,
        }],
        ..Default::default()
    };
    let accel = Accel::build(&p);
    let center = Vec3::new(1.0, 2.0, 3.0);
    let mut r = rng(9);
    for _ in 0..100 {
        let dir = vec_in(&mut r, -1.0, 1.0);
        let hit = accel
            .closest_hit(center, dir, 0.0, f32::INFINITY)
            .expect("inside: must hit");
        // The exit point lies on the ellipsoid: |M⁻¹ p| = r, in front of the origin.
        let local = object_to_world
            .inverse()
            .transform_point3(center + hit.t * dir);
        assert!(
            hit.t > 0.0 && (local.length() - 2.0).abs() < 1e-4,
            "{hit:?} {local}"
        );
        assert_eq!(hit.prim, 0);
    }
}

#[test]
fn small_distant_sphere_is_precise() {
    // A sphere of radius 1e-2 at distance 1e4: the textbook discriminant loses all its digits
    // here (Ray Tracing Gems ch. 7); the rewritten one keeps t to float precision.
    let p = Primitives {
        spheres: vec![SphereInstance {
            object_to_world: Affine3A::from_translation(Vec3::new(1e4, 0.0, 0.0)),
            radius: 1e-2,
        }],
        ..Default::default()
    };
    let accel = Accel::build(&p);
    let hit = accel
        .closest_hit(Vec3::new(0.0, 0.005, 0.0), Vec3::X, 0.0, f32::INFINITY)
        .unwrap();
    let exact = 1e4 - (1e-4f64 - 0.005f64 * 0.005).sqrt();
    assert!(
        (hit.t as f64 - exact).abs() < 2e-3,
        "t {} vs {exact}",
        hit.t
    );
}

#[test]
fn t_range_is_respected() {
    let p = Primitives {
        triangles: vec![[
            Vec3::new(-1.0, -1.0, 5.0),
            Vec3::new(1.0, -1.0, 5.0),
            Vec3::new(0.0, 1.0, 5.0),
        ]],
        spheres: vec![SphereInstance {
            object_to_world: Affine3A::from_translation(Vec3::new(0.0, 0.0, 10.0)),
            radius: 1.0,
        }],
        planes: vec![PlaneInstance {
            point: Vec3::new(0.0, 0.0, 20.0),
            normal: Vec3::Z,
        }],
        ..Default::default()
    };
    let accel = Accel::build(&p);
    let (o, d) = (Vec3::ZERO, Vec3::new(0.0, 0.0, 0.5)); // t is in units of d: twice the distance
    let hit = |t_min, t_max| {
        accel
            .closest_hit(o, d, t_min, t_max)
            .map(|h: Hit| (h.prim, h.t))
    };
    assert_eq!(hit(0.0, f32::INFINITY), Some((0, 10.0)));
    assert_eq!(hit(0.0, 10.0), None);
    assert_eq!(hit(10.0, 100.0), Some((1, 18.0)));
    assert_eq!(hit(18.0, 100.0), Some((1, 22.0)));
    assert_eq!(hit(22.0, 100.0), Some((2, 40.0)));
    assert_eq!(hit(22.0, 40.0), None);
    assert_eq!(hit(5.0, 5.0), None);
    assert!(accel.any_hit(o, d, 0.0, 10.001));
    assert!(!accel.any_hit(o, d, 0.0, 10.0));
    assert!(!accel.any_hit(o, d, 40.0, f32::INFINITY));
    assert_eq!(accel.primitive_count(), 3);
}

#[test]
fn triangle_barycentrics() {
    let p = Primitives {
        triangles: vec![[Vec3::ZERO, Vec3::X, Vec3::Y]],
        ..Default::default()
    };
    let hit = Accel::build(&p)
        .closest_hit(Vec3::new(0.25, 0.5, 1.0), -Vec3::Z, 0.0, 2.0)
        .unwrap();
    assert_eq!(
        hit,
        Hit {
            t: 1.0,
            prim: 0,
            u: 0.25,
            v: 0.5
        }
    );
}

#[test]
fn empty_scene_returns_none() {
    let accel = Accel::build(&Primitives::default());
    assert_eq!(
        accel.closest_hit(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY),
        None
    );
    assert!(!accel.any_hit(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY));
    assert_eq!((accel.stats().nodes, accel.primitive_count()), (0, 0));
}

#[test]
fn degenerate_triangles_only() {
    let p = Primitives {
        triangles: vec![
            [Vec3::ZERO; 3],
            [Vec3::ZERO, Vec3::X, Vec3::X],
            [Vec3::NAN, Vec3::X, Vec3::Y],
        ],
        ..Default::default()
    };
    let accel = Accel::build(&p);
    assert_eq!(accel.stats().nodes, 0);
    assert_eq!(accel.primitive_count(), 3);
    for dir in [Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(1.0, 1.0, 0.0)] {
        assert_eq!(accel.closest_hit(-dir, dir, 0.0, f32::INFINITY), None);
    }
}

#[test]
fn ids_stay_stable_around_degenerates() {
    let quad = |z: f32| {
        [
            Vec3::new(-1.0, -1.0, z),
            Vec3::new(3.0, -1.0, z),
            Vec3::new(-1.0, 3.0, z),
        ]
    };
    let p = Primitives {
        triangles: vec![[Vec3::ZERO; 3], quad(2.0), [Vec3::ONE; 3]],
        spheres: vec![
            SphereInstance {
                object_to_world: Affine3A::ZERO,
                radius: 1.0,
            },
            SphereInstance {
                object_to_world: Affine3A::from_translation(Vec3::new(0.0, 0.0, 5.0)),
                radius: 1.0,
            },
        ],
        planes: vec![
            PlaneInstance {
                point: Vec3::ZERO,
                normal: Vec3::ZERO,
            },
            PlaneInstance {
                point: Vec3::new(0.0, 0.0, 9.0),
                normal: -Vec3::Z,
            },
        ],
        ..Default::default()
    };
    let accel = Accel::build(&p);
    let prim = |t_min| {
        accel
            .closest_hit(Vec3::ZERO, Vec3::Z, t_min, f32::INFINITY)
            .map(|h| h.prim)
    };
    assert_eq!(
        [prim(0.0), prim(3.0), prim(7.0), prim(10.0)],
        [Some(1), Some(4), Some(6), None]
    );
}

#[test]
fn invalid_rays_return_none() {
    let p = Primitives {
        triangles: triangle_soup(&mut rng(10), 100),
        spheres: random_spheres(&mut rng(11), 10),
        planes: random_planes(&mut rng(12), 2),
        ..Default::default()
    };
    let accel = Accel::build(&p);
    let nan = Vec3::new(f32::NAN, 0.0, 0.0);
    for (o, d, t_min, t_max) in [
        (nan, Vec3::X, 0.0, f32::INFINITY),
        (Vec3::ZERO, nan, 0.0, f32::INFINITY),
        (Vec3::ZERO, Vec3::ZERO, 0.0, f32::INFINITY),
        (Vec3::ZERO, Vec3::INFINITY, 0.0, f32::INFINITY),
        (Vec3::ZERO, Vec3::X, f32::NAN, f32::INFINITY),
        (Vec3::ZERO, Vec3::X, 0.0, f32::NAN),
        (Vec3::ZERO, Vec3::X, 1.0, 0.5),
    ] {
        assert_eq!(accel.closest_hit(o, d, t_min, t_max), None);
        assert!(!accel.any_hit(o, d, t_min, t_max));
    }
}

#[test]
fn axis_parallel_rays_hit() {
    // Rays with zero direction components (infinite reciprocals), the second against a flat box.
    let p = Primitives {
        triangles: vec![
            [
                Vec3::ZERO,
                Vec3::new(1.0, 0.0, 1.0),
                Vec3::new(0.0, 1.0, 1.0),
            ],
            [
                Vec3::new(5.0, 0.0, 0.0),
                Vec3::new(6.0, 0.0, 0.0),
                Vec3::new(5.0, 1.0, 0.0),
            ],
        ],
        ..Default::default()
    };
    let accel = Accel::build(&p);
    let hit = accel
        .closest_hit(Vec3::new(0.25, 0.25, 5.0), -Vec3::Z, 0.0, f32::INFINITY)
        .unwrap();
    assert_eq!((hit.prim, hit.t), (0, 4.5));
    let hit = accel
        .closest_hit(
            Vec3::new(5.2, 0.2, 3.0),
            Vec3::new(0.0, 0.0, -1.0),
            0.0,
            f32::INFINITY,
        )
        .unwrap();
    assert_eq!((hit.prim, hit.t), (1, 3.0));
}

/// A UV sphere of 2·rings·segments triangles.
fn tessellated_sphere(rings: usize, segments: usize) -> Vec<[Vec3; 3]> {
    let point = |i: usize, j: usize| {
        let (theta, phi) = (
            std::f32::consts::PI * i as f32 / rings as f32,
            std::f32::consts::TAU * j as f32 / segments as f32,
        );
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    };
    let mut tris = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            tris.push([a, b, c]);
            tris.push([a, c, d]);
        }
    }
    tris
}

#[test]
fn sah_quality_on_a_large_mesh() {
    // 100k triangles (the pole rows are degenerate slivers: they are dropped from the tree).
    let triangles = tessellated_sphere(200, 250);
    let p = Primitives {
        triangles,
        ..Default::default()
    };
    let accel = Accel::build(&p);
    let s = accel.stats();
    let in_tree = 100_000 - 2 * 250;
    // A balanced binary tree over 99.5k primitives in leaves of ~2 is ~16 levels deep; the SAH
    // may unbalance it, but a surface mesh needs nowhere near the 64 the traversal stack holds.
    assert!(s.max_depth < 40, "max depth {}", s.max_depth);
    // The build splits every node above 8 primitives, and on a well-spread mesh the SAH
    // (leaf cost n vs 1/2 + children) stops at 1–4 primitives: the average must stay small.
    assert!(s.max_leaf_size <= 8, "max leaf {}", s.max_leaf_size);
    let mean_leaf = in_tree as f64 / s.leaves as f64;
    let bytes_per_triangle = s.bytes as f64 / in_tree as f64;
    println!(
        "mean leaf {mean_leaf}, {bytes_per_triangle} B/triangle, {} nodes, {} leaves",
        s.nodes, s.leaves
    );
    // Leaves are tested four triangles at a time, and the SAH charges them by packets: most
    // are full. The nodes are four-wide: n nodes hold n - 1 nodes and the leaves in 4n lanes,
    // and since every node has two children at least, there are fewer nodes than leaves.
    assert!(mean_leaf >= 2.5, "mean leaf size {mean_leaf}");
    assert!(s.leaves + s.nodes - 1 <= 4 * s.nodes && s.nodes < s.leaves);
    assert!(
        bytes_per_triangle <= 64.0,
        "{bytes_per_triangle} B/triangle"
    );
    // And the tree still finds the mesh: every ray from outside aimed at the center hits.
    let mut r = rng(13);
    for _ in 0..1000 {
        let o = 3.0 * vec_in(&mut r, -1.0, 1.0).normalize_or(Vec3::X);
        let hit = accel
            .closest_hit(o, -o, 0.0, f32::INFINITY)
            .expect("aimed at the mesh");
        assert!((hit.t - 2.0 / 3.0).abs() < 0.01, "t {}", hit.t);
    }
}

#[test]
fn batch_entry_points_match_single_rays() {
    let p = Primitives {
        triangles: triangle_soup(&mut rng(14), 1000),
        spheres: random_spheres(&mut rng(15), 50),
        planes: random_planes(&mut rng(16), 1),
        ..Default::default()
    };
    let accel = Accel::build(&p);
    let rays = random_rays(&mut rng(17), 3000);
    let origins: Vec<Vec3> = rays.iter().map(|r| r.origin).collect();
    let dirs: Vec<Vec3> = rays.iter().map(|r| r.dir).collect();
    let mut t_maxs: Vec<f32> = rays.iter().map(|r| r.t_max).collect();
    t_maxs[7] = 0.0; // skipped: t_max <= t_min
    let mut hits = vec![None; rays.len()];
    let mut occluded = vec![true; rays.len()];
    accel.closest_hits(&origins, &dirs, 1e-3, &t_maxs, &mut hits);
    accel.any_hits(&origins, &dirs, 1e-3, &t_maxs, None, &mut occluded);
    for i in 0..rays.len() {
        assert_eq!(
            hits[i],
            accel.closest_hit(origins[i], dirs[i], 1e-3, t_maxs[i])
        );
        assert_eq!(
            occluded[i],
            accel.any_hit(origins[i], dirs[i], 1e-3, t_maxs[i])
        );
        assert_eq!(occluded[i], hits[i].is_some());
    }
    assert!(!occluded[7]);
}

#[test]
fn coincident_primitives_still_split_into_small_leaves() {
    // 10k copies of one triangle: every centroid coincides, so no SAH plane separates them; the
    // build must split them arbitrarily rather than make one huge leaf.
    let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let p = Primitives {
        triangles: vec![t; 10_000],
        ..Default::default()
    };
    let accel = Accel::build(&p);
    let s = accel.stats();
    assert!(
        s.max_leaf_size <= 8 && s.max_depth < 64,
        "leaf {} depth {}",
        s.max_leaf_size,
        s.max_depth
    );
    let hit = accel
        .closest_hit(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z, 0.0, 2.0)
        .unwrap();
    assert_eq!(hit.t, 1.0);
    assert!(accel.any_hit(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z, 0.0, 2.0));
}

#[test]
fn far_flung_primitives_are_found() {
    // Triangles at x = 1.5^i, up to 1e35: the binned SAH peels a few far ones off per level, and
    // the axis-parallel rays (zero y and z direction) must still enter slabs at t ~ 1e34.
    let p = Primitives {
        triangles: (0..200)
            .map(|i| {
                let x = 1.5f32.powi(i);
                [
                    Vec3::new(x, 0.0, 0.0),
                    Vec3::new(x, 1.0, 0.0),
                    Vec3::new(x, 0.0, 1.0),
                ]
            })
            .collect(),
        ..Default::default()
    };
    let accel = Accel::build(&p);
    assert!(
        accel.stats().max_depth < 64,
        "depth {}",
        accel.stats().max_depth
    );
    for i in [0, 1, 50, 100, 199] {
        let x = 1.5f32.powi(i);
        let hit = accel
            .closest_hit(Vec3::new(0.9 * x, 0.25, 0.25), Vec3::X, 0.0, 0.2 * x)
            .unwrap();
        assert_eq!(hit.prim, i as u32);
    }
}

#[test]
fn arbitrary_bit_patterns_never_panic() {
    // Every float drawn from raw bits: NaNs, infinities, denormals and 1e38s in the scene and in
    // the rays. Nothing may panic, and every reported hit must lie in the open range.
    let mut r = rng(18);
    let f = |r: &mut Xoshiro256PlusPlus| {
        if r.next_u32().is_multiple_of(2) {
            f32::from_bits(r.next_u32())
        } else {
            range(r, -10.0, 10.0)
        }
    };
    let v = |r: &mut Xoshiro256PlusPlus| Vec3::new(f(r), f(r), f(r));
    let p = Primitives {
        triangles: (0..500)
            .map(|_| [v(&mut r), v(&mut r), v(&mut r)])
            .collect(),
        spheres: (0..100)
            .map(|_| SphereInstance {
                object_to_world: Affine3A::from_cols(
                    v(&mut r).into(),
                    v(&mut r).into(),
                    v(&mut r).into(),
                    v(&mut r).into(),
                ),
                radius: v(&mut r).x,
            })
            .collect(),
        planes: (0..5)
            .map(|_| PlaneInstance {
                point: v(&mut r),
                normal: v(&mut r),
            })
            .collect(),
        ..Default::default()
    };
    let accel = Accel::build(&p);
    for _ in 0..5000 {
        let (o, d, t_min, t_max) = (
            v(&mut r),
            v(&mut r),
            v(&mut r).x.abs() * 1e-3,
            v(&mut r).x.abs(),
        );
        if let Some(hit) = accel.closest_hit(o, d, t_min, t_max) {
            assert!(
                hit.t > t_min && hit.t < t_max,
                "{hit:?} outside ({t_min}, {t_max})"
            );
            assert!(accel.any_hit(o, d, t_min, t_max));
        }
    }
}

/// Shared meshes under random affine maps (rotations, non-uniform scales, mirrors), next to
/// world-space triangles, spheres and a plane: the two-level tree must report the same hits
/// as one brute-force list of the transformed triangles.
#[test]
fn instances_match_flattened_brute_force() {
    let mut r = rng(19);
    let meshes = vec![
        triangle_soup(&mut r, 40),
        tessellated_sphere(6, 8),
        Vec::new(),
    ];
    let instances: Vec<MeshInstance> = (0..60)
        .map(|k| {
            let axis = vec_in(&mut r, -1.0, 1.0).normalize_or(Vec3::X);
            let rotation = Quat::from_axis_angle(axis, range(&mut r, 0.0, std::f32::consts::TAU));
            let mut scale = vec_in(&mut r, 0.1, 1.0);
            if k % 5 == 0 {
                scale.x = -scale.x;
            }
            MeshInstance {
                mesh: k % 3,
                object_to_world: Affine3A::from_scale_rotation_translation(
                    scale,
                    rotation,
                    vec_in(&mut r, -10.0, 10.0),
                ),
            }
        })
        .collect();
    let p = Primitives {
        triangles: triangle_soup(&mut r, 300),
        spheres: random_spheres(&mut r, 20),
        planes: random_planes(&mut r, 1),
        meshes,
        instances,
        ..Default::default()
    };
    // The flat twin: world triangles, then every instance's triangles, then spheres and planes.
    let mut flat = Primitives {
        triangles: p.triangles.clone(),
        spheres: p.spheres.clone(),
        planes: p.planes.clone(),
        ..Default::default()
    };
    let mut flat_to_instance = Vec::new();
    for (k, instance) in p.instances.iter().enumerate() {
        for (j, t) in p.meshes[instance.mesh as usize].iter().enumerate() {
            flat.triangles
                .push(t.map(|v| instance.object_to_world.transform_point3(v)));
            flat_to_instance.push((k, j));
        }
    }
    let (ids, flat_ids) = (PrimitiveIds::new(&p), PrimitiveIds::new(&flat));
    assert_eq!(ids.count(), flat_ids.count());
    let to_p = |id: u32| match flat_ids.decode(id).unwrap() {
        PrimitiveRef::Triangle(i) if i < p.triangles.len() => ids.triangle(i),
        PrimitiveRef::Triangle(i) => {
            let (instance, triangle) = flat_to_instance[i - p.triangles.len()];
            let id = ids.instance_triangle(instance, triangle);
            assert_eq!(
                ids.decode(id),
                Some(PrimitiveRef::InstanceTriangle { instance, triangle })
            );
            id
        }
        PrimitiveRef::Sphere(i) => ids.sphere(i),
        PrimitiveRef::Plane(i) => ids.plane(i),
        PrimitiveRef::Disk(i) => ids.disk(i),
        PrimitiveRef::InstanceTriangle { .. } => unreachable!("the flat twin has no instances"),
    };
    check_against_flat(&p, &flat, to_p, 20, 4000);
}

/// Instances that cannot be hit (a missing mesh, an empty one, a singular or non-finite map)
/// are left out without disturbing the others' ids.
#[test]
fn degenerate_instances_are_skipped() {
    let quad = [
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(3.0, -1.0, 0.0),
        Vec3::new(-1.0, 3.0, 0.0),
    ];
    let at = |z: f32| Affine3A::from_translation(Vec3::new(0.0, 0.0, z));
    let p = Primitives {
        meshes: vec![vec![quad, [Vec3::ONE; 3]], Vec::new()],
        instances: vec![
            MeshInstance {
                mesh: 9,
                object_to_world: at(1.0),
            },
            MeshInstance {
                mesh: 1,
                object_to_world: at(2.0),
            },
            MeshInstance {
                mesh: 0,
                object_to_world: Affine3A::from_scale(Vec3::new(1.0, 1.0, 0.0)),
            },
            MeshInstance {
                mesh: 0,
                object_to_world: Affine3A::from_scale(Vec3::NAN),
            },
            MeshInstance {
                mesh: 0,
                object_to_world: at(5.0),
            },
            MeshInstance {
                mesh: 0,
                object_to_world: at(7.0) * Affine3A::from_scale(Vec3::splat(2.0)),
            },
        ],
        ..Default::default()
    };
    let accel = Accel::build(&p);
    let ids = accel.ids();
    // Ids for every instance of an existing mesh, the empty one included (it holds none).
    assert_eq!(accel.primitive_count(), 4 * 2);
    let hit = |t_min| accel.closest_hit(Vec3::ZERO, Vec3::Z, t_min, f32::INFINITY);
    let first = hit(0.0).unwrap();
    assert_eq!((first.prim, first.t), (ids.instance_triangle(4, 0), 5.0));
    let second = hit(5.0).unwrap();
    assert_eq!((second.prim, second.t), (ids.instance_triangle(5, 0), 7.0));
    assert_eq!(hit(7.0), None);
    assert!(accel.any_hit(Vec3::ZERO, Vec3::Z, 0.0, 5.5));
    assert!(!accel.any_hit(Vec3::ZERO, Vec3::Z, 0.0, 5.0));
    // The scaled instance: u and v are those of the object-space triangle.
    let hit = accel
        .closest_hit(Vec3::new(0.5, 1.0, 6.0), Vec3::Z, 0.0, 9.0)
        .unwrap();
    assert_eq!((hit.t, hit.u, hit.v), (1.0, 0.3125, 0.375));
}
