//! Ray/sphere intersection for spheres placed by an arbitrary affine map (ellipsoids included).
//!
//! The ray is carried into the sphere's object space by the inverse map. An affine map sends
//! `o + t d` to `M⁻¹o + t M⁻¹d`, so the ray parameter `t` is the same in both spaces: the object
//! space root is the world space `t`, with no rescaling.

use glam::{Affine3A, Vec3A};

use super::SphereInstance;
use super::aabb::Aabb;

/// A sphere of `radius` around the origin of the object space that `world_to_object` maps to.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Sphere {
    world_to_object: Affine3A,
    radius: f32,
}

impl Sphere {
    /// Precomputes the inverse map. Only a sphere that [`Sphere::bounds`] accepts is ever
    /// tested; a singular map (never in the tree) gets the zero map instead of dividing by zero.
    pub fn new(instance: &SphereInstance) -> Sphere {
        let m = &instance.object_to_world;
        let invertible = m.matrix3.determinant() != 0.0;
        Sphere {
            world_to_object: if invertible {
                m.inverse()
            } else {
                Affine3A::ZERO
            },
            radius: instance.radius,
        }
    }

    /// World bounds: the 8 corners of the object-space box `[-r, r]³`, mapped to world space.
    /// `None` for a sphere that cannot be hit or tested safely: a radius that is not positive
    /// and finite, or a map that is not finite and invertible.
    pub fn bounds(instance: &SphereInstance) -> Option<Aabb> {
        let m = &instance.object_to_world;
        let r = instance.radius;
        let det = m.matrix3.determinant();
        let valid = r > 0.0 && r.is_finite() && m.is_finite() && det != 0.0 && det.is_finite();
        if !valid || !m.inverse().is_finite() {
            return None;
        }
        let local = Aabb {
            min: Vec3A::splat(-r),
            max: Vec3A::splat(r),
        };
        Some(local.transformed(m)).filter(Aabb::is_finite)
    }

    /// The smallest root `t` in `(t_min, t_max)` of `|o + t d|² = r²` in object space.
    ///
    /// Solved as in pbrt-v4 §6.2.2 / Ray Tracing Gems ch. 7 (Haines et al., "Precision
    /// Improvements for Ray/Sphere Intersection"): with `a = d·d`, `b = 2 o·d`, `c = o·o - r²`,
    /// the discriminant `b² - 4ac` cancels catastrophically for a small or distant sphere, so it
    /// is rewritten as `4a (r² - |o - (b / 2a) d|²) = 4a (r + l)(r - l)`, where `l` is the distance
    /// from the center to the ray's closest point; and the roots are taken as `q / a` and `c / q`
    /// with `q = -(b + sign(b) √Δ) / 2`, which never subtracts nearly equal numbers.
    #[inline(always)]
    pub fn intersect(&self, o: Vec3A, d: Vec3A, t_min: f32, t_max: f32) -> Option<f32> {
        let o = self.world_to_object.transform_point3a(o);
        let d = self.world_to_object.transform_vector3a(d);
        let a = d.length_squared();
        let b = 2.0 * o.dot(d);
        let c = o.length_squared() - self.radius * self.radius;
        let l = (o - (b / (2.0 * a)) * d).length();
        let discriminant = 4.0 * a * (self.radius + l) * (self.radius - l);
        let root = discriminant.sqrt();
        if root.is_nan() {
            // A negative discriminant: the ray misses.
            return None;
        }
        let q = if b < 0.0 {
            -0.5 * (b - root)
        } else {
            -0.5 * (b + root)
        };
        let (t0, t1) = (q / a, c / q);
        let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        // Comparisons reject NaN (e.g. `c / q` for `q = 0`).
        if near > t_min && near < t_max {
            Some(near)
        } else if far > t_min && far < t_max {
            Some(far)
        } else {
            None
        }
    }
}
