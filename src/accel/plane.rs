//! Infinite planes: unbounded, so they live outside the BVH and are tested one by one.

use glam::Vec3A;

use super::PlaneInstance;

/// The points `p` with `(p - point) · normal = 0`, and the primitive id it answers to.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Plane {
    point: Vec3A,
    normal: Vec3A,
    pub id: u32,
}

impl Plane {
    /// `None` for a plane that is not finite or has a zero normal (it defines no plane).
    pub fn new(instance: &PlaneInstance, id: u32) -> Option<Plane> {
        let valid = instance.point.is_finite()
            && instance.normal.is_finite()
            && instance.normal.length_squared() > 0.0;
        valid.then_some(Plane {
            point: instance.point.into(),
            normal: instance.normal.into(),
            id,
        })
    }

    /// Substituting `o + t d` into the plane equation: `t = (point - o) · n / (d · n)`. A ray
    /// parallel to the plane (`d · n = 0`) gives ±∞ or NaN, both rejected by the range test.
    #[inline(always)]
    pub fn intersect(&self, o: Vec3A, d: Vec3A, t_min: f32, t_max: f32) -> Option<f32> {
        let t = (self.point - o).dot(self.normal) / d.dot(self.normal);
        (t > t_min && t < t_max).then_some(t)
    }
}
