//! The registries: scene formats by file extension (`scene::LOADERS`), cameras by name
//! (`camera::CAMERAS`), and the command line's `--camera`, which takes its values from the latter.

use std::path::Path;

use foton::camera::{self, CAMERAS};

use crate::common::{foton, temp_dir};

const WORLD: &str = "WorldBegin\nWorldEnd\n";

#[test]
fn scene_load_picks_the_loader_by_extension() {
    let dir = temp_dir("formats");
    let upper = dir.join("upper.LXS");
    std::fs::write(&upper, WORLD).unwrap();
    assert!(
        foton::scene::load(&upper).is_ok(),
        "the extension in any case"
    );
    for (name, found) in [
        ("scene.obj", "extension \".obj\""),
        ("scene", "no extension"),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, WORLD).unwrap();
        let e = foton::scene::load(&path).unwrap_err();
        assert_eq!(e.location.file, path);
        assert!(e.message.contains(found), "{e}");
        for (extensions, _) in foton::scene::LOADERS {
            for extension in *extensions {
                assert!(e.message.contains(&format!(".{extension}")), "{e}");
            }
        }
    }
}

#[test]
fn every_camera_name_finds_its_camera_in_any_case() {
    let mut seen = Vec::new();
    for camera in CAMERAS {
        for name in camera.names {
            assert_eq!(camera::find(name), Some(*camera), "{name}");
            assert_eq!(camera::find(&name.to_uppercase()), Some(*camera), "{name}");
            assert!(!seen.contains(&name.to_lowercase()), "{name} twice");
            seen.push(name.to_lowercase());
        }
    }
    assert_eq!(camera::find("no-such-camera"), None);
}

#[test]
fn the_camera_option_takes_exactly_the_registry_names() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell.lxs");
    let scene = scene.to_str().unwrap();
    let help = String::from_utf8_lossy(&foton(&["render", "--help"]).stdout).into_owned();
    let refused = foton(&["render", scene, "--camera", "no-such-camera"]);
    assert!(!refused.status.success());
    let refusal = String::from_utf8_lossy(&refused.stderr).into_owned();
    let dir = temp_dir("cameras");
    for name in camera::names() {
        assert!(help.contains(name), "--help does not list {name}: {help}");
        assert!(
            refusal.contains(name),
            "the error does not list {name}: {refusal}"
        );
        let output = dir.join(format!("{name}.exr"));
        let rendered = foton(&[
            "render",
            scene,
            "--camera",
            name,
            "--spp",
            "1",
            "--resolution",
            "8x6",
            "-o",
            output.to_str().unwrap(),
        ]);
        assert!(
            rendered.status.success(),
            "--camera {name}: {}",
            String::from_utf8_lossy(&rendered.stderr)
        );
    }
}
