//! Piecewise-constant 1D distributions, sampled by inverting their CDFs (pbrt-v3 §13.3.1).

use super::ONE_MINUS_EPSILON;

/// A piecewise-constant function on [0, 1) with `n` equal bins, and its normalised CDF.
///
/// Negative, NaN and infinite weights count as 0; all-zero weights (or none) fall back to the
/// uniform distribution, while `integral()` still reports 0.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    func: Vec<f32>,
    /// n + 1 entries from 0 to 1.
    cdf: Vec<f32>,
    integral: f32,
}

impl Distribution1D {
    pub fn new(weights: &[f32]) -> Self {
        let mut func: Vec<f32> = weights
            .iter()
            .map(|&w| if w.is_finite() && w > 0.0 { w } else { 0.0 })
            .collect();
        if func.is_empty() {
            func.push(0.0);
        }
        let n = func.len() as f64;
        // Running sums in f64: no overflow for huge weights, no drift for long tables.
        let mut sums = Vec::with_capacity(func.len() + 1);
        let mut total = 0.0f64;
        sums.push(0.0);
        for &f in &func {
            total += f64::from(f);
            sums.push(total);
        }
        let cdf = if total > 0.0 {
            sums.iter().map(|&s| (s / total) as f32).collect()
        } else {
            (0..sums.len()).map(|i| (i as f64 / n) as f32).collect()
        };
        Self {
            func,
            cdf,
            integral: (total / n) as f32,
        }
    }

    /// Number of bins.
    pub fn count(&self) -> usize {
        self.func.len()
    }

    /// The integral of the function over [0, 1): the mean weight.
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// Discrete probability of bin `index` (0 outside the table).
    pub fn pdf(&self, index: usize) -> f32 {
        match self.func.get(index) {
            Some(&f) if self.integral > 0.0 => f / self.integral / self.count() as f32,
            Some(_) => 1.0 / self.count() as f32,
            None => 0.0,
        }
    }

    /// Picks a bin with probability proportional to its weight: (index, discrete probability,
    /// `u` remapped to [0, 1) within the bin, so it can be reused).
    pub fn sample(&self, u: f32) -> (usize, f32, f32) {
        let (index, remapped) = self.invert(u);
        (index, self.pdf(index), remapped)
    }

    /// Samples x in [0, 1) with density func(x) / integral.
    pub fn sample_continuous(&self, u: f32) -> (f32, f32) {
        let (index, remapped) = self.invert(u);
        let x = (index as f32 + remapped) / self.count() as f32;
        (x.min(ONE_MINUS_EPSILON), self.density(index))
    }

    /// The continuous density on bin `index`.
    fn density(&self, index: usize) -> f32 {
        if self.integral > 0.0 {
            self.func[index] / self.integral
        } else {
            1.0
        }
    }

    /// The bin whose CDF interval holds u (never a zero-weight bin, whose interval is empty),
    /// and u's relative position in it.
    fn invert(&self, u: f32) -> (usize, f32) {
        let u = if u.is_nan() {
            0.0
        } else {
            u.clamp(0.0, ONE_MINUS_EPSILON)
        };
        let last = self.count() - 1;
        let index = self
            .cdf
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(last);
        let width = self.cdf[index + 1] - self.cdf[index];
        let remapped = if width > 0.0 {
            (u - self.cdf[index]) / width
        } else {
            0.0
        };
        (index, remapped.clamp(0.0, ONE_MINUS_EPSILON))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::PathRng;

    /// Pearson's chi-square statistic of observed counts against expected probabilities.
    fn chi_square(counts: &[u32], probs: &[f64], n: u32) -> f64 {
        counts
            .iter()
            .zip(probs)
            .filter(|(_, p)| **p > 0.0)
            .map(|(&c, &p)| {
                let e = p * f64::from(n);
                (f64::from(c) - e).powi(2) / e
            })
            .sum()
    }

    #[test]
    fn distribution1d_histogram_matches_weights() {
        // 8 bins with non-zero weight => 7 degrees of freedom; the 0.999 quantile of chi2(7) is
        // 24.3, so a correct sampler fails with probability 1e-3 (the seed is fixed: it passes
        // or fails deterministically). A bin with zero weight must never be chosen.
        let weights = [1.0, 0.0, 3.0, 0.5, 2.0, 8.0, 0.0, 1.0, 4.0, 0.25];
        let d = Distribution1D::new(&weights);
        let total: f32 = weights.iter().sum();
        assert!((d.integral() - total / 10.0).abs() < 1e-6);
        let probs: Vec<f64> = weights.iter().map(|&w| f64::from(w / total)).collect();
        let n = 100_000;
        let mut counts = vec![0u32; 10];
        let mut continuous = vec![0u32; 10];
        let mut rng = PathRng::new(1, 0, 0);
        for _ in 0..n {
            let (i, p, r) = d.sample(rng.next_f32());
            assert!((p - probs[i] as f32).abs() < 1e-6 && (0.0..1.0).contains(&r));
            counts[i] += 1;
            let (x, pdf) = d.sample_continuous(rng.next_f32());
            let bin = (x * 10.0) as usize;
            assert!((pdf - weights[bin] / d.integral()).abs() < 1e-5);
            continuous[bin] += 1;
        }
        assert_eq!(counts[1] + counts[6] + continuous[1] + continuous[6], 0);
        assert!(chi_square(&counts, &probs, n) < 24.3);
        assert!(chi_square(&continuous, &probs, n) < 24.3);
    }

    #[test]
    fn distribution1d_degenerate_inputs() {
        for weights in [
            vec![],
            vec![0.0; 4],
            vec![f32::NAN, -1.0, f32::INFINITY, f32::NEG_INFINITY],
        ] {
            let d = Distribution1D::new(&weights);
            assert_eq!(d.integral(), 0.0);
            let n = d.count();
            for u in [0.0, 0.3, 0.99999994, 1.0, -1.0, f32::NAN] {
                let (i, p, r) = d.sample(u);
                assert!(i < n && (p - 1.0 / n as f32).abs() < 1e-6 && (0.0..1.0).contains(&r));
                let (x, pdf) = d.sample_continuous(u);
                assert!((0.0..1.0).contains(&x) && pdf == 1.0);
            }
        }
        // Huge finite weights do not overflow the CDF.
        let d = Distribution1D::new(&[f32::MAX, f32::MAX, 0.0]);
        assert!((d.pdf(0) - 0.5).abs() < 1e-6 && d.pdf(2) == 0.0 && d.pdf(3) == 0.0);
        // u = 1 (out of range) never picks a trailing zero-weight bin.
        assert_eq!(Distribution1D::new(&[1.0, 0.0]).sample(1.0).0, 0);
        // NaN/inf weights are zero; the others still sample.
        let d = Distribution1D::new(&[f32::NAN, 2.0, f32::INFINITY]);
        assert_eq!(d.sample(0.7).0, 1);
    }
}
