//! The top level: a [`Bvh`] over instances of shared meshes, each mesh a [`Blas`] in its
//! object space.
//!
//! A ray reaching an instance is carried into object space by the inverse of the instance's
//! affine map. The map sends `o + t d` to `M⁻¹o + t M⁻¹d`, so the same `t` names the same point
//! in both spaces: `t_min`, `t_max` and the hit's `t` need no rescaling (the direction is not
//! renormalised).

use glam::{Affine3A, Vec3A};
use rayon::prelude::*;

use super::aabb::Aabb;
use super::blas::Blas;
use super::bvh::{BuildPrim, Bvh, Ray, Shape};
use super::{BuildStats, Hit, PrimitiveIds, Primitives};

/// A leaf payload: the run's start above `COUNT_BITS` bits of length (as in `Blas`).
const COUNT_BITS: u32 = 4;

/// An instance as traversal wants it, in leaf order.
struct Placed {
    world_to_object: Affine3A,
    mesh: u32,
    /// The id of the instance's triangle 0.
    first_id: u32,
}

pub(crate) struct Instances {
    bvh: Bvh,
    placed: Vec<Placed>,
    meshes: Vec<Blas>,
    shape: Shape,
}

impl Instances {
    /// The mesh trees (in parallel) and the tree over the instances that can be hit: those of
    /// an existing, non-empty mesh under a finite, invertible map.
    pub fn build(primitives: &Primitives, ids: &PrimitiveIds) -> Instances {
        let meshes: Vec<Blas> = (primitives.meshes.par_iter())
            .map(|mesh| Blas::build(mesh, &[], |i| i as u32, |i| i as u32))
            .collect();
        let mut prims: Vec<BuildPrim> = (primitives.instances.iter().enumerate())
            .filter_map(|(k, instance)| {
                let local = meshes.get(instance.mesh as usize)?.bvh().bounds()?;
                let m = &instance.object_to_world;
                let det = m.matrix3.determinant();
                let valid = m.is_finite() && det != 0.0 && det.is_finite();
                if !valid || !m.inverse().is_finite() {
                    return None;
                }
                let bounds = Some(local.transformed(m)).filter(Aabb::is_finite)?;
                Some(BuildPrim::new(bounds, k as u32, 0))
            })
            .collect();
        let mut placed = Vec::new();
        let (bvh, shape) = Bvh::build(&mut prims, |_, run| {
            let start = placed.len();
            placed.extend(run.iter().map(|p| {
                let k = p.id as usize;
                let instance = &primitives.instances[k];
                Placed {
                    world_to_object: instance.object_to_world.inverse(),
                    mesh: instance.mesh,
                    first_id: ids.instance_triangle(k, 0),
                }
            }));
            (start as u32) << COUNT_BITS | run.len() as u32
        });
        Instances {
            bvh,
            placed,
            meshes,
            shape,
        }
    }

    pub fn add_stats(&self, stats: &mut BuildStats) {
        let bytes = self.bvh.bytes() + std::mem::size_of_val(self.placed.as_slice());
        stats.add(&self.shape, self.bvh.node_count(), bytes);
        for mesh in &self.meshes {
            mesh.add_stats(stats);
        }
    }

    /// Whether there are no instances.
    pub fn is_empty(&self) -> bool {
        self.placed.is_empty()
    }

    /// As [`Blas::find`], over every instance the ray `origin + t dir` (valid for
    /// [`Ray::new`]) reaches. Only the test for "no instances" is inlined into the callers:
    /// the world tree's traversal, inlined beside it, keeps its registers, and its prepared
    /// ray and closest hit need not be stored in memory for this call (which prepares the ray
    /// again).
    #[inline(always)]
    pub fn find<const ANY: bool>(
        &self,
        origin: Vec3A,
        dir: Vec3A,
        t_min: f32,
        t_max: &mut f32,
        found: &mut Option<Hit>,
    ) -> bool {
        if self.placed.is_empty() {
            return false;
        }
        let (mut t, mut hit) = (*t_max, None);
        let stop = self.find_placed::<ANY>(origin, dir, t_min, &mut t, &mut hit);
        if hit.is_some() {
            (*t_max, *found) = (t, hit);
        }
        stop
    }

    #[inline(never)]
    fn find_placed<const ANY: bool>(
        &self,
        origin: Vec3A,
        dir: Vec3A,
        t_min: f32,
        t_max: &mut f32,
        found: &mut Option<Hit>,
    ) -> bool {
        let Some(ray) = Ray::new(origin, dir) else {
            return false;
        };
        self.bvh.traverse(
            &ray,
            t_min,
            t_max,
            !ANY,
            #[inline(always)]
            |payload, t_max| {
                let start = (payload >> COUNT_BITS) as usize;
                let run = start..start + (payload & ((1 << COUNT_BITS) - 1)) as usize;
                for instance in &self.placed[run] {
                    let m = &instance.world_to_object;
                    let local = Ray::new(
                        m.transform_point3a(ray.origin),
                        m.transform_vector3a(ray.dir),
                    );
                    let Some(local) = local else { continue };
                    let mut hit = None;
                    let stop = self.meshes[instance.mesh as usize]
                        .find::<ANY>(&local, t_min, t_max, &mut hit);
                    if let Some(hit) = hit {
                        *found = Some(Hit {
                            prim: instance.first_id + hit.prim,
                            ..hit
                        });
                    }
                    if stop {
                        return true;
                    }
                }
                false
            },
            |_| {},
        )
    }
}
