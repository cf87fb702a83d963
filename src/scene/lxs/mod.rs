//! The LuxRender scene format (`.lxs`, with `.lxm`/`.lxo` includes), as LuxBlend writes it and
//! as the course's scenes extend it.

mod camera;
mod car_paint;
mod film;
mod glossy_translucent;
mod lights;
mod materials;
mod measured;
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
pub mod version;
mod volumes;

use std::path::Path;

use crate::scene::desc::{Location, SceneDesc, SceneError, SceneWarning};
use version::LuxVersion;

/// Loads the scene at `path` and the files it includes. Anything skipped or read loosely is in
/// `SceneDesc::warnings`; anything that would make the image wrong is an error.
pub fn load(path: &Path) -> Result<SceneDesc, SceneError> {
    parser::parse(path, None)
}

/// [`load`] with the command line's `-D name=value` scene parameters. The format has one:
/// `lux_version`, the LuxRender release to read the scene as (`version.rs`); any other is a
/// warning, as is a version that does not read as major.minor.
pub fn load_with(path: &Path, defines: &[(String, String)]) -> Result<SceneDesc, SceneError> {
    let mut warnings = Vec::new();
    let mut version = None;
    for (name, value) in defines {
        let parsed = (name == version::OVERRIDE_PARAMETER)
            .then(|| LuxVersion::parse(value))
            .flatten();
        match parsed {
            Some(parsed) => version = Some(parsed),
            None => warnings.push(SceneWarning {
                location: Location::line(path, 0),
                message: if name == version::OVERRIDE_PARAMETER {
                    format!("-D {name}={value}: not a version such as 0.6 or 1.6, ignored")
                } else {
                    format!(
                        "-D {name}={value}: this format's only scene parameter is {}, ignored",
                        version::OVERRIDE_PARAMETER
                    )
                },
            }),
        }
    }
    let mut desc = parser::parse(path, version)?;
    desc.warnings.extend(warnings);
    Ok(desc)
}
