//! A group of [`LANES`] rays moved between the batch's columns (a `Vec2` or a `Vec3` a path,
//! components interleaved) and the camera stages' lanes (an array a component), so that their
//! kernels run in vector registers from the first load to the last store.
//!
//! With AVX2, the usual shuffles of 128-bit halves (Intel, "3D Vector Normalization Using
//! 256-Bit Intel Advanced Vector Extensions", 2012, §3: 8 `Vec3`s are six 128-bit loads, two
//! `vinsertf128` and five `vshufps` away from their x, y and z registers, and back the same
//! way); elsewhere, component by component. The values are moved, never computed, so they are
//! the same either way.

use glam::{Vec2, Vec3};

/// Rays per group of the camera stages' lane kernels: eight f32 lanes of AVX2.
pub(super) const LANES: usize = 8;

/// `LANES` 3-vectors, one array per component (x, y, z).
pub(super) type Lanes3 = [[f32; LANES]; 3];

#[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
use std::arch::x86_64::*;

/// The x and the y of `LANES` 2-vectors.
#[inline(always)]
pub(super) fn load_vec2(values: &[Vec2; LANES]) -> [[f32; LANES]; 2] {
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    // SAFETY: the loads read the 16 floats of `values` (a `Vec2` is two `f32`s, `repr(C)`);
    // AVX2 is enabled at compile time.
    unsafe {
        let p = values.as_ptr().cast::<f32>();
        // Lanes 0, 1 | 4, 5 and 2, 3 | 6, 7: each 128-bit half then takes the x's and y's of
        // its own four vectors, in order.
        let low = _mm256_loadu2_m128(p.add(8), p);
        let high = _mm256_loadu2_m128(p.add(12), p.add(4));
        [
            to_array(_mm256_shuffle_ps::<0b10_00_10_00>(low, high)),
            to_array(_mm256_shuffle_ps::<0b11_01_11_01>(low, high)),
        ]
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    [
        std::array::from_fn(|k| values[k].x),
        std::array::from_fn(|k| values[k].y),
    ]
}

/// The x, the y and the z of `LANES` 3-vectors.
#[inline(always)]
pub(super) fn load_vec3(values: &[Vec3; LANES]) -> Lanes3 {
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    // SAFETY: the loads read the 24 floats of `values` (a `Vec3` is three `f32`s,
    // `repr(C)`); AVX2 is enabled at compile time.
    unsafe {
        let p = values.as_ptr().cast::<f32>();
        // Halves of vectors 0-1 | 4-5, 1-2 | 5-6, 2-3 | 6-7: x0 y0 z0 x1, y1 z1 x2 y2,
        // z2 x3 y3 z3 below, the same four vectors on in the upper half.
        let m03 = _mm256_loadu2_m128(p.add(12), p);
        let m14 = _mm256_loadu2_m128(p.add(16), p.add(4));
        let m25 = _mm256_loadu2_m128(p.add(20), p.add(8));
        let xy = _mm256_shuffle_ps::<0b10_01_11_10>(m14, m25); // x2 y2 x3 y3
        let yz = _mm256_shuffle_ps::<0b01_00_10_01>(m03, m14); // y0 z0 y1 z1
        [
            to_array(_mm256_shuffle_ps::<0b10_00_11_00>(m03, xy)),
            to_array(_mm256_shuffle_ps::<0b11_01_10_00>(yz, xy)),
            to_array(_mm256_shuffle_ps::<0b11_00_11_01>(yz, m25)),
        ]
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    std::array::from_fn(|axis| std::array::from_fn(|k| values[k][axis]))
}

/// Stores `LANES` 3-vectors given by their x, y and z: [`load_vec3`] backwards.
#[inline(always)]
pub(super) fn store_vec3(lanes: &Lanes3, values: &mut [Vec3; LANES]) {
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    // SAFETY: the stores write the 24 floats of `values`; AVX2 is enabled at compile time.
    unsafe {
        let [x, y, z] = lanes.map(|axis| _mm256_loadu_ps(axis.as_ptr()));
        let xy = _mm256_shuffle_ps::<0b10_00_10_00>(x, y); // x0 x2 y0 y2
        let yz = _mm256_shuffle_ps::<0b11_01_11_01>(y, z); // y1 y3 z1 z3
        let zx = _mm256_shuffle_ps::<0b11_01_10_00>(z, x); // z0 z2 x1 x3
        let m03 = _mm256_shuffle_ps::<0b10_00_10_00>(xy, zx); // x0 y0 z0 x1
        let m14 = _mm256_shuffle_ps::<0b11_01_10_00>(yz, xy); // y1 z1 x2 y2
        let m25 = _mm256_shuffle_ps::<0b11_01_11_01>(zx, yz); // z2 x3 y3 z3
        let p = values.as_mut_ptr().cast::<f32>();
        _mm256_storeu2_m128(p.add(12), p, m03);
        _mm256_storeu2_m128(p.add(16), p.add(4), m14);
        _mm256_storeu2_m128(p.add(20), p.add(8), m25);
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    for (k, value) in values.iter_mut().enumerate() {
        *value = Vec3::new(lanes[0][k], lanes[1][k], lanes[2][k]);
    }
}

/// The batch's last group, shorter than `LANES`, as a whole group: `values`, then
/// `T::default()` in the lanes it lacks, whose results are dropped.
#[inline]
pub(super) fn short_group<T: Copy + Default>(values: &[T]) -> [T; LANES] {
    let mut lanes = [T::default(); LANES];
    lanes[..values.len()].copy_from_slice(values);
    lanes
}

/// A register's eight floats, in order.
#[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
#[inline(always)]
fn to_array(lanes: __m256) -> [f32; LANES] {
    let mut values = [0.0; LANES];
    // SAFETY: the store writes the eight floats of `values`; AVX is enabled at compile time.
    unsafe { _mm256_storeu_ps(values.as_mut_ptr(), lanes) };
    values
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Vectors go to their lanes and back unchanged, each component to its own lane.
    #[test]
    fn lanes_hold_each_vectors_components() {
        let vec2s: [Vec2; LANES] = std::array::from_fn(|k| Vec2::new(k as f32, -(k as f32)));
        let [x, y] = load_vec2(&vec2s);
        for k in 0..LANES {
            assert_eq!((x[k], y[k]), (k as f32, -(k as f32)));
        }
        let vec3s: [Vec3; LANES] =
            std::array::from_fn(|k| Vec3::new(k as f32, 10.0 + k as f32, 20.0 + k as f32));
        let lanes = load_vec3(&vec3s);
        for (axis, lane) in lanes.iter().enumerate() {
            assert_eq!(*lane, std::array::from_fn(|k| vec3s[k][axis]));
        }
        let mut stored = [Vec3::ZERO; LANES];
        store_vec3(&lanes, &mut stored);
        assert_eq!(stored, vec3s);
    }
}
