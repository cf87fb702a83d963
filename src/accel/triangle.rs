//! Ray/triangle intersection by Möller & Trumbore 1997, "Fast, Minimum Storage Ray/Triangle
//! Intersection" (Journal of Graphics Tools 2(1)).
//!
//! The hit point is written in barycentric form `v0 + u e1 + v e2` with `e1 = v1 - v0`,
//! `e2 = v2 - v0`; equating it with `o + t d` gives a 3×3 linear system in `(t, u, v)` that
//! Cramer's rule solves with one cross product per side: `p = d × e2`, `q = (o - v0) × e1`,
//! `det = e1 · p`, `u = (o - v0) · p / det`, `v = d · q / det`, `t = e2 · q / det`.

use glam::{Vec3, Vec3A};

use super::aabb::Aabb;

/// A triangle as the test wants it: one vertex and the two edges leaving it. The default (all
/// zero) triangle has `det = 0` for every ray, so it is never hit.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Triangle {
    v0: Vec3A,
    e1: Vec3A,
    e2: Vec3A,
}

impl Triangle {
    pub fn new(v: &[Vec3; 3]) -> Triangle {
        let v0 = Vec3A::from(v[0]);
        Triangle {
            v0,
            e1: Vec3A::from(v[1]) - v0,
            e2: Vec3A::from(v[2]) - v0,
        }
    }

    /// The bounds of a triangle that can be hit: `None` for a degenerate (zero-area) or
    /// non-finite one, which is left out of the tree.
    pub fn bounds(v: &[Vec3; 3]) -> Option<Aabb> {
        let b = Aabb::from_points(v.iter().map(|&p| Vec3A::from(p)));
        let area2 = (v[1] - v[0]).cross(v[2] - v[0]).length_squared();
        (b.is_finite() && area2 > 0.0 && area2.is_finite()).then_some(b)
    }

    /// `(t, u, v)` of the hit with `t` in `(t_min, t_max)`. Every comparison is written so that a
    /// NaN (from `det ≈ 0`) rejects the hit.
    #[inline(always)]
    pub fn intersect(&self, o: Vec3A, d: Vec3A, t_min: f32, t_max: f32) -> Option<(f32, f32, f32)> {
        let p = d.cross(self.e2);
        let det = self.e1.dot(p);
        if det == 0.0 {
            return None;
        }
        let inv_det = det.recip();
        let s = o - self.v0;
        let u = s.dot(p) * inv_det;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(self.e1);
        let v = d.dot(q) * inv_det;
        if !(v >= 0.0 && u + v <= 1.0) {
            return None;
        }
        let t = self.e2.dot(q) * inv_det;
        (t > t_min && t < t_max).then_some((t, u, v))
    }
}
