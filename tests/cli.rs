//! The binary end to end: what a user sees from `foton render`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use foton::film::{read_exr, read_png_linear};

use crate::common::{self, foton, stderr, stdout, temp_dir};

fn project_scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
        .display()
        .to_string()
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

fn code(output: &Output) -> Option<i32> {
    output.status.code()
}

/// A small scene written by a test: a lit floor seen from above (or `body` in its world).
fn write_scene(dir: &Path, name: &str, body: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(
        &path,
        format!(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [40]\n\
             Film \"fleximage\" \"integer xresolution\" [16] \"integer yresolution\" [12]\n\
             WorldBegin\n{body}\nWorldEnd\n"
        ),
    )
    .unwrap();
    path
}

const LIT_FLOOR: &str = "LightSource \"point\" \"point from\" [0 0 3] \"color L\" [10 10 10]\n\
    Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \
    \"point P\" [-2 -2 0 2 -2 0 2 2 0 -2 2 0]";

/// The output is checked before the scene is even read: a broken scene with a bad output is an
/// output error (3), not a scene error (1), and nothing is rendered.
#[test]
fn the_output_is_checked_before_loading() {
    let dir = temp_dir("output-first");
    let broken = dir.join("broken.lxs");
    std::fs::write(&broken, "WorldBegin\nBogus [\n").unwrap();
    std::fs::create_dir_all(dir.join("folder.png")).unwrap();
    for (out, says) in [
        (dir.join("x.tiff"), "unsupported image format"),
        (dir.join("missing/x.png"), "does not exist"),
        (dir.join("folder.png"), "is a folder"),
    ] {
        let output = foton(&[
            "render",
            broken.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code(&output), Some(3), "{}", stderr(&output));
        assert!(stderr(&output).contains(says), "{}", stderr(&output));
    }
    let output = foton(&[
        "render",
        broken.to_str().unwrap(),
        "-o",
        dir.join("ok.png").to_str().unwrap(),
    ]);
    assert_eq!(code(&output), Some(1), "{}", stderr(&output));
}

/// Sizes that cannot fit are refused with both figures, never an abort.
#[test]
fn renders_too_large_for_memory_are_refused() {
    let dir = temp_dir("memory");
    let out = dir.join("big.png");
    let output = foton(&[
        "render",
        &project_scene("default.lxs"),
        "-o",
        out.to_str().unwrap(),
        "--resolution",
        "65536x65536",
    ]);
    assert_eq!(code(&output), Some(4), "{}", stderr(&output));
    let message = stderr(&output);
    assert!(
        message.contains("65536x65536") && message.contains("available"),
        "{message}"
    );
    let huge = dir.join("huge.lxs");
    std::fs::write(
        &huge,
        format!(
            "Film \"fleximage\" \"integer xresolution\" [2000000] \"integer yresolution\" [2000000]\n\
             WorldBegin\n{LIT_FLOOR}\nWorldEnd\n"
        ),
    )
    .unwrap();
    let output = foton(&[
        "render",
        huge.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code(&output), Some(4), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("2000000x2000000"),
        "{}",
        stderr(&output)
    );
    assert!(!out.exists());
}

/// An empty scene is an error; a scene without lights renders, with a warning.
#[test]
fn empty_scenes_fail_and_unlit_scenes_warn() {
    let dir = temp_dir("empty");
    let empty = dir.join("empty.lxs");
    std::fs::write(&empty, "").unwrap();
    let out = dir.join("out.png");
    let output = foton(&[
        "render",
        empty.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code(&output), Some(1), "{}", stderr(&output));
    assert!(stderr(&output).contains("empty.lxs") && stderr(&output).contains("empty"));
    assert!(!out.exists());
    let unlit = write_scene(&dir, "unlit.lxs", "Shape \"sphere\" \"float radius\" [1]");
    let output = foton(&[
        "render",
        unlit.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--spp",
        "1",
    ]);
    assert_eq!(code(&output), Some(0), "{}", stderr(&output));
    assert!(stderr(&output).contains("no lights"), "{}", stderr(&output));
}

/// Starts a long render, waits until it renders (its `--verbose` description is printed just
/// before), sends `signal`, and returns what it printed and its exit code.
fn interrupted(
    args: &[&str],
    signal: &str,
    wait_for_stdout_line: bool,
) -> (Output, Option<String>) {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_foton"))
        .args(args)
        .arg("--verbose")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the foton binary runs");
    let mut first_line = None;
    if wait_for_stdout_line {
        let mut line = String::new();
        BufReader::new(child.stdout.as_mut().unwrap())
            .read_line(&mut line)
            .unwrap();
        first_line = Some(line);
    } else {
        let mut stderr = BufReader::new(child.stderr.take().unwrap());
        let mut line = String::new();
        while stderr.read_line(&mut line).unwrap() > 0 && !line.contains("schedule") {
            line.clear();
        }
        std::thread::spawn(move || std::io::copy(&mut stderr, &mut std::io::sink()));
    }
    let status = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    (child.wait_with_output().unwrap(), first_line)
}

/// SIGINT and SIGTERM keep the samples done: the image is written, the count said, the exit
/// code 130 or 143; the checkpoint written with it resumes.
#[test]
fn interrupts_write_the_image_and_exit_130_or_143() {
    let dir = temp_dir("interrupt");
    for (signal, exit) in [("-INT", 130), ("-TERM", 143)] {
        let out = dir.join(format!("interrupted{signal}.exr"));
        let (output, _) = interrupted(
            &[
                "render",
                &project_scene("default.lxs"),
                "-o",
                out.to_str().unwrap(),
                "--spp",
                "100000",
                "--resolution",
                "16x16",
            ],
            signal,
            false,
        );
        assert_eq!(code(&output), Some(exit), "{signal}");
        let (w, h, pixels) = read_exr(&out).expect("the interrupted render's image");
        assert_eq!((w, h), (16, 16));
        assert!(pixels.iter().any(|p| p.max_element() > 0.0));
        assert!(
            dir.join(format!("interrupted{signal}.exr.checkpoint"))
                .exists()
        );
    }
}

/// `--repeat` interrupted after its first render keeps the first, complete image.
#[test]
fn an_interrupted_repeat_keeps_the_complete_image() {
    let dir = temp_dir("repeat");
    let out = dir.join("repeat.exr");
    let args = [
        "render",
        &project_scene("default.lxs"),
        "-o",
        out.to_str().unwrap(),
        "--spp",
        "4",
        "--resolution",
        "16x16",
        "--repeat",
        "1000",
    ];
    let (output, first) = interrupted(&args, "-INT", true);
    assert!(first.unwrap_or_default().contains("4 spp"));
    assert_eq!(code(&output), Some(130), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("keeps the image"),
        "{}",
        stderr(&output)
    );
    // The kept image is a complete 4-spp render: the same as a fresh one.
    let fresh = dir.join("fresh.exr");
    let mut fresh_args = args[..8].to_vec();
    fresh_args[3] = fresh.to_str().unwrap();
    assert!(foton(&fresh_args).status.success());
    assert_eq!(read_exr(&out).unwrap().2, read_exr(&fresh).unwrap().2);
}

/// Renders the diffuse Cornell box at 24x16, 6 spp, seed 7 (and `extra`) to `out`; its pixels.
fn render_exr(out: &Path, extra: &[&str]) -> Vec<glam::Vec3> {
    let mut args = vec![
        "render",
        project_scene_static(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
        "--spp",
        "6",
        "--resolution",
        "24x16",
        "--seed",
        "7",
    ];
    args.extend_from_slice(extra);
    let output = foton(&args);
    assert!(output.status.success(), "{}", stderr(&output));
    read_exr(out).expect("an EXR").2
}

fn project_scene_static() -> &'static str {
    concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell-diffuse.lxs")
}

/// The same seed and spp give the same image to the bit with 1 and 2 threads, across runs, and
/// after stopping (here at the time limit, which writes a checkpoint) and `--resume`.
#[test]
fn images_are_bit_identical_across_threads_runs_and_resume() {
    let dir = temp_dir("determinism");
    let one = render_exr(&dir.join("one.exr"), &["--threads", "1"]);
    let two = render_exr(&dir.join("two.exr"), &["--threads", "2"]);
    let again = render_exr(&dir.join("again.exr"), &["--threads", "2"]);
    assert!(one == two && two == again);
    let part = dir.join("part.exr");
    let partial = render_exr(&part, &["--time-limit", "0", "--checkpoint", "1000"]);
    assert_ne!(partial, one, "the time limit stops after the first pass");
    let checkpoint = dir.join("part.exr.checkpoint");
    assert!(checkpoint.exists());
    let resumed = render_exr(
        &dir.join("resumed.exr"),
        &["--resume", checkpoint.to_str().unwrap()],
    );
    assert!(
        resumed == one,
        "a resumed render differs from an uninterrupted one"
    );
    // A checkpoint of another seed is refused.
    let output = foton(&[
        "render",
        project_scene_static(),
        "-o",
        dir.join("x.exr").to_str().unwrap(),
        "--resolution",
        "24x16",
        "--resume",
        checkpoint.to_str().unwrap(),
    ]);
    assert_eq!(code(&output), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("--seed 7"), "{}", stderr(&output));
}

/// `--crop` renders only its window, to the same values the full render has there; `--pixel`
/// prints one pixel's value.
#[test]
fn crop_and_pixel_render_part_of_the_image() {
    let dir = temp_dir("crop");
    let full = render_exr(&dir.join("full.exr"), &[]);
    let crop = render_exr(&dir.join("crop.exr"), &["--crop", "3,11,5,9"]);
    let expected: Vec<glam::Vec3> = (5..9)
        .flat_map(|y| (3..11).map(move |x| (x, y)))
        .map(|(x, y)| full[y * 24 + x])
        .collect();
    assert_eq!(crop, expected);
    assert_eq!(read_exr(&dir.join("crop.exr")).unwrap().0, 8);
    let output = foton(&[
        "render",
        project_scene_static(),
        "-o",
        dir.join("p.exr").to_str().unwrap(),
        "--spp",
        "6",
        "--resolution",
        "24x16",
        "--seed",
        "7",
        "--pixel",
        "12,8",
    ]);
    let p = full[8 * 24 + 12];
    assert!(
        stdout(&output).contains(&format!("pixel (12, 8): {} {} {}", p.x, p.y, p.z)),
        "{}",
        stdout(&output)
    );
    let output = foton(&[
        "render",
        project_scene_static(),
        "--resolution",
        "24x16",
        "--crop",
        "0,25,0,1",
    ]);
    assert_eq!(code(&output), Some(2), "{}", stderr(&output));
}

/// Exposure is a positive multiplier (or stops); it scales linear outputs too.
#[test]
fn exposure_is_validated_and_applied() {
    let dir = temp_dir("exposure");
    for bad in ["-1", "0", "nan"] {
        let output = foton(&["render", project_scene_static(), "--exposure", bad]);
        assert_eq!(code(&output), Some(2), "{bad}: {}", stderr(&output));
        let message = stderr(&output);
        assert!(
            message.contains("expected a positive multiplier") && !message.contains("use '--"),
            "{message}"
        );
    }
    let plain = render_exr(&dir.join("plain.exr"), &[]);
    let doubled = render_exr(&dir.join("doubled.exr"), &["--exposure", "2"]);
    let stops = render_exr(&dir.join("stops.exr"), &["--exposure-stops", "-1"]);
    for ((p, d), s) in plain.iter().zip(&doubled).zip(&stops) {
        assert_eq!(*p * 2.0, *d);
        assert_eq!(*p * 0.5, *s);
    }
}

/// `--json` prints why the render stopped, spp, time, rates, warnings and rejected samples.
#[test]
fn json_summary_and_quiet() {
    let dir = temp_dir("json");
    let scene = write_scene(&dir, "s.lxs", &format!("Sampler \"sobolx\"\n{LIT_FLOOR}"));
    let output = foton(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        dir.join("s.png").to_str().unwrap(),
        "--spp",
        "3",
        "--json",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let json = stdout(&output);
    for field in [
        "\"stopped\": \"done\"",
        "\"spp\": 3",
        "\"seconds\": ",
        "\"rays_per_second\": ",
        "\"warnings\": 1",
        "\"rejected_samples\": 0",
    ] {
        assert!(json.contains(field), "{field}: {json}");
    }
    assert_eq!(json.lines().count(), 1, "{json}");
    let output = foton(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        dir.join("q.png").to_str().unwrap(),
        "--spp",
        "1",
        "--quiet",
    ]);
    assert!(
        output.status.success() && stdout(&output).is_empty(),
        "{}",
        stdout(&output)
    );
}

/// Scenes exported as `untitled.lxs` get their folder's name, so they do not overwrite each other.
#[test]
fn default_output_names_do_not_collide() {
    let dir = temp_dir("names");
    let scene = write_scene(&dir, "pikachu/untitled.lxs", LIT_FLOOR);
    let output = Command::new(env!("CARGO_BIN_EXE_foton"))
        .args(["render", scene.to_str().unwrap(), "--spp", "1", "--quiet"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(dir.join("pikachu.png").exists());
    assert!(!dir.join("untitled.png").exists());
}

/// Radiance `.hdr` environment maps light the scene.
#[test]
fn hdr_environment_maps_are_read() {
    let dir = temp_dir("hdr");
    let sky = image::Rgb32FImage::from_pixel(8, 4, image::Rgb([0.5f32, 1.0, 2.0]));
    image::DynamicImage::ImageRgb32F(sky)
        .save_with_format(dir.join("sky.hdr"), image::ImageFormat::Hdr)
        .unwrap();
    let scene = write_scene(
        &dir,
        "sky.lxs",
        "LightSource \"infinite\" \"string mapname\" [\"sky.hdr\"]",
    );
    let out = dir.join("sky.exr");
    let output = foton(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--spp",
        "1",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let (_, _, pixels) = read_exr(&out).unwrap();
    // The camera sees the sky: every pixel is the map's constant radiance.
    assert!(
        pixels
            .iter()
            .all(|p| (*p - glam::Vec3::new(0.5, 1.0, 2.0)).abs().max_element() < 1e-2)
    );
}

/// The exit codes are in `--help`.
#[test]
fn help_documents_the_exit_codes() {
    let help = stdout(&foton(&["render", "--help"]));
    for code in ["0 ", "1 ", "2 ", "3 ", "4 ", "130", "143"] {
        assert!(help.contains(&format!("  {code}")), "{code}: {help}");
    }
}

/// The relMSE `foton compare A B --json` prints for the whole image.
fn rel_mse(a: &Path, b: &Path) -> f64 {
    let output = foton(&[
        "compare",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--json",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let json = stdout(&output);
    let overall = &json[json.find("\"overall\"").expect("overall in the JSON")..];
    let value = overall["\"overall\": {\"rmse\": ".len()..]
        .split("\"rel_mse\": ")
        .nth(1)
        .and_then(|rest| rest.split(',').next())
        .expect("rel_mse in the JSON");
    value.parse().unwrap_or_else(|_| panic!("{json}"))
}

#[test]
fn compare_measures_error_and_converge_charts_it() {
    let dir = temp_dir("converge");
    let scene = project_scene("cornell-diffuse.lxs");
    let render = |spp: &str, seed: &str, name: &str| {
        let out = dir.join(name);
        let output = foton(&[
            "render",
            &scene,
            "--resolution",
            "40x30",
            "--spp",
            spp,
            "--seed",
            seed,
            "-o",
            out.to_str().unwrap(),
            "--quiet",
        ]);
        assert!(output.status.success(), "{}", stderr(&output));
        out
    };
    let reference = render("16", "9", "ref.exr");
    let (one, four) = (render("1", "1", "a.exr"), render("4", "1", "b.exr"));
    // An image against itself: no error, infinite PSNR (null in JSON).
    assert_eq!(rel_mse(&one, &one), 0.0);
    // The expected relMSE of n spp against a 16-spp reference is v (1/n + 1/16): 4 spp has 0.29x
    // the error of 1 spp, and over 3600 pixel-channels the estimates spread by a few percent.
    let (e1, e4) = (rel_mse(&one, &reference), rel_mse(&four, &reference));
    assert!(e4 > 0.0 && e4 < 0.5 * e1, "1 spp {e1}, 4 spp {e4}");
    let diff = dir.join("diff.png");
    let output = foton(&[
        "compare",
        one.to_str().unwrap(),
        reference.to_str().unwrap(),
        "--diff",
        diff.to_str().unwrap(),
    ]);
    assert!(output.status.success() && stdout(&output).contains("relMSE"));
    assert_eq!(image::image_dimensions(&diff).unwrap(), (40, 30));
    let missing = foton(&["compare", "no-such.exr", reference.to_str().unwrap()]);
    assert_eq!(code(&missing), Some(1));
    assert!(
        stderr(&missing).contains("no-such.exr"),
        "{}",
        stderr(&missing)
    );

    // converge: one CSV row per spp, error falling with the samples; chart draws it again.
    let csv = dir.join("points.csv");
    let output = foton(&[
        "converge",
        &scene,
        "--reference",
        reference.to_str().unwrap(),
        "--spp",
        "1,4",
        "--config",
        "default:",
        "--config",
        "fis: --film fis",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(
        text.lines().next(),
        Some("configuration,seconds,spp,relmse")
    );
    assert_eq!(rows.len(), 4, "{text}");
    for pair in rows.chunks(2) {
        let error = |row: &Vec<&str>| row[3].parse::<f64>().unwrap();
        assert_eq!((pair[0][2], pair[1][2]), ("1", "4"), "{text}");
        assert!(error(&pair[1]) < 0.5 * error(&pair[0]), "{text}");
    }
    let svg = dir.join("chart.svg");
    let output = foton(&["chart", csv.to_str().unwrap(), "-o", svg.to_str().unwrap()]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(
        std::fs::read_to_string(&svg).is_ok_and(|s| s.contains("<svg"))
            || stderr(&output).contains("no font found"),
        "{}",
        stderr(&output)
    );
    let bad = dir.join("bad.csv");
    std::fs::write(
        &bad,
        "configuration,seconds,spp,relmse\nx,not-a-number,1,0.1\n",
    )
    .unwrap();
    assert_eq!(code(&foton(&["chart", bad.to_str().unwrap()])), Some(1));
}

/// `--clamp V` scales each sample down to a largest component of V before the film: with
/// filter importance sampling a pixel is the plain mean of its samples, so no pixel exceeds V
/// and none is brighter than without the clamp (the same seed gives the same samples); a clamp
/// above every sample changes nothing. A checkpoint remembers the clamp: resuming it without
/// the same `--clamp` is refused, with it gives the uninterrupted clamped image. Zero, negative
/// and non-numbers are refused; `bench` takes the option too.
#[test]
fn clamp_limits_every_sample_and_must_match_on_resume() {
    let dir = temp_dir("clamp");
    for bad in ["0", "-1", "nan"] {
        let output = foton(&["render", project_scene_static(), "--clamp", bad]);
        assert_eq!(code(&output), Some(2), "{bad}: {}", stderr(&output));
    }
    let limit = 0.05;
    let plain = render_exr(&dir.join("plain.exr"), &["--film", "fis"]);
    let clamped = render_exr(
        &dir.join("clamped.exr"),
        &["--film", "fis", "--clamp", "0.05"],
    );
    let brightest = plain.iter().map(|p| p.max_element()).fold(0.0, f32::max);
    assert!(
        brightest > 2.0 * limit,
        "the clamp bites nowhere: {brightest}"
    );
    for (p, c) in plain.iter().zip(&clamped) {
        assert!(c.max_element() <= limit * (1.0 + 1e-6), "{c} above {limit}");
        assert!(c.cmple(*p * (1.0 + 1e-6)).all(), "{c} brighter than {p}");
    }
    let loose = render_exr(
        &dir.join("loose.exr"),
        &["--film", "fis", "--clamp", "1e30"],
    );
    assert!(
        loose == plain,
        "a clamp above every sample changed the image"
    );

    let part = dir.join("part.exr");
    let args = ["--film", "fis", "--clamp", "0.05"];
    let stopped = [&args[..], &["--time-limit", "0", "--checkpoint", "1000"]].concat();
    render_exr(&part, &stopped);
    let checkpoint = dir.join("part.exr.checkpoint");
    let resume = ["--resume", checkpoint.to_str().unwrap()];
    let output = foton(
        &[
            &["render", project_scene_static(), "--resolution", "24x16"][..],
            &["--seed", "7", "--film", "fis"],
            &resume,
        ]
        .concat(),
    );
    assert_eq!(code(&output), Some(2), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("--clamp 0.05"),
        "{}",
        stderr(&output)
    );
    let resumed = render_exr(&dir.join("resumed.exr"), &[&args[..], &resume].concat());
    assert!(resumed == clamped, "a resumed clamped render differs");

    let scene = project_scene_static();
    let bench = [
        "bench", scene, "--clamp", "0.5", "--repeat", "1", "--spp", "1",
    ];
    let output = foton(&[&bench[..], &["--resolution", "8x8"]].concat());
    assert!(output.status.success(), "{}", stderr(&output));
}

#[test]
fn scene_parameters_come_from_the_command_line() {
    // `-D width=12` overrides the scene's `<default>` (8); a parameter the scene never reads is a
    // warning naming it, and the render goes on (for `bench` as for `render`).
    let dir = temp_dir("defines");
    let scene = dir.join("defines.xml");
    std::fs::write(
        &scene,
        r#"<scene version="3.0.0"><default name="width" value="8"/>
        <sensor type="perspective"><film type="hdrfilm">
        <integer name="width" value="$width"/><integer name="height" value="4"/></film></sensor>
        <emitter type="constant"/><shape type="sphere"/></scene>"#,
    )
    .unwrap();
    let out = dir.join("defines.exr");
    let scene = scene.to_str().unwrap();
    for (defines, width) in [(vec![], 8), (vec!["-D", "width=12"], 12)] {
        let mut args = vec!["render", scene, "-o", out.to_str().unwrap(), "--spp", "1"];
        args.extend(defines);
        let output = foton(&args);
        assert!(output.status.success(), "{}", stderr(&output));
        assert_eq!(read_exr(&out).unwrap().0, width);
    }
    for command in ["render", "bench"] {
        let mut args = vec![command, scene, "-D", "wdith=12", "--spp", "1"];
        if command == "render" {
            args.extend(["-o", out.to_str().unwrap()]);
        }
        let output = foton(&args);
        assert!(output.status.success(), "{}", stderr(&output));
        assert!(
            stderr(&output).contains("warning") && stderr(&output).contains("wdith=12"),
            "{command}: {}",
            stderr(&output)
        );
    }
}
