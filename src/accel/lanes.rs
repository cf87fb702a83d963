//! Eight or sixteen `f32` lanes with the operations the flat tests need, as `std::arch`
//! intrinsics: [`L8`] for AVX (one `__m256`), [`L16`] for AVX-512 (one `__m512`).
//!
//! Each operation is IEEE 754's, lane by lane (add, subtract, multiply, divide, square root
//! are correctly rounded; no fused multiply-add), so a lane computes the same bits as the
//! same operations on one `f32`. Comparisons are the ordered ones (false on a NaN) but for
//! `ne`, which is true on a NaN as Rust's `!=` and glam's `cmpne` are.
//!
//! A value of these types exists only inside a function compiled for its features and called
//! after `is_x86_feature_detected!` found them (see `flat.rs`): that is what makes the
//! intrinsics' `unsafe` sound. The methods are `#[inline(always)]`, so they are compiled into
//! that function, where the intrinsics inline.

#![cfg(target_arch = "x86_64")]

use std::arch::x86_64::*;
use std::ops::{Add, Div, Mul, Sub};

use glam::Vec3;

/// `LANES` floats and their comparisons' masks.
pub(crate) trait Lanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    type Mask: Copy;
    const LANES: usize;
    fn splat(x: f32) -> Self;
    /// The first `LANES` floats of `values` (which holds at least as many).
    fn load(values: &[f32]) -> Self;
    /// Into the first `LANES` floats of `values` (which holds at least as many).
    fn store(self, values: &mut [f32]);
    /// The first `LANES` points of `values` (which holds at least as many), transposed: lane
    /// `i` of axis `a` is `values[i][a]`.
    fn load_points(values: &[Vec3]) -> [Self; 3];
    fn sqrt(self) -> Self;
    /// The magnitude: the sign bit cleared.
    fn abs(self) -> Self;
    fn lt(self, other: Self) -> Self::Mask;
    fn le(self, other: Self) -> Self::Mask;
    fn gt(self, other: Self) -> Self::Mask;
    fn ge(self, other: Self) -> Self::Mask;
    fn eq(self, other: Self) -> Self::Mask;
    /// True where the lanes differ or either is NaN.
    fn ne(self, other: Self) -> Self::Mask;
    /// `if_set` where `mask` is set, else `self`.
    fn replaced(self, mask: Self::Mask, if_set: Self) -> Self;
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    fn or(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// Bit `i` set where lane `i` of the mask is.
    fn bits(mask: Self::Mask) -> u32;
}

/// Eight lanes (AVX).
#[derive(Clone, Copy)]
pub(crate) struct L8(__m256);

/// A permutation of eight lanes that moves those set in a mask (bit `i` for lane `i`) to the
/// front, in order: a group's kept lanes, stored from the next free slot, are the group
/// compacted (the lanes after them, overwritten by the next group or unused, are the dropped
/// ones).
#[derive(Clone, Copy)]
pub(crate) struct Compress(__m256i);

/// For each mask of eight lanes, the lanes set in it in order, as 4-bit fields: field `i`
/// (bits `4i..4i + 4`) is the lane that goes to lane `i`; 0 past the kept ones.
const COMPRESS_FIELDS: [u32; 256] = {
    let mut table = [0u32; 256];
    let mut mask = 0;
    while mask < 256 {
        let (mut field, mut lane) = (0, 0);
        while lane < 8 {
            if mask >> lane & 1 == 1 {
                table[mask] |= (lane as u32) << (4 * field);
                field += 1;
            }
            lane += 1;
        }
        mask += 1;
    }
    table
};

impl Compress {
    /// The permutation for the lanes set in `kept` (its low eight bits).
    #[inline(always)]
    pub(crate) fn new(kept: u32) -> Self {
        let fields = COMPRESS_FIELDS[(kept & 0xff) as usize] as i32;
        // SAFETY: see the module's documentation.
        Compress(unsafe {
            let shifts = _mm256_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28);
            let lanes = _mm256_srlv_epi32(_mm256_set1_epi32(fields), shifts);
            _mm256_and_si256(lanes, _mm256_set1_epi32(0xf))
        })
    }

    /// `values` with the kept lanes first, in order.
    #[inline(always)]
    pub(crate) fn apply(self, values: L8) -> L8 {
        // SAFETY: see the module's documentation.
        L8(unsafe { _mm256_permutevar8x32_ps(values.0, self.0) })
    }

    /// `first + i` for lanes `i` of eight, permuted (the kept lanes' indices, first).
    #[inline(always)]
    pub(crate) fn indices(self, first: u32) -> [u32; 8] {
        // SAFETY: see the module's documentation; eight u32 lanes are [u32; 8]'s bytes.
        unsafe {
            let lanes = _mm256_add_epi32(
                _mm256_set1_epi32(first as i32),
                _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7),
            );
            std::mem::transmute(_mm256_permutevar8x32_epi32(lanes, self.0))
        }
    }
}

/// Sixteen lanes (AVX-512F).
#[derive(Clone, Copy)]
pub(crate) struct L16(__m512);

macro_rules! binary_ops {
    ($t:ident, $add:ident, $sub:ident, $mul:ident, $div:ident) => {
        impl Add for $t {
            type Output = Self;
            #[inline(always)]
            fn add(self, other: Self) -> Self {
                // SAFETY: see the module's documentation.
                $t(unsafe { $add(self.0, other.0) })
            }
        }
        impl Sub for $t {
            type Output = Self;
            #[inline(always)]
            fn sub(self, other: Self) -> Self {
                // SAFETY: see the module's documentation.
                $t(unsafe { $sub(self.0, other.0) })
            }
        }
        impl Mul for $t {
            type Output = Self;
            #[inline(always)]
            fn mul(self, other: Self) -> Self {
                // SAFETY: see the module's documentation.
                $t(unsafe { $mul(self.0, other.0) })
            }
        }
        impl Div for $t {
            type Output = Self;
            #[inline(always)]
            fn div(self, other: Self) -> Self {
                // SAFETY: see the module's documentation.
                $t(unsafe { $div(self.0, other.0) })
            }
        }
    };
}

binary_ops!(
    L8,
    _mm256_add_ps,
    _mm256_sub_ps,
    _mm256_mul_ps,
    _mm256_div_ps
);
binary_ops!(
    L16,
    _mm512_add_ps,
    _mm512_sub_ps,
    _mm512_mul_ps,
    _mm512_div_ps
);

// SAFETY (every `unsafe` block below): see the module's documentation; the loads and stores
// read and write within the slices, whose lengths are checked first.
impl Lanes for L8 {
    type Mask = __m256;
    const LANES: usize = 8;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        L8(unsafe { _mm256_set1_ps(x) })
    }
    #[inline(always)]
    fn load(values: &[f32]) -> Self {
        let values = &values[..8];
        L8(unsafe { _mm256_loadu_ps(values.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, values: &mut [f32]) {
        let values = &mut values[..8];
        unsafe { _mm256_storeu_ps(values.as_mut_ptr(), self.0) }
    }
    /// The 24 floats as three vectors `a`, `b`, `c`; axis `k` of point `j` is float `3j + k`.
    /// Two blends gather each axis's floats (from `a` where `3j + k < 8`, and so on) into the
    /// lanes they occupy, a permutation puts them in point order.
    #[inline(always)]
    fn load_points(values: &[Vec3]) -> [Self; 3] {
        let values = &values[..8];
        let p = values.as_ptr().cast::<f32>();
        unsafe {
            let (a, b, c) = (
                _mm256_loadu_ps(p),
                _mm256_loadu_ps(p.add(8)),
                _mm256_loadu_ps(p.add(16)),
            );
            // x: a's lanes 0, 3, 6, b's 1, 4, 7, c's 2, 5.
            let x = _mm256_blend_ps::<0b0010_0100>(_mm256_blend_ps::<0b1001_0010>(a, b), c);
            let x = _mm256_permutevar8x32_ps(x, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
            // y: a's lanes 1, 4, 7, b's 2, 5, c's 0, 3, 6.
            let y = _mm256_blend_ps::<0b0100_1001>(_mm256_blend_ps::<0b0010_0100>(a, b), c);
            let y = _mm256_permutevar8x32_ps(y, _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
            // z: a's lanes 2, 5, b's 0, 3, 6, c's 1, 4, 7.
            let z = _mm256_blend_ps::<0b1001_0010>(_mm256_blend_ps::<0b0100_1001>(a, b), c);
            let z = _mm256_permutevar8x32_ps(z, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
            [L8(x), L8(y), L8(z)]
        }
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        L8(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        L8(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0) })
    }
    #[inline(always)]
    fn lt(self, other: Self) -> __m256 {
        unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn le(self, other: Self) -> __m256 {
        unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn gt(self, other: Self) -> __m256 {
        unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn ge(self, other: Self) -> __m256 {
        unsafe { _mm256_cmp_ps::<_CMP_GE_OQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn eq(self, other: Self) -> __m256 {
        unsafe { _mm256_cmp_ps::<_CMP_EQ_OQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn ne(self, other: Self) -> __m256 {
        unsafe { _mm256_cmp_ps::<_CMP_NEQ_UQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn replaced(self, mask: __m256, if_set: Self) -> Self {
        L8(unsafe { _mm256_blendv_ps(self.0, if_set.0, mask) })
    }
    #[inline(always)]
    fn and(a: __m256, b: __m256) -> __m256 {
        unsafe { _mm256_and_ps(a, b) }
    }
    #[inline(always)]
    fn or(a: __m256, b: __m256) -> __m256 {
        unsafe { _mm256_or_ps(a, b) }
    }
    #[inline(always)]
    fn bits(mask: __m256) -> u32 {
        unsafe { _mm256_movemask_ps(mask) as u32 }
    }
}

/// For [`L16::load_points`], axis by axis: the first permutation's indices into `a` and `b`
/// (lane `j` takes float `3j + k` where it is below 32; the others are filled by the second),
/// and the second's into the first's result and `c` (16 and up: `c`'s float `3j + k - 32`).
const POINT_AXES_AB: [[i32; 16]; 3] = point_axes(false);
const POINT_AXES_C: [[i32; 16]; 3] = point_axes(true);

const fn point_axes(with_c: bool) -> [[i32; 16]; 3] {
    let mut indices = [[0; 16]; 3];
    let mut k = 0;
    while k < 3 {
        let mut j = 0;
        while j < 16 {
            let float = (3 * j + k) as i32;
            indices[k][j] = match (float < 32, with_c) {
                (true, false) => float,
                (true, true) => j as i32,
                (false, false) => 0,
                (false, true) => 16 + float - 32,
            };
            j += 1;
        }
        k += 1;
    }
    indices
}

impl Lanes for L16 {
    type Mask = __mmask16;
    const LANES: usize = 16;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        L16(unsafe { _mm512_set1_ps(x) })
    }
    #[inline(always)]
    fn load(values: &[f32]) -> Self {
        let values = &values[..16];
        L16(unsafe { _mm512_loadu_ps(values.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, values: &mut [f32]) {
        let values = &mut values[..16];
        unsafe { _mm512_storeu_ps(values.as_mut_ptr(), self.0) }
    }
    /// The 48 floats as three vectors `a`, `b`, `c`; axis `k` of point `j` is float `3j + k`:
    /// one two-source permutation takes those in `a` and `b` (below 32), a second keeps them
    /// and adds those in `c`.
    #[inline(always)]
    fn load_points(values: &[Vec3]) -> [Self; 3] {
        let values = &values[..16];
        let p = values.as_ptr().cast::<f32>();
        unsafe {
            let (a, b, c) = (
                _mm512_loadu_ps(p),
                _mm512_loadu_ps(p.add(16)),
                _mm512_loadu_ps(p.add(32)),
            );
            let axis = |k: usize| {
                let ab = std::mem::transmute::<[i32; 16], __m512i>(POINT_AXES_AB[k]);
                let with_c = std::mem::transmute::<[i32; 16], __m512i>(POINT_AXES_C[k]);
                L16(_mm512_permutex2var_ps(
                    _mm512_permutex2var_ps(a, ab, b),
                    with_c,
                    c,
                ))
            };
            [axis(0), axis(1), axis(2)]
        }
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        L16(unsafe { _mm512_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        L16(unsafe { _mm512_abs_ps(self.0) })
    }
    #[inline(always)]
    fn lt(self, other: Self) -> __mmask16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_LT_OQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn le(self, other: Self) -> __mmask16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_LE_OQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn gt(self, other: Self) -> __mmask16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_GT_OQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn ge(self, other: Self) -> __mmask16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_GE_OQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn eq(self, other: Self) -> __mmask16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn ne(self, other: Self) -> __mmask16 {
        unsafe { _mm512_cmp_ps_mask::<_CMP_NEQ_UQ>(self.0, other.0) }
    }
    #[inline(always)]
    fn replaced(self, mask: __mmask16, if_set: Self) -> Self {
        L16(unsafe { _mm512_mask_blend_ps(mask, self.0, if_set.0) })
    }
    #[inline(always)]
    fn and(a: __mmask16, b: __mmask16) -> __mmask16 {
        a & b
    }
    #[inline(always)]
    fn or(a: __mmask16, b: __mmask16) -> __mmask16 {
        a | b
    }
    #[inline(always)]
    fn bits(mask: __mmask16) -> u32 {
        mask as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each width's `load_points` puts axis `a` of point `i` in lane `i` of vector `a`, and
    /// `load` and `store` keep a slice's floats in order, on points whose coordinates are all
    /// different.
    #[test]
    fn points_transpose_into_lanes() {
        let points: Vec<Vec3> = (0..20)
            .map(|i| Vec3::new(i as f32, 100.0 + i as f32, 200.0 + i as f32))
            .collect();
        fn check<S: Lanes>(points: &[Vec3]) {
            let axes = S::load_points(points);
            for (a, axis) in axes.iter().enumerate() {
                let mut lanes = [0.0; 16];
                axis.store(&mut lanes);
                let expected: Vec<f32> = points[..S::LANES].iter().map(|p| p[a]).collect();
                assert_eq!(lanes[..S::LANES], expected[..], "axis {a}");
                let mut again = [0.0; 16];
                S::load(&lanes).store(&mut again);
                assert_eq!(again[..S::LANES], lanes[..S::LANES]);
            }
        }
        #[target_feature(enable = "avx2")]
        fn check_avx2(points: &[Vec3]) {
            check::<L8>(points)
        }
        #[target_feature(enable = "avx512f")]
        fn check_avx512(points: &[Vec3]) {
            check::<L16>(points)
        }
        // SAFETY: each width only where the CPU has its features.
        if std::arch::is_x86_feature_detected!("avx2") {
            unsafe { check_avx2(&points) };
        }
        if std::arch::is_x86_feature_detected!("avx512f") {
            unsafe { check_avx512(&points) };
        }
    }
}
