//! Shapes as entities: geometry components, the material they wear and the light they emit.
//! At startup [`geometry::build_scene_geometry`] flattens them into the [`geometry::SceneGeometry`]
//! resource (the BVH and per-primitive shading data) that the trace and shade stages read.

pub mod geometry;
pub mod surface;
pub mod uv_derivatives;

use std::sync::Arc;

use bevy_ecs::prelude::*;
use glam::{Affine3A, Vec2, Vec3};

/// Triangles in world space.
#[derive(Component, Clone, Debug)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<Vec2>>,
    pub indices: Vec<[u32; 3]>,
}

/// A placed copy of a shared mesh (its triangles in object space): every instance of one mesh
/// holds the same `Arc`s, and the BVH builds that mesh's tree once (`accel::instances`).
#[derive(Component, Clone, Debug)]
pub struct InstancedMesh {
    pub triangles: Arc<Vec<[Vec3; 3]>>,
    /// Per-triangle vertex normals in object space, if the mesh has them.
    pub normals: Option<Arc<Vec<[Vec3; 3]>>>,
    /// Per-triangle vertex uvs, if the mesh has them and the scene samples textures.
    pub uvs: Option<Arc<Vec<[Vec2; 3]>>>,
    pub object_to_world: Affine3A,
}

/// A sphere of `radius` around its object-space origin.
#[derive(Component, Clone, Copy, Debug)]
pub struct Sphere {
    pub object_to_world: Affine3A,
    pub radius: f32,
}

/// The course's infinite plane.
#[derive(Component, Clone, Copy, Debug)]
pub struct Plane {
    pub point: Vec3,
    pub normal: Vec3,
}

/// Index into the `MaterialTable`.
#[derive(Component, Clone, Copy, Debug)]
pub struct SurfaceMaterial(pub u32);

/// An area light: the shape emits `radiance` from the side its geometric normal faces.
#[derive(Component, Clone, Copy, Debug)]
pub struct AreaEmitter {
    pub radiance: Vec3,
}
