//! `foton bench`: wavefront throughput on a scene, as the median of repeated renders measured
//! in one process (these machines are shared and noisy: compare ratios from one run).

use super::render::{Stop, prepare, render_with_progress, summary};
use super::{Failure, SceneArgs};

pub fn run(args: &SceneArgs, repeat: u32) -> Result<(), Failure> {
    let (warm_up, stop) = render_with_progress(&mut prepare(args)?)?;
    println!("warm-up: {}", summary(&warm_up));
    let mut rates = Vec::new();
    if stop != Stop::Interrupted {
        for i in 0..repeat.max(1) {
            let (stats, stop) = render_with_progress(&mut prepare(args)?)?;
            if stop == Stop::Interrupted {
                // A partial run would skew the median.
                break;
            }
            println!("run {}: {}", i + 1, summary(&stats));
            rates.push(stats.paths_per_second() / 1e6);
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
    Ok(())
}
