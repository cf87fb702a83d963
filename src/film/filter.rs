//! Pixel reconstruction filters, applied by filter importance sampling.
//!
//! Ernst et al. 2006, "Filter Importance Sampling", and pbrt-v4 §8.8: instead of splatting each
//! sample into the neighbouring pixels with filter weights, the film position of a pixel's sample
//! is drawn around the pixel centre with density proportional to the filter. For a non-negative
//! filter every sample then has weight 1 and a pixel is the plain mean of its samples.
//!
//! Filters with negative lobes (Mitchell, windowed sinc) are sampled from |f| instead, and each
//! sample carries the weight sign(f) W, with W = (integral of |f|) / (integral of f) per axis:
//! for a sample x drawn with density |f(x)| / integral |f|, E[sign(f(x)) W L(x)] =
//! integral f L / integral f, the filtered pixel value, so the pixel is still the mean of
//! weight x radiance ([`PixelFilter::weight`]).

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
    /// Mitchell and Netravali 1988 cubic with parameters B and C (LuxRender's defaults 1/3, 1/3).
    Mitchell {
        b: f32,
        c: f32,
    },
    /// A tent reaching 0 at the radius.
    Triangle,
    /// Lanczos-windowed sinc with `tau` lobes (LuxRender's `sinc`, default 3).
    Sinc {
        tau: f32,
    },
}

/// A separable filter f(x, y) = f1(x; rx) f1(y; ry) on [-rx, rx] x [-ry, ry].
#[derive(Clone, Debug)]
pub struct PixelFilter {
    kind: FilterKind,
    radius: Vec2,
    /// |offset| / r per axis, tabulated: `None` for the box, sampled exactly.
    tables: Option<[Distribution1D; 2]>,
    /// (integral of |f1|) / (integral of f1) per axis: 1 for non-negative filters.
    sign_weight: Vec2,
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
        let sign_weight = Vec2::new(sign_weight(kind, radius.x), sign_weight(kind, radius.y));
        Self {
            kind,
            radius,
            tables,
            sign_weight,
        }
    }

    /// The one-pixel box: positions uniform in the pixel, for splatting.
    pub fn pixel_box() -> Self {
        Self {
            kind: FilterKind::Box,
            radius: Vec2::splat(0.5),
            tables: None,
            sign_weight: Vec2::ONE,
        }
    }

    /// Whether this is the one-pixel box: f = 1 on the pixel, 0 beyond (radius 0.5).
    pub fn is_pixel_box(&self) -> bool {
        self.kind == FilterKind::Box && self.radius == Vec2::splat(0.5)
    }

    /// The weight of a sample drawn by [`PixelFilter::sample`] at `offset`: 1 for non-negative
    /// filters; sign(f(offset)) times the per-axis ratios of the integrals of |f| and f
    /// otherwise (see the module comment).
    pub fn weight(&self, offset: Vec2) -> f32 {
        let sign = |x, r| {
            if axis_value(self.kind, x, r) < 0.0 {
                -1.0
            } else {
                1.0
            }
        };
        sign(offset.x, self.radius.x)
            * sign(offset.y, self.radius.y)
            * self.sign_weight.x
            * self.sign_weight.y
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
    /// proportional to |filter|. Each axis is monotone in its u, so stratification survives.
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
    let t = x.abs() / r;
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
        FilterKind::Mitchell { b, c } => mitchell(2.0 * t, b, c),
        FilterKind::Triangle => 1.0 - t,
        FilterKind::Sinc { tau } => lanczos_sinc(t, tau),
    }
}

/// Mitchell and Netravali 1988 ("Reconstruction Filters in Computer Graphics", eq. 8), the
/// cubic LuxRender's `mitchell` (`filters/mitchell.h`) evaluates at x = 2 |offset| / radius:
///
///   6 k(x) = (12 - 9B - 6C) x^3 + (-18 + 12B + 6C) x^2 + (6 - 2B)          for x < 1,
///            (-B - 6C) x^3 + (6B + 30C) x^2 + (-12B - 48C) x + (8B + 24C)   for 1 <= x < 2,
///
/// continuous with a continuous slope, 0 at x = 2, and negative on part of (1, 2) for most B, C.
fn mitchell(x: f32, b: f32, c: f32) -> f32 {
    let (x2, x3) = (x * x, x * x * x);
    let k = if x < 1.0 {
        (12.0 - 9.0 * b - 6.0 * c) * x3 + (-18.0 + 12.0 * b + 6.0 * c) * x2 + (6.0 - 2.0 * b)
    } else if x < 2.0 {
        (-b - 6.0 * c) * x3
            + (6.0 * b + 30.0 * c) * x2
            + (-12.0 * b - 48.0 * c) * x
            + (8.0 * b + 24.0 * c)
    } else {
        0.0
    };
    k / 6.0
}

/// The Lanczos-windowed sinc of LuxRender's `sinc` (`filters/sinc.h`, pbrt-v1's
/// `LanczosSincFilter`) at t = |offset| / radius in [0, 1]:
/// sinc(pi t tau) sinc(pi t), with sinc(x) = sin(x) / x.
fn lanczos_sinc(t: f32, tau: f32) -> f32 {
    if t < 1e-5 {
        return 1.0;
    }
    let x = PI * t;
    (x * tau).sin() / (x * tau) * x.sin() / x
}

/// (integral of |f1|) / (integral of f1) over [0, r] (the filters are even), by the midpoint
/// rule; 1 for the non-negative filters.
fn sign_weight(kind: FilterKind, r: f32) -> f32 {
    if !matches!(kind, FilterKind::Mitchell { .. } | FilterKind::Sinc { .. }) {
        return 1.0;
    }
    const STEPS: usize = 4096;
    let (mut abs, mut signed) = (0.0f64, 0.0f64);
    for i in 0..STEPS {
        let f = f64::from(axis_value(kind, (i as f32 + 0.5) / STEPS as f32 * r, r));
        abs += f.abs();
        signed += f;
    }
    if signed > 0.0 && abs.is_finite() {
        (abs / signed) as f32
    } else {
        1.0
    }
}

/// The mass of |filter| per bin of [0, r] (composite Simpson), a piecewise-constant density whose
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
                    let f = |x| axis_value(kind, x, r).abs();
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
            (
                FilterKind::Mitchell {
                    b: 1.0 / 3.0,
                    c: 1.0 / 3.0,
                },
                Vec2::new(2.0, 1.5),
            ),
            (FilterKind::Triangle, Vec2::new(2.0, 1.0)),
            (FilterKind::Sinc { tau: 3.0 }, Vec2::new(4.0, 4.0)),
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
    /// |filter|'s marginal (integrated numerically). With n = 200k samples, bins of probability p
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
                    expected[(k * bins) / fine] += f64::from(filter.evaluate(offset).abs());
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

    /// Mitchell-Netravali cubics (any B, C) form a partition of unity: the sum over integers n
    /// of k(x - n) is 1 for every x, so k integrates to 1 over [-2, 2]. k(0) = (6 - 2B) / 6,
    /// k(2) = 0, and B = 0.75, C = 0.125 (the LuxRender test scenes' values) dip below 0 on
    /// (1.5, 2).
    #[test]
    fn mitchell_known_values() {
        for (b, c) in [
            (1.0 / 3.0, 1.0 / 3.0),
            (0.75, 0.125),
            (0.0, 0.5),
            (1.0, 0.0),
        ] {
            assert!((mitchell(0.0, b, c) - (6.0 - 2.0 * b) / 6.0).abs() < 1e-6);
            assert!(mitchell(2.0, b, c).abs() < 1e-6);
            // The two pieces meet at x = 1.
            let (below, above) = (mitchell(1.0 - 1e-4, b, c), mitchell(1.0, b, c));
            assert!((below - above).abs() < 1e-3, "{below} {above}");
            for x in [0.0f32, 0.17, 0.5, 0.83] {
                let sum: f32 = (-3..=3).map(|n| mitchell((x - n as f32).abs(), b, c)).sum();
                assert!((sum - 1.0).abs() < 1e-5, "B {b} C {c} x {x}: {sum}");
            }
        }
        assert!(mitchell(1.8, 0.75, 0.125) < 0.0);
        assert!(mitchell(1.2, 0.75, 0.125) > 0.0);
    }

    #[test]
    fn triangle_and_sinc_values() {
        let tri = PixelFilter::new(FilterKind::Triangle, Vec2::splat(2.0));
        assert!((tri.evaluate(Vec2::new(1.0, -0.5)) - 0.5 * 0.75).abs() < 1e-6);
        assert_eq!(tri.weight(Vec2::new(1.0, 1.0)), 1.0);
        // sinc(pi t tau) vanishes at t = 1 / tau, 2 / tau; the window at t = 1.
        for t in [1.0 / 3.0, 2.0 / 3.0, 1.0] {
            assert!(lanczos_sinc(t, 3.0).abs() < 1e-6, "{t}");
        }
        assert_eq!(lanczos_sinc(0.0, 3.0), 1.0);
        assert!(lanczos_sinc(0.5, 3.0) < 0.0);
    }

    /// The signed estimator: with offsets drawn from |f| and weights sign(f) W, the mean of
    /// weight x g(offset) is the filter-weighted mean of g, integral f g / integral f (here
    /// g = 1 + x^2 + y, by quadrature). 200k stratified samples; the tolerance is 5 standard
    /// deviations of the estimator (estimated from the samples) plus 0.2% for the tabulated
    /// inverse CDF, as in the histogram test.
    #[test]
    fn signed_weights_give_the_filtered_mean() {
        let n = 200_000u32;
        let sampler = PixelSampler::new(SamplerKind::Stratified, n, 6);
        for filter in filters() {
            let g = |o: Vec2| 1.0 + o.x * o.x + o.y;
            let r = filter.radius();
            let fine = 400;
            let (mut num, mut den) = (0.0f64, 0.0f64);
            for i in 0..fine {
                for j in 0..fine {
                    let o = Vec2::new(
                        -r.x + (i as f32 + 0.5) * 2.0 * r.x / fine as f32,
                        -r.y + (j as f32 + 0.5) * 2.0 * r.y / fine as f32,
                    );
                    let f = f64::from(filter.evaluate(o));
                    num += f * f64::from(g(o));
                    den += f;
                }
            }
            let expected = num / den;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for s in 0..n {
                let o = filter.sample(sampler.sample_2d(0, s, 0));
                let v = f64::from(filter.weight(o) * g(o));
                sum += v;
                sum2 += v * v;
            }
            let mean = sum / f64::from(n);
            let sd = ((sum2 / f64::from(n) - mean * mean) / f64::from(n)).sqrt();
            println!("{:?}: {mean} vs {expected} (sd {sd})", filter.kind);
            assert!(
                (mean - expected).abs() < 5.0 * sd + 2e-3 * expected.abs(),
                "{:?}: {mean} vs {expected}",
                filter.kind
            );
        }
    }
}
