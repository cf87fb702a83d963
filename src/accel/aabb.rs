//! Axis-aligned bounding boxes: the bounding volume of the BVH.

use glam::{Affine3A, Vec3A};

/// The box `[min, max]`; the empty box has `min > max` so that it is the identity of `union`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Aabb {
    pub min: Vec3A,
    pub max: Vec3A,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: Vec3A::INFINITY,
        max: Vec3A::NEG_INFINITY,
    };

    /// The smallest box holding all of `points`.
    pub fn from_points(points: impl IntoIterator<Item = Vec3A>) -> Aabb {
        points.into_iter().fold(Aabb::EMPTY, Aabb::grow)
    }

    pub fn grow(self, p: Vec3A) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// The box around this one's 8 corners mapped by `m`.
    pub fn transformed(&self, m: &Affine3A) -> Aabb {
        Aabb::from_points((0..8).map(|i| {
            let corner = |bit: u32, axis: usize| {
                if i & bit == 0 {
                    self.min[axis]
                } else {
                    self.max[axis]
                }
            };
            m.transform_point3a(Vec3A::new(corner(1, 0), corner(2, 1), corner(4, 2)))
        }))
    }

    pub fn centroid(&self) -> Vec3A {
        0.5 * (self.min + self.max)
    }

    /// `max - min`, clamped to zero so the empty box has no extent.
    pub fn extent(&self) -> Vec3A {
        (self.max - self.min).max(Vec3A::ZERO)
    }

    /// Whether both corners are finite (the empty box is not).
    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    /// The surface area, the SAH's measure of the probability that a random ray hits the box
    /// (MacDonald & Booth 1990); zero for the empty box.
    pub fn surface_area(&self) -> f32 {
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }
}
