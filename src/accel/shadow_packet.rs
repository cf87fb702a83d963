//! Packets of up to eight shadow rays (any-hit queries) that walk the tree together: rays from
//! neighbouring points towards one light, each with its own origin.
//!
//! Unlike a camera's rays ([`super::packet`]), shadow rays share no origin, but those from
//! neighbouring pixels to the same light run side by side and enter mostly the same boxes. A
//! packet fetches each node once and tests its four boxes against all its rays in AVX lanes;
//! a ray retires at its first hit, and the packet stops when all have. The rays must share
//! their direction's signs, so that a slab's entry and exit planes are the same for all
//! (Williams et al. 2005); each lane then computes exactly the single-ray box test's
//! operations (`bvh::Node::hit`) on the same values, so a ray enters the same boxes and tests
//! the same leaves either way, and as nothing shrinks an any-hit query's range before it
//! stops, finds a hit exactly when it would alone.
//!
//! A value of [`ShadowPacket`] is used only inside a function compiled for AVX2 and called
//! after `is_x86_feature_detected!` found it (`Accel::any_hits_chunk`): that makes the
//! intrinsics' `unsafe` sound. Its methods are `#[inline(always)]`, so they are compiled into
//! that function, where the intrinsics inline.

#![cfg(target_arch = "x86_64")]

use std::arch::x86_64::*;

use glam::{Vec3, Vec3A, Vec4};

use super::bvh::{SLAB_ROBUSTNESS, finite_reciprocals, slab_planes};
use super::packet::{PACKET_SIZE, RayLanes, first_lane, to_lanes};
use super::triangle_lanes::{TriangleRays, lane_mask};

/// Two rays share a packet only if their origins, and the ends of their ranges, are closer to
/// each other than this fraction of the first ray's length: the rays then run side by side
/// (neighbouring pixels' rays to one light are about 1 % of their length apart).
const SPREAD: f32 = 1.0 / 8.0;

/// Up to [`PACKET_SIZE`] rays with directions of the same signs, prepared for the box tests.
pub(crate) struct ShadowPacket {
    /// Per axis, the eight rays' origins and directions lane by lane, for the leaf tests.
    origin_lanes: [[f32; PACKET_SIZE]; 3],
    dir_lanes: [[f32; PACKET_SIZE]; 3],
    /// The eight rays' range ends.
    pub t_max: [f32; PACKET_SIZE],
    /// Per axis, the eight rays' origins, directions and reciprocal directions (made finite
    /// as `bvh::Slabs::new` does).
    origin: [__m256; 3],
    dir: [__m256; 3],
    inv_dir: [__m256; 3],
    /// Per axis, the byte offset in a node's `bounds` of the plane the rays enter the slab
    /// through, and of the one they leave through (as in `bvh::Slabs`).
    near: [usize; 3],
    far: [usize; 3],
}

impl ShadowPacket {
    /// The rays `first, first + stride, first + 2 stride, …` below `n` (at most
    /// [`PACKET_SIZE`]) of `origins`, `dirs` and `t_maxs` (as [`RayLanes::gather`] takes
    /// them), and how many of them from the first on can share a packet with it (0 if the
    /// first cannot): each [`RayLanes::traceable_with_first`], with finite ends, and origin and
    /// end within [`SPREAD`] of the first's, each test the scalar one's operations lane by
    /// lane. The lanes past that run hold other rays: the traversal masks them off.
    #[inline(always)]
    pub fn gather(
        rays: (&[Vec3], &[Vec3], &[f32]),
        t_min: f32,
        first: usize,
        stride: usize,
        n: usize,
    ) -> (ShadowPacket, usize) {
        let lanes = RayLanes::gather(rays, first, stride, n);
        let (o, d, t_max) = (lanes.origin, lanes.dir, lanes.t_max);
        // SAFETY: see the module's documentation.
        let joins = unsafe {
            let (add, sub, mul) = (_mm256_add_ps, _mm256_sub_ps, _mm256_mul_ps);
            let length_squared =
                |v: [__m256; 3]| add(add(mul(v[0], v[0]), mul(v[1], v[1])), mul(v[2], v[2]));
            let end: [__m256; 3] = std::array::from_fn(|axis| add(o[axis], mul(d[axis], t_max)));
            // NaN for an infinite range: such a ray shares no packet.
            let limit = mul(
                first_lane(length_squared(std::array::from_fn(|a| sub(end[a], o[a])))),
                _mm256_set1_ps(SPREAD * SPREAD),
            );
            let near = |p: [__m256; 3]| {
                let offset = std::array::from_fn(|axis| sub(p[axis], first_lane(p[axis])));
                _mm256_cmp_ps::<_CMP_LE_OQ>(length_squared(offset), limit)
            };
            let and = _mm256_and_ps;
            and(lanes.traceable_with_first(t_min), and(near(o), near(end)))
        };
        let (near, far) = slab_planes(Vec3A::from(rays.1[first]).is_negative_bitmask());
        let packet = ShadowPacket {
            origin_lanes: o.map(to_lanes),
            dir_lanes: d.map(to_lanes),
            t_max: to_lanes(t_max),
            origin: o,
            dir: d,
            inv_dir: d.map(finite_reciprocals),
            near,
            far,
        };
        (packet, lanes.run(joins))
    }

    /// The rays set in `rays`, for the leaf tests triangle by triangle.
    #[inline(always)]
    pub fn triangle_rays(&self, rays: u32, t_min: f32) -> TriangleRays {
        TriangleRays {
            origin: self.origin,
            dir: self.dir,
            // SAFETY: see the module's documentation.
            t_min: unsafe { _mm256_set1_ps(t_min) },
            active: lane_mask(rays),
        }
    }

    /// Ray `lane`'s origin and direction splatted over four lanes, for the leaf tests.
    #[inline(always)]
    pub fn splats(&self, lane: usize) -> ([Vec4; 3], [Vec4; 3]) {
        (
            [0, 1, 2].map(|axis| Vec4::splat(self.origin_lanes[axis][lane])),
            [0, 1, 2].map(|axis| Vec4::splat(self.dir_lanes[axis][lane])),
        )
    }

    /// The slab test of the node's four boxes (`bounds` as `bvh::Node` stores them) against
    /// the eight rays: for each box, the mask of rays entering it within `(t_min, t_max)`
    /// (their own `t_max` each), the single-ray test's operations lane by lane.
    #[inline(always)]
    pub fn hit_boxes(&self, bounds: &[Vec4; 6], t_min: __m256, t_max: __m256) -> [u32; 4] {
        let plane = |offset: usize| {
            // SAFETY: `offset` is one of `new`'s byte offsets of a `bounds` entry: in bounds
            // and 16-byte aligned.
            unsafe { *bounds.as_ptr().byte_add(offset) }.to_array()
        };
        let near = self.near.map(plane);
        let far = self.far.map(plane);
        std::array::from_fn(|child| {
            // SAFETY: see the module's documentation.
            unsafe {
                // `(bound - o) * inv_dir`, as the single ray computes it.
                let t = |planes: &[[f32; 4]; 3], axis: usize| {
                    let offset =
                        _mm256_sub_ps(_mm256_set1_ps(planes[axis][child]), self.origin[axis]);
                    _mm256_mul_ps(offset, self.inv_dir[axis])
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
                _mm256_movemask_ps(inside) as u32
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use glam::{Affine3A, Quat, Vec3};

    use super::super::SphereInstance;
    use super::super::packet::tests::bumpy_sheet;
    use super::super::{Accel, DiskInstance, PassThrough, PlaneInstance, Primitives};
    use super::*;

    /// A bumpy sheet of triangles on z ≈ 0 with spheres and a checkerboard roof above it
    /// (enough primitives for the tree), and `disks` and `planes`.
    fn scene(disks: Vec<DiskInstance>, planes: Vec<PlaneInstance>) -> Accel {
        let triangles = bumpy_sheet(Some(1.2));
        let spheres = (0..12)
            .map(|i| SphereInstance {
                object_to_world: Affine3A::from_translation(Vec3::new(
                    i as f32 * 0.35 - 2.0,
                    0.3 * i as f32 - 1.6,
                    0.6,
                )),
                radius: 0.2,
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

    /// A shadow batch as the ray caster makes it, two rays per path: from points of the
    /// sheet in pixel order (on its vertices and edges, and between) to two point lights,
    /// with empty slots between; then random rays, every one its own origin and length.
    fn batch() -> (Vec<Vec3>, Vec<Vec3>, Vec<f32>) {
        let lights = [Vec3::new(1.3, -0.7, 2.5), Vec3::new(-2.2, 1.1, 1.4)];
        let (mut origins, mut dirs, mut t_maxs) = (Vec::new(), Vec::new(), Vec::new());
        for y in 0..48 {
            for x in 0..64 {
                let point = Vec3::new(x as f32 * 0.02 - 0.6, y as f32 * 0.02 - 0.5, 0.26);
                for (l, light) in lights.iter().enumerate() {
                    let to_light = *light - point;
                    let distance = to_light.length();
                    origins.push(point);
                    dirs.push(to_light / distance);
                    t_maxs.push(match (x + 3 * y + l) % 61 {
                        0 => 0.0,
                        _ => distance * (1.0 - 1e-3),
                    });
                }
            }
        }
        let point = |i: u32| {
            let h =
                |k: u32| (i.wrapping_mul(2_654_435_761).rotate_left(k) >> 8) as f32 / 16_777_216.0;
            Vec3::new(h(0), h(7), h(13)) * 4.0 - 2.0
        };
        for i in 0..2000 {
            origins.push(point(i) + Vec3::Z * 0.5);
            dirs.push(point(i + 5000) - point(i));
            t_maxs.push(if i % 3 == 0 { f32::INFINITY } else { 0.8 });
        }
        (origins, dirs, t_maxs)
    }

    /// The strided batch query (packets where the rays are coherent) gives each ray the
    /// single query's answer, with and without pass-through surfaces, on scenes with and
    /// without a disk and a plane beside the tree; most of the lights' rays form full packets,
    /// and both answers occur often.
    #[test]
    fn shadow_packets_match_single_queries() {
        let disk = DiskInstance {
            object_to_world: Affine3A::from_scale_rotation_translation(
                Vec3::splat(0.4),
                Quat::IDENTITY,
                Vec3::new(0.3, 0.2, 1.0),
            ),
        };
        let plane = PlaneInstance {
            point: Vec3::new(1.5, 0.0, 0.0),
            normal: Vec3::new(1.0, 0.2, -0.3),
        };
        let (origins, dirs, t_maxs) = batch();
        let lit = 48 * 64 * 2;
        /// The coherent run from ray `first` on, where the CPU has AVX2.
        #[target_feature(enable = "avx2")]
        fn run(rays: (&[Vec3], &[Vec3], &[f32]), first: usize, stride: usize, n: usize) -> usize {
            ShadowPacket::gather(rays, 0.0, first, stride, n).1
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            let rays = (&origins[..], &dirs[..], &t_maxs[..]);
            // SAFETY: the CPU has AVX2.
            let full = (0..2)
                .flat_map(|first| (first..lit).step_by(16))
                .filter(|&i| unsafe { run(rays, i, 2, lit) } == PACKET_SIZE)
                .count();
            assert!(full * PACKET_SIZE > lit / 2, "{full} full packets");
            let random = (&origins[lit..], &dirs[lit..], &t_maxs[lit..]);
            // SAFETY: as above.
            let runs = (0..2000).filter(|&i| unsafe { run(random, i, 1, 2000) } >= 2);
            assert_eq!(runs.count(), 0);
        }
        for accel in [
            scene(Vec::new(), Vec::new()),
            scene(vec![disk], vec![plane]),
        ] {
            let pass = PassThrough::new(accel.primitive_count(), |id| id % 5 == 0).unwrap();
            for pass_through in [None, Some(&pass)] {
                let mut occluded = vec![false; origins.len()];
                accel.any_hits_strided(
                    &origins,
                    &dirs,
                    0.0,
                    &t_maxs,
                    Some(2),
                    pass_through,
                    &mut occluded,
                );
                let mut blocked = 0;
                for i in 0..origins.len() {
                    let (o, d, t_max) = (origins[i], dirs[i], t_maxs[i]);
                    let single = match pass_through {
                        None => accel.any_hit(o, d, 0.0, t_max),
                        Some(pass) => accel.any_opaque_hit(o, d, 0.0, t_max, pass),
                    };
                    assert_eq!(occluded[i], single, "ray {i}");
                    blocked += (i < lit && single) as usize;
                }
                assert!(
                    blocked > lit / 4 && blocked < lit * 3 / 4,
                    "{blocked} of {lit}"
                );
            }
        }
    }
}
