//! The surface point behind a hit: position, normals and texture coordinates.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::geometry::{SceneGeometry, face_normal};
use crate::accel::{Hit, PrimitiveRef};
use crate::math::normalize_or;

#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    pub position: Vec3,
    /// The true surface normal, oriented as the shape is (outward for spheres, by winding for
    /// triangles): emitters emit on its side.
    pub geometric_normal: Vec3,
    /// The interpolated normal for shading, on the same side as `geometric_normal`.
    pub shading_normal: Vec3,
    pub uv: Vec2,
    pub material: u32,
    pub emitter: u32,
    /// The accel's primitive id (for [`SceneGeometry::uv_derivatives`]).
    pub prim: u32,
}

impl SceneGeometry {
    /// The surface at `hit` on the ray from `origin` along `direction` (by reference: passed by
    /// value to this out-of-line call, each was copied to the stack first).
    ///
    /// A world triangle, the common hit, is told by one comparison: a world triangle's id is
    /// its index ([`crate::accel::PrimitiveIds::triangle`]), one face normal each, so an id
    /// below `face_normals`' length is a triangle's and indexes its normal, already
    /// bounds-checked. A sphere placed by a translation alone, without uv (the next most common
    /// hit, [`crate::accel::PrimitiveIds::as_sphere`]), is answered here too; the other kinds
    /// are decoded out of line ([`SceneGeometry::other_surface_point`]), which keeps these
    /// paths free of their registers' saves and restores. Always inlined: out of line, the
    /// point went back through the stack to the caller, which read its fields at once (the
    /// shading stage 2.6 % to 3.8 % slower on the furnace, dof-sky and the Cornell box).
    #[inline(always)]
    pub fn surface_point(&self, hit: &Hit, origin: &Vec3, direction: &Vec3) -> SurfacePoint {
        let prim = hit.prim as usize;
        let Some(&ng) = self.face_normals.get(prim) else {
            let sphere = (self.ids.as_sphere(hit.prim)).and_then(|i| self.spheres.get(i));
            if let Some(sphere) = sphere
                && !sphere.uv
                && let Some(translation) = sphere.translation_only
            {
                // `sphere_surface`'s normal, to the bit.
                let position = *origin + *direction * hit.t;
                let n = sphere_normal(position + translation, sphere.radius);
                return self.point_at(hit, (n, n, Vec2::ZERO), position);
            }
            return self.other_surface_point(hit, origin, direction);
        };
        let surface = self.triangle_surface(prim, ng, hit.u, hit.v);
        self.point_at(hit, surface, *origin + *direction * hit.t)
    }

    /// The surface point of `hit` with its (geometric normal, shading normal, uv), at `position`.
    /// Inlined into each kind's branch, which then builds the point in place.
    #[inline(always)]
    fn point_at(
        &self,
        hit: &Hit,
        (geometric_normal, shading_normal, uv): (Vec3, Vec3, Vec2),
        position: Vec3,
    ) -> SurfacePoint {
        let prim = hit.prim as usize;
        SurfacePoint {
            position,
            geometric_normal,
            shading_normal,
            uv,
            material: self.material[prim],
            emitter: self.emitter[prim],
            prim: hit.prim,
        }
    }

    /// [`SceneGeometry::surface_point`] on anything but a world triangle.
    #[inline(never)]
    fn other_surface_point(&self, hit: &Hit, origin: &Vec3, direction: &Vec3) -> SurfacePoint {
        let position = *origin + *direction * hit.t;
        let kind = (self.ids.decode(hit.prim)).expect("the accel reports only its own ids");
        let surface = match kind {
            PrimitiveRef::Triangle(i) => {
                self.triangle_surface(i, self.face_normals[i], hit.u, hit.v)
            }
            PrimitiveRef::InstanceTriangle { instance, triangle } => {
                let p = (self.world_triangle(kind)).expect("instance ids name triangles");
                let mesh = self.instances[instance].mesh as usize;
                // Normals go to world space by the instance's normal map before they are
                // interpolated, as the flattened mesh's were when it was built.
                let normals = (self.mesh_normals.get(mesh)).map(|normals| {
                    let to_world = self.instance_normal_matrices[instance];
                    normals[triangle].map(|n| to_world * n)
                });
                let uvs = self.mesh_uvs.get(mesh).map(|uvs| uvs[triangle]);
                interpolate(face_normal(&p), normals, uvs, hit.u, hit.v)
            }
            PrimitiveRef::Sphere(i) => self.sphere_surface(i, position),
            PrimitiveRef::Disk(i) => self.disk_surface(i, position),
            PrimitiveRef::Plane(i) => {
                let plane = &self.planes[i];
                let n = plane.normal;
                let uv = if self.uvs {
                    let (t, b) = n.any_orthonormal_pair();
                    let local = position - plane.point;
                    Vec2::new(local.dot(t), local.dot(b))
                } else {
                    Vec2::ZERO
                };
                (n, n, uv)
            }
        };
        self.point_at(hit, surface, position)
    }

    /// World triangle `i`'s surface, `ng` its face normal.
    #[inline(always)]
    fn triangle_surface(&self, i: usize, ng: Vec3, u: f32, v: f32) -> (Vec3, Vec3, Vec2) {
        let normals = self.triangle_normals.get(i).copied();
        let uvs = self.triangle_uvs.get(i).copied();
        interpolate(ng, normals, uvs, u, v)
    }

    fn sphere_surface(&self, i: usize, position: Vec3) -> (Vec3, Vec3, Vec2) {
        let sphere = &self.spheres[i];
        let (local, n) = match sphere.translation_only {
            // The identity's products (1 x + 0 y + 0 z) give x itself, so this is the general
            // case's value to the bit (but for the sign of a zero coordinate).
            Some(translation) => {
                let local = position + translation;
                (local, sphere_normal(local, sphere.radius))
            }
            None => {
                let local = sphere.world_to_object.transform_point3(position);
                // Normals transform by the inverse transpose.
                (
                    local,
                    normalize_or(sphere.normal_to_world.mul_vec3(local), Vec3::Z),
                )
            }
        };
        if !sphere.uv {
            return (n, n, Vec2::ZERO);
        }
        let dir = normalize_or(local, Vec3::Z);
        let phi = dir.y.atan2(dir.x);
        let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
        let uv = Vec2::new(phi / (2.0 * PI), dir.z.clamp(-1.0, 1.0).acos() / PI);
        (n, n, uv)
    }

    /// A disk's normal, and its uv as Mitsuba 3's (`disk.cpp`, `compute_surface_interaction`):
    /// u = r, v = φ / 2π with φ in [0, 2π), of the object-space point.
    fn disk_surface(&self, i: usize, position: Vec3) -> (Vec3, Vec3, Vec2) {
        let disk = &self.disks[i];
        let n = disk.normal;
        if !disk.uv {
            return (n, n, Vec2::ZERO);
        }
        let local = disk.world_to_object.transform_point3(position);
        let phi = local.y.atan2(local.x);
        let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
        let r = Vec2::new(local.x, local.y).length();
        (n, n, Vec2::new(r, phi / (2.0 * PI)))
    }
}

/// The geometric normal, shading normal and uv at barycentrics (u, v) of a world-space
/// triangle `p` with (world-space) vertex `normals` and `uvs`, where it has them.
fn interpolate(
    ng: Vec3,
    normals: Option<[Vec3; 3]>,
    uvs: Option<[Vec2; 3]>,
    u: f32,
    v: f32,
) -> (Vec3, Vec3, Vec2) {
    let w = 1.0 - u - v;
    let ns = match normals {
        Some([n0, n1, n2]) => {
            let n = normalize_or(n0 * w + n1 * u + n2 * v, ng);
            // Keep the shading normal on the geometric side (pbrt-v4 §6.5.3 does the reverse:
            // here the geometric one defines emission and inside/outside).
            if n.dot(ng) < 0.0 { -n } else { n }
        }
        None => ng,
    };
    let uv = match uvs {
        Some([t0, t1, t2]) => t0 * w + t1 * u + t2 * v,
        None => Vec2::new(u, v),
    };
    (ng, ns, uv)
}

/// How far from 1 the squared length of `local / radius` may be for [`sphere_normal`] to keep it
/// as the normal: the normal's length is then within 5e-5 of 1.
const SPHERE_NORMAL_TOLERANCE: f32 = 1e-4;

/// The outward unit normal at the point `local` (relative to the centre) of a sphere of
/// `radius`: `local / radius`, whose length differs from 1 only by the hit's rounding (relative
/// `ε (|o| + t |d|) / radius`, about 1e-7 to 1e-6 in the scenes at hand), renormalised where it
/// differs by more than [`SPHERE_NORMAL_TOLERANCE`] (a small sphere far from the ray's origin),
/// as a zero or non-finite point is (to +z). Mitsuba 3 (`sphere.cpp`) normalizes `p - centre`
/// at every hit; the quotient by the radius takes a product where that takes a square root
/// and a division in a row, on each vertex's chain of dependent operations: 10 % less time in
/// the furnace's shading, where every vertex is a sphere's (`foton bench --stages`, one
/// thread). The comparison is a branch the predictor gets right, so the normalization is off
/// the chain.
#[inline(always)]
fn sphere_normal(local: Vec3, radius: f32) -> Vec3 {
    let n = local * (1.0 / radius);
    if (n.length_squared() - 1.0).abs() <= SPHERE_NORMAL_TOLERANCE {
        n
    } else {
        normalize_or(local, Vec3::Z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on spheres of radius 1e-3 to 1e3, centred up to 1e4 from the origin, each point's
    /// world position rounded to f32 as a hit's is: the normal is parallel to `local` and of
    /// unit length within the tolerance's 5e-5 (and f32 rounding), even where the rounding
    /// moved the point by most of the radius (a small sphere far out), where `local / radius`
    /// alone is far from unit length. Zero and non-finite points give +z.
    #[test]
    fn sphere_normals_are_unit_and_outward() {
        let mut worst = 0.0f32;
        let mut far_from_unit = 0;
        for radius in [1e-3f32, 0.6, 1.0, 1e3] {
            for centre in [Vec3::ZERO, Vec3::new(-1.3, 0.6, 0.6), Vec3::splat(1e4)] {
                for k in 0..200 {
                    // Directions spread over the sphere (a golden-angle spiral).
                    let z = 1.0 - (k as f32 + 0.5) / 100.0;
                    let phi = k as f32 * 2.399_963;
                    let r = (1.0 - z * z).sqrt();
                    let u = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                    let local = (centre + u * radius) - centre;
                    let n = sphere_normal(local, radius);
                    worst = worst.max((n.length() - 1.0).abs());
                    assert!(n.dot(u) > 0.0, "outward: {n} at {u}");
                    assert!(n.cross(local).length() <= 1e-6 * local.length());
                    if ((local / radius).length() - 1.0).abs() > 1e-3 {
                        far_from_unit += 1;
                    }
                }
            }
        }
        assert!(worst <= 5e-5 + 1e-6, "a normal's length is off by {worst}");
        assert!(far_from_unit > 0, "no point rounded far off its sphere");
        for local in [
            Vec3::ZERO,
            Vec3::new(f32::NAN, 1.0, 0.0),
            Vec3::splat(f32::INFINITY),
        ] {
            assert_eq!(sphere_normal(local, 1.0), Vec3::Z);
        }
    }
}
