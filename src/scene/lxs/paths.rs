//! Finding the files a scene names: next to the naming file, then next to the main `.lxs`
//! (LuxRender's own rule: LuxBlend 2.5 names PLY and image files relative to the main file, even
//! from an included `.lxo`), else in the naming file's parent folders.

use std::path::{Path, PathBuf};

/// Where `name` was found, and whether that was above `dir` (worth a warning).
pub struct Resolved {
    pub path: PathBuf,
    pub found_in_parent: bool,
}

/// Looks for `name` in `dir` (the folder of the file that names it), then in `main_dir` (the
/// main scene file's folder), then in each parent of `dir` in turn. The error says where it
/// looked.
pub fn resolve(name: &str, dir: &Path, main_dir: &Path) -> Result<Resolved, String> {
    let or_current = |dir: &'_ Path| -> PathBuf {
        if dir.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            dir.to_path_buf()
        }
    };
    let dir = &or_current(dir);
    if let Some(path) = [dir.join(name), or_current(main_dir).join(name)]
        .into_iter()
        .find(|candidate| candidate.is_file())
    {
        return Ok(Resolved {
            path,
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
