//! A path's padded Sobol' draws computed ahead, many paths at once, and handed out by
//! [`PathDraws`] in place of the one-at-a-time scalar ones (`padded_sobol.rs`).
//!
//! The first vertex makes the [`PADDED_DRAWS`] draws in a fixed order (shade_path.rs): the
//! material's choice (1D), the light's choice (1D), the point on the light (2D), the BSDF's lobe
//! (1D) and its direction (2D). The chunk's first bounce computes them for its paths in lanes,
//! after the closest hits, skipping the groups of lanes whose camera rays all escaped (the hashes
//! and scrambles are the same integer operations lane by lane, which LLVM takes across vector
//! registers), or the first alone where that is all an integrator's first vertex surely makes (the
//! ray caster's BSDF choice). A draw that is not there (one past those computed; a path whose first
//! vertex passed through a null surface and makes them later, after the batch was compacted; a 2D
//! draw where a 1D one was computed) is computed as before. Every value is a pure function of
//! (pixel key, sample index, draw), so the table's values are bit for bit the scalar ones. A draw
//! whose value nothing in the scene uses (the material's choice where no material mixes, the
//! light's choice or point where there is no choice or no light to sample, the lobe where no BSDF
//! has two) is left out: a reader may read its stale value, or count the draw without reading it
//! ([`PathDraws::skip`]), but never uses it.
//!
//! A 1D draw is the first coordinate of the 2D draw of the same number (both scramble the
//! shuffled index's radical inverse with the same seed), so a 2D draw's x serves a 1D request.

use glam::Vec2;

use super::hash::{hash_extend, mix64, unit_f32};
use super::rng::{PADDED_DRAWS, PathRng};
use super::sobol::{owen_scramble_reversed, second_dimension_reversed};

/// The first vertex's draws that are 2D (the light's point, the BSDF's direction).
const IS_2D: [bool; PADDED_DRAWS as usize] = [false, false, true, false, true];

/// The first vertex's draws by number.
pub const MATERIAL_CHOICE_DRAW: u32 = 0;
pub const LIGHT_CHOICE_DRAW: u32 = 1;
pub const LIGHT_POINT_DRAW: u32 = 2;
pub const LOBE_DRAW: u32 = 3;

/// Where a 2D draw's y is in [`FirstDraws::values`], after its x: draw `d`'s value (a 2D
/// draw's x) is at `d`, its y at `d + Y_AFTER_X`, past the five draws' (draw 2's at 5, draw
/// 4's at 7), so that a draw's values are found without a table.
const Y_AFTER_X: usize = 3;

/// A path's values with the spare one at 6 (0): eight, one 256-bit store (the record's 40 bytes
/// as with seven values and the padding after them).
const ROW: usize = 8;

/// One path's padded draws, with the key of the stream they belong to
/// ([`PathRng::counter_key`], which tells a pass's paths apart): 40 bytes, in a table indexed
/// by the path's slot at the chunk's start (outside the batch that compaction moves).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FirstDraws {
    stream_key: u64,
    values: [f32; ROW],
}

/// Paths whose padded draws are computed together: sixteen 32-bit lanes of AVX-512, two
/// vectors of AVX2. Measured (callgrind, x86-64-v3, furnace 4 spp): 16 lanes 82.0 M
/// instructions, 32 lanes 82.9 M, 8 lanes 91.1 M (more than the scalar draws' 88.6 M).
const LANES: usize = 16;

impl FirstDraws {
    /// The padded draws of `paths`, all at their first draw and of one pass (made by one
    /// [`PassStreams`](super::PassStreams)), into `first` (as long): [`LANES`] paths at a time,
    /// the last group's missing lanes repeating its last path and dropped. Those in `draws`
    /// (bit `d` for draw `d`; at least the draws below [`PADDED_DRAWS`] set there): a
    /// [`PathDraws`] that uses the value of no other draw reads no other value (it may read
    /// one, stale, that it then leaves unused). A group none of whose paths is `needed` (by
    /// index into `paths`) is skipped, its records left as they were: stale records are never
    /// used, since a [`PathDraws`] reads a record only if its stream key is the path's.
    pub fn compute(
        paths: &[PathRng],
        first: &mut [FirstDraws],
        draws: u32,
        needed: impl Fn(usize) -> bool,
    ) {
        let any_needed = |start: usize, len: usize| (start..start + len).any(&needed);
        let mut groups = paths.chunks_exact(LANES);
        let mut outputs = first.chunks_exact_mut(LANES);
        for (group, (paths, first)) in (&mut groups).zip(&mut outputs).enumerate() {
            if any_needed(group * LANES, LANES) {
                Self::lanes(paths.try_into().unwrap(), first.try_into().unwrap(), draws);
            }
        }
        let start = paths.len() - groups.remainder().len();
        let (paths, first) = (groups.remainder(), outputs.into_remainder());
        if let Some(last) = paths.last()
            && any_needed(start, paths.len())
        {
            let lanes: [PathRng; LANES] =
                std::array::from_fn(|k| paths.get(k).unwrap_or(last).clone());
            let mut values = [Self::default(); LANES];
            Self::lanes(&lanes, &mut values, draws);
            first.copy_from_slice(&values[..first.len()]);
        }
    }

    /// The padded draws in `draws` (a set, as [`FirstDraws::compute`]'s) of [`LANES`] paths of
    /// one pass, computed lane by lane, each draw's values into an array of its own (a column
    /// of the paths' rows) before they are stored path by path (the first draw's alone where
    /// no other is computed).
    #[inline(always)]
    fn lanes(paths: &[PathRng; LANES], first: &mut [Self; LANES], draws: u32) {
        let mut keys = [0u64; LANES];
        for (key, path) in keys.iter_mut().zip(paths) {
            *key = path.pixel_key();
        }
        let index_reversed = paths[0].index_reversed();
        debug_assert!(
            paths
                .iter()
                .all(|path| path.index_reversed() == index_reversed)
        );
        let mut columns = [[0f32; LANES]; ROW];
        for (first, path) in first.iter_mut().zip(paths) {
            first.stream_key = path.counter_key();
        }
        let computes = |draw: u32| draws >> draw & 1 == 1;
        if computes(0) {
            padded_sobol_lanes::<0>(keys, index_reversed, &mut columns);
        }
        if draws >> 1 == 0 {
            for (first, &value) in first.iter_mut().zip(&columns[0]) {
                first.values[0] = value;
            }
            return;
        }
        if computes(1) {
            padded_sobol_lanes::<1>(keys, index_reversed, &mut columns);
        }
        if computes(2) {
            padded_sobol_lanes::<2>(keys, index_reversed, &mut columns);
        }
        if computes(3) {
            padded_sobol_lanes::<3>(keys, index_reversed, &mut columns);
        }
        if computes(4) {
            padded_sobol_lanes::<4>(keys, index_reversed, &mut columns);
        }
        for (eighth, first) in first.chunks_exact_mut(8).enumerate() {
            store_rows(&columns, 8 * eighth, first.try_into().unwrap());
        }
    }
}

/// Stores the rows of paths `start..start + 8`, given as columns (`columns[j][k]`: value `j`
/// of path `k`), into their records `first`: with AVX2 by an 8 x 8 transpose in registers
/// (eight unpacks, eight shuffles and eight lane permutes, the usual sequence), one 256-bit
/// store a path, rather than a load and a store a value.
#[inline(always)]
fn store_rows(columns: &[[f32; LANES]; ROW], start: usize, first: &mut [FirstDraws; 8]) {
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    {
        use std::arch::x86_64::*;
        let column = |j: usize| &columns[j][start..start + 8];
        // SAFETY: each load reads the eight floats of a column's slice, each store the eight
        // of a record's row; AVX2 is enabled at compile time.
        unsafe {
            let c: [__m256; ROW] = std::array::from_fn(|j| _mm256_loadu_ps(column(j).as_ptr()));
            let lo = |a, b| _mm256_unpacklo_ps(a, b);
            let hi = |a, b| _mm256_unpackhi_ps(a, b);
            let t = [
                lo(c[0], c[1]),
                hi(c[0], c[1]),
                lo(c[2], c[3]),
                hi(c[2], c[3]),
                lo(c[4], c[5]),
                hi(c[4], c[5]),
                lo(c[6], c[7]),
                hi(c[6], c[7]),
            ];
            let u = [
                _mm256_shuffle_ps::<0x44>(t[0], t[2]),
                _mm256_shuffle_ps::<0xee>(t[0], t[2]),
                _mm256_shuffle_ps::<0x44>(t[1], t[3]),
                _mm256_shuffle_ps::<0xee>(t[1], t[3]),
                _mm256_shuffle_ps::<0x44>(t[4], t[6]),
                _mm256_shuffle_ps::<0xee>(t[4], t[6]),
                _mm256_shuffle_ps::<0x44>(t[5], t[7]),
                _mm256_shuffle_ps::<0xee>(t[5], t[7]),
            ];
            for k in 0..4 {
                let low = _mm256_permute2f128_ps::<0x20>(u[k], u[k + 4]);
                let high = _mm256_permute2f128_ps::<0x31>(u[k], u[k + 4]);
                _mm256_storeu_ps(first[k].values.as_mut_ptr(), low);
                _mm256_storeu_ps(first[k + 4].values.as_mut_ptr(), high);
            }
        }
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    for (k, first) in first.iter_mut().enumerate() {
        first.values = std::array::from_fn(|j| columns[j][start + k]);
    }
}

/// Draw `DRAW` of [`LANES`] paths (pixel keys, and the bit-reversed sample index they
/// share), the operations of `padded_sobol_2d` (`padded_sobol_1d` for a 1D draw) one at a time
/// over the lanes, so that each loop is one vector operation: the second dimension by its
/// shift-and-XOR form rather than the byte tables, which would take gathers. The values go to
/// `columns[DRAW]` (and a 2D draw's y to `columns[DRAW + Y_AFTER_X]`).
#[inline(always)]
fn padded_sobol_lanes<const DRAW: u32>(
    keys: [u64; LANES],
    index_reversed: u32,
    columns: &mut [[f32; LANES]; ROW],
) {
    let at = DRAW as usize;
    // Loops rather than `map`s, which LLVM left out of line (a call per hash of all lanes).
    let (mut shuffle, mut x_seed, mut h) = ([0u32; LANES], [0u32; LANES], [0u64; LANES]);
    for k in 0..LANES {
        h[k] = hash_extend(keys[k], u64::from(DRAW));
        (shuffle[k], x_seed[k]) = (h[k] as u32, (h[k] >> 32) as u32);
    }
    let mut index = [0u32; LANES];
    for k in 0..LANES {
        index[k] = owen_scramble_reversed(index_reversed, shuffle[k]).reverse_bits();
    }
    for k in 0..LANES {
        columns[at][k] = unit_f32(owen_scramble_reversed(index[k], x_seed[k]).reverse_bits());
    }
    if IS_2D[DRAW as usize] {
        let mut y_seed = [0u32; LANES];
        for k in 0..LANES {
            y_seed[k] = mix64(h[k]) as u32;
        }
        for k in 0..LANES {
            let y_reversed = second_dimension_reversed(index[k]);
            columns[at + Y_AFTER_X][k] =
                unit_f32(owen_scramble_reversed(y_reversed, y_seed[k]).reverse_bits());
        }
    }
}

/// A path's stream in a shading stage: its [`PathRng`], with the padded draws computed at the
/// chunk's first bounce for the path that had its slot then (used when that path is this one), of
/// which it reads the first `AHEAD` (at most [`PADDED_DRAWS`]; at most the `draws` given to
/// [`FirstDraws::compute`]): a constant, so that the path tracer's test of a draw's number is
/// one comparison with [`PADDED_DRAWS`] as before (a count read from the table cost its shading
/// 1.7 % more instructions on the furnace).
pub struct PathDraws<'a, const AHEAD: u32 = PADDED_DRAWS> {
    rng: &'a mut PathRng,
    first: &'a FirstDraws,
}

impl<'a, const AHEAD: u32> PathDraws<'a, AHEAD> {
    #[inline(always)]
    pub fn new(rng: &'a mut PathRng, first: &'a FirstDraws) -> Self {
        const { assert!(AHEAD <= PADDED_DRAWS) };
        Self { rng, first }
    }

    /// The computed draw's index in [`FirstDraws::values`], if the next draw was computed for
    /// this path (one of the first `AHEAD`; 2D only where the first vertex makes a 2D draw).
    #[inline(always)]
    fn computed(&self, two_d: bool) -> Option<usize> {
        let draw = self.rng.draw() as usize;
        (draw < AHEAD as usize
            && (!two_d || IS_2D[draw])
            && self.first.stream_key == self.rng.counter_key())
        .then_some(draw)
    }

    /// Counts the next draw without making it: for a value nobody would read (the material's
    /// choice at a material that has none), so that the later draws keep their numbers.
    #[inline(always)]
    pub fn skip(&mut self) {
        self.rng.skip_draw();
    }

    /// [`PathDraws::next_f32`] where `needed`, else the draw counted but not made
    /// ([`PathDraws::skip`]) and 0 in its place.
    #[inline(always)]
    pub fn next_f32_if(&mut self, needed: bool) -> f32 {
        if needed {
            self.next_f32()
        } else {
            self.skip();
            0.0
        }
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
                Vec2::new(self.first.values[at], self.first.values[at + Y_AFTER_X])
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

    /// The set of all five draws.
    const ALL_DRAWS: u32 = (1 << PADDED_DRAWS) - 1;

    /// Random keys and indices (SplitMix64 outputs, sample indices of every size).
    fn random_paths<const N: usize>(round: u64) -> [PathRng; N] {
        let index = mix64(round) as u32 >> (round % 32);
        let streams = PassStreams::new(round, index, PADDED_DRAWS);
        std::array::from_fn(|k| streams.path(mix64(round ^ (k as u64) << 40) as u32))
    }

    /// The computed draws are the scalar ones bit for bit, 1D and 2D, over many random keys
    /// and sample indices, for whole groups of lanes and a last partial one, all five draws,
    /// the first alone, or any set of them; with every path needed, or a few (a group of lanes
    /// none of whose paths is needed is left untouched, the others computed whole).
    #[test]
    fn computed_draws_match_the_scalar_draws() {
        let mut skipped = 0;
        for round in 0..2_000 {
            let paths = random_paths::<40>(round);
            let count = [40, 32, 16, 5, 1][round as usize % 5];
            // All five, the first alone, and every other set of draws.
            let draws = [ALL_DRAWS, 1, round as u32 / 10 % 32][round as usize / 5 % 3];
            let few = round / 15 % 2 == 1;
            let needed = |k: usize| !few || mix64(round << 8 | k as u64).is_multiple_of(16);
            let mut firsts = vec![FirstDraws::default(); count];
            FirstDraws::compute(&paths[..count], &mut firsts, draws, needed);
            for (k, (path, first)) in paths.iter().zip(&firsts).enumerate() {
                let group = k / LANES * LANES..(k / LANES * LANES + LANES).min(count);
                if !group.clone().any(needed) {
                    assert_eq!(*first, FirstDraws::default(), "{round} {k}");
                    skipped += 1;
                    continue;
                }
                assert_eq!(first.stream_key, path.counter_key());
                let (key, index) = (path.pixel_key(), path.index_reversed());
                for d in (0..PADDED_DRAWS).filter(|d| draws >> d & 1 == 1) {
                    let at = d as usize;
                    let x = padded_sobol_1d(key, index, d);
                    assert_eq!(first.values[at].to_bits(), x.to_bits(), "{round} {d}");
                    if IS_2D[d as usize] {
                        let u = padded_sobol_2d(key, index, d);
                        assert_eq!(u.x.to_bits(), x.to_bits());
                        let y = first.values[at + Y_AFTER_X];
                        assert_eq!(y.to_bits(), u.y.to_bits(), "{d}");
                    }
                }
            }
        }
        assert!(skipped > 0, "some groups needed no path");
    }

    /// Handing out the computed draws gives a path the stream it has without them, in any
    /// order of 1D and 2D draws, all five draws computed or the first alone (the others' values
    /// then another pass's, stale, which a reader of the first alone must not read); with
    /// another path's draws (a slot after compaction) too.
    #[test]
    fn handed_out_draws_are_the_streams_own() {
        for round in 0..500 {
            let paths = random_paths::<8>(round);
            let computed = [PADDED_DRAWS, 1][round as usize % 2];
            let mut firsts = [FirstDraws::default(); 8];
            let all = |_| true;
            FirstDraws::compute(&random_paths::<8>(round + 1), &mut firsts, ALL_DRAWS, all);
            FirstDraws::compute(&paths, &mut firsts, (1 << computed) - 1, all);
            for (k, path) in paths.iter().enumerate() {
                let pattern = mix64(round + k as u64);
                for first in [&firsts[k], &firsts[(k + 1) % 8]] {
                    if computed == PADDED_DRAWS {
                        hand_out::<PADDED_DRAWS>(path, first, pattern);
                    }
                    hand_out::<1>(path, first, pattern);
                }
            }
        }
    }

    /// Eight draws of `path`'s stream, 1D or 2D as the bits of `pattern` say, through a
    /// [`PathDraws`] reading `first`'s first `AHEAD`, against the scalar draws.
    fn hand_out<const AHEAD: u32>(path: &PathRng, first: &FirstDraws, pattern: u64) {
        let (mut plain, mut handed) = (path.clone(), path.clone());
        let mut draws = PathDraws::<AHEAD>::new(&mut handed, first);
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
