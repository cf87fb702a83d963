//! Replays the fuzzers' corpora and the inputs that once crashed them (fuzz/corpus/TARGET and
//! fuzz/regressions/TARGET) through the same code as the fuzz targets: each must give a result
//! or an error, never a panic.

use std::path::{Path, PathBuf};

use foton::scene::build::{RenderOptions, build_world};
use foton::scene::desc::{SceneDesc, SceneError};
use foton::scene::io::{obj, ply, serialized};
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

/// Replays a scene fuzzer's inputs as its target does: each written to a scene file named
/// `file_name` in a scratch folder, loaded by `load`, and built at 4x4 if it loads.
fn replay_scenes(target: &str, file_name: &str, load: fn(&Path) -> Result<SceneDesc, SceneError>) {
    let inputs = inputs(target);
    assert!(!inputs.is_empty(), "fuzz/corpus/{target} is empty");
    let dir =
        std::env::temp_dir().join(format!("foton-fuzz-replay-{target}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let scene = dir.join(file_name);
    for (path, bytes) in inputs {
        std::fs::write(&scene, &bytes).expect("the scratch file");
        let replay = std::panic::catch_unwind(|| {
            if let Ok(desc) = load(&scene) {
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
fn lxs_corpus_replays_without_panics() {
    replay_scenes("lxs", "scene.lxs", lxs::load);
}

#[test]
fn xml_corpus_replays_without_panics() {
    replay_scenes("xml", "scene.xml", foton::scene::load);
}

/// Replays a reader fuzzer's inputs as its target does: `read` on each input's bytes.
fn replay_bytes(target: &str, read: impl Fn(&[u8]) + std::panic::RefUnwindSafe) {
    let inputs = inputs(target);
    assert!(!inputs.is_empty(), "fuzz/corpus/{target} is empty");
    for (path, bytes) in inputs {
        let replay = std::panic::catch_unwind(|| read(&bytes));
        assert!(replay.is_ok(), "{} panics", path.display());
    }
}

#[test]
fn ply_corpus_replays_without_panics() {
    replay_bytes("ply", |bytes| {
        let _ = ply::parse(&mut &bytes[..]);
    });
}

#[test]
fn obj_corpus_replays_without_panics() {
    replay_bytes("obj", |bytes| {
        if let Ok(text) = std::str::from_utf8(bytes) {
            let _ = obj::parse_obj(text, Path::new("fuzz.obj"));
        }
    });
}

#[test]
fn serialized_corpus_replays_without_panics() {
    replay_bytes("serialized", |bytes| {
        for shape_index in [0, 1] {
            let _ = serialized::parse_serialized(bytes, shape_index, Path::new("fuzz.serialized"));
        }
    });
}
