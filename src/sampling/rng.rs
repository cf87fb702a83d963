//! A per-path random stream.

use glam::Vec2;
use rand_xoshiro::Xoshiro128PlusPlus;
use rand_xoshiro::rand_core::{Rng, SeedableRng};

use super::hash::{hash_extend, hash_words, mix64, unit_f32};

/// xoshiro128++ (Blackman & Vigna 2018): 16 bytes of state, one per path in a batch.
///
/// The state is seeded from a SplitMix64 chain over (seed, sample index, pixel), so neighbouring
/// pixels and consecutive sample indices start from unrelated states.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PathRng(Xoshiro128PlusPlus);

/// The streams of one pass (sample index): the chain's prefix over (seed, sample index) hashed
/// once, so that seeding a path's stream costs two SplitMix64 steps, not five.
#[derive(Clone, Copy, Debug)]
pub struct PassStreams {
    prefix: u64,
}

impl PassStreams {
    pub fn new(seed: u64, sample_index: u32) -> Self {
        Self {
            prefix: hash_words(&[seed, u64::from(sample_index)]),
        }
    }

    /// The stream of `pixel`'s path in this pass.
    #[inline]
    pub fn path(self, pixel: u32) -> PathRng {
        let h = hash_extend(self.prefix, u64::from(pixel));
        PathRng::from_words(h, second_word(h))
    }

    /// The streams of `N` pixels' paths, the same as [`PassStreams::path`]'s: each hashing step
    /// done for all of them before the next, so that the compiler can take it across the lanes
    /// of vector registers.
    #[inline]
    pub fn paths<const N: usize>(self, pixels: [u32; N]) -> [PathRng; N] {
        let first = pixels.map(|pixel| hash_extend(self.prefix, u64::from(pixel)));
        let second = first.map(second_word);
        std::array::from_fn(|k| PathRng::from_words(first[k], second[k]))
    }
}

/// The second 64-bit word of a path's state, from its first.
#[inline(always)]
fn second_word(h: u64) -> u64 {
    mix64(h ^ 0x5851_f42d_4c95_7f2d)
}

impl PathRng {
    /// The stream whose 16-byte seed is the two words, little-endian.
    #[inline(always)]
    fn from_words(first: u64, second: u64) -> Self {
        let mut state = [0u8; 16];
        state[..8].copy_from_slice(&first.to_le_bytes());
        state[8..].copy_from_slice(&second.to_le_bytes());
        PathRng(Xoshiro128PlusPlus::from_seed(state))
    }

    pub fn new(seed: u64, pixel: u32, sample_index: u32) -> Self {
        PassStreams::new(seed, sample_index).path(pixel)
    }

    /// A uniform float in [0, 1): 24 random bits times 2^-24, so 1 is never returned.
    #[inline(always)]
    pub fn next_f32(&mut self) -> f32 {
        unit_f32(self.0.next_u32())
    }

    /// Two uniform floats in [0, 1), x first. Inlined: out of line, its calls from the
    /// shading stage cost Cornell's render 47 M instructions (4 spp) at stop 22's merge.
    #[inline(always)]
    pub fn next_2d(&mut self) -> Vec2 {
        let x = self.next_f32();
        Vec2::new(x, self.next_f32())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rng_in_unit_interval_and_mean_half() {
        let mut rng = PathRng::new(7, 3, 1);
        let n = 100_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let x = rng.next_f32();
            assert!((0.0..1.0).contains(&x));
            sum += f64::from(x);
        }
        // Standard error of the mean: sqrt(1/12 / n) ~ 0.0009; allow 5 sigma.
        assert!((sum / f64::from(n) - 0.5).abs() < 0.0046);
    }

    /// Eight pixels' streams at once are each pixel's own stream (the same state).
    #[test]
    fn streams_in_lanes_match_one_at_a_time() {
        for (seed, pass) in [(0, 0), (7, 3), (u64::MAX, 1_000)] {
            let streams = PassStreams::new(seed, pass);
            for first in [0, 65_536, u32::MAX - 7] {
                let pixels = std::array::from_fn::<u32, 8, _>(|k| first + k as u32);
                for (&pixel, lane) in pixels.iter().zip(streams.paths(pixels)) {
                    assert_eq!(lane, streams.path(pixel));
                }
            }
        }
    }

    #[test]
    fn rng_streams_are_deterministic_and_distinct() {
        let draw = |seed, pixel, s| {
            let mut rng = PathRng::new(seed, pixel, s);
            (0..4).map(|_| rng.next_f32()).collect::<Vec<_>>()
        };
        assert_eq!(draw(1, 2, 3), draw(1, 2, 3));
        assert_ne!(draw(1, 2, 3), draw(1, 3, 3));
        assert_ne!(draw(1, 2, 3), draw(1, 2, 4));
        assert_ne!(draw(1, 2, 3), draw(2, 2, 3));
    }

    #[test]
    fn rng_neighbouring_streams_uncorrelated() {
        // Pearson correlation of the first draws of adjacent pixels (and adjacent sample
        // indices) over n pairs: |r| ~ 1/sqrt(n) = 0.0045 for independent streams; allow 5 sigma.
        let n = 50_000u32;
        for (da, db) in [((1, 0), (0, 0)), ((0, 1), (0, 0))] {
            let (mut sxy, mut sx, mut sy, mut sxx, mut syy) = (0.0f64, 0.0, 0.0, 0.0, 0.0);
            for i in 0..n {
                let x = f64::from(PathRng::new(9, i + da.0, da.1).next_f32());
                let y = f64::from(PathRng::new(9, i + db.0, db.1).next_f32());
                sxy += x * y;
                sx += x;
                sy += y;
                sxx += x * x;
                syy += y * y;
            }
            let n = f64::from(n);
            let cov = sxy / n - sx * sy / (n * n);
            let r = cov / ((sxx / n - (sx / n).powi(2)) * (syy / n - (sy / n).powi(2))).sqrt();
            assert!(r.abs() < 0.0225, "correlation {r}");
        }
    }
}
