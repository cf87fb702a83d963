//! Pixel reconstruction filters, applied by filter importance sampling.
//!
//! Ernst et al. 2006, "Filter Importance Sampling", and pbrt-v4 §8.8: instead of splatting each
//! sample into the neighbouring pixels with filter weights, the film position of a pixel's sample
//! is drawn around the pixel centre with density proportional to the filter. The filters here are
//! non-negative, so every sample then has weight 1 and a pixel is the plain mean of its samples.

use std::f32::consts::PI;

use glam::Vec2;

use crate::sampling::Distribution1D;

/// Bins of the tabulated inverse CDF over [0, r] of each axis.
const TABLE_BINS: usize = 64;
/// Simpson panels integrating the filter over one bin.
const PANELS_PER_BIN: usize = 8;

/// The filter's profile along each axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterKind {
    Box,
    /// `alpha`: the falloff, as in pbrt: exp(-alpha x^2) - exp(-alpha r^2).
    Gaussian {
        alpha: f32,
    },
    BlackmanHarris,
}

/// A separable filter f(x, y) = f1(x; rx) f1(y; ry) on [-rx, rx] x [-ry, ry].
#[derive(Clone, Debug)]
pub struct PixelFilter {
    kind: FilterKind,
    radius: Vec2,
    /// |offset| / r per axis, tabulated: `None` for the box, sampled exactly.
    tables: Option<[Distribution1D; 2]>,
}

impl PixelFilter {
    /// A non-finite or non-positive radius is replaced by 0.5 (a one-pixel box).
    pub fn new(kind: FilterKind, radius: Vec2) -> Self {
        let sanitise = |r: f32| if r.is_finite() && r > 0.0 { r } else { 0.5 };
        let radius = Vec2::new(sanitise(radius.x), sanitise(radius.y));
        let tables = match kind {
            FilterKind::Box => None,
            kind => Some([radius.x, radius.y].map(|r| half_axis_table(kind, r))),
        };
        Self {
            kind,
            radius,
            tables,
        }
    }

    /// The one-pixel box: positions uniform in the pixel, for splatting.
    pub fn pixel_box() -> Self {
        Self {
            kind: FilterKind::Box,
            radius: Vec2::splat(0.5),
            tables: None,
        }
    }

    pub fn radius(&self) -> Vec2 {
        self.radius
    }

    /// The (unnormalised) filter value at `offset` pixels from the pixel centre.
    pub fn evaluate(&self, offset: Vec2) -> f32 {
        axis_value(self.kind, offset.x, self.radius.x)
            * axis_value(self.kind, offset.y, self.radius.y)
    }

    /// Maps u in [0,1)^2 to an offset from the pixel centre, in pixels, with density
    /// proportional to the filter. Each axis is monotone in its u, so stratification survives.
    pub fn sample(&self, u: Vec2) -> Vec2 {
        // Symmetric filters: v = 2u - 1 in [-1, 1) gives the side by its sign, and |v| is a
        // uniform sample for the half-axis [0, r].
        let v = 2.0 * u - Vec2::ONE;
        match &self.tables {
            None => v * self.radius,
            Some([tx, ty]) => Vec2::new(
                v.x.signum() * tx.sample_continuous(v.x.abs()).0 * self.radius.x,
                v.y.signum() * ty.sample_continuous(v.y.abs()).0 * self.radius.y,
            ),
        }
    }
}

/// The 1D filter f1(x; r); 0 outside [-r, r].
fn axis_value(kind: FilterKind, x: f32, r: f32) -> f32 {
    if x.abs() > r {
        return 0.0;
    }
    match kind {
        FilterKind::Box => 1.0,
        // pbrt's truncated Gaussian: shifted so it reaches 0 at the radius.
        FilterKind::Gaussian { alpha } => {
            ((-alpha * x * x).exp() - (-alpha * r * r).exp()).max(0.0)
        }
        // The 4-term Blackman-Harris window (Harris 1978) stretched over [-r, r]; t = 1/2 at x = 0.
        FilterKind::BlackmanHarris => {
            let t = 2.0 * PI * (x + r) / (2.0 * r);
            (0.35875 - 0.48829 * t.cos() + 0.14128 * (2.0 * t).cos() - 0.01168 * (3.0 * t).cos())
                .max(0.0)
        }
    }
}

/// The filter's mass per bin of [0, r] (composite Simpson), a piecewise-constant density whose
/// `sample_continuous` inverts the CDF linearly within a bin.
fn half_axis_table(kind: FilterKind, r: f32) -> Distribution1D {
    let bin = r / TABLE_BINS as f32;
    let h = bin / PANELS_PER_BIN as f32;
    let masses: Vec<f32> = (0..TABLE_BINS)
        .map(|i| {
            let x0 = i as f32 * bin;
            (0..PANELS_PER_BIN)
                .map(|j| {
                    let a = x0 + j as f32 * h;
                    let f = |x| axis_value(kind, x, r);
                    h / 6.0 * (f(a) + 4.0 * f(a + h / 2.0) + f(a + h))
                })
                .sum()
        })
        .collect();
    Distribution1D::new(&masses)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{PixelSampler, SamplerKind};

    fn filters() -> Vec<PixelFilter> {
        [
            (FilterKind::Box, Vec2::new(0.5, 1.5)),
            (FilterKind::Gaussian { alpha: 2.0 }, Vec2::new(2.0, 1.0)),
            (FilterKind::BlackmanHarris, Vec2::new(2.0, 2.0)),
        ]
        .map(|(kind, radius)| PixelFilter::new(kind, radius))
        .to_vec()
    }

    #[test]
    fn filter_offsets_stay_within_radius() {
        let sampler = PixelSampler::new(SamplerKind::Independent, 1, 0);
        for filter in filters() {
            let mut corners = vec![Vec2::ZERO, Vec2::splat(0.5), Vec2::splat(0.99999994)];
            corners.extend((0..20_000).map(|p| sampler.sample_2d(p, 0, 0)));
            for u in corners {
                let o = filter.sample(u);
                assert!(o.abs().cmple(filter.radius()).all(), "{o}");
            }
        }
    }

    #[test]
    fn filter_values() {
        let all = filters();
        let (bx, gauss, bh) = (&all[0], &all[1], &all[2]);
        assert_eq!(bx.evaluate(Vec2::new(0.4, -1.4)), 1.0);
        assert_eq!(bx.evaluate(Vec2::new(0.6, 0.0)), 0.0);
        let g0 = 1.0 - (-8.0f32).exp();
        assert!((gauss.evaluate(Vec2::ZERO) - g0 * (1.0 - (-2.0f32).exp())).abs() < 1e-6);
        assert_eq!(gauss.evaluate(Vec2::new(2.0, 0.0)), 0.0);
        // Blackman-Harris: 1 at the centre, ~6e-5 at the edge of the window.
        assert!((bh.evaluate(Vec2::ZERO) - 1.0).abs() < 1e-6);
        assert!(bh.evaluate(Vec2::new(2.0, 0.0)) < 1e-4);
    }

    /// Histogram of the offsets along each axis in 20 bins over [-r, r] against the normalised
    /// filter's marginal (integrated numerically). With n = 200k samples, bins of probability p
    /// have std sqrt(n p (1-p)); we require every bin within 5 std + 0.5% of its expectation
    /// (the 0.5% absorbs the piecewise-constant approximation inside the table's bins).
    #[test]
    fn filter_sample_histogram_matches_filter() {
        let n = 200_000u32;
        let bins = 20usize;
        let sampler = PixelSampler::new(SamplerKind::Independent, n, 4);
        for filter in filters() {
            for axis in 0..2 {
                let r = filter.radius()[axis];
                let fine = 2000;
                let mut expected = vec![0.0f64; bins];
                for k in 0..fine {
                    let mut offset = Vec2::ZERO;
                    offset[axis] = -r + (k as f32 + 0.5) * 2.0 * r / fine as f32;
                    expected[(k * bins) / fine] += f64::from(filter.evaluate(offset));
                }
                let total: f64 = expected.iter().sum();
                let mut counts = vec![0u32; bins];
                for s in 0..n {
                    let x = filter.sample(sampler.sample_2d(0, s, 0))[axis];
                    let bin = (((x + r) / (2.0 * r)) * bins as f32) as usize;
                    counts[bin.min(bins - 1)] += 1;
                }
                for (c, e) in counts.iter().zip(&expected) {
                    let p = e / total;
                    let mean = p * f64::from(n);
                    let tolerance = 5.0 * (mean * (1.0 - p)).sqrt() + 0.005 * mean + 1.0;
                    assert!(
                        (f64::from(*c) - mean).abs() < tolerance,
                        "{counts:?} {expected:?}"
                    );
                }
            }
        }
    }
}
