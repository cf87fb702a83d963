//! Mitsuba's `.serialized` meshes (format described in mitsuba3 src/shapes/serialized.cpp): one or
//! more meshes, each a little-endian header (`0x041C`, version 3 or 4) followed by a zlib stream
//! holding flags, (version 4) a name, vertex and triangle counts, positions, optional normals,
//! uvs and colours (single or double precision), and the triangle indices (32-bit, or 64-bit above
//! 2^32 vertices). The file ends with the byte offset of every mesh (64-bit in version 4, 32-bit in
//! version 3) and their number (32-bit).

use std::io::Read;
use std::path::Path;

use flate2::read::ZlibDecoder;
use glam::{Vec2, Vec3};

use super::{MeshError, TriangleMesh};

const MAGIC: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x0001;
const HAS_UVS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const FACE_NORMALS: u32 = 0x0010;
const DOUBLE_PRECISION: u32 = 0x2000;

/// Reads mesh number `shape_index` of the file at `path`.
pub fn read_serialized(path: &Path, shape_index: usize) -> Result<TriangleMesh, MeshError> {
    let bytes = std::fs::read(path).map_err(|err| {
        MeshError::new(
            path,
            None,
            format!("cannot read serialized mesh file: {err}"),
        )
    })?;
    parse_serialized(&bytes, shape_index, path)
}

/// Mesh number `shape_index` of a `.serialized` file's bytes (named `path` in errors). A mesh
/// flagged for face normals is returned without its vertex normals.
pub fn parse_serialized(
    bytes: &[u8],
    shape_index: usize,
    path: &Path,
) -> Result<TriangleMesh, MeshError> {
    let fail =
        |message: String| MeshError::new(path, None, format!("mesh {shape_index}: {message}"));
    let u16_at = |at: usize| bytes_at(bytes, at).map(u16::from_le_bytes);
    let u32_at = |at: usize| bytes_at(bytes, at).map(u32::from_le_bytes);
    let u64_at = |at: usize| bytes_at(bytes, at).map(u64::from_le_bytes);
    if u16_at(0) != Some(MAGIC) {
        return Err(fail(
            "not a Mitsuba serialized mesh file (bad header)".into(),
        ));
    }
    let version = u16_at(2).unwrap_or(0);
    if version != 3 && version != 4 {
        return Err(fail(format!(
            "unsupported file version {version} (3 or 4 expected)"
        )));
    }
    let offset = if shape_index == 0 {
        0
    } else {
        let end = bytes.len();
        let count = end
            .checked_sub(4)
            .and_then(u32_at)
            .ok_or_else(|| fail("truncated file".into()))? as usize;
        if shape_index >= count {
            return Err(fail(format!(
                "out of range: the file holds meshes 0 to {}",
                count.saturating_sub(1)
            )));
        }
        let from_end = count - shape_index;
        let offset = if version == 4 {
            end.checked_sub(8 * from_end + 4)
                .and_then(u64_at)
                .map(|o| o as usize)
        } else {
            end.checked_sub(4 * (from_end + 1))
                .and_then(u32_at)
                .map(|o| o as usize)
        };
        offset
            .filter(|&o| u16_at(o) == Some(MAGIC))
            .ok_or_else(|| fail("corrupt end-of-file dictionary".into()))?
    };
    let data = (offset.checked_add(4))
        .and_then(|start| bytes.get(start..))
        .ok_or_else(|| fail("truncated file".into()))?;
    read_mesh(&mut ZlibDecoder::new(data), version)
        .map_err(|err| fail(format!("truncated or corrupt mesh data ({err})")))
}

/// The `N` bytes at offset `at`, or `None` past the end, also for an offset so large that the
/// end would overflow (a corrupt dictionary can name one).
fn bytes_at<const N: usize>(bytes: &[u8], at: usize) -> Option<[u8; N]> {
    bytes.get(at..at.checked_add(N)?)?.try_into().ok()
}

fn read_mesh(stream: &mut impl Read, version: u16) -> std::io::Result<TriangleMesh> {
    let flags = read_u32(stream)?;
    if version == 4 {
        // The mesh's name, null-terminated.
        let mut byte = [0u8];
        loop {
            stream.read_exact(&mut byte)?;
            if byte[0] == 0 {
                break;
            }
        }
    }
    let vertex_count = read_u64(stream)?;
    let face_count = read_u64(stream)?;
    let double = flags & DOUBLE_PRECISION != 0;
    let positions = read_floats(stream, vertex_count, 3, double)?;
    let normals = if flags & HAS_NORMALS != 0 {
        Some(read_floats(stream, vertex_count, 3, double)?)
    } else {
        None
    };
    let uvs = if flags & HAS_UVS != 0 {
        Some(read_floats(stream, vertex_count, 2, double)?)
    } else {
        None
    };
    if flags & HAS_COLORS != 0 {
        read_floats(stream, vertex_count, 3, double)?;
    }
    let wide = vertex_count > u64::from(u32::MAX);
    // The counts come from the file: reserve no more than a plausible amount up front, so a
    // corrupt count fails on the missing data instead of on the allocation.
    let mut indices = Vec::with_capacity(face_count.min(1 << 20) as usize);
    for _ in 0..face_count {
        let mut tri = [0u32; 3];
        for i in &mut tri {
            let v = if wide {
                read_u64(stream)?
            } else {
                read_u32(stream)? as u64
            };
            if v >= vertex_count {
                return Err(std::io::Error::other(format!(
                    "vertex index {v} of {vertex_count}"
                )));
            }
            *i = v as u32;
        }
        indices.push(tri);
    }
    let vec3s = |v: Vec<f32>| v.chunks_exact(3).map(Vec3::from_slice).collect();
    Ok(TriangleMesh {
        positions: vec3s(positions),
        normals: normals.filter(|_| flags & FACE_NORMALS == 0).map(vec3s),
        uvs: uvs.map(|v| v.chunks_exact(2).map(Vec2::from_slice).collect()),
        indices,
    })
}

fn read_u32(stream: &mut impl Read) -> std::io::Result<u32> {
    let mut b = [0u8; 4];
    stream.read_exact(&mut b)?;
    Ok(u32::from_le_bytes(b))
}

fn read_u64(stream: &mut impl Read) -> std::io::Result<u64> {
    let mut b = [0u8; 8];
    stream.read_exact(&mut b)?;
    Ok(u64::from_le_bytes(b))
}

/// `count` vectors of `dimension` floats (f64 or f32 in the file). The bytes are read as the
/// stream yields them rather than into a buffer of the announced size, so a corrupt count in a
/// short file is an error, not an attempt to allocate it.
fn read_floats(
    stream: &mut impl Read,
    count: u64,
    dimension: u64,
    double: bool,
) -> std::io::Result<Vec<f32>> {
    let size = if double { 8 } else { 4 };
    let bytes = (count.checked_mul(dimension * size))
        .ok_or_else(|| std::io::Error::other(format!("{count} vertices")))?;
    let mut raw = Vec::new();
    stream.take(bytes).read_to_end(&mut raw)?;
    if raw.len() as u64 != bytes {
        return Err(std::io::ErrorKind::UnexpectedEof.into());
    }
    Ok(if double {
        raw.chunks_exact(8)
            .map(|b| f64::from_le_bytes(b.try_into().unwrap()) as f32)
            .collect()
    } else {
        raw.chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use flate2::Compression;
    use flate2::write::ZlibEncoder;
    use std::io::Write;

    /// One mesh as Mitsuba writes it (version 4, single precision, 32-bit indices).
    fn mesh_bytes(
        name: &str,
        positions: &[[f32; 3]],
        uvs: Option<&[[f32; 2]]>,
        tris: &[[u32; 3]],
    ) -> Vec<u8> {
        let mut body = Vec::new();
        let flags = 0x1000 | if uvs.is_some() { HAS_UVS } else { 0 };
        body.extend(flags.to_le_bytes());
        body.extend(name.as_bytes());
        body.push(0);
        body.extend((positions.len() as u64).to_le_bytes());
        body.extend((tris.len() as u64).to_le_bytes());
        positions
            .iter()
            .flatten()
            .for_each(|v| body.extend(v.to_le_bytes()));
        uvs.into_iter()
            .flatten()
            .flatten()
            .for_each(|v| body.extend(v.to_le_bytes()));
        tris.iter()
            .flatten()
            .for_each(|i| body.extend(i.to_le_bytes()));
        let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
        z.write_all(&body).unwrap();
        let mut out = vec![0x1C, 0x04, 0x04, 0x00];
        out.extend(z.finish().unwrap());
        out
    }

    fn two_meshes() -> Vec<u8> {
        let a = mesh_bytes(
            "a",
            &[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            None,
            &[[0, 1, 2]],
        );
        let b = mesh_bytes(
            "b",
            &[[0.0; 3], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [2.0, 2.0, 0.0]],
            Some(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]),
            &[[0, 1, 2], [2, 1, 3]],
        );
        let mut file = a.clone();
        file.extend(&b);
        file.extend(0u64.to_le_bytes());
        file.extend((a.len() as u64).to_le_bytes());
        file.extend(2u32.to_le_bytes());
        file
    }

    #[test]
    fn shape_index_picks_the_mesh() {
        let file = two_meshes();
        let a = parse_serialized(&file, 0, Path::new("m.serialized")).unwrap();
        assert_eq!(a.positions.len(), 3);
        assert_eq!(a.indices, vec![[0, 1, 2]]);
        assert!(a.uvs.is_none() && a.normals.is_none());
        let b = parse_serialized(&file, 1, Path::new("m.serialized")).unwrap();
        assert_eq!(b.positions[3], Vec3::new(2.0, 2.0, 0.0));
        assert_eq!(b.indices[1], [2, 1, 3]);
        assert_eq!(b.uvs.unwrap()[3], Vec2::ONE);
    }

    #[test]
    fn errors_name_the_file_and_the_mesh() {
        let file = two_meshes();
        let err = parse_serialized(&file, 2, Path::new("m.serialized")).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("m.serialized: mesh 2: out of range"),
            "{err}"
        );
        let err = parse_serialized(&file[..16], 0, Path::new("m.serialized")).unwrap_err();
        assert!(err.message.contains("truncated"), "{err}");
        assert!(parse_serialized(b"PLY", 0, Path::new("m.serialized")).is_err());
    }

    /// A dictionary entry pointing at the last byte offset there is: reading the magic there
    /// overflowed the offset (a panic where overflow is checked, as in debug and fuzz builds;
    /// the `serialized` fuzzer found it).
    #[test]
    fn a_dictionary_offset_at_the_end_of_the_address_space_is_corrupt() {
        let mut file = two_meshes();
        let entries = file.len() - 4 - 16;
        file[entries + 8..entries + 16].copy_from_slice(&u64::MAX.to_le_bytes());
        let err = parse_serialized(&file, 1, Path::new("m.serialized")).unwrap_err();
        assert!(
            err.message.contains("corrupt end-of-file dictionary"),
            "{err}"
        );
    }
}
