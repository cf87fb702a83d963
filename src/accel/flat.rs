//! A scene of a few primitives without a tree: rays in groups of 8 (AVX2) or 16 (AVX-512)
//! lanes, each group tested against every triangle and sphere in turn.
//!
//! For a dozen primitives the tree's per-ray work (the ray's splats and reciprocals, the node
//! tests, the stack, four-wide packets with one live lane) costs more than the primitives
//! themselves. Here the rays are transposed into lanes (`o[axis]`, `d[axis]`, `t_max`, one
//! ray per lane; see [`super::lanes`]) and each primitive's constants are splatted once per
//! group: SIMD across rays, not across primitives. Planes are tested first, ray by ray, as the
//! tree's queries do; disks last, in lanes.
//!
//! Each lane performs exactly the operations of [`super::triangle::Triangle4::intersect`] and
//! [`super::sphere::Sphere4::intersect`] in the same order, so a lane's `t`, `u`, `v` are the
//! tree's bit for bit (and [`super::disk::Disk::intersect`]'s), but for closest hits on
//! consecutive triangles that make a parallelogram (a rectangle's halves), tested as one
//! ([`super::parallelogram`]): within rounding of the tree's there. Ties: the primitives are
//! tested in a fixed order (planes, triangles, parallelograms, spheres, then disks) and a hit
//! replaces the lane's best only if strictly nearer, so at equal `t` the first tested wins,
//! where the tree keeps the first one its traversal meets.
//!
//! Shadow rays skip a run of coplanar triangles (a rectangle's halves) when no ray of the group
//! can reach its plane ([`super::coplanar`]): a group on its way from the walls to a lamp
//! crosses none of the walls' planes.
//!
//! Built only where the CPU has AVX2; elsewhere the tree answers.

use std::cell::RefCell;

use glam::{Vec3, Vec3A};

#[cfg(target_arch = "x86_64")]
use super::coplanar::RayScale;
use super::coplanar::{TriangleRun, coplanar_runs};
use super::disk::Disk;
#[cfg(target_arch = "x86_64")]
use super::lanes::{Compress, L8, L16, Lanes};
use super::parallelogram::{Parallelogram, pair_consecutive};
use super::pass_through::{MAX_LAYERS, PassThrough};
use super::plane::Plane;
use super::sphere::{sphere_bounds, translation_only};
use super::triangle::triangle_bounds;
use super::{Hit, SphereInstance};

/// The most triangles, spheres and disks a scene may hold to be traced flat. Measured with
/// `cargo bench --bench bvh -- flat`: see that benchmark's crossover.
pub(crate) const MAX_FLAT_PRIMITIVES: usize = 64;

/// A lane's primitive id before any hit.
const NO_HIT: u32 = u32::MAX;

/// The widest group.
const MAX_LANES: usize = 16;

/// A triangle as the packet test uses it: a vertex and the two edges from it.
#[derive(Clone, Copy, Debug)]
struct FlatTriangle {
    v0: [f32; 3],
    e1: [f32; 3],
    e2: [f32; 3],
    id: u32,
}

/// A sphere as the packet test uses it: the rows of its world-to-object map (column 3 the
/// translation) and its radius.
#[derive(Clone, Copy, Debug)]
struct FlatSphere {
    rows: [[f32; 4]; 3],
    /// The map's translation where its linear part is the identity (a sphere given by centre
    /// and radius): the test then adds it to the ray's origin and keeps the direction, rather
    /// than multiply both by the identity's rows. `1 x + 0 y + 0 z` is `x` but for the sign
    /// of a zero (`-0 + 0 = +0`), which no root's test sees: a coordinate's zero sign reaches
    /// `t` only through an exactly zero `b` and discriminant, whose roots `±0`, `±inf` or NaN
    /// fail the range tests alike (`t_min` is not negative, the extent is finite or an
    /// infinite `t_max` that `inf` fails too). The same holds of `surface::sphere_surface`.
    translation: Option<[f32; 3]>,
    radius: f32,
    id: u32,
}

/// A disk as the lane test uses it: the rows of its world-to-object map (column 3 the
/// translation).
#[derive(Clone, Copy, Debug)]
struct FlatDisk {
    rows: [[f32; 4]; 3],
    id: u32,
}

/// The triangles, spheres and disks that can be hit, in id order, and the triangles' coplanar
/// runs.
pub(crate) struct Flat {
    triangles: Vec<FlatTriangle>,
    /// For closest hits: the triangles not paired into `parallelograms`, in order, and the
    /// pairs ([`super::parallelogram`]).
    unpaired: Vec<FlatTriangle>,
    parallelograms: Vec<Parallelogram>,
    runs: Vec<TriangleRun>,
    spheres: Vec<FlatSphere>,
    disks: Vec<FlatDisk>,
}

/// A group's rays in lanes.
#[cfg(target_arch = "x86_64")]
struct Rays<S: Lanes> {
    o: [S; 3],
    d: [S; 3],
    t_min: S,
}

/// A group of up to `S::LANES` rays in lanes, their `t_max` NaN in a lane that can hit
/// nothing (no ray, an empty range, a non-finite origin or direction, a zero direction), which
/// every range test rejects, and their plane hits.
#[cfg(target_arch = "x86_64")]
struct Group<S: Lanes> {
    rays: Rays<S>,
    /// Each lane's `t_max`, shrunk to its plane hit.
    t_max: S,
    /// Each lane's hit so far (planes first).
    prim: [u32; MAX_LANES],
}

/// A group of shadow rays' test of the triangles' coplanar runs (see [`super::coplanar`]): a
/// run is skipped where every lane is clear of its plane or can hit nothing. The plane test
/// covers the range `(0, t_max)`, which holds `(t_min, t_max)` where `t_min` is not negative;
/// otherwise no run is skipped.
///
/// Closest hits do not skip runs: their rays start with an infinite `t_max`, so a group is
/// clear of a wall's plane only where no lane heads for it, and on the Cornell box the plane
/// tests cost more than the triangle tests they saved (`Flat::closest_hits` 264 M to 308 M
/// instructions, callgrind, x86-64-v3, `--threads 1 --spp 4`).
#[cfg(target_arch = "x86_64")]
struct RunCulling<S: Lanes> {
    scale: RayScale<S>,
    /// The lanes that can hit nothing (NaN `t_max`), and the bits past the lanes.
    settled: u32,
    active: bool,
}

#[cfg(target_arch = "x86_64")]
impl<S: Lanes> RunCulling<S> {
    #[inline(always)]
    fn new(rays: &Rays<S>, t_max: S, t_min: f32) -> Self {
        RunCulling {
            scale: RayScale::new(&rays.o, &rays.d),
            settled: S::bits(t_max.ne(t_max)) | !(u32::MAX >> (32 - S::LANES)),
            active: t_min >= 0.0,
        }
    }

    /// Whether no lane can hit a triangle of `run` with `t` below `t_max`.
    #[inline(always)]
    fn skips(&self, run: &TriangleRun, rays: &Rays<S>, t_max: S) -> bool {
        match &run.plane {
            Some(plane) if self.active => {
                let clear = plane.clear_lanes(&rays.o, &rays.d, &self.scale, t_max);
                clear | self.settled == u32::MAX
            }
            _ => false,
        }
    }
}

/// Rays per block of [`Packed`].
const PACKED: usize = 128;

/// The rays of a block of up to [`PACKED`] with a non-empty range, one after another, by
/// coordinate, and their indices in the batch; `t_max` NaN past them, for the last group. A
/// shadow batch has empty slots (43 % of Cornell's: no light sample at a specular vertex),
/// which would otherwise fill lanes.
///
/// One per thread ([`PACKED_RAYS`]), reused by every block of every call: setting up its
/// 4.5 kB for each rayon chunk was about a third of the renderer's `memset` instructions
/// (dof-sky: 5.6 of 14.2 M). Past `len` it holds an earlier block's rays, so [`Packed::pack`]
/// sets the `t_max` of the `MAX_LANES` slots past `len` (all a group reads past it) to NaN
/// every time: a lane with a NaN `t_max` hits nothing, so the stale `o`, `d` and `index`
/// there are never used.
struct Packed {
    o: [[f32; PACKED + MAX_LANES]; 3],
    d: [[f32; PACKED + MAX_LANES]; 3],
    t_max: [f32; PACKED + MAX_LANES],
    index: [u32; PACKED + MAX_LANES],
    len: usize,
}

thread_local! {
    /// The thread's [`Packed`] block (see there), const-initialised: no lazy set-up to check.
    static PACKED_RAYS: RefCell<Packed> = const { RefCell::new(Packed::new()) };
}

impl Packed {
    const fn new() -> Self {
        Packed {
            o: [[0.0; PACKED + MAX_LANES]; 3],
            d: [[0.0; PACKED + MAX_LANES]; 3],
            t_max: [f32::NAN; PACKED + MAX_LANES],
            index: [0; PACKED + MAX_LANES],
            len: 0,
        }
    }

    /// Packs those of the rays `start..start + PACKED` (as many as there are) whose range
    /// `(t_min, t_max)` is not empty. Eight at a time: the group transposed in registers, its
    /// kept rays moved to its front ([`Compress`]) and stored from the next free slot, which
    /// then advances past them; the last rays one by one, each written at the next slot, which
    /// advances only past a kept one. Without branches either way. One ray at a time, the
    /// packing was half of `Flat::any_hits`' time on dof-sky and a quarter on the Cornell box
    /// (`perf`), about 29 instructions a ray.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn pack(&mut self, rays: (&[Vec3], &[Vec3], &[f32]), t_min: f32, start: usize) {
        let (origins, dirs, t_maxs) = rays;
        let end = (start + PACKED)
            .min(origins.len())
            .min(dirs.len())
            .min(t_maxs.len());
        let (mut len, mut k) = (0, start);
        // A group's eight lanes, stored from `len <= k - start`, end within the block's PACKED
        // slots.
        while end - k >= L8::LANES {
            let [ox, oy, oz] = L8::load_points(&origins[k..]);
            let [dx, dy, dz] = L8::load_points(&dirs[k..]);
            let t_max = L8::load(&t_maxs[k..]);
            let kept = L8::bits(L8::splat(t_min).lt(t_max));
            let compress = Compress::new(kept);
            for (axis, (o, d)) in [(ox, dx), (oy, dy), (oz, dz)].into_iter().enumerate() {
                compress.apply(o).store(&mut self.o[axis][len..]);
                compress.apply(d).store(&mut self.d[axis][len..]);
            }
            compress.apply(t_max).store(&mut self.t_max[len..]);
            self.index[len..len + L8::LANES].copy_from_slice(&compress.indices(k as u32));
            len += kept.count_ones() as usize;
            k += L8::LANES;
        }
        let rays = (origins[k..end].iter())
            .zip(&dirs[k..end])
            .zip(&t_maxs[k..end]);
        for (k, ((o, d), &t_max)) in (k..).zip(rays) {
            for axis in 0..3 {
                self.o[axis][len] = o[axis];
                self.d[axis][len] = d[axis];
            }
            self.t_max[len] = t_max;
            self.index[len] = k as u32;
            len += (t_min < t_max) as usize;
        }
        // Every slot a group may read past `len`: an earlier block's rays otherwise.
        self.t_max[len..len + MAX_LANES].fill(f32::NAN);
        self.len = len;
    }
}

#[cfg(target_arch = "x86_64")]
impl<S: Lanes> Group<S> {
    /// The rays `start..start + S::LANES` (as many as there are), tested against the planes.
    /// A whole group is transposed in registers ([`Lanes::load_points`]), the last, partial
    /// one through arrays, its missing lanes zero with a NaN `t_max`.
    #[inline(always)]
    fn load(rays: (&[Vec3], &[Vec3], &[f32]), t_min: f32, start: usize, planes: &[Plane]) -> Self {
        let (origins, dirs, t_maxs) = rays;
        let end = (start + S::LANES)
            .min(origins.len())
            .min(dirs.len())
            .min(t_maxs.len());
        let (o, d, t_max) = if end - start == S::LANES {
            let t_max = S::load(&t_maxs[start..end]);
            let (o, d) = (&origins[start..end], &dirs[start..end]);
            (S::load_points(o), S::load_points(d), t_max)
        } else {
            let mut o = [[0.0; MAX_LANES]; 3];
            let mut d = [[0.0; MAX_LANES]; 3];
            let mut t_max = [f32::NAN; MAX_LANES];
            for (lane, i) in (start..end).enumerate() {
                for axis in 0..3 {
                    o[axis][lane] = origins[i][axis];
                    d[axis][lane] = dirs[i][axis];
                }
                t_max[lane] = t_maxs[i];
            }
            let axes = |v: &[[f32; MAX_LANES]; 3]| [S::load(&v[0]), S::load(&v[1]), S::load(&v[2])];
            (axes(&o), axes(&d), S::load(&t_max))
        };
        let ray = |lane: usize| (origins[start + lane], dirs[start + lane]);
        Group::new(o, d, t_max, t_min, planes, ray)
    }

    /// The group of the packed rays `start..start + S::LANES` (see [`Packed`]), tested against
    /// the planes.
    #[inline(always)]
    fn load_packed(
        packed: &Packed,
        rays: (&[Vec3], &[Vec3], &[f32]),
        t_min: f32,
        start: usize,
        planes: &[Plane],
    ) -> Self {
        let end = start + S::LANES;
        // Axis by axis, not `array::map`, which is not always inlined (in one partition of the
        // crate into codegen units it was a call per group: Cornell +10.9 M in `any_hits_chunk`).
        let axes = |v: &[[f32; PACKED + MAX_LANES]; 3]| {
            let axis = |axis: usize| S::load(&v[axis][start..end]);
            [axis(0), axis(1), axis(2)]
        };
        let (o, d) = (axes(&packed.o), axes(&packed.d));
        let t_max = S::load(&packed.t_max[start..end]);
        let ray = |lane: usize| {
            let i = packed.index[start + lane] as usize;
            (rays.0[i], rays.1[i])
        };
        Group::new(o, d, t_max, t_min, planes, ray)
    }

    /// The group of the rays in lanes, with each lane's ray (`ray(lane)`) for the planes.
    #[inline(always)]
    fn new(
        o: [S; 3],
        d: [S; 3],
        t_max: S,
        t_min: f32,
        planes: &[Plane],
        ray: impl Fn(usize) -> (Vec3, Vec3),
    ) -> Self {
        // As `Ray::new` and the range test of `Accel::find_closest`: `x · 0` is 0 only for a
        // finite `x`.
        let zero = S::splat(0.0);
        let finite = |axis: usize| (o[axis] * zero + d[axis] * zero).eq(zero);
        let finite = S::and(S::and(finite(0), finite(1)), finite(2));
        let moving = S::or(S::or(d[0].ne(zero), d[1].ne(zero)), d[2].ne(zero));
        let usable = S::and(S::and(finite, moving), S::splat(t_min).lt(t_max));
        let mut t_max = S::splat(f32::NAN).replaced(usable, t_max);
        let mut prim = [NO_HIT; MAX_LANES];
        if !planes.is_empty() {
            let mut t_maxs = [f32::NAN; MAX_LANES];
            t_max.store(&mut t_maxs);
            for_each_bit(u64::from(S::bits(usable)), |lane| {
                let (o, d) = ray(lane);
                let (o, d) = (Vec3A::from(o), Vec3A::from(d));
                for plane in planes {
                    if let Some(t) = plane.intersect(o, d, t_min, t_maxs[lane]) {
                        (t_maxs[lane], prim[lane]) = (t, plane.id);
                    }
                }
            });
            t_max = S::load(&t_maxs);
        }
        let t_min = S::splat(t_min);
        Group {
            rays: Rays { o, d, t_min },
            t_max,
            prim,
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn dot<S: Lanes>(a: &[S; 3], b: &[S; 3]) -> S {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn cross<S: Lanes>(a: &[S; 3], b: &[S; 3]) -> [S; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn splat3<S: Lanes>(v: &[f32; 3]) -> [S; 3] {
    [S::splat(v[0]), S::splat(v[1]), S::splat(v[2])]
}

/// The triangle test of `Triangle4::intersect`, its operations in its order, one ray per
/// lane: where the rays hit with `t` in `(t_min, t_max)` (perhaps nowhere), and `(t, u, v)`.
/// As there, the second cross product is skipped when no lane passes the first barycentric
/// test: `None` then.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn triangle_lanes<S: Lanes>(
    tri: &FlatTriangle,
    rays: &Rays<S>,
    t_max: S,
) -> Option<(S::Mask, S, S, S)> {
    moller_trumbore::<S, false>((&tri.v0, &tri.e1, &tri.e2), rays, t_max)
}

/// [`triangle_lanes`] on a parallelogram of two triangles ([`super::parallelogram`]): where
/// the rays hit it, their `t`, and the `u`, `v` and id (its bits in an `f32` lane) of the
/// triangle each hits, the half `s + r <= 1` or the other; `None` where no lane hits.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn parallelogram_lanes<S: Lanes>(
    quad: &Parallelogram,
    rays: &Rays<S>,
    t_max: S,
) -> Option<(S::Mask, S, S, S, S)> {
    let (hit, t, s, r) = moller_trumbore::<S, true>((&quad.v0, &quad.e1, &quad.e2), rays, t_max)?;
    if S::bits(hit) == 0 {
        return None;
    }
    let far_half = (s + r).gt(S::splat(1.0));
    let map = |m: &[f32; 6]| {
        (
            S::splat(m[0]) * s + S::splat(m[1]) * r + S::splat(m[2]),
            S::splat(m[3]) * s + S::splat(m[4]) * r + S::splat(m[5]),
        )
    };
    let ((u0, v0), (u1, v1)) = (map(&quad.barycentrics[0]), map(&quad.barycentrics[1]));
    let id = |id: u32| S::splat(f32::from_bits(id));
    Some((
        hit,
        t,
        u0.replaced(far_half, u1),
        v0.replaced(far_half, v1),
        id(quad.ids[0]).replaced(far_half, id(quad.ids[1])),
    ))
}

/// Möller–Trumbore against `v0 + u e1 + v e2`, one ray per lane: where the rays hit with `t`
/// in `(t_min, t_max)`, and `(t, u, v)`, the triangle `u, v >= 0, u + v <= 1` or, with
/// `PARALLELOGRAM`, the parallelogram `u, v` in `[0, 1]`; `None` where no lane passes the
/// first bound (the second cross product skipped).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn moller_trumbore<S: Lanes, const PARALLELOGRAM: bool>(
    (v0, e1, e2): (&[f32; 3], &[f32; 3], &[f32; 3]),
    rays: &Rays<S>,
    t_max: S,
) -> Option<(S::Mask, S, S, S)> {
    let [e1, e2, v0] = [splat3::<S>(e1), splat3(e2), splat3(v0)];
    let (zero, one) = (S::splat(0.0), S::splat(1.0));
    let d = &rays.d;
    let p = cross(d, &e2);
    let det = dot(&e1, &p);
    let inv_det = one / det;
    let s = [rays.o[0] - v0[0], rays.o[1] - v0[1], rays.o[2] - v0[2]];
    let u = dot(&s, &p) * inv_det;
    let u_mask = S::and(S::and(det.ne(zero), u.ge(zero)), u.le(one));
    if S::bits(u_mask) == 0 {
        return None;
    }
    let q = cross(&s, &e1);
    let v = dot(d, &q) * inv_det;
    let t = dot(&e2, &q) * inv_det;
    let far_bound = if PARALLELOGRAM { v } else { u + v };
    let uv = S::and(v.ge(zero), far_bound.le(one));
    let range = S::and(t.gt(rays.t_min), t.lt(t_max));
    let hit = S::and(u_mask, S::and(uv, range));
    Some((hit, t, u, v))
}

/// The sphere test of `Sphere4::intersect`, its operations in its order, one ray per lane:
/// where the rays hit with `t` in `(t_min, t_max)` (perhaps nowhere), and the nearest such
/// root.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn sphere_lanes<S: Lanes>(sphere: &FlatSphere, rays: &Rays<S>, t_max: S) -> (S::Mask, S) {
    let map = |row: &[f32; 4], p: &[S; 3]| {
        S::splat(row[0]) * p[0] + S::splat(row[1]) * p[1] + S::splat(row[2]) * p[2]
    };
    let (o, d) = match &sphere.translation {
        Some(t) => (
            [0, 1, 2].map(|axis| rays.o[axis] + S::splat(t[axis])),
            rays.d,
        ),
        None => {
            let [r0, r1, r2] = &sphere.rows;
            let o = [
                map(r0, &rays.o) + S::splat(r0[3]),
                map(r1, &rays.o) + S::splat(r1[3]),
                map(r2, &rays.o) + S::splat(r2[3]),
            ];
            (o, [map(r0, &rays.d), map(r1, &rays.d), map(r2, &rays.d)])
        }
    };
    let r = S::splat(sphere.radius);
    let two = S::splat(2.0);
    let a = dot(&d, &d);
    let b = two * dot(&o, &d);
    let c = dot(&o, &o) - r * r;
    let k = b / (two * a);
    let closest = [o[0] - k * d[0], o[1] - k * d[1], o[2] - k * d[2]];
    let l = dot(&closest, &closest).sqrt();
    let discriminant = S::splat(4.0) * a * (r + l) * (r - l);
    let root = discriminant.sqrt();
    let half = S::splat(-0.5);
    let q = (half * (b + root)).replaced(b.lt(S::splat(0.0)), half * (b - root));
    let (t0, t1) = (q / a, c / q);
    let ordered = t0.le(t1);
    let (near, far) = (t1.replaced(ordered, t0), t0.replaced(ordered, t1));
    let near_in = S::and(near.gt(rays.t_min), near.lt(t_max));
    let far_in = S::and(far.gt(rays.t_min), far.lt(t_max));
    let hit = S::or(near_in, far_in);
    (hit, far.replaced(near_in, near))
}

/// The disk test of `Disk::intersect`, its operations in its order, one ray per lane: where
/// the rays hit with `t` in `(t_min, t_max)` (perhaps nowhere), and `t`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn disk_lanes<S: Lanes>(disk: &FlatDisk, rays: &Rays<S>, t_max: S) -> (S::Mask, S) {
    let map = |row: &[f32; 4], p: &[S; 3]| {
        S::splat(row[0]) * p[0] + S::splat(row[1]) * p[1] + S::splat(row[2]) * p[2]
    };
    let [r0, r1, r2] = &disk.rows;
    let o = [
        map(r0, &rays.o) + S::splat(r0[3]),
        map(r1, &rays.o) + S::splat(r1[3]),
        map(r2, &rays.o) + S::splat(r2[3]),
    ];
    let d = [map(r0, &rays.d), map(r1, &rays.d), map(r2, &rays.d)];
    let t = (S::splat(0.0) - o[2]) / d[2];
    let (x, y) = (o[0] + t * d[0], o[1] + t * d[1]);
    let range = S::and(t.gt(rays.t_min), t.lt(t_max));
    let hit = S::and(range, (x * x + y * y).le(S::splat(1.0)));
    (hit, t)
}

/// Calls `f(i)` for each bit `i` set in `bits` (a group's lanes, or a list's primitives).
#[inline(always)]
fn for_each_bit(mut bits: u64, mut f: impl FnMut(usize)) {
    while bits != 0 {
        f(bits.trailing_zeros() as usize);
        bits &= bits - 1;
    }
}

/// The primitives shadow rays pass through ([`PassThrough`]), a bit each by index in
/// [`Flat`]'s lists.
///
/// The walk past them (`Accel::blocked_past_pass_through`: nearest hit first, `t_min` raised
/// to each invisible hit) blocks a ray exactly where some opaque primitive is hit, but for two
/// cases: after [`MAX_LAYERS`] invisible layers it counts the ray blocked, and an opaque hit
/// at the very `t` of an invisible one may be stepped over with it. So where a ray cannot meet
/// `MAX_LAYERS` layers, a ray with an opaque hit and no invisible one is blocked, a ray without
/// an opaque hit is not, and only a ray with both walks.
#[derive(Clone, Copy, Debug, Default)]
struct Invisible {
    triangles: u64,
    spheres: u64,
    disks: u64,
}

/// The inputs of [`Flat::any_hits`]: with `walk_blocked`, every blocked ray walks.
struct AnyHits<'a> {
    planes: &'a [Plane],
    rays: (&'a [Vec3], &'a [Vec3], &'a [f32]),
    t_min: f32,
    invisible: Invisible,
    walk_blocked: bool,
}

impl Flat {
    /// The triangles and spheres that can be hit (as the tree keeps them), and the disks;
    /// `None` where the CPU lacks AVX2.
    pub fn new(
        triangles: &[[Vec3; 3]],
        spheres: &[SphereInstance],
        disks: &[Disk],
        triangle_id: impl Fn(usize) -> u32,
        sphere_id: impl Fn(usize) -> u32,
    ) -> Option<Flat> {
        #[cfg(target_arch = "x86_64")]
        let simd = std::arch::is_x86_feature_detected!("avx2");
        #[cfg(not(target_arch = "x86_64"))]
        let simd = false;
        if !simd {
            return None;
        }
        let (vertices, ids): (Vec<[Vec3; 3]>, Vec<u32>) = (triangles.iter().enumerate())
            .filter(|(_, v)| triangle_bounds(v).is_some())
            .map(|(i, v)| (*v, triangle_id(i)))
            .unzip();
        let triangles: Vec<FlatTriangle> = (vertices.iter().zip(&ids))
            .map(|(v, &id)| FlatTriangle {
                v0: v[0].to_array(),
                e1: (v[1] - v[0]).to_array(),
                e2: (v[2] - v[0]).to_array(),
                id,
            })
            .collect();
        let (parallelograms, alone) = pair_consecutive(&vertices, &ids);
        let unpaired = alone.iter().map(|&i| triangles[i]).collect();
        let runs = coplanar_runs(
            &triangles
                .iter()
                .map(|t| (t.v0, t.e1, t.e2))
                .collect::<Vec<_>>(),
        );
        let spheres = (spheres.iter().enumerate())
            .filter(|(_, s)| sphere_bounds(s).is_some())
            .map(|(i, s)| {
                let m = s.object_to_world.inverse();
                let columns = [
                    m.matrix3.x_axis,
                    m.matrix3.y_axis,
                    m.matrix3.z_axis,
                    m.translation,
                ];
                FlatSphere {
                    rows: [0, 1, 2].map(|i| columns.map(|column| column[i])),
                    translation: translation_only(&m).map(|t| t.to_array()),
                    radius: s.radius,
                    id: sphere_id(i),
                }
            })
            .collect();
        let disks = (disks.iter())
            .map(|disk| FlatDisk {
                rows: disk.rows(),
                id: disk.id,
            })
            .collect();
        Some(Flat {
            triangles,
            unpaired,
            parallelograms,
            runs,
            spheres,
            disks,
        })
    }

    /// For each i: hits[i] = the closest hit of ray i with t in (t_min, t_maxs[i]) among the
    /// planes and these primitives, as `Accel::closest_hit` answers it (but for ties, see the
    /// module's documentation).
    pub fn closest_hits(
        &self,
        planes: &[Plane],
        rays: (&[Vec3], &[Vec3], &[f32]),
        t_min: f32,
        hits: &mut [Option<Hit>],
    ) {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: the CPU has the features the functions are compiled for (`Flat::new`
            // checked AVX2).
            if std::arch::is_x86_feature_detected!("avx512f") {
                return unsafe { self.closest_hits_avx512(planes, rays, t_min, hits) };
            }
            return unsafe { self.closest_hits_avx2(planes, rays, t_min, hits) };
        }
        #[allow(unreachable_code)]
        {
            unreachable!("a Flat is built only where the CPU has AVX2")
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn closest_hits_avx512(
        &self,
        planes: &[Plane],
        rays: (&[Vec3], &[Vec3], &[f32]),
        t_min: f32,
        hits: &mut [Option<Hit>],
    ) {
        self.closest_hits_in::<L16>(planes, rays, t_min, hits)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn closest_hits_avx2(
        &self,
        planes: &[Plane],
        rays: (&[Vec3], &[Vec3], &[f32]),
        t_min: f32,
        hits: &mut [Option<Hit>],
    ) {
        self.closest_hits_in::<L8>(planes, rays, t_min, hits)
    }

    /// [`Flat::closest_hits`] in groups of `S::LANES`.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn closest_hits_in<S: Lanes>(
        &self,
        planes: &[Plane],
        rays: (&[Vec3], &[Vec3], &[f32]),
        t_min: f32,
        hits: &mut [Option<Hit>],
    ) {
        let len = (hits.len().min(rays.0.len()).min(rays.1.len())).min(rays.2.len());
        for (group_index, hits) in hits[..len].chunks_mut(S::LANES).enumerate() {
            let group = Group::<S>::load(rays, t_min, group_index * S::LANES, planes);
            let (lanes, mut t_max) = (&group.rays, group.t_max);
            // Each lane's primitive id rides in an `f32` lane as its bit pattern (a blend moves
            // bits, never values): a hit is a blend, not a branch and a loop over its lanes,
            // whose outcome incoherent rays make unpredictable.
            let id = |id: u32| S::splat(f32::from_bits(id));
            let mut prim = S::load(&group.prim.map(f32::from_bits));
            let (zero, mut u, mut v) = (S::splat(0.0), S::splat(0.0), S::splat(0.0));
            for tri in &self.unpaired {
                if let Some((hit, t, hit_u, hit_v)) = triangle_lanes(tri, lanes, t_max) {
                    t_max = t_max.replaced(hit, t);
                    (u, v) = (u.replaced(hit, hit_u), v.replaced(hit, hit_v));
                    prim = prim.replaced(hit, id(tri.id));
                }
            }
            for quad in &self.parallelograms {
                if let Some((hit, t, hit_u, hit_v, hit_id)) =
                    parallelogram_lanes(quad, lanes, t_max)
                {
                    t_max = t_max.replaced(hit, t);
                    (u, v) = (u.replaced(hit, hit_u), v.replaced(hit, hit_v));
                    prim = prim.replaced(hit, hit_id);
                }
            }
            for sphere in &self.spheres {
                let (hit, t) = sphere_lanes(sphere, lanes, t_max);
                t_max = t_max.replaced(hit, t);
                (u, v) = (u.replaced(hit, zero), v.replaced(hit, zero));
                prim = prim.replaced(hit, id(sphere.id));
            }
            for disk in &self.disks {
                let (hit, t) = disk_lanes(disk, lanes, t_max);
                t_max = t_max.replaced(hit, t);
                (u, v) = (u.replaced(hit, zero), v.replaced(hit, zero));
                prim = prim.replaced(hit, id(disk.id));
            }
            let mut out = [[0.0; MAX_LANES]; 4];
            t_max.store(&mut out[0]);
            u.store(&mut out[1]);
            v.store(&mut out[2]);
            prim.store(&mut out[3]);
            let [ts, us, vs, prims] = out;
            for (lane, hit) in hits.iter_mut().enumerate() {
                let prim = prims[lane].to_bits();
                *hit = (prim != NO_HIT).then_some(Hit {
                    t: ts[lane],
                    prim,
                    u: us[lane],
                    v: vs[lane],
                });
            }
        }
    }

    /// For each i: occluded[i] = whether ray i hits a plane or one of these primitives with t
    /// in (t_min, t_maxs[i]); with `pass_through`, whether `Accel::any_opaque_hit` finds one
    /// not in that set, where `walk(i)` is that query's answer for ray i, called for the rays
    /// the lanes leave undecided (see [`Invisible`]). A group stops as soon as all its rays are
    /// settled.
    pub fn any_hits(
        &self,
        planes: &[Plane],
        rays: (&[Vec3], &[Vec3], &[f32]),
        t_min: f32,
        pass_through: Option<&PassThrough>,
        walk: impl Fn(usize) -> bool,
        occluded: &mut [bool],
    ) {
        let (invisible, walk_blocked) = match pass_through {
            None => (Invisible::default(), false),
            Some(pass) => match self.invisible(planes, pass) {
                Some(invisible) => (invisible, false),
                None => (Invisible::default(), true),
            },
        };
        let query = AnyHits {
            planes,
            rays,
            t_min,
            invisible,
            walk_blocked,
        };
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: as in `closest_hits`.
            if std::arch::is_x86_feature_detected!("avx512f") {
                return unsafe { self.any_hits_avx512(&query, walk, occluded) };
            }
            return unsafe { self.any_hits_avx2(&query, walk, occluded) };
        }
        #[allow(unreachable_code)]
        {
            unreachable!("a Flat is built only where the CPU has AVX2")
        }
    }

    /// The primitives of `pass_through` among these, or `None` where the lanes cannot decide
    /// without the walk: a plane passes rays (planes are tested ray by ray, nearest only), or
    /// a ray could meet [`MAX_LAYERS`] invisible surfaces (a sphere is met twice).
    fn invisible(&self, planes: &[Plane], pass_through: &PassThrough) -> Option<Invisible> {
        let bits = |ids: &mut dyn Iterator<Item = u32>| {
            (ids.enumerate()).fold(0u64, |bits, (i, id)| {
                bits | (pass_through.contains(id) as u64) << i
            })
        };
        let invisible = Invisible {
            triangles: bits(&mut self.triangles.iter().map(|tri| tri.id)),
            spheres: bits(&mut self.spheres.iter().map(|sphere| sphere.id)),
            disks: bits(&mut self.disks.iter().map(|disk| disk.id)),
        };
        let layers = invisible.triangles.count_ones()
            + 2 * invisible.spheres.count_ones()
            + invisible.disks.count_ones();
        let plane_passes = planes.iter().any(|plane| pass_through.contains(plane.id));
        (!plane_passes && layers < MAX_LAYERS).then_some(invisible)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn any_hits_avx512(
        &self,
        query: &AnyHits,
        walk: impl Fn(usize) -> bool,
        occluded: &mut [bool],
    ) {
        self.any_hits_in::<L16>(query, walk, occluded)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn any_hits_avx2(&self, query: &AnyHits, walk: impl Fn(usize) -> bool, occluded: &mut [bool]) {
        self.any_hits_in::<L8>(query, walk, occluded)
    }

    /// [`Flat::any_hits`] in groups of `S::LANES`: the invisible primitives first, then the
    /// opaque ones until every lane is settled.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn any_hits_in<S: Lanes>(
        &self,
        query: &AnyHits,
        walk: impl Fn(usize) -> bool,
        occluded: &mut [bool],
    ) {
        let (rays, t_min) = (query.rays, query.t_min);
        let len = (occluded.len().min(rays.0.len()).min(rays.1.len())).min(rays.2.len());
        let rays = (&rays.0[..len], &rays.1[..len], &rays.2[..len]);
        occluded[..len].fill(false);
        // Not re-entered: `walk` asks the trees, never a flat batch query.
        PACKED_RAYS.with_borrow_mut(|packed| {
            for block in (0..len).step_by(PACKED) {
                packed.pack(rays, t_min, block);
                for first in (0..packed.len).step_by(S::LANES) {
                    self.any_hits_group::<S>(query, packed, first, &walk, occluded);
                }
            }
        });
    }

    /// The packed rays `first..first + S::LANES` of [`Flat::any_hits_in`].
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn any_hits_group<S: Lanes>(
        &self,
        query: &AnyHits,
        packed: &Packed,
        first: usize,
        walk: impl Fn(usize) -> bool,
        occluded: &mut [bool],
    ) {
        let (rays, t_min, invisible) = (query.rays, query.t_min, &query.invisible);
        let group = Group::<S>::load_packed(packed, rays, t_min, first, query.planes);
        let (lanes, t_max) = (&group.rays, group.t_max);
        let planes_hit = (group.prim.iter().enumerate()).fold(0u32, |bits, (lane, &prim)| {
            bits | ((prim != NO_HIT) as u32) << lane
        });
        let culling = RunCulling::new(lanes, t_max, t_min);
        let mut passed = 0;
        for run in &self.runs {
            let in_run = (u64::MAX >> (64 - run.triangles.len())) << run.triangles.start;
            if invisible.triangles & in_run == 0 || culling.skips(run, lanes, t_max) {
                continue;
            }
            for_each_bit(invisible.triangles & in_run, |i| {
                if let Some((hit, ..)) = triangle_lanes(&self.triangles[i], lanes, t_max) {
                    passed |= S::bits(hit);
                }
            });
        }
        for_each_bit(invisible.spheres, |i| {
            passed |= S::bits(sphere_lanes(&self.spheres[i], lanes, t_max).0);
        });
        for_each_bit(invisible.disks, |i| {
            passed |= S::bits(disk_lanes(&self.disks[i], lanes, t_max).0);
        });
        // Settled lanes: those an opaque primitive blocks, and those that can hit nothing
        // (NaN).
        let mut blocked = planes_hit;
        let unusable = S::bits(t_max.ne(t_max));
        let all = (1u32 << S::LANES) - 1;
        'primitives: {
            for run in &self.runs {
                if (blocked | unusable) == all {
                    break 'primitives;
                }
                if culling.skips(run, lanes, t_max) {
                    continue;
                }
                for i in run.triangles.clone() {
                    if (blocked | unusable) == all {
                        break 'primitives;
                    }
                    if invisible.triangles >> i & 1 == 0
                        && let Some((hit, ..)) = triangle_lanes(&self.triangles[i], lanes, t_max)
                    {
                        blocked |= S::bits(hit);
                    }
                }
            }
            for (i, sphere) in self.spheres.iter().enumerate() {
                if (blocked | unusable) == all {
                    break 'primitives;
                }
                if invisible.spheres >> i & 1 == 0 {
                    blocked |= S::bits(sphere_lanes(sphere, lanes, t_max).0);
                }
            }
            for (i, disk) in self.disks.iter().enumerate() {
                if (blocked | unusable) == all {
                    break 'primitives;
                }
                if invisible.disks >> i & 1 == 0 {
                    blocked |= S::bits(disk_lanes(disk, lanes, t_max).0);
                }
            }
        }
        let (decided, undecided) = if query.walk_blocked {
            (0, blocked)
        } else {
            (blocked & !passed, blocked & passed)
        };
        let ray = |lane: usize| packed.index[first + lane] as usize;
        for_each_bit(u64::from(decided), |lane| occluded[ray(lane)] = true);
        for_each_bit(u64::from(undecided), |lane| {
            occluded[ray(lane)] = walk(ray(lane))
        });
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_random;
    use glam::{Affine3A, Quat};
    use rand_xoshiro::Xoshiro256PlusPlus;
    use rand_xoshiro::rand_core::{Rng, SeedableRng};

    use super::super::sphere::Sphere4;
    use super::super::triangle::Triangle4;
    use super::super::{Accel, DiskInstance, PassThrough, PlaneInstance, PrimitiveRef, Primitives};
    use super::*;

    /// A random scene of at most [`MAX_FLAT_PRIMITIVES`] primitives: triangles on a
    /// half-unit grid (shared vertices and edges, so exact edge hits and equal-`t` ties), an
    /// ellipsoid or a few, sometimes a plane, sometimes an elliptic disk or two, and one
    /// degenerate triangle and sphere.
    fn scene(rng: &mut Xoshiro256PlusPlus) -> Primitives {
        let mut uniform = |lo: f32, hi: f32| test_random::uniform(rng, lo, hi);
        let grid = |x: f32| (x * 2.0).round() * 0.5;
        let mut point = || Vec3::new(uniform(-2.0, 2.0), uniform(-2.0, 2.0), uniform(-2.0, 2.0));
        let mut triangles: Vec<[Vec3; 3]> = (0..(point().x.abs() * 7.0) as usize + 2)
            .map(|_| [point(), point(), point()].map(|p| p.map(grid)))
            .collect();
        triangles.push([Vec3::ONE; 3]);
        let spheres = (0..(point().x.abs() * 2.0) as usize + 1)
            .map(|_| SphereInstance {
                object_to_world: Affine3A::from_scale_rotation_translation(
                    point().abs() * 0.4 + 0.2,
                    Quat::from_axis_angle(point().normalize_or(Vec3::X), point().x),
                    point(),
                ),
                radius: point().x.abs() * 0.3 + 0.1,
            })
            .chain([SphereInstance {
                object_to_world: Affine3A::IDENTITY,
                radius: 0.0,
            }])
            .collect();
        let planes = if point().x > 0.0 {
            vec![PlaneInstance {
                point: Vec3::new(0.0, -1.5, 0.0),
                normal: point(),
            }]
        } else {
            Vec::new()
        };
        let disks = (0..(point().y + 1.0).max(0.0) as usize)
            .map(|_| DiskInstance {
                object_to_world: Affine3A::from_scale_rotation_translation(
                    point().abs() * 0.4 + 0.2,
                    Quat::from_axis_angle(point().normalize_or(Vec3::X), point().x),
                    point(),
                ),
            })
            .collect();
        Primitives {
            triangles,
            spheres,
            planes,
            disks,
            ..Default::default()
        }
    }

    /// Rays from all sides aimed at the triangles' vertices and edges, at the spheres' centres
    /// and at points near the disks' rims, with finite and infinite `t_max`; some unusable
    /// (zero direction, NaN, an empty range).
    fn rays(scene: &Primitives, rng: &mut Xoshiro256PlusPlus) -> (Vec<Vec3>, Vec<Vec3>, Vec<f32>) {
        let mut rays = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..203 {
            let mut uniform = |lo: f32, hi: f32| test_random::uniform(rng, lo, hi);
            let aim = if i % 7 == 5 && !scene.disks.is_empty() {
                let (s, c) = uniform(0.0, 6.3).sin_cos();
                let r = uniform(0.9, 1.1);
                let disk = scene.disks[i % scene.disks.len()].object_to_world;
                disk.transform_point3(Vec3::new(r * c, r * s, 0.0))
            } else if i % 3 == 0 {
                scene.spheres[i % scene.spheres.len()]
                    .object_to_world
                    .translation
                    .into()
            } else {
                let v = scene.triangles[i % scene.triangles.len()];
                v[i % 3].lerp(v[(i + 1) % 3], [0.0, 0.5, 0.25][i % 5 % 3])
            };
            let origin = Vec3::new(uniform(-6.0, 6.0), uniform(-6.0, 6.0), uniform(-6.0, 6.0));
            let dir = match i % 41 {
                0 => Vec3::ZERO,
                1 => Vec3::NAN,
                _ => (aim - origin) * uniform(0.2, 2.0),
            };
            let t_max = match i % 4 {
                0 => f32::INFINITY,
                1 => -1.0,
                _ => uniform(0.3, 1.5),
            };
            rays.0.push(origin);
            rays.1.push(dir);
            rays.2.push(t_max);
        }
        rays
    }

    /// `scene` with one to three parallelograms split in two (coplanar runs; every other one
    /// axis-aligned, as a room's walls) after its triangles, on the half-unit grid, so that
    /// each one's four corners lie exactly in one plane.
    fn with_parallelograms(scene: &Primitives, rng: &mut Xoshiro256PlusPlus) -> Primitives {
        let mut uniform = |lo: f32, hi: f32| test_random::uniform(rng, lo, hi);
        let grid = |x: f32| (x * 2.0).round() * 0.5;
        let mut point = || Vec3::new(uniform(-2.0, 2.0), uniform(-2.0, 2.0), uniform(-2.0, 2.0));
        let mut triangles = scene.triangles.clone();
        for k in 0..(point().z.abs() * 1.5) as usize + 1 {
            let (corner, mut a, mut b) = (point().map(grid), point().map(grid), point().map(grid));
            if k % 2 == 0 {
                (a, b) = (a * Vec3::X, b * Vec3::Y);
            }
            triangles.push([corner, corner + a, corner + a + b]);
            triangles.push([corner, corner + a + b, corner + b]);
        }
        Primitives {
            triangles,
            ..scene.clone()
        }
    }

    /// Rays that meet the planes of `flat`'s coplanar runs at the edge of their range: from
    /// points inside a run's triangles, exactly there or moved off as the renderer moves new
    /// rays (`offset_ray_origin`), in random directions; and from random points to a point of
    /// a run's triangle, ending a few ulps short of it, at it or past it (`d` the difference,
    /// `t_max` near 1). Sixteen rays in a row are of one kind and meet one run, so that whole
    /// groups leave a run's plane. A plane test whose margin is too tight skips some of their
    /// hits.
    fn run_rays(
        flat: &Flat,
        rng: &mut Xoshiro256PlusPlus,
        rays: &mut (Vec<Vec3>, Vec<Vec3>, Vec<f32>),
    ) {
        let runs: Vec<&TriangleRun> = flat.runs.iter().filter(|run| run.plane.is_some()).collect();
        // A parallelogram may be degenerate or a sliver: no run then.
        for i in (0..336).take_while(|_| !runs.is_empty()) {
            let mut uniform = |lo: f32, hi: f32| test_random::uniform(rng, lo, hi);
            let run = runs[i / 48 % runs.len()];
            let tri = &flat.triangles[run.triangles.start + i % run.triangles.len()];
            let (v0, e1, e2) = (Vec3::from(tri.v0), Vec3::from(tri.e1), Vec3::from(tri.e2));
            let (u, v) = (uniform(0.0, 1.0), uniform(0.0, 1.0));
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            let on_plane = v0 + u * e1 + v * e2;
            let random = Vec3::new(uniform(-6.0, 6.0), uniform(-6.0, 6.0), uniform(-6.0, 6.0));
            let (origin, dir, t_max) = match i / 16 % 3 {
                0 => (on_plane, random, f32::INFINITY),
                1 => {
                    let normal = e1.cross(e2).normalize();
                    let origin = crate::math::offset_ray_origin(on_plane, normal, random);
                    (origin, random, [f32::INFINITY, uniform(0.5, 4.0)][i % 2])
                }
                _ => {
                    let ulps = (i % 7) as f32 - 4.0;
                    (random, on_plane - random, 1.0 + ulps * f32::EPSILON / 2.0)
                }
            };
            rays.0.push(origin);
            rays.1.push(dir);
            rays.2.push(t_max);
        }
    }

    /// `flat` with each triangle a run of its own, without a plane: nothing skipped.
    fn without_runs(flat: &Flat) -> Flat {
        Flat {
            triangles: flat.triangles.clone(),
            unpaired: flat.unpaired.clone(),
            parallelograms: flat.parallelograms.clone(),
            runs: (0..flat.triangles.len())
                .map(|i| TriangleRun {
                    triangles: i..i + 1,
                    plane: None,
                })
                .collect(),
            spheres: flat.spheres.clone(),
            disks: flat.disks.clone(),
        }
    }

    /// How many coplanar runs the groups of `S::LANES` consecutive rays skip (the test of
    /// [`Flat::any_hits`], on groups as [`Flat::closest_hits`] loads them), summed over the
    /// groups.
    #[inline(always)]
    fn runs_skipped<S: Lanes>(flat: &Flat, rays: (&[Vec3], &[Vec3], &[f32])) -> usize {
        (0..rays.0.len())
            .step_by(S::LANES)
            .map(|start| {
                let group = Group::<S>::load(rays, 0.0, start, &[]);
                let culling = RunCulling::new(&group.rays, group.t_max, 0.0);
                (flat.runs.iter())
                    .filter(|run| culling.skips(run, &group.rays, group.t_max))
                    .count()
            })
            .sum()
    }

    /// The any-hit query of `rays` from t = 0: past `invisible` surfaces tested in lanes, or,
    /// where there are none to test so, with blocked rays walking.
    fn any_hits_query<'a>(
        planes: &'a [Plane],
        rays: (&'a [Vec3], &'a [Vec3], &'a [f32]),
        invisible: Option<Invisible>,
    ) -> AnyHits<'a> {
        AnyHits {
            planes,
            rays,
            t_min: 0.0,
            walk_blocked: invisible.is_none(),
            invisible: invisible.unwrap_or_default(),
        }
    }

    /// Closest hits, occlusion by every primitive and occlusion past the invisible ones (rays
    /// meeting both walk with `walk`) of `queries`' rays, 16 lanes at a time (`avx512`) or 8.
    fn queries_at_width(
        flat: &Flat,
        queries: (&AnyHits, &AnyHits),
        walk: impl Fn(usize) -> bool,
        avx512: bool,
    ) -> (Vec<Option<Hit>>, Vec<bool>, Vec<bool>) {
        let (all_opaque, past_invisible) = queries;
        let n = all_opaque.rays.0.len();
        let never = |_: usize| -> bool { unreachable!("no ray walks without invisible surfaces") };
        let (mut hits, mut occluded, mut opaque) = (vec![None; n], vec![false; n], vec![false; n]);
        let (planes, rays) = (all_opaque.planes, all_opaque.rays);
        // SAFETY: each width only where the CPU has its features (the callers check AVX-512;
        // a flat scene exists only where the CPU has AVX2).
        unsafe {
            if avx512 {
                flat.closest_hits_avx512(planes, rays, 0.0, &mut hits);
                flat.any_hits_avx512(all_opaque, never, &mut occluded);
                flat.any_hits_avx512(past_invisible, walk, &mut opaque);
            } else {
                flat.closest_hits_avx2(planes, rays, 0.0, &mut hits);
                flat.any_hits_avx2(all_opaque, never, &mut occluded);
                flat.any_hits_avx2(past_invisible, walk, &mut opaque);
            }
        }
        (hits, occluded, opaque)
    }

    /// The coplanar runs' plane tests skip no hit: on `scene` with parallelograms added, with
    /// its rays and rays at the edge of the plane tests ([`run_rays`]), the occlusions (all
    /// opaque, and past every third primitive) at each width are those of the same primitives
    /// without runs, bit for bit; so are the closest hits (which test every triangle, the
    /// parallelograms' as one), and they are the brute-force ones but where the
    /// parallelograms' rounding may differ ([`agrees_but_for_parallelograms`]). Returns how many
    /// runs groups of 8 and of 16 rays skipped.
    fn check_runs(scene: &Primitives, rng: &mut Xoshiro256PlusPlus) -> [usize; 2] {
        let scene = with_parallelograms(scene, rng);
        let accel = Accel::build(&scene);
        let flat = accel.flat.as_ref().expect("a small scene is traced flat");
        let unculled = without_runs(flat);
        let mut rays = (Vec::new(), Vec::new(), Vec::new());
        run_rays(flat, rng, &mut rays);
        let (mut origins, mut dirs, mut t_maxs) = rays;
        let scene_rays = self::rays(&scene, rng);
        origins.extend(scene_rays.0);
        dirs.extend(scene_rays.1);
        t_maxs.extend(scene_rays.2);
        let n = origins.len();
        let rays = (&origins[..], &dirs[..], &t_maxs[..]);
        let planes = &accel.planes;
        let pass = PassThrough::new(accel.primitive_count(), |id| id % 3 == 1).unwrap();
        let query = |invisible| any_hits_query(planes, rays, invisible);
        let (all_opaque, past_invisible) = (
            query(Some(Invisible::default())),
            query(flat.invisible(planes, &pass)),
        );
        let walk =
            |i: usize| accel.blocked_past_pass_through(origins[i], dirs[i], 0.0, t_maxs[i], &pass);
        let run = |flat: &Flat, avx512: bool| {
            queries_at_width(flat, (&all_opaque, &past_invisible), walk, avx512)
        };
        #[target_feature(enable = "avx2")]
        fn skipped_avx2(flat: &Flat, rays: (&[Vec3], &[Vec3], &[f32])) -> usize {
            runs_skipped::<L8>(flat, rays)
        }
        #[target_feature(enable = "avx512f")]
        fn skipped_avx512(flat: &Flat, rays: (&[Vec3], &[Vec3], &[f32])) -> usize {
            runs_skipped::<L16>(flat, rays)
        }
        let mut skipped = [0; 2];
        let avx512 = std::arch::is_x86_feature_detected!("avx512f");
        for (width, wide) in [false, avx512]
            .into_iter()
            .enumerate()
            .take(1 + avx512 as usize)
        {
            let (hits, occluded, opaque) = run(flat, wide);
            let (hits_0, occluded_0, opaque_0) = run(&unculled, wide);
            for i in 0..n {
                let expected = brute_force(&accel, &scene, origins[i], dirs[i], t_maxs[i]);
                assert!(
                    agrees_but_for_parallelograms(
                        flat,
                        (origins[i], dirs[i], t_maxs[i]),
                        hits[i],
                        expected
                    ),
                    "ray {i}, width {width}: {:?} against {expected:?}",
                    hits[i]
                );
                assert_eq!(hits[i], hits_0[i], "ray {i}, width {width}");
                assert_eq!(occluded[i], occluded_0[i], "ray {i}, width {width}");
                assert_eq!(opaque[i], opaque_0[i], "ray {i}, width {width}");
            }
            // SAFETY: as in `run`.
            skipped[width] = unsafe {
                if wide {
                    skipped_avx512(flat, rays)
                } else {
                    skipped_avx2(flat, rays)
                }
            };
        }
        skipped
    }

    /// Whether the flat tracer's closest hit `got` is the brute-force one `expected` on the ray
    /// `(o, d)` whose range ends at `t_max`, or differs only where `flat`'s parallelograms
    /// answer for their triangles within rounding ([`super::super::parallelogram`]): the same
    /// triangle at a `t`, `u` and `v` within a tolerance; a triangle of a pair at the other
    /// answer's `t` (a tie, or the pair's shared edge); or where the nearer of the two answers
    /// is a triangle of a pair hit within a tolerance of its edges or of the range's ends. The
    /// tolerance is 1e-5 of the scale `1 + |o| + t |d|` over the cosine between the ray and the
    /// triangle's plane: the two tests' rounding moves the point where the ray meets the plane
    /// by a few ulps of that scale across the plane, and so by that over the cosine along the
    /// ray and within the plane.
    fn agrees_but_for_parallelograms(
        flat: &Flat,
        (o, d, t_max): (Vec3, Vec3, f32),
        got: Option<Hit>,
        expected: Option<Hit>,
    ) -> bool {
        if got == expected {
            return true;
        }
        let paired =
            |hit: &Hit| (flat.parallelograms.iter()).any(|quad| quad.ids.contains(&hit.prim));
        // The tolerance in units of the ray's t and of barycentrics (the triangle's edges are
        // at most a few units long in the tests' scenes).
        let tolerance = |hit: &Hit| {
            let tri = (flat.triangles.iter()).find(|tri| tri.id == hit.prim);
            let normal = tri.map_or(Vec3::ZERO, |tri| {
                Vec3::from(tri.e1)
                    .cross(Vec3::from(tri.e2))
                    .normalize_or_zero()
            });
            let cosine = d.normalize_or_zero().dot(normal).abs().max(1e-3);
            let scale = 1.0 + o.length() + hit.t.abs() * d.length();
            (
                1e-5 * scale / (cosine * d.length().max(1e-3)),
                1e-5 * scale / cosine,
            )
        };
        if let (Some(a), Some(b)) = (got, expected) {
            let (t_tolerance, uv_tolerance) = tolerance(&a);
            let close = |x: f32, y: f32, tolerance: f32| (x - y).abs() <= tolerance;
            let same_triangle =
                a.prim == b.prim && close(a.u, b.u, uv_tolerance) && close(a.v, b.v, uv_tolerance);
            if close(a.t, b.t, t_tolerance)
                && (paired(&a) || paired(&b))
                && (a.prim != b.prim || same_triangle)
            {
                return true;
            }
        }
        let nearer = match (got, expected) {
            (Some(a), Some(b)) => Some(if a.t <= b.t { a } else { b }),
            (a, b) => a.or(b),
        };
        nearer.is_some_and(|hit| {
            let (t_tolerance, uv_tolerance) = tolerance(&hit);
            let edge = hit.u.min(hit.v).min(1.0 - hit.u - hit.v) <= uv_tolerance;
            let range_end = (hit.t - t_max).abs() <= t_tolerance || hit.t.abs() <= t_tolerance;
            paired(&hit) && (edge || range_end)
        })
    }

    /// The closest hit by brute force with the stated tie rule: planes, triangles, spheres,
    /// disks in that order, each by its one-lane packet test, a hit kept only if strictly
    /// nearer.
    fn brute_force(accel: &Accel, scene: &Primitives, o: Vec3, d: Vec3, t_max: f32) -> Option<Hit> {
        let ray = super::super::bvh::Ray::new(o.into(), d.into())?;
        if t_max.is_nan() || t_max <= 0.0 {
            return None;
        }
        let (mut t_max, mut best) = (t_max, None);
        for plane in &accel.planes {
            if let Some(t) = plane.intersect(ray.origin, ray.dir, 0.0, t_max) {
                (t_max, best) = (
                    t,
                    Some(Hit {
                        t,
                        prim: plane.id,
                        u: 0.0,
                        v: 0.0,
                    }),
                );
            }
        }
        let (o4, d4) = (&ray.origin4, &ray.dir4);
        for (i, tri) in scene.triangles.iter().enumerate() {
            // A zero-area triangle is left out, as `Flat` and the tree leave it: rounding can
            // make its `det` nonzero.
            if triangle_bounds(tri).is_none() {
                continue;
            }
            let packet = Triangle4::new([(tri, accel.ids().triangle(i))]);
            if let Some(hit) = packet.intersect::<false>(o4, d4, 0.0, t_max) {
                let prim = packet.ids[0];
                (t_max, best) = (
                    hit.t,
                    Some(Hit {
                        t: hit.t,
                        prim,
                        u: hit.u,
                        v: hit.v,
                    }),
                );
            }
        }
        for (i, sphere) in scene.spheres.iter().enumerate() {
            if sphere_bounds(sphere).is_none() {
                continue;
            }
            let packet = Sphere4::new([(sphere, accel.ids().sphere(i))]);
            if let Some(hit) = packet.intersect::<false>(o4, d4, 0.0, t_max) {
                let prim = packet.ids[0];
                (t_max, best) = (
                    hit.t,
                    Some(Hit {
                        t: hit.t,
                        prim,
                        u: 0.0,
                        v: 0.0,
                    }),
                );
            }
        }
        for disk in &accel.disks {
            if let Some(t) = disk.intersect(ray.origin, ray.dir, 0.0, t_max) {
                (t_max, best) = (
                    t,
                    Some(Hit {
                        t,
                        prim: disk.id,
                        u: 0.0,
                        v: 0.0,
                    }),
                );
            }
        }
        best
    }

    /// A block's packed rays are those with a non-empty range, in order, with their indices:
    /// against a filter of the rays, for blocks whose `t_max` are random among empty ones
    /// (zero, negative, `t_min` itself, NaN) and live ones (finite, infinite), whole and
    /// short, so that groups of eight keep every number of rays in every order; and past the
    /// packed rays, the `t_max` a group reads are NaN.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn packing_keeps_the_rays_with_a_range_in_order() {
        #[target_feature(enable = "avx2")]
        fn pack(packed: &mut Packed, rays: (&[Vec3], &[Vec3], &[f32]), t_min: f32, start: usize) {
            packed.pack(rays, t_min, start);
        }
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(42);
        let t_min = 1e-4;
        let choices = [0.0, -1.0, t_min, f32::NAN, 2.5, f32::INFINITY, 7.0, 1e-3];
        let mut packed = Box::new(Packed::new());
        for n in [PACKED, 2 * PACKED + 13, 7, 1, 300] {
            let point = |rng: &mut Xoshiro256PlusPlus| {
                Vec3::new(
                    test_random::uniform(rng, -5.0, 5.0),
                    test_random::uniform(rng, -5.0, 5.0),
                    test_random::uniform(rng, -5.0, 5.0),
                )
            };
            let origins: Vec<Vec3> = (0..n).map(|_| point(&mut rng)).collect();
            let dirs: Vec<Vec3> = (0..n).map(|_| point(&mut rng)).collect();
            let t_maxs: Vec<f32> = (0..n)
                .map(|_| choices[rng.next_u32() as usize % choices.len()])
                .collect();
            for start in (0..n).step_by(PACKED) {
                // SAFETY: the CPU has AVX2 (checked above).
                unsafe { pack(&mut packed, (&origins, &dirs, &t_maxs), t_min, start) };
                let kept: Vec<usize> = (start..n.min(start + PACKED))
                    .filter(|&i| t_min < t_maxs[i])
                    .collect();
                assert_eq!(packed.len, kept.len(), "{n} rays, block at {start}");
                for (slot, &i) in kept.iter().enumerate() {
                    assert_eq!(packed.index[slot], i as u32);
                    assert_eq!(packed.t_max[slot].to_bits(), t_maxs[i].to_bits());
                    for axis in 0..3 {
                        assert_eq!(packed.o[axis][slot], origins[i][axis]);
                        assert_eq!(packed.d[axis][slot], dirs[i][axis]);
                    }
                }
                let past = &packed.t_max[packed.len..packed.len + MAX_LANES];
                assert!(
                    past.iter().all(|t| t.is_nan()),
                    "{n} rays, block at {start}"
                );
            }
        }
    }

    /// The thread's packed block is reused from call to call: a call whose blocks hold few
    /// rays must not read an earlier call's rays past them as live. A first call with every
    /// ray blocked (a wall in front of them all) fills the block; a second, on this thread,
    /// with three rays per block heading away from the wall and the others empty, must find
    /// none blocked, as brute force does, at each width.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn shadow_queries_read_no_stale_packed_ray() {
        let wall = [
            [
                Vec3::new(-10.0, -10.0, 1.0),
                Vec3::new(10.0, -10.0, 1.0),
                Vec3::new(10.0, 10.0, 1.0),
            ],
            [
                Vec3::new(-10.0, -10.0, 1.0),
                Vec3::new(10.0, 10.0, 1.0),
                Vec3::new(-10.0, 10.0, 1.0),
            ],
        ];
        let scene = Primitives {
            triangles: wall.to_vec(),
            ..Primitives::default()
        };
        let accel = Accel::build(&scene);
        let flat = accel.flat.as_ref().expect("a small scene is traced flat");
        let n = 2 * PACKED;
        let origins: Vec<Vec3> = (0..n)
            .map(|i| {
                Vec3::new(
                    (i % 16) as f32 * 0.5 - 4.0,
                    (i / 16) as f32 * 0.25 - 4.0,
                    0.0,
                )
            })
            .collect();
        let towards_wall = (vec![Vec3::Z; n], vec![5.0; n]);
        let live = |i: usize| i % PACKED < 3;
        let away = (
            vec![-Vec3::Z; n],
            (0..n)
                .map(|i| if live(i) { 5.0 } else { 0.0 })
                .collect::<Vec<f32>>(),
        );
        let never = |_: usize| -> bool { unreachable!("no ray walks without invisible surfaces") };
        let avx512 = std::arch::is_x86_feature_detected!("avx512f");
        for wide in [false, avx512].into_iter().take(1 + avx512 as usize) {
            for ((dirs, t_maxs), all_blocked) in [(&towards_wall, true), (&away, false)] {
                let query =
                    any_hits_query(&[], (&origins, dirs, t_maxs), Some(Invisible::default()));
                let mut occluded = vec![false; n];
                // SAFETY: as in `queries_at_width`.
                unsafe {
                    if wide {
                        flat.any_hits_avx512(&query, never, &mut occluded);
                    } else {
                        flat.any_hits_avx2(&query, never, &mut occluded);
                    }
                }
                for i in 0..n {
                    let expected = brute_force(&accel, &scene, origins[i], dirs[i], t_maxs[i]);
                    assert_eq!(occluded[i], expected.is_some(), "ray {i}, 16 lanes {wide}");
                    assert_eq!(occluded[i], all_blocked, "ray {i}, 16 lanes {wide}");
                }
            }
        }
    }

    /// On random small scenes, in groups of 8 lanes (AVX2) and 16 (AVX-512, where the CPU has
    /// it) and through `Accel`'s batch entry points: every closest hit equals the brute-force
    /// one bit for bit (ties to the lowest id; the random triangles make no parallelogram), has
    /// the tree's `t` bit for bit, and every occlusion, with and without a pass-through set (in
    /// lanes at each width and through `Accel`), is the tree's. Each scene with parallelograms
    /// added skips no hit by its coplanar runs ([`check_runs`]; a second random stream, so that
    /// the scenes and rays above stay those the tree was checked on), and runs are skipped in
    /// many groups at each width.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn flat_matches_brute_force_and_tree() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(8);
        let (mut hits, mut occluded, mut passed, mut ties, mut disk_hits) = (0, 0, 0, 0, 0);
        let mut in_lanes = 0;
        let (mut rng_runs, mut skipped) = (Xoshiro256PlusPlus::seed_from_u64(9), [0; 2]);
        for _ in 0..300 {
            let scene = scene(&mut rng);
            let runs_skipped = check_runs(&scene, &mut rng_runs);
            skipped = [0, 1].map(|width| skipped[width] + runs_skipped[width]);
            let accel = Accel::build(&scene);
            let flat = accel.flat.as_ref().expect("a small scene is traced flat");
            assert!(flat.parallelograms.is_empty());
            let (origins, dirs, t_maxs) = rays(&scene, &mut rng);
            let n = origins.len();
            let rays = (&origins[..], &dirs[..], &t_maxs[..]);
            let planes = &accel.planes;
            // Every third primitive passes shadow rays.
            let pass = PassThrough::new(accel.primitive_count(), |id| id % 3 == 1).unwrap();
            let (mut by_width, mut blocked, mut opaque) = (Vec::new(), Vec::new(), Vec::new());
            let invisible = flat.invisible(planes, &pass);
            in_lanes += invisible.is_some() as usize;
            let query = |invisible| any_hits_query(planes, rays, invisible);
            let (all_opaque, past_invisible) =
                (query(Some(Invisible::default())), query(invisible));
            let walk = |i: usize| {
                accel.blocked_past_pass_through(origins[i], dirs[i], 0.0, t_maxs[i], &pass)
            };
            let mut run = |avx512: bool| {
                let (hits, occluded, opaque_lanes) =
                    queries_at_width(flat, (&all_opaque, &past_invisible), walk, avx512);
                by_width.push(hits);
                blocked.push(occluded);
                opaque.push(opaque_lanes);
            };
            run(false);
            if std::arch::is_x86_feature_detected!("avx512f") {
                run(true);
            }
            let mut hits_batch = vec![None; n];
            accel.closest_hits(&origins, &dirs, 0.0, &t_maxs, &mut hits_batch);
            by_width.push(hits_batch);
            let mut occluded_batch = vec![false; n];
            accel.any_hits(&origins, &dirs, 0.0, &t_maxs, None, &mut occluded_batch);
            blocked.push(occluded_batch);
            let mut opaque_batch = vec![false; n];
            accel.any_hits(
                &origins,
                &dirs,
                0.0,
                &t_maxs,
                Some(&pass),
                &mut opaque_batch,
            );
            opaque.push(opaque_batch);
            for i in 0..n {
                let (o, d, t_max) = (origins[i], dirs[i], t_maxs[i]);
                let expected = brute_force(&accel, &scene, o, d, t_max);
                let tree = accel.closest_hit(o, d, 0.0, t_max);
                for got in &by_width {
                    assert_eq!(got[i], expected, "ray {i}");
                }
                assert_eq!(expected.map(|h| h.t), tree.map(|h| h.t), "ray {i}");
                ties += (expected != tree) as usize;
                hits += expected.is_some() as usize;
                let on_disk =
                    |h: Hit| matches!(accel.ids().decode(h.prim), Some(PrimitiveRef::Disk(_)));
                disk_hits += expected.is_some_and(on_disk) as usize;
                let any = accel.any_hit(o, d, 0.0, t_max);
                for b in &blocked {
                    assert_eq!(b[i], any, "ray {i}");
                }
                let any_opaque = accel.any_opaque_hit(o, d, 0.0, t_max, &pass);
                for o in &opaque {
                    assert_eq!(o[i], any_opaque, "ray {i}");
                }
                occluded += any as usize;
                passed += (any && !any_opaque) as usize;
            }
        }
        // Scenes with an invisible plane walk every blocked ray; the others decide in lanes.
        assert!(
            hits > 10_000
                && occluded > 10_000
                && passed > 1000
                && ties > 0
                && disk_hits > 500
                && (1..300).contains(&in_lanes)
                && skipped[0] > 2000
                && (skipped[1] > 1000 || !std::arch::is_x86_feature_detected!("avx512f")),
            "{hits} hits ({disk_hits} on disks), {occluded} occluded, {passed} passed through, \
             {ties} ties, {in_lanes} scenes past invisible surfaces in lanes, {skipped:?} runs \
             skipped by groups of 8 and 16"
        );
    }
}
