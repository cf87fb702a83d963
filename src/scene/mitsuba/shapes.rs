//! Mitsuba shapes: meshes from files (`obj`, `ply`, `serialized`) and the analytic shapes as Mitsuba
//! parametrises them (`sphere` by centre and radius; `rectangle`, `disk`, `cube`, `cylinder` in
//! their canonical object space, tessellated), each with its `to_world`, `flip_normals`,
//! `face_normals`, BSDF and area emitter.

use std::f32::consts::TAU;

use glam::{DMat4, DVec3, Vec2, Vec3};

use super::convert::{Converter, location};
use super::tree::Object;
use super::{emitters, materials};
use crate::scene::desc::{Geometry, SceneError, SceneWarning, ShapeDesc};
use crate::scene::io::ply;
use crate::scene::io::{TriangleMesh, obj, serialized};

/// Segments around a disk or a cylinder: the area is short by (2 pi / n)^2 / 6, 0.004 %.
const SEGMENTS: usize = 256;

pub fn shape(cx: &mut Converter, object: &Object) -> Result<(), SceneError> {
    let tree = cx.tree;
    let loc = object.loc.clone();
    let mut to_world = cx.transform(object, "to_world");
    let flip = cx.bool(object, "flip_normals", false);
    let face_normals = cx.bool(object, "face_normals", false);
    let geometry = match object.plugin.as_str() {
        "obj" | "ply" | "serialized" => {
            let name = cx
                .string(object, "filename")
                .ok_or_else(|| cx.error(&loc, format!("{} needs a filename", object.describe())))?;
            let path = tree.resolve(&name);
            if !path.is_file() {
                return Err(cx.error(
                    &loc,
                    format!("mesh file \"{name}\" not found ({})", path.display()),
                ));
            }
            let mesh = match object.plugin.as_str() {
                "obj" => obj::read_obj(&path).map_err(|e| e.to_string()),
                "serialized" => {
                    let index = cx.int(object, "shape_index", 0).max(0) as usize;
                    serialized::read_serialized(&path, index).map_err(|e| e.to_string())
                }
                _ => ply_mesh(&path),
            };
            let mut mesh = mesh.map_err(|e| cx.error(&loc, format!("cannot read mesh: {e}")))?;
            if object.plugin == "obj" && cx.bool(object, "flip_tex_coords", true) {
                // Mitsuba flips OBJ texture coordinates vertically by default.
                for uv in mesh.uvs.iter_mut().flatten() {
                    uv.y = 1.0 - uv.y;
                }
            }
            mesh
        }
        "sphere" => {
            let center = cx.vec3(object, "center", Vec3::ZERO);
            let radius = cx.float(object, "radius", 1.0);
            if flip {
                cx.warn(
                    &loc,
                    "flip_normals on a sphere not supported: normals point outwards".into(),
                );
            }
            to_world *= DMat4::from_translation(center.as_dvec3());
            return finish(cx, object, Geometry::Sphere { radius }, to_world);
        }
        "rectangle" => rectangle(),
        // Analytic, as Mitsuba's; flipped, the tessellation (its triangles turn over).
        "disk" if !flip => return finish(cx, object, Geometry::Disk, to_world),
        "disk" => disk(),
        "cube" => cube(),
        "cylinder" => {
            let p0 = cx.vec3(object, "p0", Vec3::ZERO);
            let p1 = cx.vec3(object, "p1", Vec3::Z);
            let radius = cx.float(object, "radius", 1.0);
            // Mitsuba's cylinder: radius 1 around z from 0 to 1, placed by p0, p1 and radius.
            let axis = (p1 - p0).as_dvec3();
            let (u, v) = axis.normalize_or(DVec3::Z).any_orthonormal_pair();
            let frame = DMat4::from_cols(
                (u * radius as f64).extend(0.0),
                (v * radius as f64).extend(0.0),
                axis.extend(0.0),
                p0.as_dvec3().extend(1.0),
            );
            to_world *= frame;
            cylinder()
        }
        // Converted where an instance names it; alone it renders nothing, as in Mitsuba.
        "shapegroup" => {
            object.prop("id");
            return Ok(());
        }
        "instance" => return instance(cx, object, to_world),
        other => {
            let other = other.to_string();
            cx.warn(&loc, format!("shape \"{other}\" not supported, skipped"));
            for child in &object.children {
                child.used.set(true);
            }
            return Ok(());
        }
    };
    let mut mesh = geometry;
    if face_normals {
        mesh.normals = None;
    } else if mesh.normals.is_none() {
        // Mitsuba interpolates normals it computes when a mesh has none.
        mesh.normals = Some(vertex_normals(&mesh));
    }
    if flip {
        for tri in &mut mesh.indices {
            tri.swap(1, 2);
        }
        for n in mesh.normals.iter_mut().flatten() {
            *n = -*n;
        }
    }
    let geometry = Geometry::TriangleMesh {
        positions: mesh.positions,
        normals: mesh.normals,
        uvs: mesh.uvs,
        indices: mesh.indices,
    };
    finish(cx, object, geometry, to_world)
}

fn finish(
    cx: &mut Converter,
    object: &Object,
    geometry: Geometry,
    to_world: DMat4,
) -> Result<(), SceneError> {
    let tree = cx.tree;
    let bsdfs: Vec<_> = object
        .children_tagged(tree, "bsdf")
        .map(|(_, b)| b)
        .collect();
    let shape_emitters: Vec<_> = object.children_tagged(tree, "emitter").collect();
    let material = match bsdfs.first() {
        Some(b) => materials::bsdf(cx, b)?,
        None if !shape_emitters.is_empty() => materials::one_sided_diffuse(cx, 0.0),
        None => materials::default_material(cx),
    };
    if bsdfs.len() > 1 {
        cx.warn(
            &object.loc,
            format!(
                "{} has {} BSDFs: the first is used",
                object.describe(),
                bsdfs.len()
            ),
        );
    }
    let mut area_light = None;
    for (_, emitter) in shape_emitters {
        area_light = emitters::area(cx, emitter);
    }
    object.prop("id");
    cx.report_unused(object);
    cx.desc.shapes.push(ShapeDesc {
        geometry,
        object_to_world: to_world.as_mat4(),
        material: Some(material),
        area_light,
        location: location(&object.loc),
    });
    Ok(())
}

/// An `instance`: its `shapegroup` (given by `ref` or nested) placed by `to_world`.
fn instance(cx: &mut Converter, object: &Object, to_world: DMat4) -> Result<(), SceneError> {
    let tree = cx.tree;
    let group = object
        .children_tagged(tree, "shape")
        .map(|(_, shape)| shape)
        .find(|shape| shape.plugin == "shapegroup");
    let Some(group) = group else {
        cx.warn(&object.loc, "instance without a shapegroup, skipped".into());
        return Ok(());
    };
    let group = shape_group(cx, group)?;
    cx.report_unused(object);
    cx.desc.shapes.push(ShapeDesc {
        geometry: Geometry::Instance { group },
        object_to_world: to_world.as_mat4(),
        material: None,
        area_light: None,
        location: location(&object.loc),
    });
    Ok(())
}

/// The shapes of a `shapegroup` (converted once, shared by its instances), in the group's space.
fn shape_group(cx: &mut Converter, group: &Object) -> Result<usize, SceneError> {
    let tree = cx.tree;
    let key = (tree.objects.iter())
        .position(|o| std::ptr::eq(o, group))
        .unwrap_or(usize::MAX);
    if let Some(&id) = cx.shape_groups.get(&key) {
        return Ok(id);
    }
    // Each member converts as a shape of the scene would, then moves into the group.
    let first = cx.desc.shapes.len();
    for (_, member) in group.children_tagged(tree, "shape") {
        shape(cx, member)?;
    }
    let mut members: Vec<ShapeDesc> = cx.desc.shapes.drain(first..).collect();
    for member in &mut members {
        if member.area_light.take().is_some() {
            cx.desc.warnings.push(SceneWarning {
                location: member.location.clone(),
                message: "shape in a shapegroup: its emitter is ignored".into(),
            });
        }
    }
    cx.report_unused(group);
    cx.desc.shape_groups.push(members);
    let id = cx.desc.shape_groups.len() - 1;
    cx.shape_groups.insert(key, id);
    Ok(id)
}

fn ply_mesh(path: &std::path::Path) -> Result<TriangleMesh, String> {
    match ply::read(path)? {
        Geometry::TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
        } => Ok(TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
        }),
        _ => Err("not a triangle mesh".into()),
    }
}

/// Per-vertex normals: the normals of the faces around each vertex weighted by the angle they
/// make there (as Mitsuba's `recompute_vertex_normals`).
fn vertex_normals(mesh: &TriangleMesh) -> Vec<Vec3> {
    let p = &mesh.positions;
    let mut normals = vec![Vec3::ZERO; p.len()];
    for &[a, b, c] in &mesh.indices {
        let [a, b, c] = [a as usize, b as usize, c as usize];
        let n = (p[b] - p[a]).cross(p[c] - p[a]).normalize_or_zero();
        for (v, prev, next) in [(a, c, b), (b, a, c), (c, b, a)] {
            let (e0, e1) = (p[prev] - p[v], p[next] - p[v]);
            normals[v] += n * e0.angle_between(e1);
        }
    }
    normals.iter().map(|n| n.normalize_or(Vec3::Z)).collect()
}

/// [-1, 1]^2 in the plane z = 0, normal +z, uv = ((x + 1) / 2, (y + 1) / 2).
fn rectangle() -> TriangleMesh {
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    TriangleMesh {
        positions: corners.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect(),
        normals: Some(vec![Vec3::Z; 4]),
        uvs: Some(
            corners
                .iter()
                .map(|&(x, y)| Vec2::new((x + 1.0) / 2.0, (y + 1.0) / 2.0))
                .collect(),
        ),
        indices: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// The unit disk in z = 0, normal +z, uv = (r, phi / 2 pi) as Mitsuba's.
fn disk() -> TriangleMesh {
    let mut positions = vec![Vec3::ZERO];
    let mut uvs = vec![Vec2::ZERO];
    for i in 0..=SEGMENTS {
        let phi = TAU * i as f32 / SEGMENTS as f32;
        positions.push(Vec3::new(phi.cos(), phi.sin(), 0.0));
        uvs.push(Vec2::new(1.0, i as f32 / SEGMENTS as f32));
    }
    let indices = (0..SEGMENTS as u32).map(|i| [0, i + 1, i + 2]).collect();
    TriangleMesh {
        normals: Some(vec![Vec3::Z; positions.len()]),
        positions,
        uvs: Some(uvs),
        indices,
    }
}

/// [-1, 1]^3, four vertices per face with its normal.
fn cube() -> TriangleMesh {
    let mut mesh = TriangleMesh {
        normals: Some(Vec::new()),
        uvs: Some(Vec::new()),
        ..TriangleMesh::default()
    };
    for n in [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ] {
        // (s, t, n) right-handed, so that the corners below run counter-clockwise about n.
        let s =
            if n.x.abs() > 0.5 { Vec3::Y } else { Vec3::X } * n.max_element().max(-n.min_element());
        let s = if n.dot(Vec3::ONE) < 0.0 { -s } else { s };
        let t = n.cross(s);
        let base = mesh.positions.len() as u32;
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            mesh.positions.push(n + s * a + t * b);
            mesh.normals.as_mut().unwrap().push(n);
            mesh.uvs
                .as_mut()
                .unwrap()
                .push(Vec2::new((a + 1.0) / 2.0, (b + 1.0) / 2.0));
        }
        mesh.indices.push([base, base + 1, base + 2]);
        mesh.indices.push([base, base + 2, base + 3]);
    }
    mesh
}

/// The open tube of radius 1 around z from 0 to 1, normals outwards, uv = (phi / 2 pi, z).
fn cylinder() -> TriangleMesh {
    let mut mesh = TriangleMesh {
        normals: Some(Vec::new()),
        uvs: Some(Vec::new()),
        ..TriangleMesh::default()
    };
    for i in 0..=SEGMENTS {
        let phi = TAU * i as f32 / SEGMENTS as f32;
        let n = Vec3::new(phi.cos(), phi.sin(), 0.0);
        for z in [0.0, 1.0] {
            mesh.positions.push(n + Vec3::Z * z);
            mesh.normals.as_mut().unwrap().push(n);
            mesh.uvs
                .as_mut()
                .unwrap()
                .push(Vec2::new(i as f32 / SEGMENTS as f32, z));
        }
    }
    for i in 0..SEGMENTS as u32 {
        let (a, b) = (2 * i, 2 * i + 2);
        mesh.indices.push([a, b, b + 1]);
        mesh.indices.push([a, b + 1, a + 1]);
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outward(mesh: &TriangleMesh) -> bool {
        mesh.indices.iter().all(|&[a, b, c]| {
            let p = |i: u32| mesh.positions[i as usize];
            let n = (p(b) - p(a)).cross(p(c) - p(a));
            let centre = (p(a) + p(b) + p(c)) / 3.0;
            n.dot(centre - Vec3::new(0.0, 0.0, centre.z.clamp(0.0, 0.0))) > 0.0
        })
    }

    #[test]
    fn tessellated_shapes_face_outwards_with_their_normals() {
        for mesh in [cube(), cylinder()] {
            assert!(outward(&mesh));
            for (&[a, b, c], normals) in mesh
                .indices
                .iter()
                .zip(std::iter::repeat(mesh.normals.as_ref().unwrap()))
            {
                let p = |i: u32| mesh.positions[i as usize];
                let n = (p(b) - p(a)).cross(p(c) - p(a));
                assert!(n.dot(normals[a as usize]) > 0.0);
            }
        }
        let r = rectangle();
        let p = |i: u32| r.positions[i as usize];
        assert!((p(1) - p(0)).cross(p(2) - p(0)).z > 0.0);
        let d = disk();
        let area: f32 = d
            .indices
            .iter()
            .map(|&[a, b, c]| {
                let p = |i: u32| d.positions[i as usize];
                0.5 * (p(b) - p(a)).cross(p(c) - p(a)).z
            })
            .sum();
        assert!((area - std::f32::consts::PI).abs() < 1e-3 * std::f32::consts::PI);
    }

    #[test]
    fn computed_normals_of_a_flat_mesh_are_its_normal() {
        let mut r = rectangle();
        r.normals = None;
        assert!(
            vertex_normals(&r)
                .iter()
                .all(|n| (*n - Vec3::Z).length() < 1e-6)
        );
    }
}
