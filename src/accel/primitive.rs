//! Primitive ids: one number space over every primitive of a [`Primitives`], encoded and
//! decoded here and nowhere else.
//!
//! The ids number the triangles first, then the spheres, then the planes.

use super::Primitives;

/// What a primitive id names: an index into the matching list of [`Primitives`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrimitiveRef {
    Triangle(usize),
    Sphere(usize),
    Plane(usize),
}

/// The id layout of one [`Primitives`]: how many of each kind.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PrimitiveIds {
    triangles: u32,
    spheres: u32,
    planes: u32,
}

impl PrimitiveIds {
    /// The layout of `primitives`.
    pub fn new(primitives: &Primitives) -> PrimitiveIds {
        PrimitiveIds {
            triangles: primitives.triangles.len() as u32,
            spheres: primitives.spheres.len() as u32,
            planes: primitives.planes.len() as u32,
        }
    }

    /// The number of ids.
    pub fn count(&self) -> usize {
        (self.triangles + self.spheres + self.planes) as usize
    }

    pub fn triangle(&self, i: usize) -> u32 {
        i as u32
    }

    pub fn sphere(&self, i: usize) -> u32 {
        self.triangles + i as u32
    }

    pub fn plane(&self, i: usize) -> u32 {
        self.triangles + self.spheres + i as u32
    }

    /// What `id` names; `None` past the last id.
    pub fn decode(&self, id: u32) -> Option<PrimitiveRef> {
        let spheres = self.triangles + self.spheres;
        let planes = spheres + self.planes;
        Some(if id < self.triangles {
            PrimitiveRef::Triangle(id as usize)
        } else if id < spheres {
            PrimitiveRef::Sphere((id - self.triangles) as usize)
        } else if id < planes {
            PrimitiveRef::Plane((id - spheres) as usize)
        } else {
            return None;
        })
    }
}
