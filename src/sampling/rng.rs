//! A path's random numbers: its first draws from padded Owen-scrambled Sobol' (stratified
//! over the pixel's samples, `padded_sobol.rs`), the later ones hashed from a counter.

use glam::Vec2;

use super::hash::{extend_unmixed, hash_extend, hash_words, mix64, unit_f32};
use super::padded_sobol::{padded_sobol_1d, padded_sobol_2d};

/// The draws of a path (calls of `next_f32` or `next_2d`, each one draw) that come from padded
/// Sobol': the first vertex's five (the material's choice, the light's choice, the point on
/// the light, the BSDF's lobe and direction). The second vertex's too changed relMSE within
/// its noise (16 spp, five peer scenes) for 1 % to 3.5 % more instructions; hashing the 1D
/// draws instead saved 2 % to 5 % and lost a third of the gain on textured.xml (several lights).
pub const PADDED_DRAWS: u32 = 5;

/// A path's random numbers, 16 bytes per path in a batch: a pure function of (seed, pixel,
/// sample index, draw), so that any thread computes the same ones.
///
/// Draw `d < PADDED_DRAWS` is draw `d` of the padded Sobol' samples of the pixel, whose
/// scrambles depend on (seed, pixel, d) and not on the sample index: a pixel's passes together
/// are a net in each draw. Later draws are SplitMix64 (Steele, Lea & Flood 2014) outputs at
/// the counter (sample index, draw), keyed by the pixel: `mix64(key + gamma n)`, one hash per
/// draw, with both words of a 2D draw from one hash.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PathRng {
    /// The hashed draws' key with the pass's part of their counter added (see
    /// [`PathRng::hashed`]): `hash(seed, pixel)`, the pixel key, extended by
    /// [`counter_offset`] short of the mix ([`extend_unmixed`]).
    counter_key: u64,
    /// The sample index, bit-reversed (as the padded samples' index shuffle takes it).
    index_reversed: u32,
    /// Draws made so far (offset by the padded draws skipped, see [`PassStreams::new`]).
    draw: u32,
}

/// The streams of one pass (sample index): the key's prefix over the seed hashed once, so that
/// seeding a path's stream costs one SplitMix64 step.
#[derive(Clone, Copy, Debug)]
pub struct PassStreams {
    prefix: u64,
    index_reversed: u32,
    first_draw: u32,
}

/// Separates the paths' pixel keys from the camera's scramble seeds hashed from the same seed.
const PATH_DOMAIN: u64 = 0x7061_7468; // "path"

/// An odd multiplier spreading the hashed draws' counters: 2^64 / rho, rho the plastic number
/// (the constant of Roberts' R2 sequence), unrelated to the golden-ratio increment that
/// `hash_extend` adds.
const COUNTER_GAMMA: u64 = 0xc13f_a9a9_02a6_328f;

impl PassStreams {
    /// The streams of pass `sample_index`, whose first `padded_draws` draws (at most
    /// [`PADDED_DRAWS`]; 0 for the plain samplers) come from padded Sobol'.
    pub fn new(seed: u64, sample_index: u32, padded_draws: u32) -> Self {
        Self {
            prefix: hash_words(&[seed, PATH_DOMAIN]),
            index_reversed: sample_index.reverse_bits(),
            first_draw: PADDED_DRAWS - padded_draws.min(PADDED_DRAWS),
        }
    }

    /// The stream of `pixel`'s path in this pass.
    #[inline]
    pub fn path(self, pixel: u32) -> PathRng {
        PathRng {
            counter_key: extend_unmixed(
                hash_extend(self.prefix, u64::from(pixel)),
                counter_offset(self.index_reversed),
            ),
            index_reversed: self.index_reversed,
            draw: self.first_draw,
        }
    }

    /// The streams of `N` pixels' paths, the same as [`PassStreams::path`]'s: the hash done for
    /// all of them at once, so that the compiler can take it across the lanes of vector
    /// registers.
    #[inline]
    pub fn paths<const N: usize>(self, pixels: [u32; N]) -> [PathRng; N] {
        let offset = counter_offset(self.index_reversed);
        let keys = pixels.map(|pixel| hash_extend(self.prefix, u64::from(pixel)));
        keys.map(|pixel_key| PathRng {
            counter_key: extend_unmixed(pixel_key, offset),
            index_reversed: self.index_reversed,
            draw: self.first_draw,
        })
    }
}

/// The pass's part of its hashed draws' words, which extends its paths' pixel keys into their
/// [`PathRng::counter_key`]s: the hashed draws' counter is `(sample index reversed) << 32 |
/// draw`, whose two halves do not overlap, so that it is their sum and its product with
/// [`COUNTER_GAMMA`] (mod 2^64) the sum of the halves' products. The pass's half is added
/// once a path ([`extend_unmixed`]) rather than once a draw.
#[inline(always)]
fn counter_offset(index_reversed: u32) -> u64 {
    (u64::from(index_reversed) << 32).wrapping_mul(COUNTER_GAMMA)
}

impl PathRng {
    /// Pixel `pixel`'s stream in pass `sample_index`, its first draws padded Sobol'.
    pub fn new(seed: u64, pixel: u32, sample_index: u32) -> Self {
        PassStreams::new(seed, sample_index, PADDED_DRAWS).path(pixel)
    }

    /// The key of the pixel's scrambles (for the padded draws).
    #[inline(always)]
    pub(super) fn pixel_key(&self) -> u64 {
        let added = extend_unmixed(0, counter_offset(self.index_reversed));
        self.counter_key.wrapping_sub(added)
    }

    /// The key that tells the paths of a pass apart (a bijection of the pixel key).
    #[inline(always)]
    pub(super) fn counter_key(&self) -> u64 {
        self.counter_key
    }

    /// The sample index, bit-reversed.
    #[inline(always)]
    pub(super) fn index_reversed(&self) -> u32 {
        self.index_reversed
    }

    /// The next draw's number.
    #[inline(always)]
    pub(super) fn draw(&self) -> u32 {
        self.draw
    }

    /// Counts a draw made elsewhere (`first_draws.rs`).
    #[inline(always)]
    pub(super) fn skip_draw(&mut self) {
        self.take_draw();
    }

    /// The next draw's number, counting it.
    #[inline(always)]
    fn take_draw(&mut self) -> u32 {
        let draw = self.draw;
        self.draw = draw.wrapping_add(1);
        draw
    }

    /// 64 hashed bits for a draw past the padded ones: `hash_extend(pixel key, ((sample index
    /// reversed) << 32 | draw) * COUNTER_GAMMA)`, with all but the draw's part of the word in
    /// the counter key ([`extend_unmixed`]).
    #[inline(always)]
    fn hashed(&self, draw: u32) -> u64 {
        mix64(
            self.counter_key
                .wrapping_add(u64::from(draw).wrapping_mul(COUNTER_GAMMA)),
        )
    }

    /// A uniform float in [0, 1): 24 random bits times 2^-24, so 1 is never returned.
    #[inline(always)]
    pub fn next_f32(&mut self) -> f32 {
        let draw = self.take_draw();
        if draw < PADDED_DRAWS {
            padded_sobol_1d(self.pixel_key(), self.index_reversed, draw)
        } else {
            unit_f32((self.hashed(draw) >> 32) as u32)
        }
    }

    /// Two uniform floats in [0, 1), x first: one draw. Inlined: out of line, its calls from
    /// the shading stage cost Cornell's render 47 M instructions (4 spp) at stop 22's merge.
    #[inline(always)]
    pub fn next_2d(&mut self) -> Vec2 {
        let draw = self.take_draw();
        if draw < PADDED_DRAWS {
            padded_sobol_2d(self.pixel_key(), self.index_reversed, draw)
        } else {
            let h = self.hashed(draw);
            Vec2::new(unit_f32(h as u32), unit_f32((h >> 32) as u32))
        }
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
            let streams = PassStreams::new(seed, pass, PADDED_DRAWS);
            for first in [0, 65_536, u32::MAX - 7] {
                let pixels = std::array::from_fn::<u32, 8, _>(|k| first + k as u32);
                for (&pixel, lane) in pixels.iter().zip(streams.paths(pixels)) {
                    assert_eq!(lane, streams.path(pixel));
                }
            }
        }
    }

    /// A path's padded draws over a pixel's first 16 passes: each 2D draw one point in every
    /// elementary interval of area 1/16 (here the 4 x 4 grid), each 1D draw one in every
    /// sixteenth; the plain samplers' streams (no padded draws) are not stratified.
    #[test]
    fn padded_draws_are_stratified_over_a_pixels_passes() {
        let n = 16;
        let cells = |padded| {
            let mut grid = vec![0; n];
            let mut line = vec![0; n];
            for s in 0..n as u32 {
                let mut rng = PassStreams::new(3, s, padded).path(41);
                line[(rng.next_f32() * n as f32) as usize] += 1;
                let u = rng.next_2d();
                grid[(u.x * 4.0) as usize * 4 + (u.y * 4.0) as usize] += 1;
            }
            (grid, line)
        };
        let (grid, line) = cells(PADDED_DRAWS);
        assert!(
            grid.iter().chain(&line).all(|&c| c == 1),
            "{grid:?} {line:?}"
        );
        let (grid, line) = cells(0);
        assert!(grid.iter().chain(&line).any(|&c| c != 1));
    }

    /// The hashed draws are the hash of the counter (sample index reversed, draw) keyed by the
    /// pixel key, bit for bit, for sample indices with the top bit set (a counter offset that
    /// wraps) and draws near 2^32; the padded draws are keyed by the pixel key.
    #[test]
    fn hashed_draws_hash_the_counter_keyed_by_the_pixel() {
        for (seed, pixel, sample_index) in [(0, 0, 0), (7, 3, 1), (u64::MAX, 9_999, u32::MAX)] {
            let pixel_key = hash_extend(hash_words(&[seed, PATH_DOMAIN]), u64::from(pixel));
            let index_reversed = sample_index.reverse_bits();
            let mut rng = PathRng::new(seed, pixel, sample_index);
            assert_eq!(rng.pixel_key(), pixel_key);
            for draw in (0..40).chain(u32::MAX - 3..=u32::MAX) {
                rng.draw = draw;
                let counter = u64::from(index_reversed) << 32 | u64::from(draw);
                let expected = hash_extend(pixel_key, counter.wrapping_mul(COUNTER_GAMMA));
                assert_eq!(
                    rng.hashed(draw),
                    expected,
                    "{seed} {pixel} {sample_index} {draw}"
                );
                if draw >= PADDED_DRAWS {
                    let u = rng.next_2d();
                    assert_eq!(u.x, unit_f32(expected as u32));
                    assert_eq!(u.y, unit_f32((expected >> 32) as u32));
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

    /// The draw after the padded ones: a hashed one.
    fn first_hashed(seed: u64, pixel: u32, sample_index: u32) -> f32 {
        let mut rng = PathRng::new(seed, pixel, sample_index);
        for _ in 0..PADDED_DRAWS {
            rng.next_f32();
        }
        rng.next_f32()
    }

    #[test]
    fn rng_neighbouring_streams_uncorrelated() {
        // Pearson correlation of the first draws of adjacent pixels (padded Sobol', scrambled
        // per pixel) and of the first hashed draws of adjacent pixels and adjacent sample
        // indices (the padded ones of one pixel are stratified over its samples, anti-correlated
        // on purpose) over n pairs: |r| ~ 1/sqrt(n) = 0.0045 for independent streams; allow 5
        // sigma.
        let n = 50_000u32;
        let first = |seed, pixel, sample_index| PathRng::new(seed, pixel, sample_index).next_f32();
        type Draw = fn(u64, u32, u32) -> f32;
        let cases: [(Draw, (u32, u32)); 3] = [
            (first, (1, 0)),
            (first_hashed, (1, 0)),
            (first_hashed, (0, 1)),
        ];
        for (draw, da) in cases {
            let (mut sxy, mut sx, mut sy, mut sxx, mut syy) = (0.0f64, 0.0, 0.0, 0.0, 0.0);
            for i in 0..n {
                let x = f64::from(draw(9, i + da.0, da.1));
                let y = f64::from(draw(9, i, 0));
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
