//! The command line: `foton render`, `foton bench`, `foton compare`, `foton converge`,
//! `foton chart`, `foton merge`.

mod bench;
mod compare;
mod converge;
mod interrupt;
mod merge;
mod render;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::camera::fisheye::FisheyeFit;
use crate::camera::{self, CameraType};
use crate::film::Reconstruction;
use crate::light::LightSelection;
use crate::sampling::SamplerKind;
use crate::scene::build::RenderOptions;
use crate::settings::{IntegratorKind, Techniques};

/// Exit codes, documented in `--help` and the README.
pub mod exit {
    pub const SCENE_ERROR: u8 = 1;
    pub const USAGE: u8 = 2;
    pub const OUTPUT_ERROR: u8 = 3;
    pub const OUT_OF_MEMORY: u8 = 4;
}

const EXIT_CODES: &str = "Exit codes:
  0    done (also when stopped by --time-limit)
  1    scene error (unreadable or malformed scene or checkpoint, empty scene)
  2    usage error (bad command line; a checkpoint of another seed, size or crop; parts that
       do not belong together or hold a pass twice)
  3    output error (unknown image format, missing folder, not writable)
  4    out of memory (the estimate exceeds the available memory)
  130  interrupted by SIGINT (Ctrl-C): the samples done are written
  143  interrupted by SIGTERM: the samples done are written";

/// Why a command failed: the message for the user and the exit code.
#[derive(Debug)]
pub struct Failure {
    pub code: u8,
    pub message: String,
}

impl Failure {
    pub fn new(code: u8, message: impl Into<String>) -> Self {
        Self {
            code,
            message: message.into(),
        }
    }
}

#[derive(Parser, Debug)]
#[command(
    name = "foton",
    version,
    about = "A physically based wavefront path tracer for LuxRender scenes",
    after_help = EXIT_CODES
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene to an image (.png, .jpg tone-mapped; .exr, .hdr, .pfm linear).
    #[command(after_help = EXIT_CODES)]
    Render(RenderArgs),
    /// Measure wavefront throughput: render a scene several times, report the median.
    Bench(BenchArgs),
    /// Error of image A against the reference B: RMSE, relMSE, MAPE, PSNR.
    Compare(CompareArgs),
    /// Error against time: render at growing spp per configuration, write a CSV and a chart.
    Converge(ConvergeCliArgs),
    /// Draw the log-log chart of relMSE against seconds from CSVs of measured points.
    Chart(ChartArgs),
    /// Merge parts written by `render --passes` (and `--crop`) into one image.
    #[command(after_help = EXIT_CODES)]
    Merge(MergeArgs),
}

#[derive(Args, Debug)]
struct ChartArgs {
    /// CSV files (configuration, seconds, spp, relmse), as `converge` writes them.
    #[arg(required = true)]
    csvs: Vec<PathBuf>,
    /// The chart (.svg); a .png goes beside it.
    #[arg(long, short, default_value = "chart.svg")]
    output: PathBuf,
}

#[derive(Args, Debug)]
struct MergeArgs {
    /// The parts (.exr files written by `foton render --passes A..B`).
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// The merged image (.exr, .hdr, .pfm linear; .png, .jpg with the scene's tone map).
    #[arg(long, short, required_unless_present = "status")]
    output: Option<PathBuf>,
    /// Only say which passes each region holds, which are missing, and the merged spp.
    #[arg(long)]
    status: bool,
}

#[derive(Args, Debug)]
struct ConvergeCliArgs {
    /// The scene file (.lxs).
    scene: PathBuf,
    /// The converged image to measure against (.exr, the scene's resolution).
    #[arg(long)]
    reference: PathBuf,
    /// A configuration, "label: render options", e.g. "fis: --film fis" (repeatable).
    #[arg(long = "config")]
    configurations: Vec<String>,
    /// Samples per pixel to render at, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [1u32, 2, 4, 8, 16, 32, 64])]
    spp: Vec<u32>,
    /// Another renderer's points (CSV: configuration, seconds, spp, relmse), drawn beside.
    #[arg(long = "peer")]
    peers: Vec<PathBuf>,
    /// The CSV to write; the chart goes beside it as .svg.
    #[arg(long, short, default_value = "converge.csv")]
    output: PathBuf,
}

#[derive(Args, Debug)]
struct CompareArgs {
    /// The image to measure (.exr).
    a: PathBuf,
    /// The reference (.exr).
    b: PathBuf,
    /// Write a false-colour difference image (.png).
    #[arg(long)]
    diff: Option<PathBuf>,
    /// Print the measures as JSON.
    #[arg(long)]
    json: bool,
}

/// The scene and how to render it; shared by `render` and `bench`.
#[derive(Args, Debug, Clone)]
pub struct SceneArgs {
    /// The scene file; its extension picks the loader (.lxs, .xml).
    pub scene: PathBuf,
    /// A scene parameter, `-D name=value` (Mitsuba's `$name`; for LuxRender scenes
    /// `lux_version`, e.g. 1.6, the release to read them as; repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<(String, String)>,
    /// Samples per pixel (the original's -s / -aa).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub spp: Option<u32>,
    /// Maximum bounces (the original's -tr / -d).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub threads: Option<u32>,
    /// Random seed: the same seed gives the same image whatever the thread count.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Image size, e.g. 640x360.
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Stop after the pass that crosses this many seconds, and write what is done.
    #[arg(long, value_parser = parse_in(0.0, f32::MAX))]
    pub time_limit: Option<f32>,
    /// The integrator (default: the scene's, else path).
    #[arg(long, value_enum)]
    pub integrator: Option<IntegratorArg>,
    #[arg(long, value_enum, default_value_t = SamplerArg::Sobol)]
    pub sampler: SamplerArg,
    /// Use this camera instead of the scene's.
    #[arg(long, value_parser = camera_parser())]
    pub camera: Option<&'static CameraType>,
    /// Thin lens: distance to the plane in focus (the original's fd).
    #[arg(long, value_parser = parse_in(1e-4, f32::MAX))]
    pub focal_distance: Option<f32>,
    /// Thin lens: aperture radius (the original's lr); works with any camera.
    #[arg(long, value_parser = parse_in(0.0, f32::MAX))]
    pub lens_radius: Option<f32>,
    /// Fisheye aperture in degrees, 0 to 360 (the original's phi).
    #[arg(long, value_parser = parse_in(0.0, 360.0))]
    pub fisheye_fov: Option<f32>,
    #[arg(long, value_enum, default_value_t = FitArg::Ellipse)]
    pub fisheye_fit: FitArg,
    /// How next-event estimation picks a light (default: the measured best).
    #[arg(long, value_enum)]
    pub light_selection: Option<LightSelectionArg>,
    /// Bounces before Russian roulette may end a path.
    #[arg(long)]
    pub rr_depth: Option<u32>,
    /// Sample rectangle lamps uniformly in the solid angle they subtend (Ureña et al. 2013),
    /// not by area: less noise close to a lamp, more instructions per light sample.
    #[arg(long)]
    pub solid_angle_rectangles: bool,
    /// Pixel reconstruction: filter importance sampling or splatting (default: the measured best).
    #[arg(long, value_enum)]
    pub film: Option<FilmArg>,
    /// Scale down each sample whose largest RGB component exceeds V to V, against fireflies.
    /// Biased: the energy above V is lost (a darker image where rare bright paths matter).
    #[arg(long, value_name = "V", value_parser = parse_positive)]
    pub clamp: Option<f32>,
    /// List what was built: entities, resources, BVH statistics, systems.
    #[arg(long, short)]
    pub verbose: bool,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output image: .png, .jpg (tone-mapped, 8-bit sRGB), .exr (ZIP, 32-bit float, with the
    /// render's settings as metadata), .hdr, .pfm (linear). Default: the scene's name with .png
    /// in this folder (the scene's folder name for a scene file named `untitled`).
    #[arg(long, short)]
    pub output: Option<PathBuf>,
    /// A positive multiplier on linear radiance in place of the scene's tone mapping (for every
    /// format; linear formats are otherwise written unscaled).
    #[arg(
        long,
        value_parser = parse_positive,
        allow_negative_numbers = true,
        conflicts_with = "exposure_stops"
    )]
    pub exposure: Option<f32>,
    /// The same in photographic stops: a multiplier of 2^STOPS (negative darkens).
    #[arg(long, value_parser = parse_in(-64.0, 64.0), allow_negative_numbers = true)]
    pub exposure_stops: Option<f32>,
    /// Render this many times and report each time and the median (the original's -benchmark).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub repeat: u32,
    /// Write the image and a resumable checkpoint (OUTPUT.checkpoint) every this many seconds.
    #[arg(long, value_parser = parse_in(0.001, f32::MAX))]
    pub checkpoint: Option<f32>,
    /// Continue from a checkpoint written by --checkpoint or an interruption, to the image an
    /// uninterrupted render gives (same scene, seed, resolution and crop).
    #[arg(long)]
    pub resume: Option<PathBuf>,
    /// Render only pixels x0 <= x < x1, y0 <= y < y1; the image is the crop's size.
    #[arg(long, value_parser = parse_crop, conflicts_with = "pixel")]
    pub crop: Option<[u32; 4]>,
    /// Render only sample passes A to B-1 of the render (with the random streams they have in
    /// it) and write them as a part (.exr) for `foton merge`.
    #[arg(long, value_parser = merge::parse_passes, conflicts_with = "resume")]
    pub passes: Option<(u32, u32)>,
    /// Render only this pixel, print its value, and write a 1x1 image.
    #[arg(long, value_parser = parse_pixel)]
    pub pixel: Option<(u32, u32)>,
    /// Print nothing but warnings and errors (no progress, no summary).
    #[arg(long, short)]
    pub quiet: bool,
    /// Print a JSON summary on stdout at the end: why the render stopped, spp, seconds, rays/s,
    /// warnings, rejected samples.
    #[arg(long)]
    pub json: bool,
}

#[derive(Args, Debug)]
struct BenchArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Timed renders after one warm-up.
    #[arg(long, default_value_t = 5)]
    repeat: u32,
    /// Time every stage: its share of the time and its rays (or paths) per second.
    #[arg(long)]
    stages: bool,
    /// Camera paths per chunk of the wavefront (default: the renderer's).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    chunk_paths: Option<u64>,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum IntegratorArg {
    Path,
    Raycast,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum SamplerArg {
    Independent,
    Stratified,
    MultiJittered,
    Sobol,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum LightSelectionArg {
    Power,
    Uniform,
    Mixed,
    Bvh,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum FilmArg {
    Fis,
    Splat,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum FitArg {
    Ellipse,
    Circle,
}

impl SceneArgs {
    /// The sampling techniques: the defaults, with what the command line chose on top.
    pub fn techniques(&self) -> Techniques {
        let defaults = Techniques::default();
        Techniques {
            light_selection: self
                .light_selection
                .map_or(defaults.light_selection, |l| match l {
                    LightSelectionArg::Power => LightSelection::Power,
                    LightSelectionArg::Uniform => LightSelection::Uniform,
                    LightSelectionArg::Mixed => LightSelection::Mixed,
                    LightSelectionArg::Bvh => LightSelection::Bvh,
                }),
            rr_depth: self.rr_depth.unwrap_or(defaults.rr_depth),
            film: self.film.map_or(defaults.film, |f| match f {
                FilmArg::Fis => Reconstruction::FilterImportance,
                FilmArg::Splat => Reconstruction::Splat,
            }),
            solid_angle_rectangles: self.solid_angle_rectangles || defaults.solid_angle_rectangles,
        }
    }

    pub fn render_options(&self) -> RenderOptions {
        RenderOptions {
            samples_per_pixel: self.spp,
            max_depth: self.max_depth,
            resolution: self.resolution,
            seed: self.seed,
            sampler: match self.sampler {
                SamplerArg::Independent => SamplerKind::Independent,
                SamplerArg::Stratified => SamplerKind::Stratified,
                SamplerArg::MultiJittered => SamplerKind::MultiJittered,
                SamplerArg::Sobol => SamplerKind::Sobol,
            },
            integrator: self.integrator.map(|integrator| match integrator {
                IntegratorArg::Path => IntegratorKind::PathTracer,
                IntegratorArg::Raycast => IntegratorKind::RayCaster,
            }),
            time_limit: self.time_limit.map(std::time::Duration::from_secs_f32),
            camera: self.camera,
            focal_distance: self.focal_distance,
            lens_radius: self.lens_radius,
            fisheye_fov: self.fisheye_fov,
            fisheye_fit: match self.fisheye_fit {
                FitArg::Ellipse => FisheyeFit::Ellipse,
                FitArg::Circle => FisheyeFit::Circle,
            },
            pixels: None,
            clamp: self.clamp,
        }
    }
}

/// `--camera`: one of the registry's cameras, by foton's name.
fn camera_parser() -> impl TypedValueParser<Value = &'static CameraType> {
    PossibleValuesParser::new(camera::names()).try_map(|name: String| {
        camera::find(&name).ok_or_else(|| format!("no camera called {name:?}"))
    })
}

/// A parser for a number in [min, max].
fn parse_in(min: f32, max: f32) -> impl Fn(&str) -> Result<f32, String> + Clone {
    move |text| {
        text.trim()
            .parse::<f32>()
            .ok()
            .filter(|v| (min..=max).contains(v))
            .ok_or_else(|| format!("expected a number from {min} to {max}, got {text:?}"))
    }
}

/// A finite number above zero.
fn parse_positive(text: &str) -> Result<f32, String> {
    text.trim()
        .parse::<f32>()
        .ok()
        .filter(|v| v.is_finite() && *v > 0.0)
        .ok_or_else(|| format!("expected a positive multiplier, got {text:?}"))
}

/// `x0,x1,y0,y1`, each range non-empty.
fn parse_crop(text: &str) -> Result<[u32; 4], String> {
    let v: Vec<u32> = text
        .split(',')
        .map(|s| s.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected x0,x1,y0,y1 (pixels), got {text:?}"))?;
    match v[..] {
        [x0, x1, y0, y1] if x0 < x1 && y0 < y1 => Ok([x0, x1, y0, y1]),
        _ => Err(format!(
            "expected x0,x1,y0,y1 with x0 < x1 and y0 < y1, got {text:?}"
        )),
    }
}

/// `x,y`.
fn parse_pixel(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected x,y (pixels), got {text:?}");
    let (x, y) = text.split_once(',').ok_or_else(bad)?;
    Ok((
        x.trim().parse().map_err(|_| bad())?,
        y.trim().parse().map_err(|_| bad())?,
    ))
}

fn parse_define(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((name, value)) if !name.trim().is_empty() => {
            Ok((name.trim().to_string(), value.to_string()))
        }
        _ => Err(format!("expected NAME=VALUE, got {text:?}")),
    }
}

fn parse_resolution(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, got {text:?}"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<u32>()
            .ok()
            .filter(|v| (1..=65536).contains(v))
            .ok_or_else(|| format!("expected WIDTHxHEIGHT with sizes 1 to 65536, got {text:?}"))
    };
    Ok((parse(w)?, parse(h)?))
}

/// Runs the command line; errors are printed, and give the exit codes of `EXIT_CODES`.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = interrupt::install() {
        eprintln!("warning: cannot catch interrupts ({e}): Ctrl-C will lose the render");
    }
    let result = match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Bench(args) => bench::run(
            &args.scene,
            args.repeat,
            args.stages,
            args.chunk_paths.map(|n| n as usize),
        ),
        Command::Compare(args) => compare::run(&args.a, &args.b, args.diff, args.json)
            .map_err(|message| Failure::new(exit::SCENE_ERROR, message)),
        Command::Converge(args) => converge::run(&converge::ConvergeArgs {
            scene: &args.scene,
            reference: &args.reference,
            configurations: &args.configurations,
            spp: &args.spp,
            peers: &args.peers,
            output: &args.output,
        })
        .map_err(|message| Failure::new(exit::SCENE_ERROR, message)),
        Command::Chart(args) => converge::chart(&args.csvs, &args.output)
            .map_err(|message| Failure::new(exit::SCENE_ERROR, message)),
        Command::Merge(args) => merge::run(&args.parts, args.output.as_deref(), args.status),
    };
    let code = match result {
        Ok(()) => 0,
        Err(failure) => {
            eprintln!("{}", failure.message);
            failure.code
        }
    };
    ExitCode::from(interrupt::exit_code().unwrap_or(code))
}
