//! Per-pixel accumulation of radiance samples, by filter importance sampling or by splatting.

use bevy_ecs::prelude::Resource;
use glam::{DVec3, Vec2, Vec3};
use rayon::prelude::*;

use super::PixelFilter;

/// How a sample becomes pixel values.
///
/// - `FilterImportance`: the film position is drawn around the pixel centre with density
///   proportional to the filter (`filter.rs`), and the sample counts for its own pixel only,
///   with weight 1: pixel = mean of its samples.
/// - `Splat`: the film position is uniform in the pixel, and the sample adds f(x - c_j) L and
///   f(x - c_j) to the weighted sum and weight sum of every pixel j whose filter covers it
///   (pbrt-v3 §7.8, Mitsuba 3's `ImageBlock`): pixel = sum f L / sum f. Each sample informs
///   several pixels, so neighbouring pixels share noise and a wide filter smooths more per
///   sample; the ratio is consistent, not unbiased.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Reconstruction {
    FilterImportance,
    #[default]
    Splat,
}

/// Widest footprint a splat covers on one axis (a filter radius up to 7.5 pixels).
const MAX_FOOTPRINT: usize = 16;
/// Entries of the tabulated filter over [0, r] on each axis, read with linear interpolation
/// (Mitsuba 3 tabulates its filters the same way): a splat then costs table reads, not the
/// filter's exponentials.
const SPLAT_TABLE: usize = 256;

/// The filter's two axes, tabulated: f(d, 0) and f(0, d) for d in [0, r].
#[derive(Clone, Debug)]
struct SplatFilter {
    radius: Vec2,
    tables: [Vec<f32>; 2],
}

impl SplatFilter {
    fn new(filter: &PixelFilter) -> Self {
        let radius = filter.radius();
        let table = |axis: usize| {
            (0..=SPLAT_TABLE)
                .map(|i| {
                    let mut offset = Vec2::ZERO;
                    offset[axis] = radius[axis] * i as f32 / SPLAT_TABLE as f32;
                    filter.evaluate(offset)
                })
                .collect()
        };
        Self {
            radius,
            tables: [table(0), table(1)],
        }
    }

    /// The filter along `axis` at `offset` pixels (symmetric; 0 beyond the radius).
    fn value(&self, axis: usize, offset: f32) -> f32 {
        let x = offset.abs() / self.radius[axis] * SPLAT_TABLE as f32;
        if x.is_nan() || x >= SPLAT_TABLE as f32 {
            return 0.0;
        }
        // Casts, not fract(): without SSE4.1 rounding is a library call.
        let i = x as usize;
        let t = x - i as f32;
        let table = &self.tables[axis];
        table[i] + (table[i + 1] - table[i]) * t
    }
}

/// Weighted radiance sums and weight sums per pixel, rows from the top.
///
/// Sums are f64: after 1e5 samples of similar magnitude an f32 sum would keep only ~7 of its
/// 24 bits for each new sample; f64 keeps ~36.
#[derive(Resource, Clone, Debug)]
pub struct Film {
    width: u32,
    height: u32,
    sums: Vec<DVec3>,
    weights: Vec<f64>,
    /// Samples whose film position lies in the pixel.
    counts: Vec<u64>,
    rejected: u64,
    /// The filter samples are splatted with; `None` for filter importance sampling.
    splat: Option<SplatFilter>,
    /// The largest component a sample may have (`--clamp`); `None`: samples are not clamped.
    max_component: Option<f32>,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            sums: vec![DVec3::ZERO; n],
            weights: vec![0.0; n],
            counts: vec![0; n],
            rejected: 0,
            splat: None,
            max_component: None,
        }
    }

    /// From now on, a sample whose largest component exceeds `max_component` is scaled down to
    /// it (`None`: no clamping), as pbrt-v4's `RGBFilm::AddSample` does with its
    /// `maxcomponentvalue`. Scaling the whole colour keeps the sample's hue. This removes
    /// fireflies at the price of bias: the energy above the limit is lost, so the image is
    /// darker where rare bright paths (caustics, small bright lights seen by reflection) matter.
    pub fn clamp_samples(&mut self, max_component: Option<f32>) {
        self.max_component = max_component;
    }

    /// The limit of [`Film::clamp_samples`] (for checkpoints).
    pub fn max_component(&self) -> Option<f32> {
        self.max_component
    }

    /// From now on, samples are splatted with `filter` (their positions must then be uniform
    /// in their pixels).
    pub fn splat_with(&mut self, filter: PixelFilter) {
        self.splat = Some(SplatFilter::new(&filter));
    }

    /// A film from its saved sums, weights and counts (a checkpoint); `None` if the sizes
    /// disagree. Its reconstruction is filter importance sampling until [`Film::restore`] moves
    /// the sums into a film that splats.
    pub fn from_parts(
        width: u32,
        height: u32,
        sums: Vec<DVec3>,
        weights: Vec<f64>,
        counts: Vec<u64>,
        rejected: u64,
        max_component: Option<f32>,
    ) -> Option<Self> {
        let n = width as usize * height as usize;
        (sums.len() == n && weights.len() == n && counts.len() == n).then_some(Self {
            width,
            height,
            sums,
            weights,
            counts,
            rejected,
            splat: None,
            max_component,
        })
    }

    /// Takes `saved`'s sums, weights and counts (a checkpoint of a film of the same size),
    /// keeping this film's reconstruction; false, and nothing taken, if the sizes differ.
    pub fn restore(&mut self, saved: Film) -> bool {
        if (saved.width, saved.height) != (self.width, self.height) {
            return false;
        }
        self.sums = saved.sums;
        self.weights = saved.weights;
        self.counts = saved.counts;
        self.rejected = saved.rejected;
        true
    }

    /// Weighted radiance sums per pixel (for checkpoints).
    pub fn sums(&self) -> &[DVec3] {
        &self.sums
    }

    /// Weight sums per pixel (for checkpoints).
    pub fn weights(&self) -> &[f64] {
        &self.weights
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

    /// Adds one sample, taken at raster position `position`, to `pixel` (y * width + x), the
    /// pixel that position lies in; splatted over the filter's footprint when splatting. A
    /// sample with a NaN, infinite or negative component, or for a pixel outside the film, is
    /// dropped and counted.
    pub fn add_sample(&mut self, pixel: u32, position: Vec2, radiance: Vec3) {
        let valid = radiance.is_finite() && radiance.cmpge(Vec3::ZERO).all();
        let Some(count) = self.counts.get_mut(pixel as usize).filter(|_| valid) else {
            self.rejected += 1;
            return;
        };
        *count += 1;
        let largest = radiance.max_element();
        let radiance = match self.max_component {
            Some(max) if largest > max => radiance * (max / largest),
            _ => radiance,
        }
        .as_dvec3();
        match &self.splat {
            None => {
                self.sums[pixel as usize] += radiance;
                self.weights[pixel as usize] += 1.0;
            }
            Some(filter) => {
                // The pixels whose centres c = (x + 0.5, y + 0.5) lie within the radius.
                let radius = filter.radius;
                let (xs, wx) = footprint(position.x, radius.x, self.width, |d| filter.value(0, d));
                let (ys, wy) = footprint(position.y, radius.y, self.height, |d| filter.value(1, d));
                // The filter is separable: f(dx, 0) f(0, dy) = f(dx, dy) f(0, 0), and the
                // constant f(0, 0) cancels in sum / weight.
                for (j, &fy) in wy.iter().enumerate().take(ys.1) {
                    let row = (ys.0 + j) * self.width as usize;
                    for (i, &fx) in wx.iter().enumerate().take(xs.1) {
                        let w = f64::from(fx * fy);
                        self.sums[row + xs.0 + i] += radiance * w;
                        self.weights[row + xs.0 + i] += w;
                    }
                }
            }
        }
    }

    /// The estimate of every pixel (weighted sum over weight sum); black where nothing arrived.
    pub fn mean(&self) -> Vec<Vec3> {
        self.sums
            .par_iter()
            .zip(self.weights.par_iter())
            .map(|(&sum, &weight)| {
                if weight > 0.0 {
                    (sum / weight).as_vec3()
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

/// The pixels along one axis whose centres lie within `radius` of `position`, as (first,
/// count), and the filter's value at each.
fn footprint(
    position: f32,
    radius: f32,
    size: u32,
    value: impl Fn(f32) -> f32,
) -> ((usize, usize), [f32; MAX_FOOTPRINT]) {
    // ceil and floor by casts (which truncate towards zero), as in `SplatFilter::value`.
    let (low, high) = (position - 0.5 - radius, position - 0.5 + radius);
    let first = (low as i64 + i64::from((low as i64 as f32) < low)).max(0) as usize;
    let last = (high as i64 - i64::from((high as i64 as f32) > high)).min(i64::from(size) - 1);
    let count = (last + 1 - first as i64).clamp(0, MAX_FOOTPRINT as i64) as usize;
    let mut weights = [0.0; MAX_FOOTPRINT];
    for (i, w) in weights.iter_mut().enumerate().take(count) {
        *w = value(position - ((first + i) as f32 + 0.5));
    }
    ((first, count), weights)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn film_means_and_rejects_invalid_samples() {
        let mut film = Film::new(3, 2);
        film.add_sample(0, Vec2::splat(0.5), Vec3::new(1.0, 2.0, 3.0));
        film.add_sample(0, Vec2::splat(0.5), Vec3::new(3.0, 2.0, 1.0));
        film.add_sample(1, Vec2::new(1.5, 0.5), Vec3::new(f32::NAN, 0.0, 0.0));
        film.add_sample(1, Vec2::new(1.5, 0.5), Vec3::new(0.0, f32::INFINITY, 0.0));
        film.add_sample(1, Vec2::new(1.5, 0.5), Vec3::new(0.0, 0.0, -1.0));
        film.add_sample(6, Vec2::new(0.5, 2.5), Vec3::ONE);
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
            film.add_sample(
                0,
                Vec2::splat(0.5),
                Vec3::splat(if i % 2 == 0 { 1e3 } else { 1e-3 }),
            );
        }
        let m = film.mean()[0].x;
        assert!((m - 500.0005).abs() < 1e-4, "{m}");
    }
}
