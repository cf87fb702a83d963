//! Ray queries against the scene's geometry: a two-level, four-wide BVH over triangles,
//! transformed spheres and instances of shared meshes, plus unbounded planes and a scene's few
//! disks tested outside the trees.
//!
//! The bottom level ([`Blas`]) is a [`bvh::Bvh`] over triangles and spheres in one space: its
//! triangle leaves are [`triangle::Triangle4`] packets tested four at a time, its sphere leaves
//! runs of spheres (never in the same leaf as triangles). The world-space triangles and spheres
//! form one such tree; every shared mesh another, in its object space. The top level is a
//! `Bvh` over the instances' world bounds: a ray reaching an instance is carried into the
//! mesh's object space by the inverse of its affine map, where `t` is unchanged (an affine map
//! sends `o + t d` to `M⁻¹o + t M⁻¹d`). Degenerate primitives (zero-area triangles, singular or
//! zero-radius spheres, zero-normal planes, singular instances, anything non-finite) are left
//! out: they can never be hit, and the ids of the others stay those of [`PrimitiveIds`].

mod aabb;
mod blas;
mod bvh;
mod coplanar;
mod disk;
mod flat;
mod instances;
mod lanes;
mod memory;
mod packet;
mod parallelogram;
mod pass_through;
mod plane;
mod primitive;
mod shadow_packet;
mod sphere;
#[cfg(test)]
mod test_random;
mod triangle;
mod triangle_lanes;
pub(crate) mod vex;

use std::time::{Duration, Instant};

use glam::{Affine3A, Vec3, Vec3A};
use rayon::prelude::*;

pub(crate) use aabb::Aabb;
use blas::Blas;
use bvh::{Ray, Shape};
use disk::Disk;
use flat::Flat;
use instances::Instances;
pub(crate) use parallelogram::shared_edge;
pub use pass_through::PassThrough;
use plane::Plane;
pub use primitive::{PrimitiveIds, PrimitiveRef};
pub use sphere::translation_only;

/// A sphere of `radius` around the origin of its object space, placed by `object_to_world` (any
/// affine map: a non-uniform scale makes an ellipsoid).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereInstance {
    pub object_to_world: Affine3A,
    pub radius: f32,
}

/// The course's infinite plane: the points p with (p - point) . normal = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneInstance {
    pub point: Vec3,
    pub normal: Vec3,
}

/// The unit disk `z = 0, x² + y² <= 1` of its object space (normal +z), placed by
/// `object_to_world` (any affine map: a non-uniform scale makes an ellipse).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiskInstance {
    pub object_to_world: Affine3A,
}

/// A placed copy of `meshes[mesh]`: its triangles mapped by `object_to_world` (any affine map).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshInstance {
    pub mesh: u32,
    pub object_to_world: Affine3A,
}

/// The scene's primitives: triangles, spheres, planes and disks in world space, and instances of
/// shared meshes (given in their object space). [`PrimitiveIds`] numbers them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Primitives {
    pub triangles: Vec<[Vec3; 3]>,
    pub spheres: Vec<SphereInstance>,
    pub planes: Vec<PlaneInstance>,
    pub disks: Vec<DiskInstance>,
    pub meshes: Vec<Vec<[Vec3; 3]>>,
    pub instances: Vec<MeshInstance>,
}

impl Primitives {
    /// The number of triangles of `meshes[mesh]`; 0 for a missing mesh.
    pub fn mesh_len(&self, mesh: u32) -> usize {
        self.meshes.get(mesh as usize).map_or(0, Vec::len)
    }
}

/// A ray's hit: its parameter, the original primitive id, and the surface coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub prim: u32,
    /// barycentrics of vertices 1 and 2 for a triangle; 0 otherwise
    pub u: f32,
    pub v: f32,
}

/// The trees' shape (summed over the world tree, the mesh trees and the instance tree; depth
/// of the deepest; the root is at depth 0 and an empty tree has no nodes), their memory, and
/// how long the build took.
#[derive(Clone, Debug)]
pub struct BuildStats {
    pub nodes: usize,
    pub leaves: usize,
    pub max_depth: usize,
    pub max_leaf_size: usize,
    /// Bytes of nodes, triangle packets, spheres and instances held by the accel.
    pub bytes: usize,
    pub build_time: Duration,
}

impl BuildStats {
    fn add(&mut self, shape: &Shape, nodes: usize, bytes: usize) {
        self.nodes += nodes;
        self.leaves += shape.leaves;
        self.max_depth = self.max_depth.max(shape.max_depth);
        self.max_leaf_size = self.max_leaf_size.max(shape.max_leaf_size);
        self.bytes += bytes;
    }
}

/// The scene's ray-query structure: built once from [`Primitives`], then shared read-only by
/// all threads.
pub struct Accel {
    world: Blas,
    /// The world's triangles, spheres and disks for the batch queries when they are few and
    /// there are no instances (see [`flat`]).
    flat: Option<Flat>,
    instances: Instances,
    planes: Vec<Plane>,
    disks: Vec<Disk>,
    prim_ids: PrimitiveIds,
    stats: BuildStats,
}

/// Rays per rayon task in the batch entry points.
const BATCH_CHUNK: usize = 256;

/// Keeps in `closest` the nearest hit below `t_max` of the primitives tested beside the trees
/// (planes, disks), shrinking `t_max` to it: `hit` gives a primitive's `t` within
/// (t_min, t_max) and its id, or `None`.
#[inline(always)]
fn keep_nearest<P>(
    prims: &[P],
    t_max: &mut f32,
    closest: &mut Option<Hit>,
    hit: impl Fn(&P, f32) -> Option<(f32, u32)>,
) {
    for prim in prims {
        if let Some((t, id)) = hit(prim, *t_max) {
            *t_max = t;
            *closest = Some(Hit {
                t,
                prim: id,
                u: 0.0,
                v: 0.0,
            });
        }
    }
}

impl Accel {
    /// Builds the trees (each in parallel for large subtrees, the mesh trees in parallel with
    /// each other) and prepares the planes.
    pub fn build(primitives: &Primitives) -> Accel {
        Accel::build_with_flat_limit(primitives, flat::MAX_FLAT_PRIMITIVES)
    }

    /// [`Accel::build`], with the batch queries tested flat (see [`flat`]) for up to
    /// `max_flat` triangles, spheres and disks rather than [`flat::MAX_FLAT_PRIMITIVES`]: 0 keeps
    /// the tree for every scene (benchmarks compare the two).
    pub fn build_with_flat_limit(primitives: &Primitives, max_flat: usize) -> Accel {
        let start = Instant::now();
        let prim_ids = PrimitiveIds::new(primitives);
        let (world, instances) = rayon::join(
            || {
                Blas::build(
                    &primitives.triangles,
                    &primitives.spheres,
                    |i| prim_ids.triangle(i),
                    |i| prim_ids.sphere(i),
                )
            },
            || Instances::build(primitives, &prim_ids),
        );
        let disks: Vec<Disk> = (primitives.disks.iter().enumerate())
            .filter_map(|(i, d)| Disk::new(d, prim_ids.disk(i)))
            .collect();
        let few = primitives.triangles.len() + primitives.spheres.len() + disks.len() <= max_flat;
        let flat = if few && primitives.instances.is_empty() {
            Flat::new(
                &primitives.triangles,
                &primitives.spheres,
                &disks,
                |i| prim_ids.triangle(i),
                |i| prim_ids.sphere(i),
            )
        } else {
            None
        };
        let planes = (primitives.planes.iter().enumerate())
            .filter_map(|(i, p)| Plane::new(p, prim_ids.plane(i)))
            .collect();
        let mut stats = BuildStats {
            nodes: 0,
            leaves: 0,
            max_depth: 0,
            max_leaf_size: 0,
            bytes: 0,
            build_time: Duration::ZERO,
        };
        world.add_stats(&mut stats);
        instances.add_stats(&mut stats);
        stats.build_time = start.elapsed();
        Accel {
            world,
            flat,
            instances,
            planes,
            disks,
            prim_ids,
            stats,
        }
    }

    pub fn stats(&self) -> &BuildStats {
        &self.stats
    }

    /// The number of primitive ids, degenerate primitives included.
    pub fn primitive_count(&self) -> usize {
        self.prim_ids.count()
    }

    /// How the primitive ids of the hits are numbered.
    pub fn ids(&self) -> &PrimitiveIds {
        &self.prim_ids
    }

    /// Closest hit with t in (t_min, t_max), ray p = origin + t * dir (dir need not be unit
    /// length; t is in its units).
    ///
    /// Planes and disks are tested first: their hit shrinks `t_max` before traversal, so a
    /// ground plane culls everything beneath it. A tree's hit replaces it only if strictly
    /// nearer.
    pub fn closest_hit(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Option<Hit> {
        vex::run(|| self.find_closest(origin, dir, t_min, t_max))
    }

    /// [`Accel::closest_hit`], inlined into the batch loop: a call per ray would save and
    /// restore registers and reload the trees' fields for each.
    #[inline(always)]
    fn find_closest(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Option<Hit> {
        // The range first: it is the cheaper test, and a batch's empty slots fail it.
        if t_min.is_nan() || t_max.is_nan() || t_min >= t_max {
            return None;
        }
        let ray = Ray::new(origin.into(), dir.into())?;
        let mut t_max = t_max;
        let mut closest = None;
        self.find_beside_trees(ray.origin, ray.dir, t_min, &mut t_max, &mut closest);
        self.world
            .find::<false>(&ray, t_min, &mut t_max, &mut closest);
        self.instances
            .find::<false>(ray.origin, ray.dir, t_min, &mut t_max, &mut closest);
        closest
    }

    /// The planes and disks, tested beside the trees and before them: their nearest hit below
    /// `t_max` goes into `closest` and shrinks `t_max`, so that a ground plane culls the tree
    /// beneath it.
    #[inline(always)]
    fn find_beside_trees(
        &self,
        o: Vec3A,
        d: Vec3A,
        t_min: f32,
        t_max: &mut f32,
        closest: &mut Option<Hit>,
    ) {
        keep_nearest(&self.planes, t_max, closest, |plane, t_max| {
            Some((plane.intersect(o, d, t_min, t_max)?, plane.id))
        });
        keep_nearest(&self.disks, t_max, closest, |disk, t_max| {
            Some((disk.intersect(o, d, t_min, t_max)?, disk.id))
        });
    }

    /// Whether anything is hit with t in (t_min, t_max): stops at the first hit found.
    pub fn any_hit(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> bool {
        vex::run(|| self.find_any(origin, dir, t_min, t_max))
    }

    /// [`Accel::any_hit`], inlined into the batch loop.
    #[inline(always)]
    fn find_any(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> bool {
        if t_min.is_nan() || t_max.is_nan() || t_min >= t_max {
            return false;
        }
        let Some(ray) = Ray::new(origin.into(), dir.into()) else {
            return false;
        };
        if self.any_beside_trees(ray.origin, ray.dir, t_min, t_max) {
            return true;
        }
        let (mut t_max, mut found) = (t_max, None);
        self.world.find::<true>(&ray, t_min, &mut t_max, &mut found)
            || self
                .instances
                .find::<true>(ray.origin, ray.dir, t_min, &mut t_max, &mut found)
    }

    /// Whether a plane or a disk (tested beside the trees) is hit with t in (t_min, t_max).
    #[inline(always)]
    fn any_beside_trees(&self, o: Vec3A, d: Vec3A, t_min: f32, t_max: f32) -> bool {
        (self.planes.iter()).any(|p| p.intersect(o, d, t_min, t_max).is_some())
            || (self.disks.iter()).any(|disk| disk.intersect(o, d, t_min, t_max).is_some())
    }

    /// For each i: hits[i] = closest_hit(origins[i], dirs[i], t_min, t_maxs[i]); parallel with
    /// rayon over chunks. Only the first `min` of the slices' lengths entries are computed.
    pub fn closest_hits(
        &self,
        origins: &[Vec3],
        dirs: &[Vec3],
        t_min: f32,
        t_maxs: &[f32],
        hits: &mut [Option<Hit>],
    ) {
        (hits.par_chunks_mut(BATCH_CHUNK))
            .zip(origins.par_chunks(BATCH_CHUNK))
            .zip(dirs.par_chunks(BATCH_CHUNK))
            .zip(t_maxs.par_chunks(BATCH_CHUNK))
            .for_each(|(((hits, origins), dirs), t_maxs)| {
                self.closest_hits_chunk(origins, dirs, t_min, t_maxs, hits)
            });
    }

    /// One rayon task of [`Accel::closest_hits`]: a plain loop with the query inlined (a
    /// function of its own, so that profiles name it), compiled twice (see [`vex`]).
    #[inline(never)]
    fn closest_hits_chunk(
        &self,
        origins: &[Vec3],
        dirs: &[Vec3],
        t_min: f32,
        t_maxs: &[f32],
        hits: &mut [Option<Hit>],
    ) {
        if let Some(flat) = &self.flat {
            return flat.closest_hits(&self.planes, (origins, dirs, t_maxs), t_min, hits);
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("bmi1")
            && std::arch::is_x86_feature_detected!("bmi2")
        {
            // SAFETY: the CPU has the features the function is compiled for.
            return unsafe { self.closest_hits_in_packets(origins, dirs, t_min, t_maxs, hits) };
        }
        vex::run(
            #[inline(always)]
            || {
                for (((hit, &o), &d), &t_max) in hits.iter_mut().zip(origins).zip(dirs).zip(t_maxs)
                {
                    *hit = self.find_closest(o, d, t_min, t_max);
                }
            },
        )
    }

    /// [`Accel::closest_hits_chunk`] with runs of coherent rays ([`packet::coherent_packet`]:
    /// a camera's) traced through the world tree as packets, the others one by one. Each ray
    /// of a packet meets the planes and disks first, as in [`Accel::find_closest`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2")]
    fn closest_hits_in_packets(
        &self,
        origins: &[Vec3],
        dirs: &[Vec3],
        t_min: f32,
        t_maxs: &[f32],
        hits: &mut [Option<Hit>],
    ) {
        let n = (hits.len().min(origins.len()))
            .min(dirs.len())
            .min(t_maxs.len());
        let beside_trees = !(self.planes.is_empty() && self.disks.is_empty());
        let mut i = 0;
        while i < n {
            let (packet, run) =
                match packet::coherent_packet(&origins[i..n], &dirs[i..n], t_min, &t_maxs[i..n]) {
                    Some((packet, run)) if run >= packet::MIN_PACKET => (packet, run),
                    short => {
                        let singles = short.map_or(1, |(_, run)| run.max(1));
                        for k in i..i + singles {
                            hits[k] = self.find_closest(origins[k], dirs[k], t_min, t_maxs[k]);
                        }
                        i += singles;
                        continue;
                    }
                };
            let mut t_max = packet.t_max;
            let mut found = [None; packet::PACKET_SIZE];
            if beside_trees {
                for lane in 0..run {
                    let d = dirs[i + lane].into();
                    let (t_max, found) = (&mut t_max[lane], &mut found[lane]);
                    self.find_beside_trees(packet.origin, d, t_min, t_max, found);
                }
            }
            self.world
                .find_packet(&packet, (1 << run) - 1, t_min, &mut t_max, &mut found);
            if !self.instances.is_empty() {
                for lane in 0..run {
                    let (o, d) = (packet.origin, dirs[i + lane].into());
                    (self.instances).find::<false>(o, d, t_min, &mut t_max[lane], &mut found[lane]);
                }
            }
            hits[i..i + run].copy_from_slice(&found[..run]);
            i += run;
        }
    }

    /// occluded[i] = any_hit(...), or `any_opaque_hit` past the primitives of `pass_through`;
    /// entries with t_maxs[i] <= t_min are skipped and set false. Only the first `min` of the
    /// slices' lengths entries are computed.
    pub fn any_hits(
        &self,
        origins: &[Vec3],
        dirs: &[Vec3],
        t_min: f32,
        t_maxs: &[f32],
        pass_through: Option<&PassThrough>,
        occluded: &mut [bool],
    ) {
        self.any_hits_strided(origins, dirs, t_min, t_maxs, None, pass_through, occluded);
    }

    /// [`Accel::any_hits`]; with a `stride`, for a batch whose rays `stride` apart run side by
    /// side (a shadow batch with `stride` rays per path, one per light: the rays of
    /// neighbouring paths to one light), which are traced as packets where they are coherent
    /// enough ([`shadow_packet`]). The results are the single queries' whatever the stride.
    /// No stride for incoherent batches (a path tracer's, whose neighbouring rays go to lights
    /// drawn at random): their short packets cost more than single rays.
    #[allow(clippy::too_many_arguments)]
    pub fn any_hits_strided(
        &self,
        origins: &[Vec3],
        dirs: &[Vec3],
        t_min: f32,
        t_maxs: &[f32],
        stride: Option<usize>,
        pass_through: Option<&PassThrough>,
        occluded: &mut [bool],
    ) {
        let stride = stride.map(|stride| stride.max(1));
        // A chunk holds whole groups of `stride` rays, so that each of its runs is one light's.
        let chunk = BATCH_CHUNK * stride.unwrap_or(1);
        (occluded.par_chunks_mut(chunk))
            .zip(origins.par_chunks(chunk))
            .zip(dirs.par_chunks(chunk))
            .zip(t_maxs.par_chunks(chunk))
            .for_each(|(((occluded, origins), dirs), t_maxs)| {
                let rays = (origins, dirs, t_maxs);
                self.any_hits_chunk(rays, t_min, stride, pass_through, occluded)
            });
    }

    /// One rayon task of [`Accel::any_hits_strided`], as [`Accel::closest_hits_chunk`].
    #[inline(never)]
    fn any_hits_chunk(
        &self,
        (origins, dirs, t_maxs): (&[Vec3], &[Vec3], &[f32]),
        t_min: f32,
        stride: Option<usize>,
        pass_through: Option<&PassThrough>,
        occluded: &mut [bool],
    ) {
        if let Some(flat) = &self.flat {
            let walk = |i: usize| {
                let pass = pass_through.expect("only rays past invisible surfaces walk");
                self.blocked_past_pass_through(origins[i], dirs[i], t_min, t_maxs[i], pass)
            };
            let rays = (origins, dirs, t_maxs);
            return flat.any_hits(&self.planes, rays, t_min, pass_through, walk, occluded);
        }
        #[cfg(target_arch = "x86_64")]
        if let Some(stride) = stride
            && std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("bmi1")
            && std::arch::is_x86_feature_detected!("bmi2")
        {
            let rays = (origins, dirs, t_maxs);
            // SAFETY: the CPU has the features the function is compiled for.
            return unsafe {
                self.any_hits_in_packets(rays, t_min, stride, pass_through, occluded)
            };
        }
        vex::run(
            #[inline(always)]
            || {
                for (((occ, &o), &d), &t_max) in
                    occluded.iter_mut().zip(origins).zip(dirs).zip(t_maxs)
                {
                    // `find_any` returns false for an empty range (t_max <= t_min) before any
                    // work.
                    *occ = match pass_through {
                        None => self.find_any(o, d, t_min, t_max),
                        Some(pass) => self.find_any_opaque(o, d, t_min, t_max, pass),
                    };
                }
            },
        )
    }

    /// [`Accel::any_hits_chunk`] with each of the `stride` interleaved sequences of rays cut
    /// into runs of coherent rays ([`shadow_packet::ShadowPacket::gather`]) traced through the
    /// world tree as packets, the others one by one. Each ray of a packet meets the planes and
    /// disks first and the instances last, as in [`Accel::find_any`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2")]
    fn any_hits_in_packets(
        &self,
        (origins, dirs, t_maxs): (&[Vec3], &[Vec3], &[f32]),
        t_min: f32,
        stride: usize,
        pass_through: Option<&PassThrough>,
        occluded: &mut [bool],
    ) {
        let n = (occluded.len().min(origins.len()))
            .min(dirs.len())
            .min(t_maxs.len());
        let single = |k: usize| match pass_through {
            None => self.find_any(origins[k], dirs[k], t_min, t_maxs[k]),
            Some(pass) => self.find_any_opaque(origins[k], dirs[k], t_min, t_maxs[k], pass),
        };
        let beside_trees = !(self.planes.is_empty() && self.disks.is_empty());
        for first in 0..stride.min(n) {
            let mut i = first;
            while i < n {
                // An empty slot (a point the light does not reach: `t_max <= t_min`) has no
                // ray to trace.
                if t_min.partial_cmp(&t_maxs[i]) != Some(std::cmp::Ordering::Less) {
                    occluded[i] = false;
                    i += stride;
                    continue;
                }
                let rays = (origins, dirs, t_maxs);
                let (packet, run) = shadow_packet::ShadowPacket::gather(rays, t_min, i, stride, n);
                if run < packet::MIN_PACKET {
                    for lane in 0..run.max(1) {
                        let k = i + lane * stride;
                        occluded[k] = single(k);
                    }
                    i += run.max(1) * stride;
                    continue;
                }
                let lanes = (0..run).map(|lane| i + lane * stride);
                let mut hit = 0;
                if beside_trees {
                    for (lane, k) in lanes.clone().enumerate() {
                        let (o, d) = (origins[k].into(), dirs[k].into());
                        hit |= (self.any_beside_trees(o, d, t_min, t_maxs[k]) as u32) << lane;
                    }
                }
                let active = ((1 << run) - 1) & !hit;
                if active != 0 {
                    hit |= (self.world).find_shadow_packet(&packet, active, t_min, &packet.t_max);
                }
                if !self.instances.is_empty() {
                    for (lane, k) in lanes.clone().enumerate() {
                        let (o, d) = (origins[k].into(), dirs[k].into());
                        let t_max = &mut { t_maxs[k] };
                        let blocked = hit & (1 << lane) != 0
                            || (self.instances).find::<true>(o, d, t_min, t_max, &mut None);
                        hit |= (blocked as u32) << lane;
                    }
                }
                for (lane, k) in lanes.enumerate() {
                    let blocked = hit & (1 << lane) != 0;
                    occluded[k] = match pass_through {
                        Some(pass) if blocked => self
                            .blocked_past_pass_through(origins[k], dirs[k], t_min, t_maxs[k], pass),
                        _ => blocked,
                    };
                }
                i += run * stride;
            }
        }
    }
}
