//! dp/du and dp/dv at a surface point: how the position moves with the texture coordinates,
//! which bump mapping needs (and nothing else, so they are computed only for bumped materials).

use std::f32::consts::PI;

use glam::{Vec2, Vec3, Vec3A};

use super::geometry::SceneGeometry;
use crate::accel::PrimitiveRef;

impl SceneGeometry {
    /// (dp/du, dp/dv) in world space at `position` on primitive `prim` (a primitive id of the
    /// accel), for the uvs [`SceneGeometry::surface_point`] gives there. A degenerate
    /// parameterisation gives two directions spanning the surface at unit rate.
    pub fn uv_derivatives(&self, prim: u32, position: Vec3) -> (Vec3, Vec3) {
        let Some(kind) = self.ids.decode(prim) else {
            return (Vec3::X, Vec3::Y);
        };
        match kind {
            PrimitiveRef::Triangle(i) => {
                let uvs =
                    self.triangle_uvs
                        .get(i)
                        .copied()
                        .unwrap_or([Vec2::ZERO, Vec2::X, Vec2::Y]);
                triangle_derivatives(self.triangles[i], uvs)
            }
            PrimitiveRef::InstanceTriangle { instance, triangle } => {
                let mesh = self.instances[instance].mesh as usize;
                let uvs = (self.mesh_uvs.get(mesh))
                    .map_or([Vec2::ZERO, Vec2::X, Vec2::Y], |uvs| uvs[triangle]);
                match self.world_triangle(kind) {
                    Some(p) => triangle_derivatives(p, uvs),
                    None => (Vec3::X, Vec3::Y),
                }
            }
            PrimitiveRef::Sphere(i) => {
                let sphere = &self.spheres[i];
                let local = sphere.world_to_object.transform_point3(position);
                let (dpdu, dpdv) = sphere_derivatives(local);
                let to_world = sphere.object_to_world.matrix3;
                (to_world * dpdu, to_world * dpdv)
            }
            // With u = r, v = φ / 2π of the object-space point (r cos φ, r sin φ, 0):
            // dp/du = M (cos φ, sin φ, 0) and dp/dv = 2π r M (-sin φ, cos φ, 0); at the centre
            // (r = 0) φ is undefined and the map's axes stand in.
            PrimitiveRef::Disk(i) => {
                let disk = &self.disks[i];
                let local = disk.world_to_object.transform_point3(position);
                let r = Vec2::new(local.x, local.y).length();
                let m = disk.object_to_world.matrix3;
                if r > 0.0 {
                    let (cos, sin) = (local.x / r, local.y / r);
                    let dpdu = m * Vec3A::new(cos, sin, 0.0);
                    let dpdv = m * Vec3A::new(-sin, cos, 0.0) * (2.0 * PI * r);
                    (dpdu.into(), dpdv.into())
                } else {
                    (m.x_axis.into(), m.y_axis.into())
                }
            }
            // The plane's uvs are the point's coordinates along the pair `surface_point` uses.
            PrimitiveRef::Plane(i) => self.planes[i].normal.any_orthonormal_pair(),
        }
    }
}

/// A triangle's dp/du, dp/dv from its vertices and their uvs (pbrt-v4 §6.5.3): with
/// p = p2 + (u - u2) dp/du + (v - v2) dp/dv at each vertex, the 2x2 system
/// [duv02; duv12] [dpdu; dpdv] = [dp02; dp12] solved by Cramer's rule. A degenerate uv
/// triangle falls back to an orthonormal pair in its plane.
pub fn triangle_derivatives(p: [Vec3; 3], uv: [Vec2; 3]) -> (Vec3, Vec3) {
    let (duv02, duv12) = (uv[0] - uv[2], uv[1] - uv[2]);
    let (dp02, dp12) = (p[0] - p[2], p[1] - p[2]);
    let det = duv02.x * duv12.y - duv02.y * duv12.x;
    let dpdu = (duv12.y * dp02 - duv02.y * dp12) / det;
    let dpdv = (duv02.x * dp12 - duv12.x * dp02) / det;
    if det.abs() > 1e-12 && dpdu.is_finite() && dpdv.is_finite() {
        (dpdu, dpdv)
    } else {
        (p[1] - p[0])
            .cross(p[2] - p[0])
            .normalize_or(Vec3::Z)
            .any_orthonormal_pair()
    }
}

/// dp/du, dp/dv of a sphere in object space at `p`, for `surface_point`'s u = phi / 2pi and
/// v = theta / pi (theta from +z): p = r (sin theta cos phi, sin theta sin phi, cos theta), so
/// dp/du = 2pi (-y, x, 0) and dp/dv = pi (z cos phi, z sin phi, -r sin theta) (pbrt-v4
/// §6.2.3 with theta measured from +z). At the poles dp/du vanishes: an orthonormal pair then.
pub fn sphere_derivatives(p: Vec3) -> (Vec3, Vec3) {
    let r = p.length();
    let rho = p.truncate().length();
    if rho < 1e-6 * r.max(f32::MIN_POSITIVE) {
        return (Vec3::X, Vec3::Y);
    }
    let (cos_phi, sin_phi) = (p.x / rho, p.y / rho);
    let dpdu = 2.0 * PI * Vec3::new(-p.y, p.x, 0.0);
    let dpdv = PI * Vec3::new(p.z * cos_phi, p.z * sin_phi, -rho);
    (dpdu, dpdv)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The derivatives predict the vertices from each other's uvs.
    #[test]
    fn triangle_derivatives_reproduce_the_vertices() {
        let p = [
            Vec3::new(1.0, 2.0, 0.5),
            Vec3::new(3.0, 2.5, 0.0),
            Vec3::new(0.5, 4.0, 1.0),
        ];
        let uv = [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.9, 0.3),
            Vec2::new(0.2, 0.8),
        ];
        let (dpdu, dpdv) = triangle_derivatives(p, uv);
        for i in 0..3 {
            let d = uv[i] - uv[2];
            let predicted = p[2] + d.x * dpdu + d.y * dpdv;
            assert!((predicted - p[i]).length() < 1e-5, "{i}: {predicted}");
        }
    }

    /// Against central differences of the sphere's parameterisation.
    #[test]
    fn sphere_derivatives_match_finite_differences() {
        let r = 2.0;
        let at = |u: f32, v: f32| {
            let (phi, theta) = (2.0 * PI * u, PI * v);
            r * Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            )
        };
        let (u, v, h) = (0.3, 0.4, 1e-3);
        let (dpdu, dpdv) = sphere_derivatives(at(u, v));
        let fd_u = (at(u + h, v) - at(u - h, v)) / (2.0 * h);
        let fd_v = (at(u, v + h) - at(u, v - h)) / (2.0 * h);
        assert!(
            (dpdu - fd_u).length() < 1e-2 * fd_u.length(),
            "{dpdu} {fd_u}"
        );
        assert!(
            (dpdv - fd_v).length() < 1e-2 * fd_v.length(),
            "{dpdv} {fd_v}"
        );
    }
}
