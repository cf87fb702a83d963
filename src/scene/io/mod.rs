//! File readers every scene format shares: meshes and images. They know no format's scene
//! language; each returns a message saying what is wrong with the file, which the loader wraps
//! with the scene file and line that named it. Meshes (OBJ, PLY, Mitsuba's `.serialized`) read
//! into a format-neutral [`TriangleMesh`] (OBJ and `.serialized`) or the description's geometry.

pub mod image;
pub mod obj;
pub mod ply;
pub mod serialized;

use std::fmt;
use std::path::PathBuf;

use glam::{Vec2, Vec3};

/// An indexed triangle mesh as a file stores it (object space, nothing transformed or flipped).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex normals, if the file has them.
    pub normals: Option<Vec<Vec3>>,
    /// Per-vertex texture coordinates, if the file has them.
    pub uvs: Option<Vec<Vec2>>,
    pub indices: Vec<[u32; 3]>,
}

/// A mesh file could not be read: which file, where in it if that means something, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshError {
    pub path: PathBuf,
    /// 1-based line, for text formats.
    pub line: Option<usize>,
    pub message: String,
}

impl MeshError {
    pub fn new(path: impl Into<PathBuf>, line: Option<usize>, message: impl Into<String>) -> Self {
        Self {
            path: path.into(),
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{line}: {}", self.path.display(), self.message),
            None => write!(f, "{}: {}", self.path.display(), self.message),
        }
    }
}

impl std::error::Error for MeshError {}
