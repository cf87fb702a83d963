//! A bottom-level tree: triangles and spheres in one space (the world, or a shared mesh's
//! object space) under a four-wide [`Bvh`].
//!
//! A triangle leaf is a run of [`Triangle4`] packets, a sphere leaf a run of [`Sphere4`]
//! packets; the leaf payload says which, where the run starts and how long it is. Each packet
//! lane carries its primitive id, so a hit needs no lookup.

use std::ops::Range;

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::bvh::{BuildPrim, Bvh, LEAF_BLOCK, Ray, Shape};
use super::memory::{on_huge_pages, prefetch};
#[cfg(target_arch = "x86_64")]
use super::packet::to_lanes;
#[cfg(target_arch = "x86_64")]
use super::packet::{PACKET_SIZE, RayPacket};
#[cfg(target_arch = "x86_64")]
use super::shadow_packet::ShadowPacket;
use super::sphere::{Sphere4, sphere_bounds};
use super::triangle::{LaneHit, Triangle4, triangle_bounds};
#[cfg(target_arch = "x86_64")]
use super::triangle_lanes::TriangleRays;
use super::{BuildStats, Hit, SphereInstance};

/// Payload bit of a sphere leaf.
const SPHERE_LEAF: u32 = 1 << 30;
/// The low bits of a payload count the leaf's primitives (at most `MAX_LEAF_SIZE`), in packets
/// of [`LEAF_BLOCK`]; the bits above them up to bit 29 hold the packets' start, so a tree holds
/// at most 2²⁶ packets of each kind (2²⁸ triangles, as many spheres).
const COUNT_BITS: u32 = 4;
const MAX_START: usize = 1 << (30 - COUNT_BITS);

/// Cache lines a leaf's first packet spans at most (160 bytes from a 16-byte boundary).
const PACKET_LINES: usize = 4;

/// Build groups: a leaf holds one kind only.
const TRIANGLES: u32 = 0;
const SPHERES: u32 = 1;

pub(crate) struct Blas {
    bvh: Bvh,
    packets: Vec<Triangle4>,
    spheres: Vec<Sphere4>,
    shape: Shape,
}

impl Blas {
    /// The tree over the triangles and spheres that can be hit; triangle `i` answers to id
    /// `triangle_id(i)`, sphere `i` to `sphere_id(i)`.
    pub fn build(
        triangles: &[[Vec3; 3]],
        spheres: &[SphereInstance],
        triangle_id: impl Fn(usize) -> u32 + Sync,
        sphere_id: impl Fn(usize) -> u32,
    ) -> Blas {
        let triangle_prims = (triangles.par_iter().enumerate())
            .filter_map(|(i, t)| Some(BuildPrim::new(triangle_bounds(t)?, i as u32, TRIANGLES)));
        let sphere_prims = (spheres.par_iter().enumerate())
            .filter_map(|(i, s)| Some(BuildPrim::new(sphere_bounds(s)?, i as u32, SPHERES)));
        let mut prims: Vec<BuildPrim> = triangle_prims.chain(sphere_prims).collect();
        // The tree's walk over the leaves only numbers the packets; they are packed afterwards,
        // in parallel, from the triangle leaves' runs of `prims` in that order.
        let mut triangle_runs: Vec<Range<usize>> = Vec::new();
        let mut packet_count = 0;
        let mut sphere_list = Vec::new();
        let (bvh, shape) = Bvh::build(&mut prims, |first, run| {
            let (start, count, kind) = if run[0].group == TRIANGLES {
                let start = packet_count;
                packet_count += run.len().div_ceil(LEAF_BLOCK);
                triangle_runs.push(first..first + run.len());
                (start, run.len(), 0)
            } else {
                let start = sphere_list.len();
                sphere_list.extend(run.chunks(LEAF_BLOCK).map(|block| {
                    let lanes = block.iter().map(|p| p.id as usize);
                    Sphere4::new(lanes.map(|i| (&spheres[i], sphere_id(i))))
                }));
                (start, run.len(), SPHERE_LEAF)
            };
            assert!(start < MAX_START, "more than 2^26 leaf runs in one tree");
            kind | (start as u32) << COUNT_BITS | count as u32
        });
        let packets: Vec<Triangle4> = (triangle_runs.par_iter())
            .flat_map_iter(|run| {
                prims[run.clone()].chunks(LEAF_BLOCK).map(|block| {
                    let lanes = block.iter().map(|p| p.id as usize);
                    Triangle4::new(lanes.map(|i| (&triangles[i], triangle_id(i))))
                })
            })
            .collect();
        Blas {
            bvh,
            packets: on_huge_pages(packets),
            spheres: sphere_list,
            shape,
        }
    }

    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    pub fn add_stats(&self, stats: &mut BuildStats) {
        let bytes = self.bvh.bytes()
            + std::mem::size_of_val(self.packets.as_slice())
            + std::mem::size_of_val(self.spheres.as_slice());
        stats.add(&self.shape, self.bvh.node_count(), bytes);
    }

    /// Looks for hits with `t` in `(t_min, t_max)`: records each nearer one in `found` and
    /// shrinks `t_max` to it. With `ANY`, stops at the first and returns `true`.
    #[inline(always)]
    pub fn find<const ANY: bool>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: &mut f32,
        found: &mut Option<Hit>,
    ) -> bool {
        self.bvh.traverse(
            ray,
            t_min,
            t_max,
            !ANY,
            #[inline(always)]
            |payload, t_max| {
                self.test_leaf::<ANY>(payload, &ray.origin4, &ray.dir4, t_min, t_max, found)
            },
            #[inline(always)]
            |payload| self.prefetch_leaf(payload),
        )
    }
}

impl Blas {
    /// [`Blas::find`] (closest hits) for the rays of `packet` set in `active`, walking the
    /// tree together ([`Bvh::traverse_packet`]); ray `lane`'s range ends at `t_max[lane]` and
    /// its hit goes to `found[lane]`. Each leaf's packets are tested ray by ray, as
    /// [`Blas::find`] tests them.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub fn find_packet(
        &self,
        packet: &RayPacket,
        active: u32,
        t_min: f32,
        t_max: &mut [f32; PACKET_SIZE],
        found: &mut [Option<Hit>; PACKET_SIZE],
    ) {
        self.bvh.traverse_packet(
            packet,
            active,
            t_min,
            t_max,
            #[inline(always)]
            |payload, mut rays, t_max| {
                if payload & SPHERE_LEAF == 0 && rays.count_ones() >= TRIANGLE_BY_TRIANGLE {
                    let lanes = packet.triangle_rays(rays, t_min);
                    return self.closest_in_lanes(payload, &lanes, t_max, found);
                }
                while rays != 0 {
                    let lane = rays.trailing_zeros() as usize;
                    rays &= rays - 1;
                    let d = &packet.dir4(lane);
                    let (t_max, found) = (&mut t_max[lane], &mut found[lane]);
                    self.test_leaf::<false>(payload, &packet.origin4, d, t_min, t_max, found);
                }
            },
            #[inline(always)]
            |payload| self.prefetch_leaf(payload),
        )
    }
}

impl Blas {
    /// [`Blas::find`] as an any-hit query for the rays of `packet` set in `active`, walking
    /// the tree together ([`Bvh::traverse_shadow_packet`]); ray `lane`'s range ends at
    /// `t_max[lane]`. Each leaf's packets are tested ray by ray, as [`Blas::find`] tests them.
    /// Returns the mask of the rays that hit something.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub fn find_shadow_packet(
        &self,
        packet: &ShadowPacket,
        active: u32,
        t_min: f32,
        t_max: &[f32; PACKET_SIZE],
    ) -> u32 {
        self.bvh.traverse_shadow_packet(
            packet,
            active,
            t_min,
            t_max,
            #[inline(always)]
            |payload, mut rays| {
                if payload & SPHERE_LEAF == 0 && rays.count_ones() >= TRIANGLE_BY_TRIANGLE {
                    let lanes = packet.triangle_rays(rays, t_min);
                    return self.any_in_lanes(payload, &lanes, t_max);
                }
                let mut hits = 0;
                while rays != 0 {
                    let lane = rays.trailing_zeros() as usize;
                    rays &= rays - 1;
                    let (o, d) = &packet.splats(lane);
                    let (mut t, mut found) = (t_max[lane], None);
                    let hit = self.test_leaf::<true>(payload, o, d, t_min, &mut t, &mut found);
                    hits |= (hit as u32) << lane;
                }
                hits
            },
            #[inline(always)]
            |payload| self.prefetch_leaf(payload),
        )
    }
}

/// A triangle leaf reached by at least this many rays of a packet is tested triangle by
/// triangle against all of them at once ([`TriangleRays`]), by fewer ray by ray against four
/// triangles at once: a triangle against eight lanes costs about as much as a ray against a
/// packet of four triangles, and a leaf holds up to four triangles in most trees. (Under
/// callgrind the ray caster's render counts 540, 532, 529, 530 and 532 M instructions from 2
/// to 6 rays.)
#[cfg(target_arch = "x86_64")]
const TRIANGLE_BY_TRIANGLE: u32 = 4;

#[cfg(target_arch = "x86_64")]
impl Blas {
    /// The triangles of leaf `payload` in turn against `rays` (closest hits): a ray's hit is
    /// recorded in `found[lane]` and shrinks `t_max[lane]`, as [`Blas::test_leaf`] records
    /// it. A ray's nearest hit is the first of the leaf's triangles at its least `t`, as
    /// there, where ties go to the first packet and in it to the first lane.
    #[inline(always)]
    fn closest_in_lanes(
        &self,
        payload: u32,
        rays: &TriangleRays,
        t_max: &mut [f32; PACKET_SIZE],
        found: &mut [Option<Hit>; PACKET_SIZE],
    ) {
        use std::arch::x86_64::*;
        // SAFETY (every intrinsic below): see `triangle_lanes`' module documentation.
        let (mut t, mut u, mut v, mut id, mut hit) = unsafe {
            let zero = _mm256_setzero_ps();
            (_mm256_loadu_ps(t_max.as_ptr()), zero, zero, zero, zero)
        };
        let count = primitives(payload);
        for (first, packet) in (0..)
            .step_by(LEAF_BLOCK)
            .zip(&self.packets[packets(payload)])
        {
            for lane in 0..(count - first).min(LEAF_BLOCK) {
                if let Some(new) = rays.hit(packet, lane, t) {
                    // SAFETY: as above.
                    unsafe {
                        let ids = _mm256_castsi256_ps(_mm256_set1_epi32(packet.ids[lane] as i32));
                        t = _mm256_blendv_ps(t, new.t, new.mask);
                        u = _mm256_blendv_ps(u, new.u, new.mask);
                        v = _mm256_blendv_ps(v, new.v, new.mask);
                        id = _mm256_blendv_ps(id, ids, new.mask);
                        hit = _mm256_or_ps(hit, new.mask);
                    }
                }
            }
        }
        // SAFETY: as above.
        let mut hits = unsafe { _mm256_movemask_ps(hit) } as u32;
        if hits == 0 {
            return;
        }
        let (t, u, v, id) = (to_lanes(t), to_lanes(u), to_lanes(v), to_lanes(id));
        while hits != 0 {
            let lane = hits.trailing_zeros() as usize;
            hits &= hits - 1;
            t_max[lane] = t[lane];
            found[lane] = Some(Hit {
                t: t[lane],
                prim: id[lane].to_bits(),
                u: u[lane],
                v: v[lane],
            });
        }
    }

    /// The triangles of leaf `payload` in turn against `rays` (any hit), each with its range
    /// up to `t_max[lane]`: the mask of those that hit one of them.
    #[inline(always)]
    fn any_in_lanes(&self, payload: u32, rays: &TriangleRays, t_max: &[f32; PACKET_SIZE]) -> u32 {
        use std::arch::x86_64::*;
        // SAFETY (every intrinsic below): see `triangle_lanes`' module documentation.
        let (t_max, all) = unsafe {
            (
                _mm256_loadu_ps(t_max.as_ptr()),
                _mm256_movemask_ps(rays.active) as u32,
            )
        };
        let count = primitives(payload);
        let mut hits = 0;
        for (first, packet) in (0..)
            .step_by(LEAF_BLOCK)
            .zip(&self.packets[packets(payload)])
        {
            for lane in 0..(count - first).min(LEAF_BLOCK) {
                if let Some(new) = rays.hit(packet, lane, t_max) {
                    // SAFETY: as above.
                    hits |= unsafe { _mm256_movemask_ps(new.mask) } as u32;
                    if hits == all {
                        return hits;
                    }
                }
            }
        }
        hits
    }
}

impl Blas {
    /// Tests the leaf `payload` names (a run of triangle or sphere packets) against one ray,
    /// its origin `o` and direction `d` splat across the lanes, as [`test_run`] does.
    #[inline(always)]
    fn test_leaf<const ANY: bool>(
        &self,
        payload: u32,
        o: &[Vec4; 3],
        d: &[Vec4; 3],
        t_min: f32,
        t_max: &mut f32,
        found: &mut Option<Hit>,
    ) -> bool {
        let run = packets(payload);
        if payload & SPHERE_LEAF == 0 {
            test_run::<ANY, _>(
                &self.packets[run],
                |packet, t_max| packet.intersect::<ANY>(o, d, t_min, t_max),
                |packet, lane| packet.ids[lane],
                t_max,
                found,
            )
        } else {
            test_run::<ANY, _>(
                &self.spheres[run],
                |packet, t_max| packet.intersect::<ANY>(o, d, t_min, t_max),
                |packet, lane| packet.ids[lane],
                t_max,
                found,
            )
        }
    }

    /// Starts fetching a triangle leaf's packets while its box test finishes.
    #[inline(always)]
    fn prefetch_leaf(&self, payload: u32) {
        if payload & SPHERE_LEAF == 0 {
            let start = (payload >> COUNT_BITS) as usize;
            prefetch(self.packets.as_ptr().wrapping_add(start), PACKET_LINES);
        }
    }
}

/// The leaf `payload`'s packets: their indices in its kind's list.
#[inline(always)]
fn packets(payload: u32) -> Range<usize> {
    let start = ((payload & !SPHERE_LEAF) >> COUNT_BITS) as usize;
    start..start + primitives(payload).div_ceil(LEAF_BLOCK)
}

/// How many primitives the leaf `payload` holds.
#[inline(always)]
fn primitives(payload: u32) -> usize {
    (payload & ((1 << COUNT_BITS) - 1)) as usize
}

/// Tests a leaf's packets in turn: each hit (nearer than `t_max`, as the packet tests only
/// accept) is recorded in `found` with its lane's `id` and shrinks `t_max`. With `ANY`, stops
/// at the first and returns `true`.
#[inline(always)]
fn test_run<const ANY: bool, P>(
    packets: &[P],
    intersect: impl Fn(&P, f32) -> Option<LaneHit>,
    id: impl Fn(&P, usize) -> u32,
    t_max: &mut f32,
    found: &mut Option<Hit>,
) -> bool {
    for packet in packets {
        if let Some(hit) = intersect(packet, *t_max) {
            *t_max = hit.t;
            *found = Some(Hit {
                t: hit.t,
                prim: id(packet, hit.lane),
                u: hit.u,
                v: hit.v,
            });
            if ANY {
                return true;
            }
        }
    }
    false
}
