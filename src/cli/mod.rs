//! The command line: `foton render`, `foton bench`, `foton compare`.

mod bench;
mod compare;
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

#[derive(Parser, Debug)]
#[command(
    name = "foton",
    version,
    about = "A physically based wavefront path tracer for LuxRender scenes"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene to an image (.png tone-mapped, .exr linear).
    Render(RenderArgs),
    /// Measure wavefront throughput: render a scene several times, report the median.
    Bench(BenchArgs),
    /// Error of image A against the reference B: RMSE, relMSE, MAPE, PSNR.
    Compare(CompareArgs),
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
    /// The scene file; its extension picks the loader (.lxs).
    pub scene: PathBuf,
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
    #[arg(long, value_enum, default_value_t = IntegratorArg::Path)]
    pub integrator: IntegratorArg,
    #[arg(long, value_enum, default_value_t = SamplerArg::MultiJittered)]
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
    /// Pixel reconstruction: filter importance sampling or splatting (default: the measured best).
    #[arg(long, value_enum)]
    pub film: Option<FilmArg>,
    /// List what was built: entities, resources, BVH statistics, systems.
    #[arg(long, short)]
    pub verbose: bool,
}

#[derive(Args, Debug)]
struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output image (.png or .exr); default: the scene's name with .png, in this folder.
    #[arg(long, short)]
    output: Option<PathBuf>,
    /// Linear exposure for the PNG instead of the scene's tone mapping.
    #[arg(long)]
    exposure: Option<f32>,
    /// Render this many times and report each time and the median (the original's -benchmark).
    #[arg(long, default_value_t = 1)]
    repeat: u32,
}

#[derive(Args, Debug)]
struct BenchArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Timed renders after one warm-up.
    #[arg(long, default_value_t = 5)]
    repeat: u32,
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
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum LightSelectionArg {
    Power,
    Uniform,
    Mixed,
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
                }),
            rr_depth: self.rr_depth.unwrap_or(defaults.rr_depth),
            film: self.film.map_or(defaults.film, |f| match f {
                FilmArg::Fis => Reconstruction::FilterImportance,
                FilmArg::Splat => Reconstruction::Splat,
            }),
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
            },
            integrator: match self.integrator {
                IntegratorArg::Path => IntegratorKind::PathTracer,
                IntegratorArg::Raycast => IntegratorKind::RayCaster,
            },
            time_limit: self.time_limit.map(std::time::Duration::from_secs_f32),
            camera: self.camera,
            focal_distance: self.focal_distance,
            lens_radius: self.lens_radius,
            fisheye_fov: self.fisheye_fov,
            fisheye_fit: match self.fisheye_fit {
                FitArg::Ellipse => FisheyeFit::Ellipse,
                FitArg::Circle => FisheyeFit::Circle,
            },
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

/// Runs the command line; errors are printed, and give a non-zero exit code.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    render::stop_gracefully_on_interrupt();
    let result = match cli.command {
        Command::Render(args) => render::run(&args.scene, args.output, args.exposure, args.repeat),
        Command::Bench(args) => bench::run(&args.scene, args.repeat),
        Command::Compare(args) => compare::run(&args.a, &args.b, args.diff, args.json),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("{message}");
            ExitCode::FAILURE
        }
    }
}
