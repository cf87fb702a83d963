//! PLY meshes (Turk's polygon file format: ASCII, and binary in either byte order): positions,
//! optional normals and uv, polygons fanned into triangles; other elements and properties are
//! read past. Read by hand, as pbrt's and Mitsuba's readers are: the header's elements and their
//! properties, then each record's values straight into the mesh's arrays (`ply-rs`, used
//! before, built a map of named values per record: 380 M instructions for the ray caster's
//! 65,536-triangle torus).

use std::io::BufRead;
use std::path::Path;

use glam::{Vec2, Vec3};

use crate::scene::desc::Geometry;

/// Reads one PLY file into a triangle mesh; the message says what is wrong with the file.
pub fn read(path: &Path) -> Result<Geometry, String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    parse_bytes(&bytes)
}

/// Reads a PLY file's bytes into a triangle mesh (the fuzzer's entry point).
pub fn parse(reader: &mut impl BufRead) -> Result<Geometry, String> {
    let mut bytes = Vec::new();
    reader.read_to_end(&mut bytes).map_err(|e| e.to_string())?;
    parse_bytes(&bytes)
}

/// The names a vertex's uv may have, in the order they are looked for.
const UV_NAMES: [(&str, &str); 4] = [
    ("u", "v"),
    ("s", "t"),
    ("texture_u", "texture_v"),
    ("texture_s", "texture_t"),
];

fn parse_bytes(bytes: &[u8]) -> Result<Geometry, String> {
    let (format, elements, body) = header(bytes)?;
    let vertex = elements.iter().position(|e| e.name == "vertex");
    let vertex = vertex.ok_or("no \"vertex\" element")?;
    let face = elements.iter().position(|e| e.name == "face");
    let face = face.ok_or("no \"face\" element")?;
    let roles = VertexRoles::new(&elements[vertex])?;
    let face_list = (elements[face].properties.iter())
        .position(|p| {
            matches!(p.kind, Kind::List { .. })
                && (p.name == "vertex_indices" || p.name == "vertex_index")
        })
        .ok_or("a face without vertex_indices")?;

    let mut values = match format {
        Format::Ascii => Values::Ascii(&bytes[body..]),
        Format::Binary { big_endian } => Values::Binary {
            bytes: &bytes[body..],
            big_endian,
        },
    };
    let mut mesh = MeshArrays::default();
    let mut polygon = Vec::new();
    for (index, element) in elements.iter().enumerate() {
        // Every property takes at least a byte a record: records of none are not read (a
        // header's count alone could make that loop endless), and no more vertices are
        // reserved than the body could hold.
        if element.properties.is_empty() {
            continue;
        }
        if index == vertex {
            mesh.reserve(
                element.count.min(bytes.len() / element.properties.len()),
                &roles,
            );
        }
        for record in 0..element.count {
            let at = |e: String| {
                format!(
                    "element \"{}\", record {} of {}: {e}",
                    element.name,
                    record + 1,
                    element.count
                )
            };
            for (p, property) in element.properties.iter().enumerate() {
                match property.kind {
                    Kind::Scalar(ty) => {
                        let value = values.scalar(ty).map_err(at)?;
                        if index == vertex {
                            mesh.set(roles.of[p], value as f32);
                        }
                    }
                    Kind::List { count, item } => {
                        let n = values.scalar(count).map_err(at)?;
                        let n = usize::try_from(n as i64)
                            .ok()
                            .filter(|_| n >= 0.0 && n.fract() == 0.0)
                            .ok_or_else(|| at(format!("a list of {n} items")))?;
                        let keep = index == face && p == face_list;
                        polygon.clear();
                        for _ in 0..n {
                            let value = values.scalar(item).map_err(at)?;
                            if keep {
                                polygon.push(value);
                            }
                        }
                        if keep {
                            fan(&polygon, &mut mesh.indices).map_err(at)?;
                        }
                    }
                }
            }
            if index == vertex {
                mesh.end_vertex(&roles);
            }
        }
    }
    let vertices = mesh.positions.len();
    if let Some(bad) = mesh
        .indices
        .iter()
        .flatten()
        .find(|&&i| i as usize >= vertices)
    {
        return Err(format!(
            "face index {bad} out of range ({vertices} vertices)"
        ));
    }
    Ok(Geometry::TriangleMesh {
        positions: mesh.positions,
        normals: roles.has_normals.then_some(mesh.normals),
        uvs: roles.has_uvs.then_some(mesh.uvs),
        indices: mesh.indices,
    })
}

/// Fans the polygon's corners (0, i, i + 1) into triangles of vertex indices.
fn fan(polygon: &[f64], indices: &mut Vec<[u32; 3]>) -> Result<(), String> {
    let index = |value: f64| {
        u32::try_from(value as i64)
            .ok()
            .filter(|_| value.fract() == 0.0)
            .ok_or_else(|| format!("face index {value} out of range"))
    };
    for i in 1..polygon.len().saturating_sub(1) {
        indices.push([
            index(polygon[0])?,
            index(polygon[i])?,
            index(polygon[i + 1])?,
        ]);
    }
    Ok(())
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Format {
    Ascii,
    Binary { big_endian: bool },
}

/// A property's value type.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    /// The type a header names (both the original names and the sized ones).
    fn named(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Debug)]
struct Property {
    name: String,
    kind: Kind,
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Parses the header: the format, the elements in file order, and where the body starts.
fn header(bytes: &[u8]) -> Result<(Format, Vec<Element>, usize), String> {
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    let (mut start, mut number) = (0, 0);
    loop {
        number += 1;
        let end = (bytes[start..].iter().position(|&b| b == b'\n'))
            .ok_or("the header does not end (no end_header line)")?;
        let line = std::str::from_utf8(&bytes[start..start + end])
            .map_err(|_| format!("header line {number} is not text"))?;
        start += end + 1;
        let err = |what: &str| format!("header line {number} (\"{}\"): {what}", line.trim());
        let mut words = line.split_ascii_whitespace();
        let keyword = words.next();
        if number == 1 {
            if keyword != Some("ply") || words.next().is_some() {
                return Err(err("not a PLY file (the first line is not \"ply\")"));
            }
            continue;
        }
        match keyword {
            Some("format") => {
                format = Some(match (words.next(), words.next()) {
                    (Some("ascii"), Some(_)) => Format::Ascii,
                    (Some("binary_little_endian"), Some(_)) => Format::Binary { big_endian: false },
                    (Some("binary_big_endian"), Some(_)) => Format::Binary { big_endian: true },
                    _ => return Err(err("an unknown format")),
                });
            }
            Some("element") => {
                let (Some(name), Some(count)) = (words.next(), words.next()) else {
                    return Err(err("an element needs a name and a count"));
                };
                let count = count
                    .parse()
                    .map_err(|_| err("a count that is not a number"))?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            Some("property") => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| err("a property before any element"))?;
                let type_of = |name: Option<&str>| {
                    name.and_then(Scalar::named)
                        .ok_or_else(|| err("an unknown property type"))
                };
                let first = words.next();
                let kind = if first == Some("list") {
                    let count = type_of(words.next())?;
                    let item = type_of(words.next())?;
                    if matches!(count, Scalar::F32 | Scalar::F64) {
                        return Err(err("a list counted by a floating-point type"));
                    }
                    Kind::List { count, item }
                } else {
                    Kind::Scalar(type_of(first)?)
                };
                let name = words
                    .next()
                    .ok_or_else(|| err("a property without a name"))?;
                element.properties.push(Property {
                    name: name.to_string(),
                    kind,
                });
            }
            Some("end_header") => {
                let format = format.ok_or("no format line before end_header")?;
                return Ok((format, elements, start));
            }
            Some("comment" | "obj_info") | None => {}
            Some(_) => return Err(err("an unknown header keyword")),
        }
    }
}

/// What a vertex property is for.
#[derive(Clone, Copy, PartialEq)]
enum Role {
    Position(usize),
    Normal(usize),
    Uv(usize),
    Other,
}

/// The role of each of the vertex element's properties.
struct VertexRoles {
    of: Vec<Role>,
    has_normals: bool,
    has_uvs: bool,
}

impl VertexRoles {
    fn new(vertex: &Element) -> Result<Self, String> {
        let scalar = |name: &str| {
            (vertex.properties.iter())
                .position(|p| p.name == name && matches!(p.kind, Kind::Scalar(_)))
        };
        let all = |names: &[&str]| names.iter().map(|&n| scalar(n)).collect::<Option<Vec<_>>>();
        let positions = all(&["x", "y", "z"]).ok_or("a vertex without x, y, z")?;
        let normals = all(&["nx", "ny", "nz"]);
        let uvs = UV_NAMES.iter().find_map(|&(u, v)| all(&[u, v]));
        let mut of = vec![Role::Other; vertex.properties.len()];
        for (axis, &p) in positions.iter().enumerate() {
            of[p] = Role::Position(axis);
        }
        for (axis, &p) in normals.iter().flatten().enumerate() {
            of[p] = Role::Normal(axis);
        }
        for (axis, &p) in uvs.iter().flatten().enumerate() {
            of[p] = Role::Uv(axis);
        }
        Ok(Self {
            of,
            has_normals: normals.is_some(),
            has_uvs: uvs.is_some(),
        })
    }
}

/// The mesh as it is read: the current vertex's values, then every vertex's and the triangles.
#[derive(Default)]
struct MeshArrays {
    position: Vec3,
    normal: Vec3,
    uv: Vec2,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    indices: Vec<[u32; 3]>,
}

impl MeshArrays {
    fn reserve(&mut self, vertices: usize, roles: &VertexRoles) {
        self.positions.reserve(vertices);
        if roles.has_normals {
            self.normals.reserve(vertices);
        }
        if roles.has_uvs {
            self.uvs.reserve(vertices);
        }
    }

    fn set(&mut self, role: Role, value: f32) {
        match role {
            Role::Position(axis) => self.position[axis] = value,
            Role::Normal(axis) => self.normal[axis] = value,
            Role::Uv(axis) => self.uv[axis] = value,
            Role::Other => {}
        }
    }

    fn end_vertex(&mut self, roles: &VertexRoles) {
        self.positions.push(self.position);
        if roles.has_normals {
            self.normals.push(self.normal);
        }
        if roles.has_uvs {
            self.uvs.push(self.uv);
        }
    }
}

/// The body's values in order: ASCII words, or binary numbers in the file's byte order.
enum Values<'a> {
    /// The rest of the body, read word by word (what follows the last value, which need not
    /// be text, is never looked at).
    Ascii(&'a [u8]),
    Binary {
        bytes: &'a [u8],
        big_endian: bool,
    },
}

impl Values<'_> {
    /// The next value, of type `ty`, as f64 (which holds every type's values exactly).
    fn scalar(&mut self, ty: Scalar) -> Result<f64, String> {
        match self {
            Values::Ascii(rest) => {
                let start = (rest.iter().position(|b| !b.is_ascii_whitespace()))
                    .ok_or("the file ends early")?;
                let len = (rest[start..].iter().position(u8::is_ascii_whitespace))
                    .unwrap_or(rest.len() - start);
                let word = &rest[start..start + len];
                *rest = &rest[start + len..];
                let word = std::str::from_utf8(word)
                    .map_err(|_| format!("{:?} is not text", String::from_utf8_lossy(word)))?;
                let bad = || format!("\"{word}\" is not a {ty:?} value");
                // Parsed as the declared type, then widened exactly.
                Ok(match ty {
                    Scalar::I8 => f64::from(word.parse::<i8>().map_err(|_| bad())?),
                    Scalar::U8 => f64::from(word.parse::<u8>().map_err(|_| bad())?),
                    Scalar::I16 => f64::from(word.parse::<i16>().map_err(|_| bad())?),
                    Scalar::U16 => f64::from(word.parse::<u16>().map_err(|_| bad())?),
                    Scalar::I32 => f64::from(word.parse::<i32>().map_err(|_| bad())?),
                    Scalar::U32 => f64::from(word.parse::<u32>().map_err(|_| bad())?),
                    Scalar::F32 => f64::from(word.parse::<f32>().map_err(|_| bad())?),
                    Scalar::F64 => word.parse::<f64>().map_err(|_| bad())?,
                })
            }
            Values::Binary { bytes, big_endian } => {
                macro_rules! take {
                    ($t:ty) => {{
                        const N: usize = std::mem::size_of::<$t>();
                        let (head, rest) = bytes
                            .split_first_chunk::<N>()
                            .ok_or("the file ends early")?;
                        *bytes = rest;
                        if *big_endian {
                            <$t>::from_be_bytes(*head)
                        } else {
                            <$t>::from_le_bytes(*head)
                        }
                    }};
                }
                Ok(match ty {
                    Scalar::I8 => f64::from(take!(i8)),
                    Scalar::U8 => f64::from(take!(u8)),
                    Scalar::I16 => f64::from(take!(i16)),
                    Scalar::U16 => f64::from(take!(u16)),
                    Scalar::I32 => f64::from(take!(i32)),
                    Scalar::U32 => f64::from(take!(u32)),
                    Scalar::F32 => f64::from(take!(f32)),
                    Scalar::F64 => take!(f64),
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reader foton had before, on `ply-rs`: the reference the hand-written one is held to.
    fn reference(bytes: &[u8]) -> Option<Geometry> {
        use ply_rs::parser::Parser;
        use ply_rs::ply::{DefaultElement, Property};
        let scalar = |element: &DefaultElement, key: &str| -> Option<f32> {
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
        };
        let ply =
            std::panic::catch_unwind(|| Parser::<DefaultElement>::new().read_ply(&mut &bytes[..]))
                .ok()?
                .ok()?;
        let vertices = ply.payload.get("vertex")?;
        let vec3 = |v: &DefaultElement, [x, y, z]: [&str; 3]| {
            Some(Vec3::new(scalar(v, x)?, scalar(v, y)?, scalar(v, z)?))
        };
        let positions: Option<Vec<Vec3>> =
            vertices.iter().map(|v| vec3(v, ["x", "y", "z"])).collect();
        let normals = vertices
            .iter()
            .map(|v| vec3(v, ["nx", "ny", "nz"]))
            .collect();
        let uvs = UV_NAMES.iter().find_map(|(u, v)| {
            (vertices.iter())
                .map(|e| Some(Vec2::new(scalar(e, u)?, scalar(e, v)?)))
                .collect()
        });
        let positions = positions?;
        let mut indices = Vec::new();
        for face in ply.payload.get("face")? {
            let list = face
                .get("vertex_indices")
                .or_else(|| face.get("vertex_index"))?;
            let polygon: Vec<i64> = match list {
                Property::ListChar(v) => v.iter().map(|&i| i64::from(i)).collect(),
                Property::ListUChar(v) => v.iter().map(|&i| i64::from(i)).collect(),
                Property::ListShort(v) => v.iter().map(|&i| i64::from(i)).collect(),
                Property::ListUShort(v) => v.iter().map(|&i| i64::from(i)).collect(),
                Property::ListInt(v) => v.iter().map(|&i| i64::from(i)).collect(),
                Property::ListUInt(v) => v.iter().map(|&i| i64::from(i)).collect(),
                _ => return None,
            };
            let vertex = |i: i64| {
                u32::try_from(i)
                    .ok()
                    .filter(|&i| (i as usize) < positions.len())
            };
            for i in 1..polygon.len().saturating_sub(1) {
                indices.push([
                    vertex(polygon[0])?,
                    vertex(polygon[i])?,
                    vertex(polygon[i + 1])?,
                ]);
            }
        }
        Some(Geometry::TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
        })
    }

    /// A mesh's values as bits, so that NaNs compare too. Without vertices, "no normals" and
    /// "no normals for no vertices" (the reference's answer then) are the same.
    fn bits(geometry: &Geometry) -> Vec<u32> {
        let Geometry::TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
        } = geometry
        else {
            panic!("a triangle mesh");
        };
        let vec3s = positions.iter().chain(normals.iter().flatten());
        let floats = (vec3s.flat_map(|v| v.to_array()))
            .chain(uvs.iter().flatten().flat_map(|v| v.to_array()));
        let given = |n: Option<usize>| u32::from(n.is_some_and(|n| n > 0));
        let flags = [
            given(normals.as_ref().map(Vec::len)),
            given(uvs.as_ref().map(Vec::len)),
        ];
        let counts = [positions.len() as u32, indices.len() as u32];
        (floats.map(f32::to_bits))
            .chain(indices.iter().flatten().copied())
            .chain(flags)
            .chain(counts)
            .collect()
    }

    /// A quad and a triangle with normals, uv (as s, t), a colour the reader skips and an
    /// element after the faces that it reads past, written in one of the three formats.
    fn mesh_file(format: &str) -> Vec<u8> {
        let positions = [
            [0.0f32, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.5],
            [0.0, 1.0, -0.25],
            [2.0, 0.5, 1e-3],
        ];
        let faces: [&[i32]; 2] = [&[0, 1, 2, 3], &[1, 4, 2]];
        let mut file = format!(
            "ply\nformat {format} 1.0\ncomment written by a test\nelement vertex 5\nproperty float x\n\
             property float y\nproperty double z\nproperty uchar red\nproperty float nx\nproperty float ny\n\
             property float nz\nproperty float s\nproperty float t\nelement face 2\n\
             property list uchar int vertex_indices\nproperty short flags\nelement material 1\n\
             property list ushort float weights\nend_header\n"
        )
        .into_bytes();
        let big = format == "binary_big_endian";
        let put = |file: &mut Vec<u8>, bytes: &[u8], text: String| {
            if format == "ascii" {
                file.extend(text.into_bytes());
                file.push(b' ');
            } else if big {
                file.extend(bytes.iter().rev());
            } else {
                file.extend(bytes);
            }
        };
        for (i, p) in positions.iter().enumerate() {
            let i = i as f32;
            let floats = [p[0], p[1]];
            for v in floats {
                put(&mut file, &v.to_le_bytes(), format!("{v:?}"));
            }
            put(
                &mut file,
                &f64::from(p[2]).to_le_bytes(),
                format!("{:?}", f64::from(p[2])),
            );
            put(&mut file, &[200], "200".into());
            for v in [0.0, i / 8.0, 1.0, 0.25 * i, 1.0 - 0.125 * i] {
                put(&mut file, &f32::to_le_bytes(v), format!("{v:?}"));
            }
            if format == "ascii" {
                file.push(b'\n');
            }
        }
        for face in faces {
            put(&mut file, &[face.len() as u8], face.len().to_string());
            for &i in face {
                put(&mut file, &i.to_le_bytes(), i.to_string());
            }
            put(&mut file, &(-7i16).to_le_bytes(), "-7".into());
            if format == "ascii" {
                file.push(b'\n');
            }
        }
        put(&mut file, &2u16.to_le_bytes(), "2".into());
        for w in [0.5f32, 2.0] {
            put(&mut file, &w.to_le_bytes(), format!("{w:?}"));
        }
        if format == "ascii" {
            file.push(b'\n');
        }
        file
    }

    /// Known answers: the three formats give the same mesh, the quad fanned into two
    /// triangles, the double z rounded to f32, and the reference reader agrees.
    #[test]
    fn every_format_reads_the_mesh_it_was_written_with() {
        let expected = Geometry::TriangleMesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.5),
                Vec3::new(0.0, 1.0, -0.25),
                Vec3::new(2.0, 0.5, 1e-3),
            ],
            normals: Some(
                (0..5)
                    .map(|i| Vec3::new(0.0, i as f32 / 8.0, 1.0))
                    .collect(),
            ),
            uvs: Some(
                (0..5)
                    .map(|i| Vec2::new(0.25 * i as f32, 1.0 - 0.125 * i as f32))
                    .collect(),
            ),
            indices: vec![[0, 1, 2], [0, 2, 3], [1, 4, 2]],
        };
        for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
            let file = mesh_file(format);
            let mesh = parse_bytes(&file).unwrap_or_else(|e| panic!("{format}: {e}"));
            assert_eq!(mesh, expected, "{format}");
            assert_eq!(reference(&file), Some(expected.clone()), "{format}, ply-rs");
        }
    }

    /// Every file the reference reads gives the same mesh, to the bit: the ray caster's binary
    /// torus (where it was written), the shared scenes' meshes (where `../shared` is present)
    /// and the fuzzer's corpus
    /// (whose inputs are mostly malformed: those the reference rejects need only not panic,
    /// which `tests/fuzz_corpus.rs` checks).
    #[test]
    fn agrees_with_the_reference_on_every_file_it_reads() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        // The torus is written by `scripts/raycast_scene.py`, not kept in the repository.
        let torus = root.join("scenes/raycast/torus.ply");
        let mut files = Vec::new();
        if torus.exists() {
            files.push(torus);
        } else {
            eprintln!("skipping the torus: run scripts/raycast_scene.py to write it");
        }
        let corpus = std::fs::read_dir(root.join("fuzz/corpus/ply")).expect("the PLY corpus");
        files.extend(corpus.map(|entry| entry.expect("a corpus entry").path()));
        let shared = root.join("../shared/scenes");
        for dir in [
            "luxrender/texture-examples",
            "mitsuba/mdata-hello/common/meshes",
        ] {
            match std::fs::read_dir(shared.join(dir)) {
                Ok(entries) => files.extend(
                    entries
                        .map(|entry| entry.expect("a directory entry").path())
                        .filter(|path| path.extension().is_some_and(|e| e == "ply")),
                ),
                Err(_) => eprintln!("skipping {}: ../shared is absent", dir),
            }
        }
        let mut compared = 0;
        for path in &files {
            let bytes = std::fs::read(path).expect("a readable file");
            if let Some(expected) = reference(&bytes) {
                let mesh =
                    parse_bytes(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                assert_eq!(bits(&mesh), bits(&expected), "{}", path.display());
                compared += 1;
            }
        }
        // At least the corpus's 11 well-formed inputs.
        assert!(compared >= 11, "{compared} files compared");
        eprintln!("{compared} of {} files compared", files.len());
    }

    /// Bad files are errors that say where: the header's line, the element and record.
    #[test]
    fn errors_say_where() {
        let error = |text: &[u8]| parse_bytes(text).expect_err("an error");
        let header = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n";
        assert!(error(b"plx\n").contains("line 1"));
        assert!(
            error(format!("{header}propertee float y\nend_header\n").as_bytes())
                .contains("header line 5")
        );
        assert!(error(format!("{header}property float y\n").as_bytes()).contains("end_header"));
        let mesh = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                    property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
        let e = error(format!("{mesh}0 0 0 1 0 0 0 1 0 3 0 1 7\n").as_bytes());
        assert!(e.contains("face index 7 out of range (3 vertices)"), "{e}");
        let e = error(format!("{mesh}0 0 0 1 0 0 0 1 0 3 0 1\n").as_bytes());
        assert!(
            e.contains("element \"face\", record 1 of 1") && e.contains("ends early"),
            "{e}"
        );
        let e = error(format!("{mesh}0 0 0 1 0 0 0 one 0 3 0 1 2\n").as_bytes());
        assert!(
            e.contains("element \"vertex\", record 3 of 3") && e.contains("\"one\""),
            "{e}"
        );
        let binary = mesh.replace("ascii", "binary_little_endian");
        let e = error(format!("{binary}\0\0\0").as_bytes());
        assert!(e.contains("element \"vertex\", record 1 of 3"), "{e}");
        assert!(
            error(b"ply\nformat ascii 1.0\nelement face 0\nend_header\n").contains("no \"vertex\"")
        );
    }
}
