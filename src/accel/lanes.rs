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

/// `LANES` floats and their comparisons' masks.
pub(crate) trait Lanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    type Mask: Copy;
    const LANES: usize;
    fn splat(x: f32) -> Self;
    /// The first `LANES` floats of `values`.
    fn load(values: &[f32; 16]) -> Self;
    fn store(self, values: &mut [f32; 16]);
    fn sqrt(self) -> Self;
    fn lt(self, other: Self) -> Self::Mask;
    fn le(self, other: Self) -> Self::Mask;
    fn gt(self, other: Self) -> Self::Mask;
    fn ge(self, other: Self) -> Self::Mask;
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
// read and write within the 16-float arrays.
impl Lanes for L8 {
    type Mask = __m256;
    const LANES: usize = 8;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        L8(unsafe { _mm256_set1_ps(x) })
    }
    #[inline(always)]
    fn load(values: &[f32; 16]) -> Self {
        L8(unsafe { _mm256_loadu_ps(values.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, values: &mut [f32; 16]) {
        unsafe { _mm256_storeu_ps(values.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        L8(unsafe { _mm256_sqrt_ps(self.0) })
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

impl Lanes for L16 {
    type Mask = __mmask16;
    const LANES: usize = 16;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        L16(unsafe { _mm512_set1_ps(x) })
    }
    #[inline(always)]
    fn load(values: &[f32; 16]) -> Self {
        L16(unsafe { _mm512_loadu_ps(values.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, values: &mut [f32; 16]) {
        unsafe { _mm512_storeu_ps(values.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        L16(unsafe { _mm512_sqrt_ps(self.0) })
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
