//! The Mitsuba XML loader and the world built from what it reads, on arbitrary scene text.
//! Errors are fine; a panic, an abort or a hang is a finding.
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use foton::scene::build::{RenderOptions, build_world};
use foton::scene;
use libfuzzer_sys::fuzz_target;

/// One scratch folder per fuzzing process: the scene is read from a file, as `foton render` does,
/// so that includes and relative paths take the real code path.
fn scene_path() -> &'static PathBuf {
    static PATH: OnceLock<PathBuf> = OnceLock::new();
    PATH.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("foton-fuzz-xml-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a scratch folder");
        dir.join("scene.xml")
    })
}

fuzz_target!(|data: &[u8]| {
    let path = scene_path();
    std::fs::write(path, data).expect("the scratch file is writable");
    if let Ok(desc) = scene::load(path) {
        // A tiny film: the fuzzer looks for crashes in building, not for large allocations.
        let options = RenderOptions {
            resolution: Some((4, 4)),
            samples_per_pixel: Some(1),
            ..RenderOptions::default()
        };
        let _ = build_world(desc, &options);
    }
});
