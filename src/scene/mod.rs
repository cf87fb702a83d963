//! Scene loading: one loader per format, each producing a [`desc::SceneDesc`], chosen by the
//! file's extension in [`LOADERS`].

pub mod build;
pub mod desc;
pub mod io;
pub mod lxs;
pub mod mitsuba;

use std::path::Path;

use desc::{Location, SceneDesc, SceneError};

/// Reads a scene file, and the files it names, into a description; the pairs are the command
/// line's `-D name=value` scene parameters.
pub type Loader = fn(&Path, &[(String, String)]) -> Result<SceneDesc, SceneError>;

/// Every scene format: the file extensions it takes (lower case, without the dot) and its
/// loader. One line per format.
pub const LOADERS: &[(&[&str], Loader)] =
    &[(&["lxs"], lxs::load_with), (&["xml"], mitsuba::load_with)];

/// Loads the scene at `path` with the loader its extension names (in any case).
pub fn load(path: &Path) -> Result<SceneDesc, SceneError> {
    load_with(path, &[])
}

/// [`load`] with `-D name=value` scene parameters (Mitsuba's `$name`).
pub fn load_with(path: &Path, defines: &[(String, String)]) -> Result<SceneDesc, SceneError> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let loader = LOADERS
        .iter()
        .find(|(extensions, _)| extensions.contains(&extension.as_str()))
        .map(|(_, loader)| loader);
    match loader {
        Some(loader) => loader(path, defines),
        None => {
            let known: Vec<String> = LOADERS
                .iter()
                .flat_map(|(extensions, _)| extensions.iter().map(|e| format!(".{e}")))
                .collect();
            let found = if extension.is_empty() {
                "no extension".to_string()
            } else {
                format!("extension \".{extension}\"")
            };
            Err(SceneError {
                location: Location::line(path, 0),
                message: format!(
                    "unknown scene format ({found}): the known extensions are {}",
                    known.join(", ")
                ),
            })
        }
    }
}
