//! Packets of up to eight coherent rays: one origin, directions of the same signs (a camera's
//! rays through neighbouring pixels), which walk the tree together, each node's four boxes
//! tested against all eight rays at once in AVX lanes.
//!
//! Coherence is found in the rays themselves ([`coherent_packet`]), never from the camera: a
//! run of consecutive rays with the bit-identical origin and the same direction octant.
//! Sharing the origin makes a box plane's offset `bound - o` one subtraction per node for all
//! rays (four children at once); sharing the octant makes the slab's entry and exit planes the
//! same for all rays (Williams et al. 2005), so the per-ray work at a node is one product per
//! plane and child. Each lane computes exactly the operations of the single-ray box test
//! ([`super::bvh`]) on the same values, so a ray enters the same boxes either way.
//!
//! The rays are read eight at a time ([`RayLanes`], which the shadow packets share), and the
//! tests that decide which of them can share a packet are made in their lanes.
//!
//! A value of [`RayPacket`] or [`RayLanes`] is used only inside a function compiled for AVX2
//! and called after `is_x86_feature_detected!` found it (`Accel::closest_hits_chunk`,
//! `Accel::any_hits_chunk`): that makes the intrinsics' `unsafe` sound. Their methods are
//! `#[inline(always)]`, so they are compiled into that function, where the intrinsics inline.

#![cfg(target_arch = "x86_64")]

use std::arch::x86_64::*;

use glam::{Vec3, Vec3A, Vec4};

use super::bvh::{SLAB_ROBUSTNESS, finite_reciprocals, slab_planes};
use super::triangle_lanes::{TriangleRays, lane_mask};

/// Rays per packet: the lanes of one AVX register.
pub(crate) const PACKET_SIZE: usize = 8;
/// A coherent run shorter than this is traced ray by ray: the packet's per-node work is for
/// eight rays whatever the number of live lanes.
pub(crate) const MIN_PACKET: usize = 4;

/// Up to [`PACKET_SIZE`] rays of a batch in AVX lanes: the rays `first, first + stride, …`
/// below `n`, each axis of their origins and directions and their range ends in one register
/// each. Lanes past `n` hold the last ray below it again.
pub(crate) struct RayLanes {
    pub origin: [__m256; 3],
    pub dir: [__m256; 3],
    pub t_max: __m256,
    /// How many lanes hold rays below `n`.
    count: usize,
}

impl RayLanes {
    /// The rays `first, first + stride, …` below `n` (at most [`PACKET_SIZE`]) of `origins`,
    /// `dirs` and `t_maxs`, each of which holds at least `n` entries; `first < n < 2³¹ / 3`.
    #[inline(always)]
    pub fn gather(
        (origins, dirs, t_maxs): (&[Vec3], &[Vec3], &[f32]),
        first: usize,
        stride: usize,
        n: usize,
    ) -> RayLanes {
        let n = n.min(origins.len()).min(dirs.len()).min(t_maxs.len());
        assert!(first < n && n <= i32::MAX as usize / 3);
        let count = (n - first).div_ceil(stride).min(PACKET_SIZE);
        // SAFETY: see the module's documentation; the gathers read entries `first + lane
        // stride` with `lane < count`, all below `n`, each slice's length at most.
        unsafe {
            let lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
            let lane = _mm256_min_epi32(lane, _mm256_set1_epi32(count as i32 - 1));
            let index = _mm256_add_epi32(
                _mm256_set1_epi32(first as i32),
                _mm256_mullo_epi32(lane, _mm256_set1_epi32(stride as i32)),
            );
            // A `Vec3` is three `f32`s: axis `axis` of entry `i` is float `3 i + axis`.
            let float = _mm256_mullo_epi32(index, _mm256_set1_epi32(3));
            let points = |values: &[Vec3]| {
                std::array::from_fn(|axis| {
                    let base = values.as_ptr().cast::<f32>().add(axis);
                    _mm256_i32gather_ps::<4>(base, float)
                })
            };
            RayLanes {
                origin: points(origins),
                dir: points(dirs),
                t_max: _mm256_i32gather_ps::<4>(t_maxs.as_ptr(), index),
                count,
            }
        }
    }

    /// The lanes whose ray can be traced with the first's: its range `t_min < t_max` is
    /// valid, [`Ray::new`](super::bvh::Ray::new) accepts it, and its direction has the
    /// first's signs (the sign bits, so that `-0` and `+0` enter their slabs from the same
    /// side, as in the single-ray test). Each test is the scalar one's operations lane by
    /// lane.
    #[inline(always)]
    pub fn traceable_with_first(&self, t_min: f32) -> __m256 {
        let (o, d) = (&self.origin, &self.dir);
        // SAFETY: see the module's documentation.
        unsafe {
            let (add, mul, and, or) = (_mm256_add_ps, _mm256_mul_ps, _mm256_and_ps, _mm256_or_ps);
            // `Ray::new`'s test: `x · 0` is 0 for a finite `x`, NaN otherwise.
            let zero = _mm256_setzero_ps();
            let finite = |axis: usize| {
                let sum = add(mul(o[axis], zero), mul(d[axis], zero));
                _mm256_cmp_ps::<_CMP_EQ_OQ>(sum, zero)
            };
            let nonzero = |axis: usize| _mm256_cmp_ps::<_CMP_NEQ_UQ>(d[axis], zero);
            let valid = and(
                _mm256_cmp_ps::<_CMP_LT_OQ>(_mm256_set1_ps(t_min), self.t_max),
                or(or(nonzero(0), nonzero(1)), nonzero(2)),
            );
            let finite = and(and(finite(0), finite(1)), finite(2));
            // A lane's sign bits differ from the first's where `d ^ d₀` is negative.
            let flip = |axis: usize| _mm256_xor_ps(d[axis], first_lane(d[axis]));
            let flipped = or(or(flip(0), flip(1)), flip(2));
            _mm256_andnot_ps(flipped, and(valid, finite))
        }
    }

    /// How many lanes from the first on are set in `joins`, up to the first that is not.
    #[inline(always)]
    pub fn run(&self, joins: __m256) -> usize {
        // SAFETY: see the module's documentation.
        let joins = unsafe { _mm256_movemask_ps(joins) } as u32;
        (!(joins & ((1 << self.count) - 1))).trailing_zeros() as usize
    }
}

/// `v`'s first lane in all eight.
#[inline(always)]
pub(crate) fn first_lane(v: __m256) -> __m256 {
    // SAFETY: see the module's documentation.
    unsafe { _mm256_permutevar8x32_ps(v, _mm256_setzero_si256()) }
}

/// The eight lanes of `v` as an array.
#[inline(always)]
pub(crate) fn to_lanes(v: __m256) -> [f32; PACKET_SIZE] {
    let mut lanes = [0.0f32; PACKET_SIZE];
    // SAFETY: see the module's documentation; the store writes the array's eight floats.
    unsafe { _mm256_storeu_ps(lanes.as_mut_ptr(), v) };
    lanes
}

/// The packet of the first coherent rays of `origins`, `dirs` and `t_maxs` (rays from the
/// first on, at most [`PACKET_SIZE`]), and how many they are: rays that [`RayLanes::
/// traceable_with_first`] finds, with an origin bit-identical to the first's; `None` for
/// incoherent rays (the path tracer's bounces), told apart by one comparison first: the ray
/// `MIN_PACKET - 1` on has another origin (the run is then too short to count).
#[inline(always)]
pub(crate) fn coherent_packet(
    origins: &[Vec3],
    dirs: &[Vec3],
    t_min: f32,
    t_maxs: &[f32],
) -> Option<(RayPacket, usize)> {
    if origins.get(MIN_PACKET - 1) != Some(&origins[0]) {
        return None;
    }
    let rays = RayLanes::gather((origins, dirs, t_maxs), 0, 1, origins.len());
    // SAFETY: see the module's documentation.
    let same_origin = rays.origin.map(|axis| unsafe {
        let bits = _mm256_castps_si256(axis);
        let first = _mm256_castps_si256(first_lane(axis));
        _mm256_castsi256_ps(_mm256_cmpeq_epi32(bits, first))
    });
    // SAFETY: as above.
    let joins = unsafe {
        let and = _mm256_and_ps;
        let origin = and(and(same_origin[0], same_origin[1]), same_origin[2]);
        and(origin, rays.traceable_with_first(t_min))
    };
    let octant = Vec3A::from(dirs[0]).is_negative_bitmask();
    let packet = RayPacket::new(Vec3A::from(origins[0]), octant, &rays);
    Some((packet, rays.run(joins)))
}

/// Up to [`PACKET_SIZE`] rays from one origin with directions of the same signs, prepared for
/// the box tests. Lanes past the packet's run hold other rays: the traversal masks them off.
pub(crate) struct RayPacket {
    pub origin: Vec3A,
    pub origin4: [Vec4; 3],
    /// The rays' range ends.
    pub t_max: [f32; PACKET_SIZE],
    /// Per axis, the eight rays' directions, and lane by lane, for the leaf tests.
    dir: [__m256; 3],
    dir_lanes: [[f32; PACKET_SIZE]; 3],
    /// Per axis, the eight rays' reciprocal directions (made finite as `Slabs::new` does).
    inv_dir: [__m256; 3],
    /// Per axis, the byte offset in a node's `bounds` of the plane the rays enter the slab
    /// through, and of the one they leave through (as in `Slabs`).
    near: [usize; 3],
    far: [usize; 3],
}

impl RayPacket {
    /// The packet of `rays` from `origin`, whose directions have the sign bits `octant`.
    #[inline(always)]
    fn new(origin: Vec3A, octant: u32, rays: &RayLanes) -> RayPacket {
        let (near, far) = slab_planes(octant);
        RayPacket {
            origin,
            origin4: [0, 1, 2].map(|axis| Vec4::splat(origin[axis])),
            t_max: to_lanes(rays.t_max),
            dir: rays.dir,
            dir_lanes: rays.dir.map(to_lanes),
            inv_dir: rays.dir.map(finite_reciprocals),
            near,
            far,
        }
    }

    /// The rays set in `rays`, for the leaf tests triangle by triangle.
    #[inline(always)]
    pub fn triangle_rays(&self, rays: u32, t_min: f32) -> TriangleRays {
        // SAFETY: see the module's documentation.
        let splat = |x: f32| unsafe { _mm256_set1_ps(x) };
        TriangleRays {
            origin: [0, 1, 2].map(|axis| splat(self.origin[axis])),
            dir: self.dir,
            t_min: splat(t_min),
            active: lane_mask(rays),
        }
    }

    /// The direction of ray `lane` splatted over four lanes, for the leaf tests.
    #[inline(always)]
    pub fn dir4(&self, lane: usize) -> [Vec4; 3] {
        [0, 1, 2].map(|axis| Vec4::splat(self.dir_lanes[axis][lane]))
    }

    /// The slab test of the node's four boxes (`bounds` as `bvh::Node` stores them) against
    /// the eight rays: for each box, the rays' entry distances and the mask of rays entering
    /// it within `(t_min, t_max)` (their own `t_max` each), the single-ray test's operations
    /// lane by lane.
    #[inline(always)]
    pub fn hit_boxes(
        &self,
        bounds: &[Vec4; 6],
        t_min: __m256,
        t_max: __m256,
    ) -> [(__m256, u32); 4] {
        let offset = |offset: usize, axis: usize| {
            // SAFETY: `offset` is one of `new`'s byte offsets of a `bounds` entry: in bounds
            // and 16-byte aligned.
            let bound = unsafe { *bounds.as_ptr().byte_add(offset) };
            (bound - self.origin4[axis]).to_array()
        };
        let near: [_; 3] = std::array::from_fn(|axis| offset(self.near[axis], axis));
        let far: [_; 3] = std::array::from_fn(|axis| offset(self.far[axis], axis));
        std::array::from_fn(|child| {
            // SAFETY: see the module's documentation.
            unsafe {
                let t = |plane: &[[f32; 4]; 3], axis: usize| {
                    _mm256_mul_ps(_mm256_set1_ps(plane[axis][child]), self.inv_dir[axis])
                };
                let entry = _mm256_max_ps(_mm256_max_ps(t(&near, 0), t(&near, 1)), t(&near, 2));
                let exit = _mm256_mul_ps(
                    _mm256_min_ps(_mm256_min_ps(t(&far, 0), t(&far, 1)), t(&far, 2)),
                    _mm256_set1_ps(SLAB_ROBUSTNESS),
                );
                let inside = _mm256_cmp_ps::<_CMP_LE_OQ>(
                    _mm256_max_ps(entry, t_min),
                    _mm256_min_ps(exit, t_max),
                );
                (entry, _mm256_movemask_ps(inside) as u32)
            }
        })
    }
}

#[cfg(test)]
pub(super) mod tests {
    use glam::Vec3;

    use super::super::{Accel, DiskInstance, PlaneInstance, Primitives, SphereInstance};
    use super::*;

    /// A bumpy sheet of 40 x 40 quads, two triangles each, around z = 0; with `roof`, a
    /// checkerboard of quads at that height above it, which shades about half of the sheet.
    pub(in crate::accel) fn bumpy_sheet(roof: Option<f32>) -> Vec<[Vec3; 3]> {
        let height = |x: usize, y: usize| ((x * 7 + y * 13) % 5) as f32 * 0.05;
        let vertex = |x: usize, y: usize| {
            Vec3::new(x as f32 * 0.1 - 2.0, y as f32 * 0.1 - 2.0, height(x, y))
        };
        let mut triangles = Vec::new();
        for y in 0..40 {
            for x in 0..40 {
                let [a, b, c, d] =
                    [(x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1)].map(|(x, y)| vertex(x, y));
                triangles.extend([[a, b, d], [a, d, c]]);
                if let Some(z) = roof
                    && (x + y) % 2 == 0
                {
                    let [a, b, c, d] = [a, b, c, d].map(|v| Vec3::new(v.x, v.y, z));
                    triangles.extend([[a, b, d], [a, d, c]]);
                }
            }
        }
        triangles
    }

    /// A bumpy sheet of triangles with spheres above it (enough primitives for the tree), and
    /// `disks` and `planes`.
    fn scene(disks: Vec<DiskInstance>, planes: Vec<PlaneInstance>) -> Accel {
        let triangles = bumpy_sheet(None);
        let spheres = (0..10)
            .map(|i| SphereInstance {
                object_to_world: glam::Affine3A::from_translation(Vec3::new(
                    i as f32 * 0.4 - 2.0,
                    0.3 * i as f32 - 1.5,
                    0.5,
                )),
                radius: 0.15,
            })
            .collect();
        Accel::build(&Primitives {
            triangles,
            spheres,
            disks,
            planes,
            ..Default::default()
        })
    }

    /// Camera-like batches (one origin, a grid of directions in pixel order, some of them on
    /// the sheet's vertices and edges, empty slots between) and random ones (every ray its own
    /// origin) give through the batch query the hits of single queries, bit for bit but for
    /// ties (another primitive at the same `t` but for rounding, on a shared edge); the
    /// camera's rays are coherent enough to form full packets.
    #[test]
    fn packets_match_single_queries() {
        // A disk of radius 0.5 over the sheet's middle, and a tilted plane through the sheet:
        // both are tested beside the tree, and each ray of a packet must meet them first.
        let disk = DiskInstance {
            object_to_world: glam::Affine3A::from_scale_rotation_translation(
                Vec3::splat(0.5),
                glam::Quat::IDENTITY,
                Vec3::new(0.0, 0.0, 0.8),
            ),
        };
        let plane = PlaneInstance {
            point: Vec3::new(0.0, 0.0, 0.1),
            normal: Vec3::new(1.0, 0.0, 2.0),
        };
        for accel in [
            scene(Vec::new(), Vec::new()),
            scene(vec![disk], vec![plane]),
        ] {
            check_against_single_queries(&accel);
        }
    }

    fn check_against_single_queries(accel: &Accel) {
        let eye = Vec3::new(0.31, -0.23, 3.07);
        let (width, height) = (64, 48);
        let mut origins = Vec::new();
        let mut dirs = Vec::new();
        let mut t_maxs = Vec::new();
        for y in 0..height {
            for x in 0..width {
                // Through the grid's vertices (x, y multiples of 0.1 on z = 0) and between.
                let target = Vec3::new(x as f32 * 0.05 - 1.6, y as f32 * 0.05 - 1.2, 0.0);
                origins.push(eye);
                dirs.push(target - eye);
                t_maxs.push(match (x + y) % 29 {
                    0 => 0.0,
                    1 => 0.9,
                    _ => f32::INFINITY,
                });
            }
        }
        let camera = origins.len();
        let point = |i: u32| {
            let h =
                |k: u32| (i.wrapping_mul(2_654_435_761).rotate_left(k) >> 8) as f32 / 16_777_216.0;
            Vec3::new(h(0), h(7), h(13)) * 4.0 - 2.0
        };
        for i in 0..2000 {
            origins.push(point(i) + Vec3::Z);
            dirs.push(point(i + 5000) - origins[camera + i as usize]);
            t_maxs.push(f32::INFINITY);
        }
        /// The coherent run from ray `first` on, where the CPU has AVX2.
        #[target_feature(enable = "avx2")]
        fn run(origins: &[Vec3], dirs: &[Vec3], t_maxs: &[f32], first: usize) -> usize {
            let rays = (&origins[first..], &dirs[first..], 0.0, &t_maxs[first..]);
            coherent_packet(rays.0, rays.1, rays.2, rays.3).map_or(0, |(_, run)| run)
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2.
            let full = (0..camera - 8)
                .step_by(8)
                .filter(|&i| unsafe { run(&origins, &dirs, &t_maxs, i) } == 8)
                .count();
            assert!(full * 8 > camera / 2, "{full} full packets");
            // SAFETY: as above.
            assert_eq!(unsafe { run(&origins, &dirs, &t_maxs, camera) }, 0);
        }
        let mut hits = vec![None; origins.len()];
        accel.closest_hits(&origins, &dirs, 0.0, &t_maxs, &mut hits);
        let (mut found, mut ties) = (0, 0);
        for i in 0..origins.len() {
            let single = accel.find_closest(origins[i], dirs[i], 0.0, t_maxs[i]);
            // A ray through a shared vertex or edge hits two primitives at the same `t` up to
            // rounding, and a box's entry distance may round past a hit on its face: which
            // one wins depends on the order the leaves are met in, and a packet may meet
            // them in another.
            match (hits[i], single) {
                (Some(packet), Some(alone)) if packet.prim != alone.prim => {
                    let ulps = packet.t.to_bits().abs_diff(alone.t.to_bits());
                    assert!(ulps <= 64, "ray {i}: {packet:?} alone {alone:?}");
                    ties += 1;
                }
                (packet, alone) => assert_eq!(packet, alone, "ray {i}"),
            }
            found += single.is_some() as usize;
        }
        assert!(
            found > camera / 2 && ties < found / 50,
            "{found} hits, {ties} ties"
        );
    }
}
