//! Per-pixel accumulation of radiance samples.

use bevy_ecs::prelude::Resource;
use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// Radiance sums and sample counts per pixel, rows from the top.
///
/// Sums are f64: after 1e5 samples of similar magnitude an f32 sum would keep only ~7 of its
/// 24 bits for each new sample; f64 keeps ~36.
#[derive(Resource, Clone, Debug)]
pub struct Film {
    width: u32,
    height: u32,
    sums: Vec<DVec3>,
    counts: Vec<u64>,
    rejected: u64,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            sums: vec![DVec3::ZERO; n],
            counts: vec![0; n],
            rejected: 0,
        }
    }

    /// A film from its saved sums and counts (a checkpoint); `None` if the sizes disagree.
    pub fn from_parts(
        width: u32,
        height: u32,
        sums: Vec<DVec3>,
        counts: Vec<u64>,
        rejected: u64,
    ) -> Option<Self> {
        let n = width as usize * height as usize;
        (sums.len() == n && counts.len() == n).then_some(Self {
            width,
            height,
            sums,
            counts,
            rejected,
        })
    }

    /// Radiance sums per pixel (for checkpoints).
    pub fn sums(&self) -> &[DVec3] {
        &self.sums
    }

    /// Samples per pixel received (for checkpoints).
    pub fn counts(&self) -> &[u64] {
        &self.counts
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// Adds one sample to `pixel` (y * width + x). A sample with a NaN, infinite or negative
    /// component, or for a pixel outside the film, is dropped and counted.
    pub fn add_sample(&mut self, pixel: u32, radiance: Vec3) {
        let accepted = match (
            self.sums.get_mut(pixel as usize),
            self.counts.get_mut(pixel as usize),
        ) {
            (Some(sum), Some(count)) => accumulate(sum, count, radiance),
            _ => false,
        };
        self.rejected += u64::from(!accepted);
    }

    /// The mean radiance of every pixel; black where no sample arrived.
    pub fn mean(&self) -> Vec<Vec3> {
        self.sums
            .par_iter()
            .zip(self.counts.par_iter())
            .map(|(&sum, &count)| {
                if count > 0 {
                    (sum / count as f64).as_vec3()
                } else {
                    Vec3::ZERO
                }
            })
            .collect()
    }

    /// The fewest samples any pixel has received (0 for an empty film).
    pub fn samples_per_pixel_min(&self) -> u64 {
        self.counts.iter().copied().min().unwrap_or(0)
    }

    /// Samples dropped for being non-finite or negative, or outside the film.
    pub fn rejected_samples(&self) -> u64 {
        self.rejected
    }
}

/// Adds `radiance` to a pixel if it is finite and non-negative; returns whether it was.
fn accumulate(sum: &mut DVec3, count: &mut u64, radiance: Vec3) -> bool {
    let valid = radiance.is_finite() && radiance.cmpge(Vec3::ZERO).all();
    if valid {
        *sum += radiance.as_dvec3();
        *count += 1;
    }
    valid
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn film_means_and_rejects_invalid_samples() {
        let mut film = Film::new(3, 2);
        film.add_sample(0, Vec3::new(1.0, 2.0, 3.0));
        film.add_sample(0, Vec3::new(3.0, 2.0, 1.0));
        film.add_sample(1, Vec3::new(f32::NAN, 0.0, 0.0));
        film.add_sample(1, Vec3::new(0.0, f32::INFINITY, 0.0));
        film.add_sample(1, Vec3::new(0.0, 0.0, -1.0));
        film.add_sample(6, Vec3::ONE);
        let mean = film.mean();
        assert_eq!(mean[0], Vec3::splat(2.0));
        assert_eq!(mean[1], Vec3::ZERO);
        assert_eq!(film.rejected_samples(), 4);
        assert_eq!(film.samples_per_pixel_min(), 0);
        assert_eq!((film.width(), film.height()), (3, 2));
    }

    #[test]
    fn film_keeps_precision_over_many_samples() {
        // 1e5 samples alternating 1e3 and 1e-3 per pixel: exact mean 500.0005.
        let mut film = Film::new(1, 1);
        for i in 0..100_000 {
            film.add_sample(0, Vec3::splat(if i % 2 == 0 { 1e3 } else { 1e-3 }));
        }
        let m = film.mean()[0].x;
        assert!((m - 500.0005).abs() < 1e-4, "{m}");
    }
}
