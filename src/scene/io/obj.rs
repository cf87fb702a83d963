//! Wavefront OBJ meshes: `v`, `vt`, `vn` and `f` (polygons fanned into triangles, negative indices
//! counted back from the last element so far). A vertex is a distinct (position, uv, normal) index
//! triple, numbered in order of first use, as Mitsuba's OBJ loader numbers them. Groups, objects,
//! materials and smoothing groups are ignored; every face goes into the one mesh.

use std::collections::HashMap;
use std::path::Path;

use glam::{Vec2, Vec3};

use super::{MeshError, TriangleMesh};

pub fn read_obj(path: &Path) -> Result<TriangleMesh, MeshError> {
    let text = std::fs::read_to_string(path)
        .map_err(|err| MeshError::new(path, None, format!("cannot read OBJ file: {err}")))?;
    parse_obj(&text, path)
}

/// A face corner: position, and uv and normal if given (0-based).
type Corner = (u32, Option<u32>, Option<u32>);

/// Reads OBJ `text` (named `path` in errors). Texture coordinates are returned as written (no
/// flip); a corner without one gets (0, 0). Normals are returned only if every corner has one.
pub fn parse_obj(text: &str, path: &Path) -> Result<TriangleMesh, MeshError> {
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    let mut normals = Vec::new();
    let mut corners: Vec<Corner> = Vec::new();
    let mut vertex_of: HashMap<Corner, u32> = HashMap::new();
    let mut indices = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let error =
            |what: &str| MeshError::new(path, Some(n + 1), format!("{what} in `{}`", line.trim()));
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let mut numbers = |count: usize, min: usize| -> Result<Vec<f32>, MeshError> {
            let values: Vec<f32> = words
                .by_ref()
                .take(count)
                .map(|w| w.parse::<f32>())
                .collect::<Result<_, _>>()
                .map_err(|_| error("a number could not be read"))?;
            if values.len() < min || values.iter().any(|v| !v.is_finite()) {
                return Err(error(&format!("expected {min} finite numbers")));
            }
            Ok(values)
        };
        match keyword {
            "v" => {
                let v = numbers(3, 3)?;
                positions.push(Vec3::new(v[0], v[1], v[2]));
            }
            "vt" => {
                let v = numbers(2, 1)?;
                uvs.push(Vec2::new(v[0], v.get(1).copied().unwrap_or(0.0)));
            }
            "vn" => {
                let v = numbers(3, 3)?;
                normals.push(Vec3::new(v[0], v[1], v[2]));
            }
            "f" => {
                let mut face = Vec::new();
                for word in words {
                    let mut parts = word.split('/');
                    let index = |part: Option<&str>,
                                 count: usize,
                                 what: &str|
                     -> Result<Option<u32>, MeshError> {
                        let Some(part) = part.filter(|p| !p.is_empty()) else {
                            return Ok(None);
                        };
                        let i: i64 = part
                            .parse()
                            .map_err(|_| error(&format!("bad {what} index `{part}`")))?;
                        // 1-based from the start, or negative from the end of what is read so far.
                        let resolved = if i > 0 { i - 1 } else { count as i64 + i };
                        if i == 0 || resolved < 0 || resolved >= count as i64 {
                            return Err(error(&format!(
                                "{what} index {i} out of range (1..={count})"
                            )));
                        }
                        Ok(Some(resolved as u32))
                    };
                    let p = index(parts.next(), positions.len(), "position")?
                        .ok_or_else(|| error("a face corner without a position"))?;
                    let t = index(parts.next(), uvs.len(), "texture coordinate")?;
                    let nn = index(parts.next(), normals.len(), "normal")?;
                    let corner = (p, t, nn);
                    let id = *vertex_of.entry(corner).or_insert_with(|| {
                        corners.push(corner);
                        (corners.len() - 1) as u32
                    });
                    face.push(id);
                }
                if face.len() < 3 {
                    return Err(error("a face needs at least 3 corners"));
                }
                for k in 1..face.len() - 1 {
                    indices.push([face[0], face[k], face[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if indices.is_empty() {
        return Err(MeshError::new(path, None, "no faces"));
    }
    let any_uv = corners.iter().any(|c| c.1.is_some());
    let all_normals = corners.iter().all(|c| c.2.is_some());
    Ok(TriangleMesh {
        positions: corners.iter().map(|c| positions[c.0 as usize]).collect(),
        uvs: any_uv.then(|| {
            corners
                .iter()
                .map(|c| c.1.map_or(Vec2::ZERO, |t| uvs[t as usize]))
                .collect()
        }),
        normals: all_normals.then(|| {
            corners
                .iter()
                .map(|c| normals[c.2.unwrap() as usize])
                .collect()
        }),
        indices,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<TriangleMesh, MeshError> {
        parse_obj(text, Path::new("m.obj"))
    }

    #[test]
    fn a_quad_is_fanned_into_two_triangles() {
        let mesh = parse("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
        assert_eq!(mesh.positions.len(), 4);
        assert_eq!(mesh.indices, vec![[0, 1, 2], [0, 2, 3]]);
        assert!(mesh.normals.is_none() && mesh.uvs.is_none());
    }

    #[test]
    fn negative_indices_count_back_from_the_last_vertex() {
        let mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n").unwrap();
        assert_eq!(mesh.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(mesh.indices, vec![[0, 1, 2]]);
    }

    #[test]
    fn corners_with_different_attributes_become_different_vertices() {
        // One position used with two normals: two vertices; repeated triples are shared.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.25\nvn 0 0 1\nvn 0 0 -1\n\
                    f 1/1/1 2/1/1 3/1/1\nf 1/1/2 3/1/2 2/1/2\nf 1/1/1 3/1/1 2/1/1\n";
        let mesh = parse(text).unwrap();
        assert_eq!(mesh.positions.len(), 6);
        assert_eq!(mesh.indices[2], [0, 2, 1]);
        let normals = mesh.normals.unwrap();
        assert_eq!(normals[0], Vec3::Z);
        assert_eq!(normals[3], Vec3::NEG_Z);
        assert_eq!(mesh.uvs.unwrap()[4], Vec2::new(0.5, 0.25));
    }

    #[test]
    fn normals_only_when_every_corner_has_one() {
        let mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3\n").unwrap();
        assert!(mesh.normals.is_none());
    }

    #[test]
    fn errors_name_file_line_and_text() {
        let err = parse("v 0 0 0\nv 1 0 0\nf 1 2 3\n").unwrap_err();
        assert_eq!(err.line, Some(3));
        assert!(
            err.to_string().starts_with("m.obj:3:") && err.message.contains("f 1 2 3"),
            "{err}"
        );
        let err = parse("v 0 0 x\n").unwrap_err();
        assert_eq!(err.line, Some(1), "{err}");
        assert!(parse("f 0 1 2\n").is_err());
        assert!(parse("v 0 0 0\n").unwrap_err().message.contains("no faces"));
    }
}
