//! `foton render`: check the output, load, check the memory, build, render (with checkpoints and
//! interruption), write.

use std::mem::size_of;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::{DVec3, Vec2, Vec3};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::{Failure, RenderArgs, SceneArgs, exit, interrupt, merge};
use crate::accel::Hit;
use crate::film::checkpoint::{CheckpointInfo, pixel_set_hash, read_checkpoint, write_checkpoint};
use crate::film::{
    Film, ImageMetadata, Reconstruction, apply_display_tone_map, check_output, exposure_scale,
    is_linear_output, write_image,
};
use crate::integrator::{RenderStats, Renderer};
use crate::sampling::PathRng;
use crate::scene;
use crate::scene::build::{RenderOptions, build_world, tone_map};
use crate::scene::desc::{FilmDesc, Geometry, SceneDesc};
use crate::settings::RenderSettings;

/// Loads the scene and prints its warnings; an unreadable, malformed or empty scene is an error.
fn load(args: &SceneArgs) -> Result<(SceneDesc, usize), Failure> {
    let desc = scene::load_with(&args.scene, &args.define)
        .map_err(|e| Failure::new(exit::SCENE_ERROR, e.to_string()))?;
    for warning in &desc.warnings {
        eprintln!("{warning}");
    }
    for note in &desc.notes {
        eprintln!("{}: note: {note}", args.scene.display());
    }
    let mut warnings = desc.warnings.len();
    let has_area_lights = desc.shapes.iter().any(|s| s.area_light.is_some());
    if desc.shapes.is_empty() && desc.lights.is_empty() {
        return Err(Failure::new(
            exit::SCENE_ERROR,
            format!(
                "{}: error: the scene is empty (no shapes, no lights): nothing to render",
                args.scene.display()
            ),
        ));
    }
    if desc.lights.is_empty() && !has_area_lights {
        eprintln!(
            "{}: warning: the scene has no lights: the image will be black",
            args.scene.display()
        );
        warnings += 1;
    }
    Ok((desc, warnings))
}

/// Bytes one camera path needs in the wavefront batches: the path, its hit and its shadow rays.
fn bytes_per_path(shadow_rays: usize) -> usize {
    let path = size_of::<u32>() * 3
        + size_of::<Vec2>()
        + size_of::<Vec3>() * 4
        + size_of::<PathRng>()
        + size_of::<f32>()
        + size_of::<bool>();
    let hit = size_of::<Option<Hit>>() + size_of::<f32>();
    let shadow = size_of::<Vec3>() * 3 + size_of::<f32>() + size_of::<bool>();
    path + hit + shadow * shadow_rays
}

/// What the render will allocate: the film (sums, counts), the image buffers written at the end,
/// the batches, and the acceleration structure and shading data per triangle (an estimate:
/// about two BVH nodes and the triangle's vertices, normals and uv).
fn estimate_bytes(desc: &SceneDesc, width: u32, height: u32, paths: usize) -> u128 {
    let pixels = u128::from(width) * u128::from(height);
    let film = pixels * (size_of::<DVec3>() + size_of::<u64>()) as u128;
    let image = pixels * (2 * size_of::<Vec3>() + 4) as u128;
    let batches = paths as u128 * bytes_per_path(desc.lights.len().max(1)) as u128;
    let triangles: usize = desc
        .shapes
        .iter()
        .map(|s| match &s.geometry {
            Geometry::TriangleMesh { indices, .. } => indices.len(),
            _ => 1,
        })
        .sum();
    film + image + batches + triangles as u128 * 256
}

/// MemAvailable from /proc/meminfo, in bytes; `None` where there is no such file.
fn available_memory() -> Option<u128> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u128 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

fn gib(bytes: u128) -> String {
    format!("{:.1} GiB", bytes as f64 / f64::from(1u32 << 30))
}

/// Refuses, before anything large is allocated, a render that cannot fit: more pixels than a
/// 32-bit index reaches, or an estimate above the available memory.
fn check_memory(desc: &SceneDesc, width: u32, height: u32, paths: usize) -> Result<(), Failure> {
    let needed = estimate_bytes(desc, width, height, paths);
    if let Some(available) = available_memory().filter(|&a| needed > a) {
        return Err(Failure::new(
            exit::OUT_OF_MEMORY,
            format!(
                "error: a {width}x{height} render needs about {} of memory, {} is available \
                 (lower --resolution, or the Film's xresolution and yresolution)",
                gib(needed),
                gib(available)
            ),
        ));
    }
    if u64::from(width) * u64::from(height) > u64::from(u32::MAX) {
        return Err(Failure::new(
            exit::OUT_OF_MEMORY,
            format!("error: a {width}x{height} film has more than 2^32 - 1 pixels"),
        ));
    }
    Ok(())
}

/// Builds the world and the schedules from a loaded scene.
fn build(args: &SceneArgs, desc: SceneDesc, options: &RenderOptions) -> (Renderer, usize) {
    let (mut world, notes) = build_world(desc, options);
    world.insert_resource(args.techniques());
    for note in &notes {
        eprintln!("{}: note: {note}", args.scene.display());
    }
    let mut renderer = Renderer::new(world);
    if args.verbose {
        eprintln!("{}", renderer.describe());
    }
    (renderer, notes.len())
}

/// Loads, checks and builds the scene with the options of `args`.
pub fn prepare(args: &SceneArgs) -> Result<Renderer, Failure> {
    set_threads(args);
    let options = args.render_options();
    let (desc, _) = load(args)?;
    let (width, height) = options
        .resolution
        .unwrap_or((desc.film.x_resolution, desc.film.y_resolution));
    check_memory(&desc, width, height, width as usize * height as usize)?;
    Ok(build(args, desc, &options).0)
}

fn set_threads(args: &SceneArgs) {
    if let Some(threads) = args.threads {
        // Fails only if the pool was built already (a second render in one process).
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(threads as usize)
            .build_global();
    }
}

/// Why a render ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    Done,
    TimeLimit,
    Interrupted,
}

impl Stop {
    fn name(self) -> &'static str {
        match self {
            Stop::Done => "done",
            Stop::TimeLimit => "time limit",
            Stop::Interrupted => "interrupted",
        }
    }
}

fn progress_bar(spp: u32, quiet: bool) -> ProgressBar {
    let bar = ProgressBar::new(1);
    if quiet {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{elapsed_precise}} [{{bar:40}}] {{msg}}/{spp} spp, ETA {{eta}}"
        ))
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar
}

/// Renders to the end, the time limit or an interrupt, with a progress bar and ETA on a
/// terminal (advancing chunk by chunk); every `checkpoint` interval, `save` is called between
/// passes. Interrupts and limits act at the end of the pass under way, so that a checkpoint holds
/// whole passes only.
pub fn render_until_stopped(
    renderer: &mut Renderer,
    quiet: bool,
    checkpoint: Option<Duration>,
    mut save: impl FnMut(&Renderer, u32) -> Result<(), Failure>,
) -> Result<(RenderStats, Stop), Failure> {
    let settings = renderer.world.resource::<RenderSettings>().clone();
    let bar = progress_bar(settings.samples_per_pixel, quiet);
    let path_count = (settings.path_count() as u64).max(1);
    let start = Instant::now();
    let time_up = || settings.time_limit.is_some_and(|l| start.elapsed() >= l);
    let mut last_save = Instant::now();
    let mut total = RenderStats::empty(0);
    let stop = loop {
        let stats = renderer.render(|progress| {
            bar.set_length(progress.paths_total);
            bar.set_position(progress.paths_done);
            bar.set_message(progress.passes_done.to_string());
            let pass_boundary = progress.paths_done % path_count == 0;
            !pass_boundary
                || (!interrupt::requested()
                    && !time_up()
                    && checkpoint.is_none_or(|c| last_save.elapsed() < c))
        });
        total.passes = stats.passes;
        total.complete_passes = stats.complete_passes;
        total.paths += stats.paths;
        total.rays += stats.rays;
        total.elapsed += stats.elapsed;
        if stats.passes >= renderer.end_pass() {
            break Stop::Done;
        } else if interrupt::requested() {
            break Stop::Interrupted;
        } else if time_up() {
            break Stop::TimeLimit;
        }
        save(renderer, stats.passes)?;
        last_save = Instant::now();
    };
    bar.finish_and_clear();
    Ok((total, stop))
}

/// Renders without checkpoints (for `bench`).
pub fn render_with_progress(renderer: &mut Renderer) -> Result<(RenderStats, Stop), Failure> {
    render_until_stopped(renderer, false, None, |_, _| Ok(()))
}

pub fn summary(stats: &RenderStats) -> String {
    format!(
        "{:.3} s, {} spp, {:.2} M paths/s, {:.2} M rays/s",
        stats.elapsed.as_secs_f64(),
        stats.passes,
        stats.paths_per_second() / 1e6,
        rays_per_second(stats) / 1e6
    )
}

fn rays_per_second(stats: &RenderStats) -> f64 {
    stats.rays as f64 / stats.elapsed.as_secs_f64().max(1e-9)
}

/// Where the image goes when `-o` is not given: the scene's name with `.png` in this folder, or
/// the name of the scene's folder for a scene file named `untitled` (as exporters name them).
fn default_output(scene: &Path) -> PathBuf {
    let stem = scene.file_stem().unwrap_or_default().to_string_lossy();
    let folder = std::path::absolute(scene)
        .ok()
        .and_then(|p| Some(p.parent()?.file_name()?.to_string_lossy().into_owned()));
    match folder {
        Some(folder) if stem.eq_ignore_ascii_case("untitled") => {
            PathBuf::from(format!("{folder}.png"))
        }
        _ => PathBuf::from(format!("{stem}.png")),
    }
}

/// The checkpoint beside the image: `IMAGE.checkpoint`.
fn checkpoint_path(output: &Path) -> PathBuf {
    let mut name = output.as_os_str().to_owned();
    name.push(".checkpoint");
    PathBuf::from(name)
}

/// The part of the film written out: all of it, or the crop window `[x0, x1, y0, y1]`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Window {
    pub x0: u32,
    pub x1: u32,
    pub y0: u32,
    pub y1: u32,
}

impl Window {
    /// The window grown by the pixels whose samples a splatting filter of radius `reach` carries
    /// into it, within the film: those are rendered too, so that the window gets every sample
    /// the full render gives it (and crops stitch into the full image). A sample in pixel p lies
    /// in [p, p + 1) and reaches the centre j + 1/2 of pixel j when |p - j| - 1/2 <= radius.
    fn with_splat_reach(self, reach: Vec2, width: u32, height: u32) -> Window {
        let margin = |r: f32| (r + 0.5).floor().max(0.0) as u32;
        let (mx, my) = (margin(reach.x), margin(reach.y));
        Window {
            x0: self.x0.saturating_sub(mx),
            x1: self.x1.saturating_add(mx).min(width),
            y0: self.y0.saturating_sub(my),
            y1: self.y1.saturating_add(my).min(height),
        }
    }

    pub fn pixels(self, film_width: u32) -> Vec<u32> {
        (self.y0..self.y1)
            .flat_map(|y| (self.x0..self.x1).map(move |x| y * film_width + x))
            .collect()
    }
}

/// How the image is written: where, the window, the exposure, and the metadata; or, for
/// `--passes`, the part (`film/part.rs`) holding the passes from `first_pass` on.
pub(super) struct ImageTarget<'a> {
    pub output: &'a Path,
    pub window: Option<Window>,
    pub exposure: Option<f32>,
    pub film: &'a FilmDesc,
    pub seed: u64,
    pub part: Option<merge::PartTemplate>,
}

impl ImageTarget<'_> {
    fn write(&self, renderer: &Renderer, passes: u32, seconds: f64) -> Result<(), Failure> {
        let film = renderer.world.resource::<Film>();
        match &self.part {
            Some(part) => part.write(self.output, film, self.window, passes),
            None => self.write_film(film, passes, seconds),
        }
    }

    /// Writes the film's mean over the window, tone-mapped or exposed as the output asks.
    pub fn write_film(&self, film: &Film, passes: u32, seconds: f64) -> Result<(), Failure> {
        let mean = film.mean();
        let (width, height, pixels) = match self.window {
            None => (film.width(), film.height(), mean),
            Some(w) => (
                w.x1 - w.x0,
                w.y1 - w.y0,
                w.pixels(film.width())
                    .into_iter()
                    .map(|i| mean[i as usize])
                    .collect(),
            ),
        };
        let linear = is_linear_output(self.output).unwrap_or(false);
        let mut pixels = pixels;
        let tone = tone_map(self.film.tonemap);
        if self.exposure.is_none() && !linear {
            apply_display_tone_map(tone, &mut pixels, self.film.gamma);
        }
        let scale = self.exposure.unwrap_or_else(|| {
            if linear {
                1.0
            } else {
                exposure_scale(tone, &pixels, self.film.gamma)
            }
        });
        let metadata = ImageMetadata {
            samples_per_pixel: passes,
            seconds,
            seed: self.seed,
            command_line: std::env::args().collect::<Vec<_>>().join(" "),
        };
        write_image(self.output, width, height, &pixels, scale, &metadata)
            .map_err(|e| Failure::new(exit::OUTPUT_ERROR, format!("error: {e}")))
    }
}

fn json_string(text: &str) -> String {
    let mut out = String::from("\"");
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if u32::from(c) < 0x20 => out.push_str(&format!("\\u{:04x}", u32::from(c))),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

pub fn run(args: &RenderArgs) -> Result<(), Failure> {
    let scene = &args.scene;
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(&scene.scene));
    check_output(&output).map_err(|e| Failure::new(exit::OUTPUT_ERROR, format!("error: {e}")))?;
    if args.passes.is_some() {
        merge::check_part_output(&output)?;
    }
    let exposure = args.exposure.or(args.exposure_stops.map(|s| s.exp2()));
    let resumed = match &args.resume {
        Some(path) => Some(
            read_checkpoint(path)
                .map_err(|e| Failure::new(exit::SCENE_ERROR, format!("error: {e}")))?,
        ),
        None => None,
    };
    let checkpoint = checkpoint_path(&output);
    let mut times = Vec::new();
    for run in 0..args.repeat {
        set_threads(scene);
        let (desc, warnings) = load(scene)?;
        let mut options = scene.render_options();
        let (width, height) = options
            .resolution
            .unwrap_or((desc.film.x_resolution, desc.film.y_resolution));
        let window = crop_window(args, width, height)?;
        let splats = scene.techniques().film == Reconstruction::Splat;
        options.pixels = window.map(|w| {
            let reach = if splats {
                desc.filter.radius
            } else {
                Vec2::ZERO
            };
            w.with_splat_reach(reach, width, height).pixels(width)
        });
        let paths = options
            .pixels
            .as_ref()
            .map_or(width as usize * height as usize, Vec::len);
        check_memory(&desc, width, height, paths)?;
        let film_desc = desc.film.clone();
        let (mut renderer, notes) = build(scene, desc, &options);
        let part = match args.passes {
            Some(passes) => Some(merge::PartTemplate::start(
                scene,
                &mut renderer,
                passes,
                window.map(|w| [w.x0, w.x1, w.y0, w.y1]),
            )?),
            None => None,
        };
        let pixel_set = pixel_set_hash(options.pixels.as_deref());
        if let Some((film, info)) = &resumed {
            check_resume(args, film, info, width, height, pixel_set)?;
            if !renderer.resume(film.clone(), info.passes) {
                return Err(Failure::new(
                    exit::USAGE,
                    "error: the checkpoint's film is not this render's size",
                ));
            }
        }
        let target = ImageTarget {
            output: &output,
            window,
            exposure,
            film: &film_desc,
            seed: scene.seed,
            part,
        };
        let started = Instant::now();
        let save = |renderer: &Renderer, passes: u32| -> Result<(), Failure> {
            target.write(renderer, passes, started.elapsed().as_secs_f64())?;
            if target.part.is_some() {
                // A part of the passes done is itself a part: no checkpoint needed.
                return Ok(());
            }
            save_checkpoint(renderer, &checkpoint, passes, scene.seed, pixel_set)
        };
        let (stats, stop) = render_until_stopped(
            &mut renderer,
            args.quiet,
            args.checkpoint.map(Duration::from_secs_f32),
            save,
        )?;
        let rejected = renderer.world.resource::<Film>().rejected_samples();
        let mut warnings = warnings + notes;
        if stop == Stop::Interrupted && run > 0 {
            // The image of the previous, complete render is better than this partial one.
            eprintln!(
                "interrupted: {} keeps the image of render {run} of {}",
                output.display(),
                args.repeat
            );
            return Ok(());
        }
        target.write(&renderer, stats.passes, stats.elapsed.as_secs_f64())?;
        if target.part.is_some() {
            // A part stopped early holds the passes done; the rest can be another part.
        } else if stop == Stop::Interrupted || args.checkpoint.is_some() && stop != Stop::Done {
            save_checkpoint(&renderer, &checkpoint, stats.passes, scene.seed, pixel_set)?;
        } else if args.checkpoint.is_some() {
            // Finished: the checkpoint this render wrote is not needed any more.
            let _ = std::fs::remove_file(&checkpoint);
        }
        if stop == Stop::Interrupted && target.part.is_none() {
            eprintln!(
                "interrupted: {} written with the {} samples per pixel done; continue with \
                 --resume {}",
                output.display(),
                stats.passes,
                checkpoint.display()
            );
        }
        if rejected > 0 {
            eprintln!("warning: {rejected} non-finite samples were dropped");
            warnings += 1;
        } else if scene.verbose {
            eprintln!("rejected non-finite samples: 0");
        }
        if let (Some((x, y)), Some(w)) = (args.pixel, window) {
            let film = renderer.world.resource::<Film>();
            let value = film.mean()[w.pixels(film.width())[0] as usize];
            println!("pixel ({x}, {y}): {} {} {}", value.x, value.y, value.z);
        }
        if args.json {
            println!(
                "{{\"stopped\": {}, \"output\": {}, \"spp\": {}, \"seconds\": {:.6}, \
                 \"paths_per_second\": {:.1}, \"rays_per_second\": {:.1}, \"warnings\": {}, \
                 \"rejected_samples\": {}}}",
                json_string(stop.name()),
                json_string(&output.display().to_string()),
                stats.passes,
                stats.elapsed.as_secs_f64(),
                stats.paths_per_second(),
                rays_per_second(&stats),
                warnings,
                rejected
            );
        } else if !args.quiet {
            println!("{} written: {}", output.display(), summary(&stats));
        }
        times.push(stats.elapsed);
        if stop == Stop::Interrupted {
            return Ok(());
        }
    }
    if times.len() > 1 && !args.quiet && !args.json {
        times.sort();
        println!(
            "{} renders: median {:.2} s (min {:.2} s, max {:.2} s)",
            times.len(),
            times[times.len() / 2].as_secs_f64(),
            times[0].as_secs_f64(),
            times[times.len() - 1].as_secs_f64()
        );
    }
    Ok(())
}

/// The window of `--crop` or `--pixel`, checked against the film.
fn crop_window(args: &RenderArgs, width: u32, height: u32) -> Result<Option<Window>, Failure> {
    let window = match (args.crop, args.pixel) {
        (Some([x0, x1, y0, y1]), _) => Window { x0, x1, y0, y1 },
        (None, Some((x, y))) => Window {
            x0: x,
            x1: x.saturating_add(1),
            y0: y,
            y1: y.saturating_add(1),
        },
        (None, None) => return Ok(None),
    };
    if window.x1 > width || window.y1 > height {
        return Err(Failure::new(
            exit::USAGE,
            format!(
                "error: --crop/--pixel {},{},{},{} reaches outside the {width}x{height} image",
                window.x0, window.x1, window.y0, window.y1
            ),
        ));
    }
    Ok(Some(window))
}

fn check_resume(
    args: &RenderArgs,
    film: &Film,
    info: &CheckpointInfo,
    width: u32,
    height: u32,
    pixel_set: u64,
) -> Result<(), Failure> {
    let path = args.resume.as_deref().unwrap_or(Path::new("")).display();
    let mismatch = if (film.width(), film.height()) != (width, height) {
        Some(format!(
            "its film is {}x{}, this render's {width}x{height}",
            film.width(),
            film.height()
        ))
    } else if info.seed != args.scene.seed {
        Some(format!(
            "it was rendered with --seed {}, this render has {}",
            info.seed, args.scene.seed
        ))
    } else if info.pixel_set != pixel_set {
        Some("it was rendered with another --crop or --pixel".to_string())
    } else if film.max_component() != args.scene.clamp {
        let clamp = |c: Option<f32>| c.map_or("no --clamp".to_string(), |v| format!("--clamp {v}"));
        Some(format!(
            "it was rendered with {}, this render has {}",
            clamp(film.max_component()),
            clamp(args.scene.clamp)
        ))
    } else {
        None
    };
    match mismatch {
        Some(why) => Err(Failure::new(
            exit::USAGE,
            format!("error: {path} cannot be resumed here: {why}"),
        )),
        None => Ok(()),
    }
}

fn save_checkpoint(
    renderer: &Renderer,
    path: &Path,
    passes: u32,
    seed: u64,
    pixel_set: u64,
) -> Result<(), Failure> {
    let info = CheckpointInfo {
        passes,
        seed,
        pixel_set,
    };
    write_checkpoint(path, renderer.world.resource::<Film>(), info)
        .map_err(|e| Failure::new(exit::OUTPUT_ERROR, format!("error: {e}")))
}
