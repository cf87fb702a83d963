//! The flattened scene: every primitive of every shape entity, the BVH over them, and what the
//! shade stage needs per primitive. Only what the scene has is stored: no uv arrays without
//! textures, no shading normals where no mesh has any.

use std::collections::HashMap;
use std::sync::Arc;

use bevy_ecs::prelude::*;
use glam::{Affine3A, Mat3, Mat3A, Vec2, Vec3};

use super::{
    AreaEmitter, Disk, FLAT_NORMAL_COS, InstancedMesh, Plane, Sphere, SurfaceMaterial,
    TriangleMesh, normals_follow_faces,
};
use crate::accel::{
    Accel, DiskInstance, MeshInstance, PassThrough, PlaneInstance, PrimitiveIds, PrimitiveRef,
    Primitives, SphereInstance, translation_only,
};
use crate::material::MaterialTable;
use crate::shared::Shared;

/// No emitter on this primitive.
pub const NO_EMITTER: u32 = u32::MAX;

/// One emissive shape, for the light table: its primitives and radiance.
#[derive(Clone, Debug)]
pub struct EmissiveShape {
    pub primitives: Vec<u32>,
    pub radiance: Vec3,
}

#[derive(Resource)]
pub struct SceneGeometry {
    pub accel: Arc<Accel>,
    /// How primitive ids number the lists below (the accel's numbering).
    pub ids: PrimitiveIds,
    /// World-space vertices of each triangle.
    pub triangles: Vec<[Vec3; 3]>,
    /// Unit geometric normal of each triangle (by its winding), computed once here rather than
    /// at every hit: the shading reads 12 bytes instead of the 36 of the vertices, and no cross
    /// product and normalisation.
    pub face_normals: Vec<Vec3>,
    /// Per-triangle vertex normals; empty when no mesh has normals.
    pub triangle_normals: Vec<[Vec3; 3]>,
    /// Per-triangle vertex uvs; empty unless the scene samples textures.
    pub triangle_uvs: Vec<[Vec2; 3]>,
    /// Whether the scene samples textures: without them a hit's uv is never read, and spheres
    /// and planes skip computing theirs (an atan2 and an acos per sphere hit).
    pub uvs: bool,
    pub spheres: Vec<SphereShape>,
    pub planes: Vec<Plane>,
    pub disks: Vec<DiskShape>,
    /// Shared meshes (object-space triangles) and their placed copies.
    pub meshes: Vec<Vec<[Vec3; 3]>>,
    pub instances: Vec<MeshInstance>,
    /// Per-triangle object-space vertex normals of each shared mesh (face normals for a mesh
    /// without), and each instance's map for normals (the inverse transpose of its linear
    /// part); both empty when no shared mesh has normals.
    pub mesh_normals: Vec<Vec<[Vec3; 3]>>,
    pub instance_normal_matrices: Vec<Mat3>,
    /// Per-triangle uvs of each shared mesh; empty unless the scene samples textures.
    pub mesh_uvs: Vec<Vec<[Vec2; 3]>>,
    /// Material index of each primitive, by id.
    pub material: Vec<u32>,
    /// The primitives shadow rays pass through (null material); `None` if there are none.
    pub pass_through: Option<PassThrough>,
    /// Emitter (index into `emissive_shapes`) of each primitive by id, or [`NO_EMITTER`].
    pub emitter: Vec<u32>,
    pub emissive_shapes: Vec<EmissiveShape>,
    /// Centre and radius of a sphere bounding the scene (for distant and infinite lights).
    pub bounds_centre: Vec3,
    pub bounds_radius: f32,
}

#[derive(Clone, Copy, Debug)]
pub struct SphereShape {
    pub object_to_world: Affine3A,
    pub world_to_object: Affine3A,
    /// Maps object-space normals to world space: the inverse transpose of the linear part of
    /// `object_to_world`, i.e. `world_to_object`'s transposed (transposed once here, not at
    /// every hit).
    pub normal_to_world: Mat3A,
    /// `world_to_object`'s translation where its linear part is exactly the identity (a sphere
    /// placed by its centre, as Mitsuba's `center` and LuxRender's translations place them):
    /// the hit's object-space point is then the world point plus it, and its normal that
    /// point normalised, without the two matrix products.
    pub translation_only: Option<Vec3>,
    pub radius: f32,
    /// Whether a hit's uv is read: the scene samples textures and the sphere's material varies
    /// over its surface (a material of constant inputs never reads it: `Scene::bsdf_at`), so a
    /// glass or metal sphere in a textured scene skips the atan2 and acos.
    pub uv: bool,
}

/// A disk as the shade stage and the lights use it: the unit disk of its object space placed by
/// `object_to_world`, whose centre is `M·0` and whose points are `M·0 + a Mx + b My` for
/// `a² + b² <= 1` (`Mx`, `My` the map's first two columns).
#[derive(Clone, Copy, Debug)]
pub struct DiskShape {
    pub object_to_world: Affine3A,
    pub world_to_object: Affine3A,
    /// The unit normal `Mx × My` normalised: the side a tessellated disk's winding faces (and
    /// Mitsuba's `m_frame.n`), so a mirroring map turns it as it turns the triangles.
    pub normal: Vec3,
    /// `π |Mx × My|`: the ellipse's area.
    pub area: f32,
    /// Whether a hit's uv is read (as [`SphereShape::uv`]).
    pub uv: bool,
}

impl DiskShape {
    pub fn new(object_to_world: Affine3A, uv: bool) -> DiskShape {
        let m = object_to_world.matrix3;
        let across = Vec3::from(m.x_axis.cross(m.y_axis));
        DiskShape {
            object_to_world,
            world_to_object: object_to_world.inverse(),
            normal: across.normalize_or(Vec3::Z),
            area: std::f32::consts::PI * across.length(),
            uv,
        }
    }

    /// The four corners of the square `[-1, 1]² × {0}` around the disk, in world space: their
    /// hull holds the disk.
    fn corners(&self) -> impl Iterator<Item = Vec3> + '_ {
        [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
            .into_iter()
            .map(|(x, y)| self.object_to_world.transform_point3(Vec3::new(x, y, 0.0)))
    }
}

/// What the world builder asks of the flattening.
#[derive(Resource, Clone, Copy, Debug)]
pub struct GeometryNeeds {
    pub uvs: bool,
}

type ShapeQuery<'a, T> = (&'a T, &'a SurfaceMaterial, Option<&'a AreaEmitter>);

/// Startup system: gathers the shape entities into [`SceneGeometry`] and builds the BVH.
pub fn build_scene_geometry(
    meshes: Query<ShapeQuery<TriangleMesh>>,
    spheres: Query<ShapeQuery<Sphere>>,
    (planes, disks): (Query<ShapeQuery<Plane>>, Query<ShapeQuery<Disk>>),
    instanced: Query<(&InstancedMesh, &SurfaceMaterial)>,
    needs: Res<GeometryNeeds>,
    materials: Res<MaterialTable>,
    mut commands: Commands,
) {
    // Vertex normals that only repeat the faces' (Mitsuba's rectangles and cubes carry them)
    // are not kept: a hit then takes the face normal, without interpolating and normalising.
    let any_normals = meshes.iter().any(|(mesh, _, _)| {
        (mesh.normals.as_ref()).is_some_and(|normals| {
            !normals_follow_faces(&mesh.positions, normals, &mesh.indices, FLAT_NORMAL_COS)
        })
    });
    let mut triangles = Vec::new();
    let mut triangle_normals = Vec::new();
    let mut triangle_uvs = Vec::new();
    let mut material = Vec::new();
    let mut emitter = Vec::new();
    // Each emitter's primitives (as ranges of triangle, sphere or disk indices, turned into ids once
    // all are counted) and radiance.
    let mut emitters: Vec<(EmitterPrimitives, Vec3)> = Vec::new();

    let mut next_emitter = |primitives: EmitterPrimitives, light: Option<&AreaEmitter>| {
        light.map_or(NO_EMITTER, |light| {
            emitters.push((primitives, light.radiance));
            (emitters.len() - 1) as u32
        })
    };

    for (mesh, surface, light) in &meshes {
        let first = triangles.len();
        let id = next_emitter(
            EmitterPrimitives::Triangles(first..first + mesh.indices.len()),
            light,
        );
        for tri in &mesh.indices {
            let [a, b, c] = tri.map(|i| i as usize);
            let vertices = [mesh.positions[a], mesh.positions[b], mesh.positions[c]];
            triangles.push(vertices);
            if any_normals {
                let normals = (mesh.normals.as_ref()).map(|n| [n[a], n[b], n[c]]);
                triangle_normals.push(vertex_normals(vertices, normals));
            }
            if needs.uvs {
                let uvs = (mesh.uvs.as_ref()).map(|uv| [uv[a], uv[b], uv[c]]);
                triangle_uvs.push(uvs.unwrap_or(NO_UVS));
            }
            material.push(surface.0);
            emitter.push(id);
        }
    }
    let mut sphere_shapes = Vec::new();
    for (sphere, surface, light) in &spheres {
        emitter.push(next_emitter(
            EmitterPrimitives::Sphere(sphere_shapes.len()),
            light,
        ));
        material.push(surface.0);
        let world_to_object = sphere.object_to_world.inverse();
        sphere_shapes.push(SphereShape {
            object_to_world: sphere.object_to_world,
            world_to_object,
            normal_to_world: world_to_object.matrix3.transpose(),
            translation_only: translation_only(&world_to_object).map(Vec3::from),
            radius: sphere.radius,
            uv: needs.uvs && materials.fixed_bsdf(surface.0).is_none(),
        });
    }
    let mut plane_shapes = Vec::new();
    for (plane, surface, _) in &planes {
        // An infinite plane cannot be sampled as a light; the builder warned of it.
        emitter.push(NO_EMITTER);
        material.push(surface.0);
        plane_shapes.push(*plane);
    }
    let mut disk_shapes = Vec::new();
    for (disk, surface, light) in &disks {
        emitter.push(next_emitter(
            EmitterPrimitives::Disk(disk_shapes.len()),
            light,
        ));
        material.push(surface.0);
        let uv = needs.uvs && materials.fixed_bsdf(surface.0).is_none();
        disk_shapes.push(DiskShape::new(disk.object_to_world, uv));
    }

    // Instance triangles take the ids after the planes and disks, instance by instance (`PrimitiveIds`).
    // Instanced meshes emit no light (loaders place emitters as shapes of their own).
    let any_instance_normals = instanced.iter().any(|(m, _)| m.normals.is_some());
    let mut meshes: Vec<Vec<[Vec3; 3]>> = Vec::new();
    let mut mesh_normals = Vec::new();
    let mut mesh_uvs = Vec::new();
    let mut mesh_of: HashMap<*const Vec<[Vec3; 3]>, u32> = HashMap::new();
    let mut instances = Vec::new();
    let mut instance_normal_matrices = Vec::new();
    for (instance, surface) in &instanced {
        let shared = &instance.triangles;
        let mesh = *mesh_of.entry(Arc::as_ptr(shared)).or_insert_with(|| {
            meshes.push(shared.as_ref().clone());
            if any_instance_normals {
                let normals = |k: usize| instance.normals.as_ref().map(|n| n[k]);
                let per_triangle = shared.iter().enumerate();
                mesh_normals.push(
                    per_triangle
                        .map(|(k, &t)| vertex_normals(t, normals(k)))
                        .collect(),
                );
            }
            if needs.uvs {
                let uvs = instance.uvs.as_ref().map_or(&[][..], |uvs| uvs.as_slice());
                mesh_uvs.push(
                    (0..shared.len())
                        .map(|k| *uvs.get(k).unwrap_or(&NO_UVS))
                        .collect(),
                );
            }
            (meshes.len() - 1) as u32
        });
        if any_instance_normals {
            let linear = Mat3::from(instance.object_to_world.matrix3);
            instance_normal_matrices.push(linear.inverse().transpose());
        }
        instances.push(MeshInstance {
            mesh,
            object_to_world: instance.object_to_world,
        });
        material.extend(std::iter::repeat_n(surface.0, shared.len()));
        emitter.extend(std::iter::repeat_n(NO_EMITTER, shared.len()));
    }
    let instanced_points = instances.iter().flat_map(|instance| {
        let to_world = instance.object_to_world;
        meshes[instance.mesh as usize]
            .iter()
            .flatten()
            .map(move |p| to_world.transform_point3(*p))
    });
    let disk_points = disk_shapes.iter().flat_map(DiskShape::corners);
    let (bounds_centre, bounds_radius) = bounding_sphere(
        (triangles.iter().flatten().copied())
            .chain(instanced_points)
            .chain(disk_points),
        &sphere_shapes,
    );

    let primitives = Primitives {
        triangles: triangles.clone(),
        spheres: sphere_shapes
            .iter()
            .map(|s| SphereInstance {
                object_to_world: s.object_to_world,
                radius: s.radius,
            })
            .collect(),
        planes: plane_shapes
            .iter()
            .map(|p| PlaneInstance {
                point: p.point,
                normal: p.normal,
            })
            .collect(),
        disks: (disk_shapes.iter())
            .map(|d| DiskInstance {
                object_to_world: d.object_to_world,
            })
            .collect(),
        meshes,
        instances,
    };
    let ids = PrimitiveIds::new(&primitives);
    let emissive_shapes = (emitters.into_iter())
        .map(|(primitives, radiance)| EmissiveShape {
            primitives: match primitives {
                EmitterPrimitives::Triangles(range) => range.map(|i| ids.triangle(i)).collect(),
                EmitterPrimitives::Sphere(i) => vec![ids.sphere(i)],
                EmitterPrimitives::Disk(i) => vec![ids.disk(i)],
            },
            radiance,
        })
        .collect();
    let pass_through = PassThrough::new(ids.count(), |id| {
        (material.get(id as usize)).is_some_and(|&m| materials.is_null(m))
    });
    let face_normals = triangles.iter().map(face_normal).collect();
    commands.insert_resource(Shared::new(SceneGeometry {
        accel: Arc::new(Accel::build(&primitives)),
        ids,
        triangles,
        face_normals,
        triangle_normals,
        triangle_uvs,
        uvs: needs.uvs,
        spheres: sphere_shapes,
        planes: plane_shapes,
        disks: disk_shapes,
        meshes: primitives.meshes,
        instances: primitives.instances,
        mesh_normals,
        instance_normal_matrices,
        mesh_uvs,
        material,
        pass_through,
        emitter,
        emissive_shapes,
        bounds_centre,
        bounds_radius,
    }));
}

impl SceneGeometry {
    /// The world-space vertices of a triangle or an instance's triangle; `None` for any other
    /// primitive.
    pub fn world_triangle(&self, prim: PrimitiveRef) -> Option<[Vec3; 3]> {
        match prim {
            PrimitiveRef::Triangle(i) => self.triangles.get(i).copied(),
            PrimitiveRef::InstanceTriangle { instance, triangle } => {
                let instance = self.instances.get(instance)?;
                let t = self.meshes.get(instance.mesh as usize)?.get(triangle)?;
                Some(t.map(|p| instance.object_to_world.transform_point3(p)))
            }
            PrimitiveRef::Sphere(_) | PrimitiveRef::Plane(_) | PrimitiveRef::Disk(_) => None,
        }
    }
}

/// A triangle's unit normal by its winding; +z for a degenerate one.
pub fn face_normal(&[p0, p1, p2]: &[Vec3; 3]) -> Vec3 {
    (p1 - p0).cross(p2 - p0).normalize_or(Vec3::Z)
}

/// The uvs of a triangle whose mesh has none (where the scene samples textures).
const NO_UVS: [Vec2; 3] = [Vec2::ZERO, Vec2::X, Vec2::ONE];

/// A triangle's vertex normals for shading: the mesh's, a zero one replaced by the face
/// normal; the face normal at every vertex for a mesh without normals.
fn vertex_normals(vertices: [Vec3; 3], normals: Option<[Vec3; 3]>) -> [Vec3; 3] {
    let [a, b, c] = vertices;
    let face = (b - a).cross(c - a).normalize_or_zero();
    normals.map_or([face; 3], |n| n.map(|n| n.normalize_or(face)))
}

/// An emissive shape's primitives, before ids are assigned.
enum EmitterPrimitives {
    Triangles(std::ops::Range<usize>),
    Sphere(usize),
    Disk(usize),
}

/// A sphere around every bounded primitive (planes are unbounded and left out): the world-space
/// points given (triangles' vertices, disks' corners) and the spheres.
fn bounding_sphere(vertices: impl Iterator<Item = Vec3>, spheres: &[SphereShape]) -> (Vec3, f32) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for p in vertices {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    for s in spheres {
        let centre = Vec3::from(s.object_to_world.translation);
        let m = s.object_to_world.matrix3;
        let reach =
            Vec3::splat(s.radius * (m.x_axis.length() + m.y_axis.length() + m.z_axis.length()));
        lo = lo.min(centre - reach);
        hi = hi.max(centre + reach);
    }
    if lo.cmpgt(hi).any() {
        return (Vec3::ZERO, 1.0);
    }
    let centre = (lo + hi) * 0.5;
    (centre, ((hi - lo) * 0.5).length().max(1e-3))
}
