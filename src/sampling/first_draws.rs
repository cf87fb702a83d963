//! A path's padded Sobol' draws computed ahead, many paths at once, and handed out by
//! [`PathDraws`] in place of the one-at-a-time scalar ones (`padded_sobol.rs`).
//!
//! The first vertex makes the [`PADDED_DRAWS`] draws in a fixed order (shade_path.rs): the
//! material's choice (1D), the light's choice (1D), the point on the light (2D), the BSDF's
//! lobe (1D) and its direction (2D). The chunk's start computes them for all its paths in
//! lanes (the hashes and scrambles are the same integer operations lane by lane, which LLVM
//! takes across vector registers); a draw that is not there (a path whose first vertex passed
//! through a null surface and makes them later, after the batch was compacted; a 2D draw where
//! a 1D one was computed) is computed as before. Every value is a pure function of (pixel key,
//! sample index, draw), so the table's values are bit for bit the scalar ones.
//!
//! A 1D draw is the first coordinate of the 2D draw of the same number (both scramble the
//! shuffled index's radical inverse with the same seed), so a 2D draw's x serves a 1D request.

use glam::Vec2;

use super::hash::{hash_extend, mix64, unit_f32};
use super::rng::{PADDED_DRAWS, PathRng};
use super::sobol::{owen_scramble_reversed, second_dimension_reversed};

/// The first vertex's draws that are 2D (the light's point, the BSDF's direction).
const IS_2D: [bool; PADDED_DRAWS as usize] = [false, false, true, false, true];

/// Where draw `d` starts in [`FirstDraws::values`]: one value a 1D draw, two a 2D one.
const OFFSET: [usize; PADDED_DRAWS as usize] = [0, 1, 2, 4, 5];

/// The values of all the padded draws, 1D and 2D.
const VALUES: usize = 7;

/// One path's padded draws, with the pixel key they belong to: 40 bytes, in a table indexed by
/// the path's slot at the chunk's start (outside the batch that compaction moves).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FirstDraws {
    pixel_key: u64,
    values: [f32; VALUES],
}

impl FirstDraws {
    /// The padded draws of `N` paths that are at their first draw, computed lane by lane
    /// (`N` 32-bit lanes a vector: 8 with AVX2, 16 with AVX-512).
    #[inline]
    pub fn lanes<const N: usize>(paths: &[PathRng; N]) -> [Self; N] {
        let keys = paths.each_ref().map(PathRng::pixel_key);
        let index_reversed = paths.each_ref().map(PathRng::index_reversed);
        let mut draws = [Self::default(); N];
        for (k, draw) in draws.iter_mut().enumerate() {
            draw.pixel_key = keys[k];
        }
        for d in 0..PADDED_DRAWS {
            let (x, y) = padded_sobol_lanes(keys, index_reversed, d, IS_2D[d as usize]);
            let at = OFFSET[d as usize];
            for (k, draw) in draws.iter_mut().enumerate() {
                draw.values[at] = x[k];
                if IS_2D[d as usize] {
                    draw.values[at + 1] = y[k];
                }
            }
        }
        draws
    }
}

/// Draw `draw` of `N` paths (pixel keys and bit-reversed sample indices), the operations of
/// `padded_sobol_2d` (`padded_sobol_1d` when not `two_d`: the y left 0) one at a time over
/// the lanes, so that each loop is one vector operation: the second dimension by its
/// shift-and-XOR form rather than the byte tables, which would take gathers.
#[inline(always)]
fn padded_sobol_lanes<const N: usize>(
    keys: [u64; N],
    index_reversed: [u32; N],
    draw: u32,
    two_d: bool,
) -> ([f32; N], [f32; N]) {
    let h = keys.map(|key| hash_extend(key, u64::from(draw)));
    let shuffle = h.map(|h| h as u32);
    let x_seed = h.map(|h| (h >> 32) as u32);
    let mut index = [0u32; N];
    for k in 0..N {
        index[k] = owen_scramble_reversed(index_reversed[k], shuffle[k]).reverse_bits();
    }
    let mut x = [0f32; N];
    for k in 0..N {
        x[k] = unit_f32(owen_scramble_reversed(index[k], x_seed[k]).reverse_bits());
    }
    let mut y = [0f32; N];
    if two_d {
        let y_seed = h.map(|h| mix64(h) as u32);
        for k in 0..N {
            let y_reversed = second_dimension_reversed(index[k]);
            y[k] = unit_f32(owen_scramble_reversed(y_reversed, y_seed[k]).reverse_bits());
        }
    }
    (x, y)
}

/// A path's stream in a shading stage: its [`PathRng`], with the padded draws computed at the
/// chunk's start for the path that had its slot then (used when that path is this one).
pub struct PathDraws<'a> {
    rng: &'a mut PathRng,
    first: &'a FirstDraws,
}

impl<'a> PathDraws<'a> {
    #[inline(always)]
    pub fn new(rng: &'a mut PathRng, first: &'a FirstDraws) -> Self {
        Self { rng, first }
    }

    /// The computed draw's index in [`FirstDraws::values`], if the next draw was computed for
    /// this path (2D only where the first vertex makes a 2D draw).
    #[inline(always)]
    fn computed(&self, two_d: bool) -> Option<usize> {
        let draw = self.rng.draw() as usize;
        (draw < PADDED_DRAWS as usize
            && (!two_d || IS_2D[draw])
            && self.first.pixel_key == self.rng.pixel_key())
        .then(|| OFFSET[draw])
    }

    /// [`PathRng::next_f32`].
    #[inline(always)]
    pub fn next_f32(&mut self) -> f32 {
        match self.computed(false) {
            Some(at) => {
                self.rng.skip_draw();
                self.first.values[at]
            }
            None => self.rng.next_f32(),
        }
    }

    /// [`PathRng::next_2d`].
    #[inline(always)]
    pub fn next_2d(&mut self) -> Vec2 {
        match self.computed(true) {
            Some(at) => {
                self.rng.skip_draw();
                Vec2::new(self.first.values[at], self.first.values[at + 1])
            }
            None => self.rng.next_2d(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::padded_sobol::{padded_sobol_1d, padded_sobol_2d};
    use crate::sampling::rng::PassStreams;

    /// Random keys and indices (SplitMix64 outputs, sample indices of every size).
    fn random_paths<const N: usize>(round: u64) -> [PathRng; N] {
        let index = mix64(round) as u32 >> (round % 32);
        let streams = PassStreams::new(round, index, PADDED_DRAWS);
        std::array::from_fn(|k| streams.path(mix64(round ^ (k as u64) << 40) as u32))
    }

    /// The lanes' draws are the scalar ones bit for bit, 1D and 2D, over many random keys and
    /// sample indices, at 8 and 16 lanes.
    fn lanes_match_scalar<const N: usize>() {
        for round in 0..2_000 {
            let paths = random_paths::<N>(round);
            for (path, first) in paths.iter().zip(FirstDraws::lanes(&paths)) {
                assert_eq!(first.pixel_key, path.pixel_key());
                let (key, index) = (path.pixel_key(), path.index_reversed());
                for d in 0..PADDED_DRAWS {
                    let at = OFFSET[d as usize];
                    let x = padded_sobol_1d(key, index, d);
                    assert_eq!(first.values[at].to_bits(), x.to_bits(), "{round} {d}");
                    if IS_2D[d as usize] {
                        let u = padded_sobol_2d(key, index, d);
                        assert_eq!(u.x.to_bits(), x.to_bits());
                        assert_eq!(first.values[at + 1].to_bits(), u.y.to_bits(), "{d}");
                    }
                }
            }
        }
    }

    #[test]
    fn lanes_match_the_scalar_draws() {
        lanes_match_scalar::<8>();
        lanes_match_scalar::<16>();
    }

    /// Handing out the computed draws gives a path the stream it has without them, in any
    /// order of 1D and 2D draws; with another path's draws (a slot after compaction) too.
    #[test]
    fn handed_out_draws_are_the_streams_own() {
        for round in 0..500 {
            let paths = random_paths::<8>(round);
            let firsts = FirstDraws::lanes(&paths);
            for (k, path) in paths.iter().enumerate() {
                for first in [&firsts[k], &firsts[(k + 1) % 8]] {
                    let (mut plain, mut handed) = (path.clone(), path.clone());
                    let mut draws = PathDraws::new(&mut handed, first);
                    let pattern = mix64(round + k as u64);
                    for i in 0..8 {
                        if pattern >> i & 1 == 1 {
                            let (a, b) = (plain.next_2d(), draws.next_2d());
                            assert_eq!(
                                (a.x.to_bits(), a.y.to_bits()),
                                (b.x.to_bits(), b.y.to_bits())
                            );
                        } else {
                            assert_eq!(plain.next_f32().to_bits(), draws.next_f32().to_bits());
                        }
                    }
                    assert_eq!(plain, handed);
                }
            }
        }
    }
}
