//! File readers every scene format shares: meshes and images. They know no format's scene
//! language; each returns a message saying what is wrong with the file, which the loader wraps
//! with the scene file and line that named it.

pub mod image;
pub mod ply;
