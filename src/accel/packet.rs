//! Packets of up to eight coherent rays: one origin, directions of the same signs (a camera's
//! rays through neighbouring pixels), which walk the tree together, each node's four boxes
//! tested against all eight rays at once in AVX lanes.
//!
//! Coherence is found in the rays themselves ([`coherent_run`]), never from the camera: a run
//! of consecutive rays with the bit-identical origin and the same direction octant. Sharing the
//! origin makes a box plane's offset `bound - o` one subtraction per node for all rays (four
//! children at once); sharing the octant makes the slab's entry and exit planes the same for
//! all rays (Williams et al. 2005), so the per-ray work at a node is one product per plane and
//! child. Each lane computes exactly the operations of the single-ray box test
//! ([`super::bvh`]) on the same values, so a ray enters the same boxes either way.
//!
//! A value of [`RayPacket`] is used only inside a function compiled for AVX2 and called after
//! `is_x86_feature_detected!` found it (`Accel::closest_hits_chunk`): that makes the
//! intrinsics' `unsafe` sound. Its methods are `#[inline(always)]`, so they are compiled into
//! that function, where the intrinsics inline.

#![cfg(target_arch = "x86_64")]

use std::arch::x86_64::*;

use glam::{Vec3, Vec3A, Vec4};

use super::bvh::{Ray, SLAB_ROBUSTNESS, finite_reciprocals, slab_planes};

/// Rays per packet: the lanes of one AVX register.
pub(crate) const PACKET_SIZE: usize = 8;
/// A coherent run shorter than this is traced ray by ray: the packet's per-node work is for
/// eight rays whatever the number of live lanes.
pub(crate) const MIN_PACKET: usize = 4;

/// How many rays from the first on (at most [`PACKET_SIZE`]; or 0 if fewer than [`MIN_PACKET`]) can share a packet: each with
/// a valid range `t_min < t_max` (an empty slot ends the run), an origin bit-identical to the
/// first's, and a direction that [`Ray::new`] accepts with the first's signs (the sign bits,
/// so that `-0` and `+0` enter their slabs from the same side, as in the single-ray test).
/// Incoherent rays (the path tracer's bounces) are told apart by one comparison first: the ray
/// `MIN_PACKET - 1` on has another origin (the run is then too short to count).
pub(crate) fn coherent_run(origins: &[Vec3], dirs: &[Vec3], t_min: f32, t_maxs: &[f32]) -> usize {
    if origins.get(MIN_PACKET - 1) != Some(&origins[0]) {
        return 0;
    }
    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
    let origin = bits(origins[0]);
    let octant = Vec3A::from(dirs[0]).is_negative_bitmask();
    let rays = origins.iter().zip(dirs).zip(t_maxs).take(PACKET_SIZE);
    rays.take_while(|&((&o, &d), &t_max)| {
        t_min < t_max
            && bits(o) == origin
            && Vec3A::from(d).is_negative_bitmask() == octant
            && Ray::new(o.into(), d.into()).is_some()
    })
    .count()
}

/// Up to [`PACKET_SIZE`] rays from one origin with directions of the same signs, prepared for
/// the box tests. Unused lanes repeat the first ray.
pub(crate) struct RayPacket {
    pub origin: Vec3A,
    pub origin4: [Vec4; 3],
    pub dirs: [Vec3A; PACKET_SIZE],
    /// Per axis, the eight rays' reciprocal directions (made finite as `Slabs::new` does).
    inv_dir: [__m256; 3],
    /// Per axis, the byte offset in a node's `bounds` of the plane the rays enter the slab
    /// through, and of the one they leave through (as in `Slabs`).
    near: [usize; 3],
    far: [usize; 3],
}

impl RayPacket {
    /// The packet of `dirs` (1 to [`PACKET_SIZE`] of them, a [`coherent_run`]) from `origin`.
    #[inline(always)]
    pub fn new(origin: Vec3, dirs: &[Vec3]) -> RayPacket {
        let mut all = [Vec3A::from(dirs[0]); PACKET_SIZE];
        // Per axis, the directions lane by lane, whose reciprocals are then computed eight
        // lanes at a time.
        let mut d = [[0.0f32; PACKET_SIZE]; 3];
        for (lane, dir) in all.iter_mut().enumerate() {
            if let Some(&v) = dirs.get(lane) {
                *dir = v.into();
            }
            (d[0][lane], d[1][lane], d[2][lane]) = (dir.x, dir.y, dir.z);
        }
        let (near, far) = slab_planes(Vec3A::from(dirs[0]).is_negative_bitmask());
        let origin = Vec3A::from(origin);
        RayPacket {
            origin,
            origin4: [0, 1, 2].map(|axis| Vec4::splat(origin[axis])),
            dirs: all,
            // SAFETY: see the module's documentation.
            inv_dir: d.map(|lanes| finite_reciprocals(unsafe { _mm256_loadu_ps(lanes.as_ptr()) })),
            near,
            far,
        }
    }

    /// The direction of ray `lane` splatted over four lanes, for the leaf tests.
    #[inline(always)]
    pub fn dir4(&self, lane: usize) -> [Vec4; 3] {
        let dir = self.dirs[lane];
        [0, 1, 2].map(|axis| Vec4::splat(dir[axis]))
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
        let full = (0..camera - 8)
            .step_by(8)
            .filter(|&i| coherent_run(&origins[i..], &dirs[i..], 0.0, &t_maxs[i..]) == 8)
            .count();
        assert!(full * 8 > camera / 2, "{full} full packets");
        assert_eq!(
            coherent_run(&origins[camera..], &dirs[camera..], 0.0, &t_maxs[camera..]),
            0
        );
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
