//! Random numbers for the acceleration structures' tests.

use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::Rng;

/// A float uniform in `[lo, hi)`: the top 24 bits of a draw over 2^24 (exact), scaled to the
/// interval.
pub(super) fn uniform(rng: &mut Xoshiro256PlusPlus, lo: f32, hi: f32) -> f32 {
    lo + (hi - lo) * (rng.next_u32() >> 8) as f32 / 16_777_216.0
}
