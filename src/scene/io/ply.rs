//! PLY meshes (ASCII and binary): positions, optional normals and uv, polygons fanned into
//! triangles.

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use glam::{Vec2, Vec3};
use ply_rs::parser::Parser;
use ply_rs::ply::{DefaultElement, Property};

use crate::scene::desc::Geometry;

fn scalar(element: &DefaultElement, key: &str) -> Option<f32> {
    Some(match element.get(key)? {
        Property::Char(v) => f32::from(*v),
        Property::UChar(v) => f32::from(*v),
        Property::Short(v) => f32::from(*v),
        Property::UShort(v) => f32::from(*v),
        Property::Int(v) => *v as f32,
        Property::UInt(v) => *v as f32,
        Property::Float(v) => *v,
        Property::Double(v) => *v as f32,
        _ => return None,
    })
}

fn index_list(element: &DefaultElement) -> Option<Vec<i64>> {
    let list = element
        .get("vertex_indices")
        .or_else(|| element.get("vertex_index"))?;
    Some(match list {
        Property::ListChar(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListUChar(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListShort(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListUShort(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListInt(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListUInt(v) => v.iter().map(|&i| i64::from(i)).collect(),
        _ => return None,
    })
}

/// Reads one PLY file into a triangle mesh; the message says what is wrong with the file.
pub fn read(path: &Path) -> Result<Geometry, String> {
    let file = File::open(path).map_err(|e| e.to_string())?;
    parse(&mut BufReader::new(file))
}

/// Reads a PLY file's bytes into a triangle mesh (the fuzzer's entry point).
pub fn parse(reader: &mut impl BufRead) -> Result<Geometry, String> {
    // ply-rs panics on some malformed headers: turn that into an error too.
    let ply = catch_unwind(AssertUnwindSafe(|| {
        Parser::<DefaultElement>::new().read_ply(reader)
    }))
    .map_err(|_| "malformed PLY file".to_string())?
    .map_err(|e| e.to_string())?;

    let vertices = ply.payload.get("vertex").ok_or("no \"vertex\" element")?;
    let vec3 = |v: &DefaultElement, keys: [&str; 3]| -> Option<Vec3> {
        Some(Vec3::new(
            scalar(v, keys[0])?,
            scalar(v, keys[1])?,
            scalar(v, keys[2])?,
        ))
    };
    let positions = vertices
        .iter()
        .map(|v| vec3(v, ["x", "y", "z"]))
        .collect::<Option<Vec<Vec3>>>()
        .ok_or("a vertex without x, y, z")?;
    let normals = vertices
        .iter()
        .map(|v| vec3(v, ["nx", "ny", "nz"]))
        .collect::<Option<Vec<Vec3>>>();
    let uvs = [
        ("u", "v"),
        ("s", "t"),
        ("texture_u", "texture_v"),
        ("texture_s", "texture_t"),
    ]
    .iter()
    .find_map(|(u, v)| {
        vertices
            .iter()
            .map(|e| Some(Vec2::new(scalar(e, u)?, scalar(e, v)?)))
            .collect::<Option<Vec<Vec2>>>()
    });

    let faces = ply.payload.get("face").ok_or("no \"face\" element")?;
    let mut indices = Vec::new();
    for face in faces {
        let polygon = index_list(face).ok_or("a face without vertex_indices")?;
        let vertex = |i: i64| {
            u32::try_from(i)
                .ok()
                .filter(|&i| (i as usize) < positions.len())
                .ok_or_else(|| {
                    format!("face index {i} out of range ({} vertices)", positions.len())
                })
        };
        // Fan triangulation: (0, i, i + 1).
        for i in 1..polygon.len().saturating_sub(1) {
            indices.push([
                vertex(polygon[0])?,
                vertex(polygon[i])?,
                vertex(polygon[i + 1])?,
            ]);
        }
    }
    Ok(Geometry::TriangleMesh {
        positions,
        normals,
        uvs,
        indices,
    })
}
