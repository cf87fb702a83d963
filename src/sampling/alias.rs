//! Alias tables: O(1) sampling of a discrete distribution (Walker 1977, built with Vose's
//! 1991 method; pbrt-v4 §A.1 `AliasTable`).
//!
//! Each of the n bins holds a threshold q_i and an alias a_i: u picks bin i = floor(u n)
//! uniformly, then i itself with probability q_i, else a_i. Vose's construction splits the bins
//! into those with scaled weight p_i n below 1 ("small") and the rest ("large"), and repeatedly
//! fills a small bin up to 1 with mass from a large one, so every bin's two entries sum to
//! exactly 1/n of the total and each index receives exactly its p_i over all bins.

use glam::Vec4;

use super::ONE_MINUS_EPSILON;
use crate::math::select_lanes as select;

#[derive(Clone, Debug)]
pub struct AliasTable {
    bins: Vec<AliasBin>,
}

#[derive(Clone, Copy, Debug)]
struct AliasBin {
    /// Probability of keeping this bin's own index once the bin is chosen.
    threshold: f32,
    alias: u32,
    /// The index's own probability p_i (for `pdf` and for the sample's weight).
    probability: f32,
}

impl AliasTable {
    /// Negative, NaN and infinite weights count as 0; all-zero weights (or none) fall back to
    /// the uniform distribution.
    pub fn new(weights: &[f32]) -> Self {
        let mut clean: Vec<f64> = weights
            .iter()
            .map(|&w| {
                if w.is_finite() && w > 0.0 {
                    f64::from(w)
                } else {
                    0.0
                }
            })
            .collect();
        if clean.is_empty() {
            clean.push(0.0);
        }
        let n = clean.len();
        // Bin numbers go through i32 ([`AliasTable::sample_index_four`]).
        assert!(n < 1 << 30, "an alias table of {n} bins");
        let total: f64 = clean.iter().sum();
        if total <= 0.0 {
            clean.iter_mut().for_each(|w| *w = 1.0);
        }
        let total: f64 = clean.iter().sum();
        let probability: Vec<f64> = clean.iter().map(|w| w / total).collect();
        // Scaled weights p_i n: the mass each bin must end up with is exactly 1.
        let mut scaled: Vec<f64> = probability.iter().map(|p| p * n as f64).collect();
        let mut bins: Vec<AliasBin> = probability
            .iter()
            .enumerate()
            .map(|(i, &p)| AliasBin {
                threshold: 1.0,
                alias: i as u32,
                probability: p as f32,
            })
            .collect();
        let (mut small, mut large): (Vec<usize>, Vec<usize>) =
            (0..n).partition(|&i| scaled[i] < 1.0);
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            large.pop();
            bins[s].threshold = scaled[s] as f32;
            bins[s].alias = l as u32;
            // The large bin gives 1 - scaled[s] of its mass to fill the small one.
            scaled[l] += scaled[s] - 1.0;
            if scaled[l] < 1.0 {
                small.push(l);
            } else {
                large.push(l);
            }
        }
        // What is left is 1 up to rounding: such bins keep their own index.
        for i in small.into_iter().chain(large) {
            bins[i].threshold = 1.0;
        }
        Self { bins }
    }

    pub fn count(&self) -> usize {
        self.bins.len()
    }

    /// Probability of index `index` (0 outside the table).
    pub fn pdf(&self, index: usize) -> f32 {
        self.bins.get(index).map_or(0.0, |b| b.probability)
    }

    /// Picks an index with probability proportional to its weight: (index, probability, `u`
    /// remapped to [0, 1), uniform and independent of the choice, so it can be reused).
    pub fn sample(&self, u: f32) -> (usize, f32, f32) {
        let (index, remapped) = self.sample_index(u);
        (index, self.bins[index].probability, remapped)
    }

    /// [`AliasTable::sample`] without the probability, for a caller that has the density
    /// elsewhere: one dependent load fewer.
    pub fn sample_index(&self, u: f32) -> (usize, f32) {
        let u = if u.is_nan() {
            0.0
        } else {
            u.clamp(0.0, ONE_MINUS_EPSILON)
        };
        // One bin (one light, one triangle) is the choice, and u is already uniform: what the
        // general case below gives (bin 0, frac u, threshold 1), without its arithmetic.
        if self.bins.len() == 1 {
            return (0, u);
        }
        // Bin numbers in u32 (the table holds at most u32::MAX bins: `alias` is a u32), and
        // u n truncated through i32 (u n >= 0, and below 2^31 for tables of fewer than 2^31 bins):
        // f32 -> i32 is one instruction on every x86-64, f32 -> u32 one only with AVX-512
        // (eight before it), f32 -> usize a dozen.
        let n = self.bins.len() as u32;
        let scaled = u * n as f32;
        let bin = (scaled as i32 as u32).min(n - 1);
        let frac = (scaled - bin as f32).clamp(0.0, ONE_MINUS_EPSILON);
        let entry = &self.bins[bin as usize];
        let (index, remapped) = if frac < entry.threshold {
            (bin, frac / entry.threshold)
        } else {
            (
                entry.alias,
                (frac - entry.threshold) / (1.0 - entry.threshold),
            )
        };
        (index as usize, remapped.clamp(0.0, ONE_MINUS_EPSILON))
    }
}

impl AliasTable {
    /// [`AliasTable::sample_index`] of four numbers, to the bit: its arithmetic on the four
    /// lanes of glam's `Vec4` (one SSE instruction each), its branches as selects (both sides
    /// computed), and each lane's bin read alone. For the environment map's light samples
    /// taken four at a time.
    #[inline]
    pub fn sample_index_four(&self, u: Vec4) -> ([usize; 4], Vec4) {
        let (zero, below_one) = (Vec4::ZERO, Vec4::splat(ONE_MINUS_EPSILON));
        // `f32::clamp` (a NaN stays NaN) and the NaN test.
        let clamp = |x: Vec4| {
            let x = select(x.cmplt(zero), zero, x);
            select(x.cmpgt(below_one), below_one, x)
        };
        let u = select(u.cmpeq(u), clamp(u), zero);
        if self.bins.len() == 1 {
            return ([0; 4], u);
        }
        let n = self.bins.len() as u32;
        let scaled = u * n as f32;
        // Plain loops: `array::map` with a bounds check inside was not inlined.
        let (mut bins, mut bin_floats, mut thresholds) = ([0u32; 4], [0.0; 4], [0.0; 4]);
        for lane in 0..4 {
            // SAFETY: u n is finite, in [0, n], and n is below 2^30 (asserted by `new`).
            let bin = (unsafe { scaled[lane].to_int_unchecked::<i32>() } as u32).min(n - 1);
            (bins[lane], bin_floats[lane]) = (bin, bin as f32);
            thresholds[lane] = self.bins[bin as usize].threshold;
        }
        let frac = clamp(scaled - Vec4::from_array(bin_floats));
        let threshold = Vec4::from_array(thresholds);
        let kept = frac.cmplt(threshold);
        let remapped = select(
            kept,
            frac / threshold,
            (frac - threshold) / (1.0 - threshold),
        );
        let kept = kept.bitmask();
        let mut index = [0; 4];
        for lane in 0..4 {
            let bin = bins[lane] as usize;
            index[lane] = if kept & (1 << lane) != 0 {
                bin
            } else {
                self.bins[bin].alias as usize
            };
        }
        (index, clamp(remapped))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::PathRng;

    #[test]
    fn alias_table_histogram_matches_weights() {
        // 8 non-zero weights => 7 degrees of freedom; the 0.999 quantile of chi2(7) is 24.3, so
        // a correct table fails with probability 1e-3 (fixed seed: deterministic). Zero-weight
        // bins must never be chosen, and the remapped u must stay uniform: its mean within
        // 4.5 standard errors (sd 1/sqrt(12 n)) of 1/2.
        let weights = [1.0, 0.0, 3.0, 0.5, 2.0, 8.0, 0.0, 1.0, 4.0, 0.25];
        let table = AliasTable::new(&weights);
        let total: f32 = weights.iter().sum();
        let n = 200_000u32;
        let mut counts = [0u32; 10];
        let mut remapped_sum = 0.0f64;
        let mut rng = PathRng::new(3, 0, 0);
        for _ in 0..n {
            let (i, p, r) = table.sample(rng.next_f32());
            assert!((p - weights[i] / total).abs() < 1e-6 && (0.0..1.0).contains(&r));
            assert!((table.pdf(i) - p).abs() < 1e-7);
            counts[i] += 1;
            remapped_sum += f64::from(r);
        }
        assert_eq!(counts[1] + counts[6], 0);
        let chi2: f64 = counts
            .iter()
            .zip(weights)
            .filter(|(_, w)| *w > 0.0)
            .map(|(&c, w)| {
                let e = f64::from(w / total) * f64::from(n);
                (f64::from(c) - e).powi(2) / e
            })
            .sum();
        assert!(chi2 < 24.3, "chi2 {chi2}");
        let se = (1.0 / (12.0 * f64::from(n))).sqrt();
        assert!((remapped_sum / f64::from(n) - 0.5).abs() < 4.5 * se);
    }

    #[test]
    fn alias_table_degenerate_inputs() {
        for weights in [vec![], vec![0.0; 4], vec![f32::NAN, -1.0, f32::INFINITY]] {
            let table = AliasTable::new(&weights);
            let n = table.count();
            for u in [0.0, 0.3, 0.99999994, 1.0, -1.0, f32::NAN] {
                let (i, p, r) = table.sample(u);
                assert!(i < n && (p - 1.0 / n as f32).abs() < 1e-6 && (0.0..1.0).contains(&r));
                // One bin hands u on unchanged (clamped into [0, 1)).
                if n == 1 && (0.0..1.0).contains(&u) {
                    assert_eq!(r, u);
                }
            }
        }
        let table = AliasTable::new(&[f32::MAX, f32::MAX, 0.0]);
        assert!((table.pdf(0) - 0.5).abs() < 1e-6 && table.pdf(2) == 0.0 && table.pdf(3) == 0.0);
        for k in 0..1000 {
            assert_ne!(table.sample(k as f32 / 1000.0).0, 2);
        }
    }
}
