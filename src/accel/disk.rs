//! Disks: the unit disk `z = 0, x² + y² <= 1` of an object space placed by an affine map (an
//! ellipse under a non-uniform scale), as Mitsuba 3's `disk` (`src/shapes/disk.cpp`). A scene
//! has a few (lamps), so they live outside the trees and each ray tests each: beside the planes
//! in the tree's queries, in lanes after the spheres on the flat path (`flat::disk_lanes`).
//!
//! The ray is carried into the disk's object space by the inverse map; an affine map sends
//! `o + t d` to `M⁻¹o + t M⁻¹d`, so `t` is the same in both spaces. There the plane `z = 0`
//! is met at `t = -o_z / d_z` (Mitsuba's `ray_intersect`), and the point `o + t d` is on the
//! disk where `x² + y² <= 1`.

use glam::{Affine3A, Vec3A};

use super::DiskInstance;

/// A disk that can be hit: its world-to-object map and the primitive id it answers to.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Disk {
    world_to_object: Affine3A,
    pub id: u32,
}

impl Disk {
    /// `None` for a disk that cannot be hit or tested safely: a map that is not finite, or
    /// not invertible (a disk squashed to a segment or a point has no area).
    pub fn new(instance: &DiskInstance, id: u32) -> Option<Disk> {
        let m = &instance.object_to_world;
        let det = m.matrix3.determinant();
        let valid = m.is_finite() && det != 0.0 && det.is_finite();
        let world_to_object = m.inverse();
        (valid && world_to_object.is_finite()).then_some(Disk {
            world_to_object,
            id,
        })
    }

    /// The rows of the world-to-object map (column 3 the translation), for the flat tests.
    pub fn rows(&self) -> [[f32; 4]; 3] {
        let m = &self.world_to_object;
        let columns = [
            m.matrix3.x_axis,
            m.matrix3.y_axis,
            m.matrix3.z_axis,
            m.translation,
        ];
        [0, 1, 2].map(|i| columns.map(|column| column[i]))
    }

    /// The hit's `t` in `(t_min, t_max)`, if the ray `o + t d` meets the disk. A ray parallel
    /// to the disk's plane (`d_z = 0` in object space) gives `t` = ±∞ or NaN, which the range
    /// test rejects.
    #[inline(always)]
    pub fn intersect(&self, o: Vec3A, d: Vec3A, t_min: f32, t_max: f32) -> Option<f32> {
        let o = self.world_to_object.transform_point3a(o);
        let d = self.world_to_object.transform_vector3a(d);
        let t = (0.0 - o.z) / d.z;
        let (x, y) = (o.x + t * d.x, o.y + t * d.y);
        (t > t_min && t < t_max && x * x + y * y <= 1.0).then_some(t)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_random;
    use super::*;
    use glam::{Quat, Vec3};
    use rand_xoshiro::Xoshiro256PlusPlus;
    use rand_xoshiro::rand_core::SeedableRng;

    /// Random placed disks (rotated, non-uniformly scaled, moved) and rays aimed near them:
    /// each answer must be the brute-force geometry's, found in world space without the
    /// inverse map: the ray meets the disk's plane (through `M·0`, normal `Mx × My`) at `t`,
    /// and the point there is `M·(a, b, 0)` with `a² + b² <= 1`, `(a, b)` solved from the
    /// plane's two axes `Mx`, `My`. A wrong radius test or a wrong map fails it: the rays
    /// graze the rim on both sides.
    #[test]
    fn hits_match_world_space_geometry() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(9);
        let mut uniform = |lo: f32, hi: f32| test_random::uniform(&mut rng, lo, hi);
        let (mut hits, mut misses_near_rim, mut hits_near_rim) = (0, 0, 0);
        for _ in 0..20_000 {
            let scale = Vec3::new(uniform(0.2, 3.0), uniform(0.2, 3.0), uniform(0.2, 3.0));
            let axis = Vec3::new(uniform(-1.0, 1.0), uniform(-1.0, 1.0), 1.0).normalize();
            let centre = Vec3::new(uniform(-3.0, 3.0), uniform(-3.0, 3.0), uniform(-3.0, 3.0));
            let m = Affine3A::from_scale_rotation_translation(
                scale,
                Quat::from_axis_angle(axis, uniform(0.0, 6.0)),
                centre,
            );
            let disk = Disk::new(&DiskInstance { object_to_world: m }, 7).unwrap();
            // Aim at a point of the disk's plane within 1.2 of its centre (in object units).
            let (a, b) = (uniform(-1.2, 1.2), uniform(-1.2, 1.2));
            let target = m.transform_point3a(Vec3A::new(a, b, 0.0));
            let origin =
                target + Vec3A::new(uniform(-4.0, 4.0), uniform(-4.0, 4.0), uniform(-4.0, 4.0));
            let d = (target - origin) * uniform(0.3, 2.0);
            let t_max = uniform(0.2, 4.0);
            let got = disk.intersect(origin, d, 0.0, t_max);

            let (mx, my) = (m.matrix3.x_axis, m.matrix3.y_axis);
            let normal = mx.cross(my);
            let t = (m.translation - origin).dot(normal) / d.dot(normal);
            let p = origin + t * d - m.translation;
            // p = a Mx + b My: solve the 2x2 normal equations.
            let (xx, xy, yy) = (mx.dot(mx), mx.dot(my), my.dot(my));
            let (px, py) = (p.dot(mx), p.dot(my));
            let det = xx * yy - xy * xy;
            let (pa, pb) = ((px * yy - py * xy) / det, (py * xx - px * xy) / det);
            let r2 = pa * pa + pb * pb;
            let expected = t > 0.0 && t < t_max && r2 <= 1.0;
            // A grazing ray's `t` is ill-conditioned: its rounding error grows as 1 / cos, the
            // cosine between the ray and the normal. Within that error of the rim or of the
            // range's ends either answer is right.
            let cos = d.dot(normal).abs() / (d.length() * normal.length());
            let tolerance = 1e-5 / cos;
            let near_rim = (r2 - 1.0).abs() < 1e2 * tolerance;
            let near_end = (t - t_max).abs() < tolerance * t_max || t.abs() < tolerance;
            if !near_rim && !near_end && cos > 1e-3 {
                assert_eq!(got.is_some(), expected, "r² {r2}, t {t}");
                if let Some(got) = got {
                    assert!(
                        (got - t).abs() <= tolerance * t.abs().max(1.0),
                        "{got} vs {t}"
                    );
                }
            }
            hits += got.is_some() as usize;
            let rim = (r2 - 1.0).abs() < 0.05 && t > 0.0 && t < t_max;
            hits_near_rim += (rim && r2 < 1.0) as usize;
            misses_near_rim += (rim && r2 > 1.0) as usize;
        }
        assert!(
            hits > 5000 && hits_near_rim > 200 && misses_near_rim > 200,
            "{hits} hits, {hits_near_rim} just inside the rim, {misses_near_rim} just outside"
        );
    }

    /// A singular or non-finite map gives no disk.
    #[test]
    fn degenerate_maps_are_refused() {
        let squashed = Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0));
        let huge = Affine3A::from_translation(Vec3::new(f32::INFINITY, 0.0, 0.0));
        for m in [squashed, huge] {
            assert!(Disk::new(&DiskInstance { object_to_world: m }, 0).is_none());
        }
    }
}
