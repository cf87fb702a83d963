//! Renders split into parts (`foton render --passes`, `--crop`) and merged (`foton merge`): the
//! merged image is the one render's, bit for bit; parts that do not belong together are refused.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use foton::film::part::read_part;
use foton::film::read_exr;

use crate::common::{foton, stderr, stdout, temp_dir};

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell.lxs");
/// A small render of the Cornell box (Blackman-Harris filter of radius 1.5, splatted: samples
/// reach neighbouring pixels, which crops must account for).
const SETTINGS: [&str; 6] = ["--resolution", "40x28", "--spp", "8", "--seed", "5"];

fn path(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 path")
}

/// Renders with `SETTINGS` and `extra` to `out`, and checks it succeeded.
fn render(out: &Path, extra: &[&str]) {
    let mut args = vec!["render", SCENE, "-o", path(out), "--quiet"];
    args.extend(SETTINGS);
    args.extend(extra);
    let output = foton(&args);
    assert!(output.status.success(), "{args:?}: {}", stderr(&output));
}

fn merge(parts: &[&Path], out: &Path) -> Output {
    let mut args = vec!["merge", "-o", path(out)];
    args.extend(parts.iter().map(|p| path(p)));
    foton(&args)
}

/// The image's bits: equal images have equal bits (no -0 against 0, no NaN).
fn bits(image: &Path) -> Vec<[u32; 3]> {
    read_exr(image)
        .expect("an EXR")
        .2
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

/// Four parts of different lengths rendered by four processes at once, merged, give the image of
/// one render of all passes, in EXR and in PNG (through the scene's tone map).
#[test]
fn four_process_parallel_parts_merge_to_one_render() {
    let dir = temp_dir("four");
    let full = dir.join("full.exr");
    render(&full, &[]);
    render(&dir.join("full.png"), &[]);
    let ranges = ["0..1", "1..3", "3..6", "6..8"];
    let parts: Vec<PathBuf> = ranges
        .iter()
        .map(|r| dir.join(format!("part-{r}.exr")))
        .collect();
    let children: Vec<_> = ranges
        .iter()
        .zip(&parts)
        .map(|(range, part)| {
            Command::new(env!("CARGO_BIN_EXE_foton"))
                .args([
                    "render",
                    SCENE,
                    "-o",
                    path(part),
                    "--quiet",
                    "--threads",
                    "1",
                ])
                .args(SETTINGS)
                .args(["--passes", range])
                .spawn()
                .expect("foton starts")
        })
        .collect();
    for child in children {
        let status = child.wait_with_output().expect("foton ends").status;
        assert!(status.success());
    }
    let part_paths: Vec<&Path> = parts.iter().map(PathBuf::as_path).collect();
    // Given out of order: merge sums in pass order.
    let shuffled = [part_paths[2], part_paths[0], part_paths[3], part_paths[1]];
    let merged = dir.join("merged.exr");
    let output = merge(&shuffled, &merged);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(
        stdout(&output).contains("4 parts, 8 spp"),
        "{}",
        stdout(&output)
    );
    assert_eq!(
        bits(&merged),
        bits(&full),
        "the merged image is not the render's"
    );
    let merged_png = dir.join("merged.png");
    let output = merge(&shuffled, &merged_png);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        std::fs::read(&merged_png).expect("merged PNG"),
        std::fs::read(dir.join("full.png")).expect("full PNG")
    );
    // The f64 sums differ from one render's only by the order of additions: count them.
    let whole = dir.join("whole.exr");
    render(&whole, &["--passes", "0..8"]);
    let whole = read_part(&whole).expect("a part");
    let sums: Vec<_> = parts
        .iter()
        .map(|p| read_part(p).expect("a part").sums)
        .collect();
    let differing = (0..whole.sums.len())
        .filter(|&i| sums.iter().map(|s| s[i]).sum::<glam::DVec3>() != whole.sums[i])
        .count();
    println!(
        "{differing} of {} pixels' f64 sums differ in their last bits from one render's",
        whole.sums.len()
    );
    // Status: what each part holds and the merged samples per pixel.
    let mut args = vec!["merge", "--status"];
    args.extend(part_paths.iter().map(|p| path(p)));
    let output = foton(&args);
    let text = stdout(&output);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(
        text.contains("missing: none") && text.contains("merged: 8 of 8 spp"),
        "{text}"
    );
}

/// A pass twice, other settings, another seed, or a file that is not a part are refused with
/// the reason; a gap is merged with a warning naming the missing passes.
#[test]
fn parts_that_do_not_belong_together_are_refused_and_gaps_reported() {
    let dir = temp_dir("refused");
    let a = dir.join("a.exr");
    render(&a, &["--passes", "0..3"]);
    let b = dir.join("b.exr");
    render(&b, &["--passes", "2..4"]);
    let c = dir.join("c.exr");
    render(&c, &["--passes", "6..8"]);
    let out = dir.join("out.exr");
    let output = merge(&[&a, &b], &out);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("passes 2..3 are in both"),
        "{}",
        stderr(&output)
    );
    assert!(!out.exists());
    let depth = dir.join("depth.exr");
    render(&depth, &["--passes", "3..6", "--max-depth", "3"]);
    let output = merge(&[&a, &depth], &out);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("max_depth: Some(3) here"),
        "{}",
        stderr(&output)
    );
    let seed = dir.join("seed.exr");
    let output = foton(&[
        "render",
        SCENE,
        "-o",
        path(&seed),
        "--resolution",
        "40x28",
        "--spp",
        "8",
        "--seed",
        "6",
        "--passes",
        "3..6",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let output = merge(&[&a, &seed], &out);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("--seed 6"), "{}", stderr(&output));
    let plain = dir.join("plain.exr");
    render(&plain, &[]);
    let output = merge(&[&a, &plain], &out);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("plain.exr: not a foton part"),
        "{}",
        stderr(&output)
    );
    // A gap: merged, and said.
    let output = merge(&[&c, &a], &out);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("missing: 3..6") && stdout(&output).contains("5 spp"),
        "{}",
        stderr(&output)
    );
    // Passes beyond the render's, and a part that is not an EXR, are refused before rendering.
    for (passes, out) in [("6..9", "x.exr"), ("0..2", "x.png")] {
        let output = foton(&[
            "render",
            SCENE,
            "--spp",
            "8",
            "--passes",
            passes,
            "-o",
            path(&dir.join(out)),
        ]);
        assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    }
}

/// Crop parts, each with its own passes, stitch into the full image; overlapping crops are
/// refused.
#[test]
fn crop_parts_stitch_into_the_full_image() {
    let dir = temp_dir("crops");
    let full = dir.join("full.exr");
    render(&full, &[]);
    let mut parts = Vec::new();
    for (i, crop) in ["0,17,0,28", "17,40,0,11", "17,40,11,28"]
        .iter()
        .enumerate()
    {
        for passes in ["0..5", "5..8"] {
            let part = dir.join(format!("crop{i}-{passes}.exr"));
            render(&part, &["--crop", crop, "--passes", passes]);
            parts.push(part);
        }
    }
    let part_paths: Vec<&Path> = parts.iter().map(PathBuf::as_path).collect();
    let merged = dir.join("merged.exr");
    let output = merge(&part_paths, &merged);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        bits(&merged),
        bits(&full),
        "the stitched image is not the render's"
    );
    let overlap = dir.join("overlap.exr");
    render(&overlap, &["--crop", "10,20,5,6", "--passes", "0..8"]);
    let output = merge(&[part_paths[0], &overlap], &dir.join("x.exr"));
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("overlap"), "{}", stderr(&output));
}
