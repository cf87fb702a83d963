//! Finding the files a scene names: next to the naming file, else in its parent folders.

use std::path::{Path, PathBuf};

/// Where `name` was found, and whether that was above `dir` (worth a warning).
pub struct Resolved {
    pub path: PathBuf,
    pub found_in_parent: bool,
}

/// Looks for `name` in `dir` (the folder of the file that names it), then in each parent of
/// `dir` in turn. The error says where it looked.
pub fn resolve(name: &str, dir: &Path) -> Result<Resolved, String> {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let direct = dir.join(name);
    if direct.is_file() {
        return Ok(Resolved {
            path: direct,
            found_in_parent: false,
        });
    }
    let absolute = std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf());
    absolute
        .ancestors()
        .skip(1)
        .map(|ancestor| ancestor.join(name))
        .find(|candidate| candidate.is_file())
        .map(|path| Resolved {
            path,
            found_in_parent: true,
        })
        .ok_or_else(|| {
            format!(
                "file not found (looked in {} and its parent folders)",
                absolute.display()
            )
        })
}
