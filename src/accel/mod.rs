//! Ray queries against the scene's geometry: a BVH over triangles and transformed spheres, plus
//! unbounded planes tested outside the tree.
//!
//! Triangles and spheres go into one binned-SAH BVH ([`bvh`]); its leaves hold contiguous ranges
//! of "slots", a reordering of the primitives. Per slot we keep the original primitive id and the
//! triangle's Möller-Trumbore data (a zero, never-hit triangle in sphere slots); spheres are kept
//! in their original order, found from the slot's id. Degenerate primitives (zero-area
//! triangles, singular or zero-radius spheres, zero-normal planes, anything non-finite) are left
//! out: they can never be hit, and ids of the others stay those of [`Primitives`].
//!
//! "Model no more than a scene needs": the leaf test is a const-generic function
//! `leaf::<SPHERES, ANY>`, and `closest_hit` / `any_hit` pick `SPHERES` once per ray from whether
//! the tree holds any sphere. With `SPHERES = false` the compiled loop walks the slot's triangles
//! and contains no id lookup and no sphere branch. Planes cost one empty-slice check per ray in a
//! scene without planes.

mod aabb;
mod bvh;
mod plane;
mod primitive;
mod sphere;
mod triangle;

use std::ops::Range;
use std::time::{Duration, Instant};

use glam::{Affine3A, Vec3};
use rayon::prelude::*;

use bvh::{BuildPrim, Bvh, Ray};
use plane::Plane;
pub use primitive::{PrimitiveIds, PrimitiveRef};
use sphere::Sphere;
use triangle::Triangle;

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

/// The scene's primitives, in world space. [`PrimitiveIds`] numbers them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Primitives {
    pub triangles: Vec<[Vec3; 3]>,
    pub spheres: Vec<SphereInstance>,
    pub planes: Vec<PlaneInstance>,
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

/// The tree's shape (the root is at depth 0; an empty tree has no nodes) and how long the
/// build took.
#[derive(Clone, Debug)]
pub struct BuildStats {
    pub nodes: usize,
    pub leaves: usize,
    pub max_depth: usize,
    pub max_leaf_size: usize,
    pub build_time: Duration,
}

/// The scene's ray-query structure: built once from [`Primitives`], then shared read-only by
/// all threads.
pub struct Accel {
    bvh: Bvh,
    /// Per slot: the original primitive id.
    ids: Vec<u32>,
    /// Per slot: the triangle (a never-hit zero triangle in sphere slots).
    triangles: Vec<Triangle>,
    /// Per sphere, in original order.
    spheres: Vec<Sphere>,
    planes: Vec<Plane>,
    prim_ids: PrimitiveIds,
    /// Whether any slot holds a sphere: selects the traversal instance.
    has_spheres: bool,
    stats: BuildStats,
}

/// Rays per rayon task in the batch entry points.
const BATCH_CHUNK: usize = 256;

impl Accel {
    /// Builds the BVH over the triangles and spheres that can be hit (in parallel for large
    /// subtrees) and prepares the planes.
    pub fn build(primitives: &Primitives) -> Accel {
        let start = Instant::now();
        let prim_ids = PrimitiveIds::new(primitives);
        let triangle_prims = (primitives.triangles.iter().enumerate())
            .filter_map(|(i, t)| Some(BuildPrim::new(Triangle::bounds(t)?, prim_ids.triangle(i))));
        let sphere_prims = (primitives.spheres.iter().enumerate())
            .filter_map(|(i, s)| Some(BuildPrim::new(Sphere::bounds(s)?, prim_ids.sphere(i))));
        let mut prims: Vec<BuildPrim> = triangle_prims.chain(sphere_prims).collect();
        let (bvh, shape) = Bvh::build(&mut prims);

        let ids: Vec<u32> = prims.iter().map(|p| p.id).collect();
        let triangles = (ids.iter())
            .map(|&id| match prim_ids.decode(id) {
                Some(PrimitiveRef::Triangle(i)) => Triangle::new(&primitives.triangles[i]),
                _ => Triangle::default(),
            })
            .collect();
        let planes = (primitives.planes.iter().enumerate())
            .filter_map(|(i, p)| Plane::new(p, prim_ids.plane(i)))
            .collect();
        Accel {
            has_spheres: (ids.iter())
                .any(|&id| matches!(prim_ids.decode(id), Some(PrimitiveRef::Sphere(_)))),
            ids,
            triangles,
            spheres: primitives.spheres.iter().map(Sphere::new).collect(),
            planes,
            prim_ids,
            stats: BuildStats {
                nodes: bvh.node_count(),
                leaves: shape.leaves,
                max_depth: shape.max_depth,
                max_leaf_size: shape.max_leaf_size,
                build_time: start.elapsed(),
            },
            bvh,
        }
    }

    pub fn stats(&self) -> &BuildStats {
        &self.stats
    }

    /// The number of primitive ids: triangles + spheres + planes, degenerate ones included.
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
    /// Planes are tested first: a plane hit shrinks `t_max` before traversal, so a ground plane
    /// culls everything beneath it. The tree's hit replaces it only if strictly nearer.
    pub fn closest_hit(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Option<Hit> {
        let ray = Ray::new(origin, dir)?;
        if t_min.is_nan() || t_max.is_nan() || t_min >= t_max {
            return None;
        }
        let mut t_max = t_max;
        let mut closest = None;
        for plane in &self.planes {
            if let Some(t) = plane.intersect(ray.origin, ray.dir, t_min, t_max) {
                t_max = t;
                closest = Some(Hit {
                    t,
                    prim: plane.id,
                    u: 0.0,
                    v: 0.0,
                });
            }
        }
        let in_tree = if self.has_spheres {
            self.closest_in_tree::<true>(&ray, t_min, t_max)
        } else {
            self.closest_in_tree::<false>(&ray, t_min, t_max)
        };
        in_tree.or(closest)
    }

    /// Whether anything is hit with t in (t_min, t_max): stops at the first hit found.
    pub fn any_hit(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> bool {
        let Some(ray) = Ray::new(origin, dir) else {
            return false;
        };
        if t_min.is_nan() || t_max.is_nan() || t_min >= t_max {
            return false;
        }
        if (self.planes.iter()).any(|p| p.intersect(ray.origin, ray.dir, t_min, t_max).is_some()) {
            return true;
        }
        if self.has_spheres {
            self.any_in_tree::<true>(&ray, t_min, t_max)
        } else {
            self.any_in_tree::<false>(&ray, t_min, t_max)
        }
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
                for (((hit, &o), &d), &t_max) in hits.iter_mut().zip(origins).zip(dirs).zip(t_maxs)
                {
                    *hit = self.closest_hit(o, d, t_min, t_max);
                }
            });
    }

    /// occluded[i] = any_hit(...); entries with t_maxs[i] <= t_min are skipped and set false.
    /// Only the first `min` of the slices' lengths entries are computed.
    pub fn any_hits(
        &self,
        origins: &[Vec3],
        dirs: &[Vec3],
        t_min: f32,
        t_maxs: &[f32],
        occluded: &mut [bool],
    ) {
        (occluded.par_chunks_mut(BATCH_CHUNK))
            .zip(origins.par_chunks(BATCH_CHUNK))
            .zip(dirs.par_chunks(BATCH_CHUNK))
            .zip(t_maxs.par_chunks(BATCH_CHUNK))
            .for_each(|(((occluded, origins), dirs), t_maxs)| {
                for (((occ, &o), &d), &t_max) in
                    occluded.iter_mut().zip(origins).zip(dirs).zip(t_maxs)
                {
                    // `any_hit` returns false for an empty range (t_max <= t_min) before any work.
                    *occ = self.any_hit(o, d, t_min, t_max);
                }
            });
    }

    /// The closest hit in the tree, for a tree that holds spheres or not (`SPHERES`).
    fn closest_in_tree<const SPHERES: bool>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<Hit> {
        let mut found = None;
        self.bvh.traverse(ray, t_min, t_max, |slots, t_max| {
            self.leaf::<SPHERES, false>(ray, t_min, t_max, slots, &mut found)
        });
        found.map(|(slot, hit)| Hit {
            prim: self.ids[slot],
            ..hit
        })
    }

    /// Whether the tree holds a hit, for a tree that holds spheres or not (`SPHERES`).
    fn any_in_tree<const SPHERES: bool>(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        let mut found = None;
        self.bvh.traverse(ray, t_min, t_max, |slots, t_max| {
            self.leaf::<SPHERES, true>(ray, t_min, t_max, slots, &mut found)
        });
        found.is_some()
    }

    /// Tests the primitives in `slots`, recording a hit (and its slot) in `found` and shrinking `t_max` to it;
    /// returns whether to stop (`ANY` and a hit). With `SPHERES = false` the loop is over
    /// triangles only: no id is read and no sphere test is compiled in.
    #[inline(always)]
    fn leaf<const SPHERES: bool, const ANY: bool>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: &mut f32,
        slots: Range<usize>,
        found: &mut Option<(usize, Hit)>,
    ) -> bool {
        let (o, d) = (ray.origin, ray.dir);
        for (slot, triangle) in slots.clone().zip(&self.triangles[slots]) {
            let sphere = match self.prim_ids.decode(self.ids[slot]) {
                Some(PrimitiveRef::Sphere(i)) if SPHERES => Some(&self.spheres[i]),
                _ => None,
            };
            let hit = match sphere {
                Some(sphere) => sphere.intersect(o, d, t_min, *t_max).map(|t| (t, 0.0, 0.0)),
                None => triangle.intersect(o, d, t_min, *t_max),
            };
            if let Some((t, u, v)) = hit {
                *t_max = t;
                // The id is looked up once, after traversal, from the slot.
                *found = Some((slot, Hit { t, prim: 0, u, v }));
                if ANY {
                    return true;
                }
            }
        }
        false
    }
}
