//! `foton bench`: wavefront throughput on a scene, as the median of repeated renders measured
//! in one process (these machines are shared and noisy: compare ratios from one run).

use super::SceneArgs;
use super::render::{prepare, render_with_progress, summary};

pub fn run(args: &SceneArgs, repeat: u32) -> Result<(), String> {
    let mut warm_up = prepare(args)?;
    println!(
        "warm-up: {}",
        summary(&render_with_progress(&mut warm_up.renderer))
    );
    let mut rates = Vec::new();
    for i in 0..repeat.max(1) {
        let mut prepared = prepare(args)?;
        let stats = render_with_progress(&mut prepared.renderer);
        println!("run {}: {}", i + 1, summary(&stats));
        rates.push(stats.paths_per_second() / 1e6);
    }
    rates.sort_by(f64::total_cmp);
    println!(
        "median {:.3} M paths/s over {} runs (min {:.3}, max {:.3})",
        rates[rates.len() / 2],
        rates.len(),
        rates[0],
        rates[rates.len() - 1]
    );
    Ok(())
}
