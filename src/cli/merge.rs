//! Renders split over machines: `foton render --passes A..B` writes a part (`film/part.rs`),
//! `foton merge` checks that parts belong together and sums them into the image one render of
//! all their passes gives; `foton merge --status` says what the parts hold.
//!
//! Exactness: a pass is seeded by seed, pixel and pass, so a part's samples are the full
//! render's. The film adds samples one by one in f64; a part starts from an empty film, and
//! merging adds the parts' sums in pass order. Floating-point addition is not associative, so
//! the merged f64 sums can differ from one render's in their last bits (about 1e-16 relative);
//! the image is written in 32-bit floats, whose rounding hides that (one value in about 1e8 can
//! round the other way; the tests compare every pixel bit for bit).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::DVec3;

use super::render::{ImageTarget, Window};
use super::{Failure, SceneArgs, exit};
use crate::film::part::{Part, PartInfo, content_hash, read_part, write_part};
use crate::film::{Film, ImageMetadata, is_linear_output, write_image};
use crate::integrator::Renderer;
use crate::settings::RenderSettings;

/// `--passes A..B`: a non-empty range of sample passes.
pub fn parse_passes(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected A..B (sample passes A to B-1, A < B), got {text:?}");
    let (a, b) = text.split_once("..").ok_or_else(bad)?;
    let (a, b): (u32, u32) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if a < b { Ok((a, b)) } else { Err(bad()) }
}

/// A part is an EXR: refused before loading otherwise.
pub fn check_part_output(output: &Path) -> Result<(), Failure> {
    let exr = output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if exr {
        Ok(())
    } else {
        Err(Failure::new(
            exit::USAGE,
            format!(
                "error: {}: --passes writes a part, an .exr file (merge parts with foton merge)",
                output.display()
            ),
        ))
    }
}

/// Every setting that changes the image besides seed, resolution and passes, one per line: the
/// scene options as given, with those that do not change the image (scene path, threads, time
/// limit, verbosity) blanked and the samples per pixel resolved. Options added to `SceneArgs`
/// later are compared without further work.
fn image_settings(args: &SceneArgs, spp: u32, width: u32, height: u32) -> String {
    let settings = SceneArgs {
        scene: PathBuf::new(),
        spp: Some(spp),
        resolution: Some((width, height)),
        threads: None,
        time_limit: None,
        verbose: false,
        ..args.clone()
    };
    fields(&format!("{settings:?}")).join("\n")
}

/// The fields of a struct's one-line `Debug` text, `name: value` each: split at the commas
/// between its braces that no bracket encloses.
fn fields(debug: &str) -> Vec<String> {
    let inner = debug
        .split_once('{')
        .and_then(|(_, rest)| rest.rsplit_once('}'))
        .map_or(debug, |(inner, _)| inner);
    let (mut list, mut field, mut depth) = (Vec::new(), String::new(), 0i32);
    for c in inner.chars() {
        match c {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth -= 1,
            ',' if depth == 0 => {
                list.push(field.trim().to_string());
                field.clear();
                continue;
            }
            _ => {}
        }
        field.push(c);
    }
    list.push(field.trim().to_string());
    list.retain(|f| !f.is_empty());
    list
}

/// What a part rendered by this process is, but for the passes done.
pub struct PartTemplate {
    info: PartInfo,
}

impl PartTemplate {
    /// Describes the part of `passes` of `args`'s scene over `window` (none: the whole film), and
    /// sets `renderer` to render only those passes; refuses passes beyond the samples per pixel.
    pub fn start(
        args: &SceneArgs,
        renderer: &mut Renderer,
        (first, end): (u32, u32),
        window: Option<[u32; 4]>,
    ) -> Result<Self, Failure> {
        let settings = renderer.world.resource::<RenderSettings>();
        let (width, height, spp) = (settings.width, settings.height, settings.samples_per_pixel);
        if end > spp {
            return Err(Failure::new(
                exit::USAGE,
                format!(
                    "error: --passes {first}..{end} goes beyond the render's {spp} spp (--spp)"
                ),
            ));
        }
        let bytes = std::fs::read(&args.scene).map_err(|e| {
            Failure::new(
                exit::SCENE_ERROR,
                format!("error: {}: {e}", args.scene.display()),
            )
        })?;
        renderer.render_only_passes(first, end);
        let scene = std::path::absolute(&args.scene).unwrap_or_else(|_| args.scene.clone());
        Ok(Self {
            info: PartInfo {
                scene: scene.display().to_string(),
                scene_hash: content_hash(&bytes),
                first_pass: first,
                end_pass: end,
                render_spp: spp,
                seed: args.seed,
                width,
                height,
                window: window.unwrap_or([0, width, 0, height]),
                settings: image_settings(args, spp, width, height),
                rejected: 0,
            },
        })
    }

    /// Writes the film, holding the passes from the first up to `passes_done`, as a part.
    pub fn write(
        &self,
        output: &Path,
        film: &Film,
        window: Option<Window>,
        passes_done: u32,
    ) -> Result<(), Failure> {
        let pixels = window.map_or_else(
            || (0..film.width() * film.height()).collect(),
            |w| w.pixels(film.width()),
        );
        let pick = |i: &u32| *i as usize;
        let part = Part {
            info: PartInfo {
                end_pass: passes_done,
                rejected: film.rejected_samples(),
                ..self.info.clone()
            },
            sums: pixels.iter().map(|i| film.sum(pick(i))).collect(),
            weights: pixels.iter().map(|i| film.weight(pick(i))).collect(),
            counts: pixels.iter().map(|i| film.counts()[pick(i)]).collect(),
        };
        if passes_done <= self.info.first_pass {
            return Err(Failure::new(
                exit::OUTPUT_ERROR,
                format!(
                    "error: {}: no pass was completed: no part written",
                    output.display()
                ),
            ));
        }
        write_part(output, &part)
            .map_err(|e| Failure::new(exit::OUTPUT_ERROR, format!("error: {e}")))
    }
}

/// `A..B, C..D` for a list of pass ranges.
fn ranges(list: &[(u32, u32)]) -> String {
    let names: Vec<String> = list.iter().map(|(a, b)| format!("{a}..{b}")).collect();
    names.join(", ")
}

/// One region of the image (a crop window, or the whole film) and the parts covering it, in
/// pass order.
struct Region<'a> {
    window: [u32; 4],
    parts: Vec<(&'a Path, &'a Part)>,
}

impl Region<'_> {
    /// The passes no part holds, as ranges within the render's.
    fn missing(&self, render_spp: u32) -> Vec<(u32, u32)> {
        let mut missing = Vec::new();
        let mut next = 0;
        for (_, part) in &self.parts {
            if part.info.first_pass > next {
                missing.push((next, part.info.first_pass));
            }
            next = part.info.end_pass;
        }
        if next < render_spp {
            missing.push((next, render_spp));
        }
        missing
    }

    fn passes(&self) -> u32 {
        self.parts
            .iter()
            .map(|(_, p)| p.info.end_pass - p.info.first_pass)
            .sum()
    }

    fn name(&self) -> String {
        let [x0, x1, y0, y1] = self.window;
        format!("pixels {x0}..{x1} x {y0}..{y1}")
    }
}

/// Refuses a part unlike the first: another scene, size, seed or settings.
fn check_belongs(first: (&Path, &PartInfo), other: (&Path, &PartInfo)) -> Result<(), Failure> {
    let ((pa, a), (pb, b)) = (first, other);
    let why = if a.scene_hash != b.scene_hash {
        Some(format!(
            "its scene {} is not {}'s {} (the files differ)",
            b.scene,
            pa.display(),
            a.scene
        ))
    } else if (a.width, a.height) != (b.width, b.height) {
        Some(format!(
            "it is {}x{}, {} is {}x{}",
            b.width,
            b.height,
            pa.display(),
            a.width,
            a.height
        ))
    } else if a.seed != b.seed {
        Some(format!(
            "it was rendered with --seed {}, {} with {}",
            b.seed,
            pa.display(),
            a.seed
        ))
    } else if a.settings != b.settings {
        let differences: Vec<String> = a
            .settings
            .lines()
            .zip(b.settings.lines())
            .filter(|(x, y)| x != y)
            .map(|(x, y)| format!("{} here, {} in {}", y.trim(), x.trim(), pa.display()))
            .collect();
        Some(format!("other settings: {}", differences.join("; ")))
    } else {
        None
    };
    match why {
        Some(why) => Err(Failure::new(
            exit::USAGE,
            format!(
                "error: {} does not belong with {}: {why}",
                pb.display(),
                pa.display()
            ),
        )),
        None => Ok(()),
    }
}

/// Groups the parts by window, each in pass order; refuses windows that overlap without being
/// equal and passes held twice.
fn regions<'a>(parts: &'a [(PathBuf, Part)]) -> Result<Vec<Region<'a>>, Failure> {
    let mut by_window: BTreeMap<[u32; 4], Vec<(&Path, &Part)>> = BTreeMap::new();
    for (path, part) in parts {
        by_window
            .entry(part.info.window)
            .or_default()
            .push((path.as_path(), part));
    }
    let regions: Vec<Region> = by_window
        .into_iter()
        .map(|(window, mut parts)| {
            parts.sort_by_key(|(_, p)| p.info.first_pass);
            Region { window, parts }
        })
        .collect();
    for (i, a) in regions.iter().enumerate() {
        for b in &regions[i + 1..] {
            let [ax0, ax1, ay0, ay1] = a.window;
            let [bx0, bx1, by0, by1] = b.window;
            if ax0 < bx1 && bx0 < ax1 && ay0 < by1 && by0 < ay1 {
                return Err(Failure::new(
                    exit::USAGE,
                    format!(
                        "error: the crops of {} ({}) and {} ({}) overlap: crop parts must tile \
                         the image",
                        a.parts[0].0.display(),
                        a.name(),
                        b.parts[0].0.display(),
                        b.name()
                    ),
                ));
            }
        }
    }
    for region in &regions {
        for pair in region.parts.windows(2) {
            let ((pa, a), (pb, b)) = (pair[0], pair[1]);
            if b.info.first_pass < a.info.end_pass {
                return Err(Failure::new(
                    exit::USAGE,
                    format!(
                        "error: passes {}..{} are in both {} ({}..{}) and {} ({}..{}): a pass \
                         must be merged once",
                        b.info.first_pass,
                        a.info.end_pass.min(b.info.end_pass),
                        pa.display(),
                        a.info.first_pass,
                        a.info.end_pass,
                        pb.display(),
                        b.info.first_pass,
                        b.info.end_pass
                    ),
                ));
            }
        }
    }
    Ok(regions)
}

/// What `merge` and `merge --status` say about each region: its parts, missing passes and the
/// merged samples per pixel.
fn describe(region: &Region, render_spp: u32) -> String {
    let held: Vec<String> = region
        .parts
        .iter()
        .map(|(path, p)| {
            format!(
                "{}..{} ({})",
                p.info.first_pass,
                p.info.end_pass,
                path.display()
            )
        })
        .collect();
    let missing = region.missing(render_spp);
    format!(
        "{}: passes {}; missing: {}; merged: {} of {render_spp} spp",
        region.name(),
        held.join(", "),
        if missing.is_empty() {
            "none".to_string()
        } else {
            ranges(&missing)
        },
        region.passes()
    )
}

/// `foton merge`: reads the parts, checks them, and writes the merged image to `output`, or
/// with `status` only says what they hold.
pub fn run(paths: &[PathBuf], output: Option<&Path>, status: bool) -> Result<(), Failure> {
    if let Some(output) = output {
        crate::film::check_output(output)
            .map_err(|e| Failure::new(exit::OUTPUT_ERROR, format!("error: {e}")))?;
    }
    let parts: Vec<(PathBuf, Part)> = paths
        .iter()
        .map(|path| {
            read_part(path)
                .map(|part| (path.clone(), part))
                .map_err(|e| Failure::new(exit::SCENE_ERROR, format!("error: {e}")))
        })
        .collect::<Result<_, _>>()?;
    let Some((first_path, first)) = parts.first() else {
        return Err(Failure::new(exit::USAGE, "error: no parts given"));
    };
    for (path, part) in &parts[1..] {
        check_belongs((first_path, &first.info), (path, &part.info))?;
    }
    let info = &first.info;
    let regions = regions(&parts)?;
    let covered: u64 = regions
        .iter()
        .map(|r| {
            let (w, h) = (r.window[1] - r.window[0], r.window[3] - r.window[2]);
            u64::from(w) * u64::from(h)
        })
        .sum();
    let uncovered = u64::from(info.width) * u64::from(info.height) - covered;
    let lines: Vec<String> = regions
        .iter()
        .map(|r| describe(r, info.render_spp))
        .collect();
    if status {
        println!(
            "{} parts of {} ({}x{}, seed {}, {} spp)",
            parts.len(),
            info.scene,
            info.width,
            info.height,
            info.seed,
            info.render_spp
        );
        for line in &lines {
            println!("{line}");
        }
        if uncovered > 0 {
            println!("{uncovered} pixels are in no part");
        }
        return Ok(());
    }
    for (region, line) in regions.iter().zip(&lines) {
        if !region.missing(info.render_spp).is_empty() {
            eprintln!("warning: {line}");
        }
    }
    if uncovered > 0 {
        eprintln!("warning: {uncovered} pixels are in no part: they are black");
    }
    let film = merged_film(info, &regions);
    let Some(output) = output else {
        return Err(Failure::new(
            exit::USAGE,
            "error: -o OUTPUT is needed to merge",
        ));
    };
    let spp = regions.iter().map(Region::passes).min().unwrap_or(0);
    write_merged(output, &film, info, spp)?;
    println!(
        "{} written: {} parts, {spp} spp",
        output.display(),
        parts.len()
    );
    Ok(())
}

/// The whole film: each region's parts' sums, weights and counts added in pass order, so that
/// the first part's values are taken as they are (0 + x = x) and the next ones added as the
/// render would have.
fn merged_film(info: &PartInfo, regions: &[Region]) -> Film {
    let n = info.width as usize * info.height as usize;
    let mut sums = vec![DVec3::ZERO; n];
    let mut weights = vec![0.0; n];
    let mut counts = vec![0; n];
    let mut rejected = 0;
    for region in regions {
        let [x0, x1, y0, y1] = region.window;
        let pixels = Window { x0, x1, y0, y1 }.pixels(info.width);
        for (_, part) in &region.parts {
            rejected += part.info.rejected;
            for (k, &i) in pixels.iter().enumerate() {
                let i = i as usize;
                sums[i] += part.sums[k];
                weights[i] += part.weights[k];
                counts[i] += part.counts[k];
            }
        }
    }
    Film::from_parts(
        info.width,
        info.height,
        sums,
        weights,
        counts,
        rejected,
        None,
    )
    .unwrap_or_else(|| Film::new(info.width, info.height))
}

/// Writes the merged image: linear formats as they are; 8-bit formats through the scene's tone
/// map, which needs the scene file the parts name.
fn write_merged(output: &Path, film: &Film, info: &PartInfo, spp: u32) -> Result<(), Failure> {
    let output_error = |e: String| Failure::new(exit::OUTPUT_ERROR, format!("error: {e}"));
    let metadata = ImageMetadata {
        samples_per_pixel: spp,
        seconds: 0.0,
        seed: info.seed,
        command_line: std::env::args().collect::<Vec<_>>().join(" "),
    };
    if is_linear_output(output).map_err(output_error)? {
        return write_image(
            output,
            film.width(),
            film.height(),
            &film.mean(),
            1.0,
            &metadata,
        )
        .map_err(output_error);
    }
    let scene = Path::new(&info.scene);
    let desc = crate::scene::load(scene).map_err(|e| {
        Failure::new(
            exit::SCENE_ERROR,
            format!(
                "error: {} needs the scene's tone map: {e} (write .exr to merge without the scene)",
                output.display()
            ),
        )
    })?;
    if content_hash(&std::fs::read(scene).unwrap_or_default()) != info.scene_hash {
        eprintln!(
            "warning: {} changed since the parts were rendered: its tone map is used as it is now",
            scene.display()
        );
    }
    ImageTarget {
        output,
        window: None,
        exposure: None,
        film: &desc.film,
        seed: info.seed,
        part: None,
    }
    .write_film(film, spp, 0.0)
}
