//! Primitive ids: one number space over every primitive of a [`Primitives`], encoded and
//! decoded here and nowhere else.
//!
//! The ids number the world-space triangles first, then the spheres, then the planes, then the
//! disks, then the triangles of each mesh instance in turn (instance `k` holds as many ids as its mesh has
//! triangles). Instances come last so that adding them leaves every other id unchanged.

use super::Primitives;

/// What a primitive id names: an index into the matching list of [`Primitives`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrimitiveRef {
    Triangle(usize),
    Sphere(usize),
    Plane(usize),
    Disk(usize),
    /// Triangle `triangle` of the mesh that instance `instance` places.
    InstanceTriangle {
        instance: usize,
        triangle: usize,
    },
}

/// The id layout of one [`Primitives`]: how many of each kind, and where each instance starts.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PrimitiveIds {
    triangles: u32,
    spheres: u32,
    planes: u32,
    disks: u32,
    /// First id of each instance, then one past the last id.
    instance_starts: Vec<u32>,
}

impl PrimitiveIds {
    /// The layout of `primitives`. An instance of a missing mesh holds no ids.
    pub fn new(primitives: &Primitives) -> PrimitiveIds {
        let (triangles, spheres, planes, disks) = (
            primitives.triangles.len() as u32,
            primitives.spheres.len() as u32,
            primitives.planes.len() as u32,
            primitives.disks.len() as u32,
        );
        let mut next = triangles + spheres + planes + disks;
        let mut instance_starts = vec![next];
        for instance in &primitives.instances {
            next += primitives.mesh_len(instance.mesh) as u32;
            instance_starts.push(next);
        }
        PrimitiveIds {
            triangles,
            spheres,
            planes,
            disks,
            instance_starts,
        }
    }

    /// The number of ids.
    pub fn count(&self) -> usize {
        self.instance_starts.last().map_or(0, |&end| end as usize)
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

    pub fn disk(&self, i: usize) -> u32 {
        self.triangles + self.spheres + self.planes + i as u32
    }

    pub fn instance_triangle(&self, instance: usize, triangle: usize) -> u32 {
        self.instance_starts[instance] + triangle as u32
    }

    /// The sphere `id` names, if it names one: for the hot paths that handle the commonest
    /// kinds before a full [`PrimitiveIds::decode`].
    #[inline(always)]
    pub fn as_sphere(&self, id: u32) -> Option<usize> {
        let i = id.wrapping_sub(self.triangles);
        (i < self.spheres).then_some(i as usize)
    }

    /// What `id` names; `None` past the last id.
    pub fn decode(&self, id: u32) -> Option<PrimitiveRef> {
        let spheres = self.triangles + self.spheres;
        let planes = spheres + self.planes;
        let disks = planes + self.disks;
        Some(if id < self.triangles {
            PrimitiveRef::Triangle(id as usize)
        } else if id < spheres {
            PrimitiveRef::Sphere((id - self.triangles) as usize)
        } else if id < planes {
            PrimitiveRef::Plane((id - spheres) as usize)
        } else if id < disks {
            PrimitiveRef::Disk((id - planes) as usize)
        } else {
            if id as usize >= self.count() {
                return None;
            }
            // The last instance starting at or before `id` (instances of empty meshes share
            // their start with the next one, and hold no id).
            let instance = self.instance_starts.partition_point(|&start| start <= id) - 1;
            PrimitiveRef::InstanceTriangle {
                instance,
                triangle: (id - self.instance_starts[instance]) as usize,
            }
        })
    }
}
