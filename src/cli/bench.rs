//! `foton bench`: wavefront throughput on a scene, as the median of repeated renders measured
//! in one process (these machines are shared and noisy: compare ratios from one run).

use super::render::{Stop, prepare, render_with_progress, summary};
use super::{Failure, SceneArgs};
use crate::integrator::{Renderer, StageTime};

pub fn run(
    args: &SceneArgs,
    repeat: u32,
    stages: bool,
    chunk_paths: Option<usize>,
) -> Result<(), Failure> {
    let prepare_run = || -> Result<Renderer, Failure> {
        let mut renderer = prepare(args)?;
        if let Some(paths) = chunk_paths {
            renderer.set_chunk_paths(paths);
        }
        if stages {
            renderer.time_stages();
        }
        Ok(renderer)
    };
    let (warm_up, stop) = render_with_progress(&mut prepare_run()?)?;
    println!("warm-up: {}", summary(&warm_up));
    let mut rates = Vec::new();
    let mut runs = Vec::new();
    if stop != Stop::Interrupted {
        for i in 0..repeat.max(1) {
            let mut renderer = prepare_run()?;
            let (stats, stop) = render_with_progress(&mut renderer)?;
            if stop == Stop::Interrupted {
                // A partial run would skew the median.
                break;
            }
            println!("run {}: {}", i + 1, summary(&stats));
            rates.push(stats.paths_per_second() / 1e6);
            if let Some(times) = renderer.stage_times() {
                runs.push(times.to_vec());
            }
        }
    }
    if rates.is_empty() {
        eprintln!("interrupted: no timed run finished");
        return Ok(());
    }
    rates.sort_by(f64::total_cmp);
    println!(
        "median {:.3} M paths/s over {} runs (min {:.3}, max {:.3}){}",
        rates[rates.len() / 2],
        rates.len(),
        rates[0],
        rates[rates.len() - 1],
        if rates.len() < repeat.max(1) as usize {
            " (interrupted)"
        } else {
            ""
        }
    );
    if !runs.is_empty() {
        print_stages(&runs);
    }
    Ok(())
}

/// Each stage's median time over the runs, its share of the stages' total and its throughput.
fn print_stages(runs: &[Vec<StageTime>]) {
    let median = |stage: usize| {
        let mut times: Vec<f64> = runs.iter().map(|r| r[stage].time.as_secs_f64()).collect();
        times.sort_by(f64::total_cmp);
        times[times.len() / 2]
    };
    let medians: Vec<f64> = (0..runs[0].len()).map(median).collect();
    let total: f64 = medians.iter().sum();
    println!(
        "{:<28} {:>9} {:>7} {:>12} {:>12}",
        "stage (median of runs)", "time ms", "share", "items", "M items/s"
    );
    for (stage, time) in runs[0].iter().zip(&medians) {
        println!(
            "{:<28} {:>9.1} {:>6.1}% {:>12} {:>12.2}",
            stage.name,
            time * 1e3,
            100.0 * time / total.max(1e-12),
            stage.items,
            stage.items as f64 / time.max(1e-12) / 1e6
        );
    }
    println!(
        "items: camera paths for the chunk start and compute_first_draws, shadow rays for \
         trace_shadow_rays, film samples for the splat, live paths otherwise; the splat runs on \
         one thread beside the other stages, and with several threads the bounces of as many \
         chunks run at once, each world's stage times summed: the times overlap"
    );
}
