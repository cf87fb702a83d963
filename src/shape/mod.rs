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

/// Whether every triangle's vertex normals lie within the angle of cosine `min_cos` of its
/// face normal, so that shading with face normals looks the same. Degenerate triangles count
/// as flat.
pub fn normals_follow_faces(
    positions: &[Vec3],
    normals: &[Vec3],
    indices: &[[u32; 3]],
    min_cos: f32,
) -> bool {
    indices.iter().all(|&[a, b, c]| {
        let p = |i: u32| positions[i as usize];
        let face = (p(b) - p(a)).cross(p(c) - p(a)).normalize_or_zero();
        face == Vec3::ZERO
            || [a, b, c]
                .iter()
                .all(|&i| normals[i as usize].normalize_or_zero().dot(face) >= min_cos)
    })
}

/// Vertex normals within this cosine of their faces' (an angle of 1.4e-3 radians, a few float
/// roundings of the face normal) are the faces' own: the geometry keeps none of them.
pub const FLAT_NORMAL_COS: f32 = 1.0 - 1e-6;

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

/// The unit disk in z = 0 of its object space (normal +z), placed by `object_to_world`.
#[derive(Component, Clone, Copy, Debug)]
pub struct Disk {
    pub object_to_world: Affine3A,
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_follow_faces_only_where_each_vertex_normal_is_its_face_normal() {
        // The unit square in z = 0, wound counter-clockwise about +z.
        let positions = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let indices = [[0, 1, 2], [0, 2, 3]];
        let follows =
            |normals: &[Vec3]| normals_follow_faces(&positions, normals, &indices, FLAT_NORMAL_COS);
        // Unnormalised normals along the face count as the face's.
        assert!(follows(&[Vec3::Z, Vec3::Z * 2.0, Vec3::Z, Vec3::Z]));
        // Flipped, or one tilted by 0.01 radians: not the face's.
        assert!(!follows(&[Vec3::NEG_Z; 4]));
        let tilted = Vec3::new(0.01f32.sin(), 0.0, 0.01f32.cos());
        assert!(!follows(&[Vec3::Z, Vec3::Z, tilted, Vec3::Z]));
        // A degenerate triangle has no face normal to differ from.
        let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        assert!(normals_follow_faces(
            &line,
            &[Vec3::Y; 3],
            &[[0, 1, 2]],
            FLAT_NORMAL_COS
        ));
    }
}
