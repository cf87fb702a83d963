//! The LuxRender scene format (`.lxs`, with `.lxm`/`.lxo` includes), as LuxBlend writes it and
//! as the course's scenes extend it.

mod camera;
mod car_paint;
mod glossy_translucent;
mod lights;
mod materials;
mod nk;
mod objects;
mod params;
mod parser;
mod paths;
mod quadrics;
mod shapes;
mod sky;
mod sun;
mod textures;
mod tokenizer;
mod volumes;

use std::path::Path;

use crate::scene::desc::{SceneDesc, SceneError};

/// Loads the scene at `path` and the files it includes. Anything skipped or read loosely is in
/// `SceneDesc::warnings`; anything that would make the image wrong is an error.
pub fn load(path: &Path) -> Result<SceneDesc, SceneError> {
    parser::parse(path)
}
