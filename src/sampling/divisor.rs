//! Exact division and remainder by a fixed divisor, by multiplication: hardware division costs
//! tens of cycles, and the pixel sampler divides several times per sample by the same few numbers.

/// A `u32` divisor `d` with `c = ceil(2^64 / d)`. Lemire, Kaser & Kurz 2019, "Faster remainder
/// by direct computation" (Theorem 1 with N = 32, F = 64): for every 32-bit `a`,
/// `a / d = floor(c a / 2^64)` and `a % d = floor((c a mod 2^64) d / 2^64)`. `d = 1` would need a
/// 65-bit `c` and is special-cased.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Divisor {
    d: u32,
    c: u64,
}

impl Divisor {
    /// `d` must be at least 1.
    pub fn new(d: u32) -> Self {
        let d = d.max(1);
        Self {
            d,
            c: (u64::MAX / u64::from(d)).wrapping_add(1),
        }
    }

    pub fn get(self) -> u32 {
        self.d
    }

    pub fn quotient(self, a: u32) -> u32 {
        if self.d == 1 {
            return a;
        }
        ((u128::from(self.c) * u128::from(a)) >> 64) as u32
    }

    pub fn remainder(self, a: u32) -> u32 {
        if self.d == 1 {
            return 0;
        }
        let low = self.c.wrapping_mul(u64::from(a));
        ((u128::from(low) * u128::from(self.d)) >> 64) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::hash::mix64;

    #[test]
    fn divides_like_the_hardware() {
        let mut divisors = vec![1, 2, 3, 5, 7, 16, 100, 255, 256, 1600, 65_537, u32::MAX - 1];
        divisors.push(u32::MAX);
        let mut numerators = vec![0, 1, 2, 255, 256, 1599, 1600, u32::MAX - 1, u32::MAX];
        numerators.extend((0..2000).map(|i| mix64(i) as u32));
        for (i, d) in divisors
            .into_iter()
            .chain((0..200).map(|i| (mix64(i + 7777) as u32 >> (i % 32)).max(1)))
            .enumerate()
        {
            let divisor = Divisor::new(d);
            for &a in numerators
                .iter()
                .chain(&[d - 1, d, d.wrapping_add(1), i as u32])
            {
                assert_eq!(divisor.quotient(a), a / d, "{a} / {d}");
                assert_eq!(divisor.remainder(a), a % d, "{a} % {d}");
            }
        }
    }
}
