//! `foton render`: load, build, render, write.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

use super::SceneArgs;
use crate::film::{Film, apply_display_tone_map, exposure_scale, write_image};
use crate::integrator::{RenderStats, Renderer};
use crate::scene;
use crate::scene::build::{build_world, tone_map};
use crate::scene::desc::FilmDesc;

/// A loaded scene, ready to render.
pub struct Prepared {
    pub renderer: Renderer,
    pub film: FilmDesc,
}

/// Loads the scene, prints its warnings, builds the world and the schedules.
pub fn prepare(args: &SceneArgs) -> Result<Prepared, String> {
    if let Some(threads) = args.threads {
        // Fails only if the pool was built already (a second render in one process).
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(threads as usize)
            .build_global();
    }
    let desc = scene::load(&args.scene).map_err(|e| e.to_string())?;
    for warning in &desc.warnings {
        eprintln!("{warning}");
    }
    let film = desc.film.clone();
    let (mut world, notes) = build_world(desc, &args.render_options());
    world.insert_resource(args.techniques());
    for note in notes {
        eprintln!("{}: note: {note}", args.scene.display());
    }
    let mut renderer = Renderer::new(world);
    if args.verbose {
        eprintln!("{}", renderer.describe());
    }
    Ok(Prepared { renderer, film })
}

pub fn run(
    args: &SceneArgs,
    output: Option<PathBuf>,
    exposure: Option<f32>,
    repeat: u32,
) -> Result<(), String> {
    let output = output.unwrap_or_else(|| default_output(&args.scene));
    let mut all = Vec::new();
    for _ in 0..repeat.max(1) {
        let mut prepared = prepare(args)?;
        let stats = render_with_progress(&mut prepared.renderer);
        let film = prepared.renderer.world.resource::<Film>();
        let mut pixels = film.mean();
        let png = output
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if exposure.is_none() && png {
            apply_display_tone_map(
                tone_map(prepared.film.tonemap),
                &mut pixels,
                prepared.film.gamma,
            );
        }
        let scale = exposure.unwrap_or_else(|| {
            exposure_scale(
                tone_map(prepared.film.tonemap),
                &pixels,
                prepared.film.gamma,
            )
        });
        write_image(&output, film.width(), film.height(), &pixels, scale)
            .map_err(|e| format!("error: {e}"))?;
        if film.rejected_samples() > 0 {
            eprintln!(
                "warning: {} non-finite samples were dropped",
                film.rejected_samples()
            );
        }
        println!("{} written: {}", output.display(), summary(&stats));
        all.push(stats);
    }
    if all.len() > 1 {
        let mut times: Vec<Duration> = all.iter().map(|s| s.elapsed).collect();
        times.sort();
        println!(
            "{} renders: median {:.2} s (min {:.2} s, max {:.2} s)",
            all.len(),
            times[times.len() / 2].as_secs_f64(),
            times[0].as_secs_f64(),
            times[times.len() - 1].as_secs_f64()
        );
    }
    Ok(())
}

/// Set by Ctrl-C: the render stops after the pass under way, and its image is still written.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Makes Ctrl-C finish the current pass and keep the work done, instead of losing it.
pub fn stop_gracefully_on_interrupt() {
    // Fails only if a handler is already installed, which then does the same.
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::Relaxed));
}

/// Renders, with a progress bar and ETA on a terminal.
pub fn render_with_progress(renderer: &mut Renderer) -> RenderStats {
    let spp = renderer.samples_per_pixel();
    let bar = ProgressBar::new(1);
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{elapsed_precise}} [{{bar:40}}] {{msg}}/{spp} spp, ETA {{eta}}"
        ))
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    let stats = renderer.render(|progress| {
        bar.set_length(progress.paths_total);
        bar.set_position(progress.paths_done);
        bar.set_message(progress.passes_done.to_string());
        !INTERRUPTED.load(Ordering::Relaxed)
    });
    bar.finish_and_clear();
    if INTERRUPTED.load(Ordering::Relaxed) {
        eprintln!("interrupted: keeping the {} passes done", stats.passes);
    }
    stats
}

pub fn summary(stats: &RenderStats) -> String {
    format!(
        "{:.3} s, {} spp, {:.2} M paths/s, {:.2} M rays/s",
        stats.elapsed.as_secs_f64(),
        stats.passes,
        stats.paths_per_second() / 1e6,
        stats.rays as f64 / stats.elapsed.as_secs_f64().max(1e-9) / 1e6
    )
}

fn default_output(scene: &Path) -> PathBuf {
    let stem = scene.file_stem().unwrap_or_default().to_string_lossy();
    PathBuf::from(format!("{stem}.png"))
}
