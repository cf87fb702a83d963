//! Replays the fuzzers' corpora and the inputs that once crashed them (fuzz/corpus/TARGET and
//! fuzz/regressions/TARGET) through the same code as the fuzz targets: each must give a result
//! or an error, never a panic.

use std::path::{Path, PathBuf};

use foton::scene::build::{RenderOptions, build_world};
use foton::scene::io::ply;
use foton::scene::lxs;

/// The inputs of one fuzz target, with their paths.
fn inputs(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let fuzz = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let mut found = Vec::new();
    for folder in ["corpus", "regressions"] {
        let Ok(entries) = std::fs::read_dir(fuzz.join(folder).join(target)) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let bytes = std::fs::read(&path).expect("a corpus file");
            found.push((path, bytes));
        }
    }
    found.sort();
    found
}

#[test]
fn lxs_corpus_replays_without_panics() {
    let inputs = inputs("lxs");
    assert!(!inputs.is_empty(), "fuzz/corpus/lxs is empty");
    let dir = std::env::temp_dir().join(format!("foton-fuzz-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let scene = dir.join("scene.lxs");
    for (path, bytes) in inputs {
        std::fs::write(&scene, &bytes).expect("the scratch file");
        let replay = std::panic::catch_unwind(|| {
            if let Ok(desc) = lxs::load(&scene) {
                let options = RenderOptions {
                    resolution: Some((4, 4)),
                    samples_per_pixel: Some(1),
                    ..RenderOptions::default()
                };
                let _ = build_world(desc, &options);
            }
        });
        assert!(replay.is_ok(), "{} panics", path.display());
    }
}

#[test]
fn ply_corpus_replays_without_panics() {
    let inputs = inputs("ply");
    assert!(!inputs.is_empty(), "fuzz/corpus/ply is empty");
    for (path, bytes) in inputs {
        let replay = std::panic::catch_unwind(|| ply::parse(&mut &bytes[..]));
        assert!(replay.is_ok(), "{} panics", path.display());
    }
}
