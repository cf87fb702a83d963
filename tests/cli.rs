//! The binary end to end: what a user sees from `foton render`.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use foton::film::{read_exr, read_png_linear};

fn foton(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_foton"))
        .args(args)
        .output()
        .expect("the foton binary runs")
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("foton-cli-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn project_scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
        .display()
        .to_string()
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn renders_the_default_scene_to_png_and_exr() {
    let dir = temp_dir("default");
    for ext in ["png", "exr"] {
        let out = dir.join(format!("default.{ext}"));
        let output = foton(&[
            "render",
            &project_scene("default.lxs"),
            "-o",
            out.to_str().unwrap(),
            "--spp",
            "2",
            "--resolution",
            "40x30",
        ]);
        assert!(output.status.success(), "{}", stderr(&output));
        // The last line: wall time, samples per pixel, millions of paths per second.
        let last = stdout(&output);
        assert!(
            last.contains("2 spp") && last.contains("M paths/s"),
            "{last}"
        );
        let (w, h, pixels) = if ext == "png" {
            read_png_linear(&out).expect("a PNG")
        } else {
            read_exr(&out).expect("an EXR")
        };
        assert_eq!((w, h), (40, 30));
        assert!(pixels.iter().all(|p| p.is_finite()));
        assert!(pixels.iter().any(|p| p.max_element() > 0.0));
    }
}

#[test]
fn a_malformed_scene_is_an_error_naming_file_and_line_and_writes_nothing() {
    let dir = temp_dir("malformed");
    let scene = dir.join("broken.lxs");
    std::fs::write(
        &scene,
        "Camera \"perspective\"\nWorldBegin\nInclude \"missing.lxo\"\nWorldEnd\n",
    )
    .unwrap();
    let out = dir.join("broken.png");
    let output = foton(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!output.status.success());
    let message = stderr(&output);
    assert!(message.contains("broken.lxs:3"), "{message}");
    assert!(message.contains("missing.lxo"), "{message}");
    assert!(!message.contains("panicked"), "{message}");
    assert!(
        !out.exists(),
        "no image may be written for a scene that failed"
    );
}

#[test]
fn an_unknown_output_format_is_an_error() {
    let dir = temp_dir("format");
    let out = dir.join("image.tiff");
    let output = foton(&[
        "render",
        &project_scene("default.lxs"),
        "-o",
        out.to_str().unwrap(),
        "--spp",
        "1",
        "--resolution",
        "8x8",
    ]);
    assert!(!output.status.success());
    assert!(
        stderr(&output).contains("image.tiff"),
        "{}",
        stderr(&output)
    );
}

/// The course's scenes with their geometry render; those whose geometry is missing upstream
/// fail with an error naming the missing file and the line that includes it.
#[test]
fn course_scenes_render_or_fail_clearly() {
    let Some(itba) = common::shared_scenes() else {
        return;
    };
    let dir = temp_dir("course");
    for scene in [
        "CornellBox/cornell-box.lxs",
        "CornellBoxSphere/cornell-box.lxs",
        "metal2_scene/untitled.lxs",
        "pikachu/untitled.lxs",
        "charizard/untitled.lxs",
        "scene_2/scene_2.lxs",
    ] {
        let out = dir.join(scene.replace('/', "_")).with_extension("png");
        let output = foton(&[
            "render",
            itba.join(scene).to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--spp",
            "2",
            "--resolution",
            "64x36",
        ]);
        assert!(output.status.success(), "{scene}: {}", stderr(&output));
        assert!(out.exists(), "{scene}");
    }
    for (scene, missing) in [
        ("scene_hard/scene_hard.lxs", "scene_hard.lxo"),
        ("scene_1/scene_1.lxs", "scene_1.lxo"),
        ("scene_3/scene_3.lxs", "scene_3.lxo"),
        ("glass_bunny/glass_bunny.lxs", "LuxRender-Geometry.lxo"),
        ("Dragon/dragon.lxs", "LuxRender-Geometry.lxo"),
        ("Sponza/sponza.lxs", "LuxRender-Geometry.lxo"),
    ] {
        let out = dir.join("missing.png");
        let output = foton(&[
            "render",
            itba.join(scene).to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(!output.status.success(), "{scene} must fail");
        let message = stderr(&output);
        let file = Path::new(scene).file_name().unwrap().to_str().unwrap();
        assert!(message.contains(&format!("{file}:")), "{scene}: {message}");
        assert!(message.contains(missing), "{scene}: {message}");
        assert!(!out.exists());
    }
}
