//! One triangle against the eight rays of a packet at once, one ray per AVX lane: the
//! Möller–Trumbore test of [`Triangle4::intersect`] with the roles of the lanes swapped (there
//! four triangles against one ray). A leaf reached by several rays of a packet is tested
//! triangle by triangle this way, rather than ray by ray.
//!
//! Each lane computes exactly the operations of `Triangle4::intersect` in the same order on
//! the same values (IEEE products, sums and quotients, no fused multiply-add, the same
//! comparisons), so each ray gets the same `t`, `u` and `v` to the bit, and hits the same
//! triangles.
//!
//! Used only inside functions compiled for AVX2 and called after `is_x86_feature_detected!`
//! found it (`Accel::closest_hits_chunk`, `Accel::any_hits_chunk`): that makes the
//! intrinsics' `unsafe` sound. `#[inline(always)]`, so it is compiled into those functions,
//! where the intrinsics inline.

#![cfg(target_arch = "x86_64")]

use std::arch::x86_64::*;

use super::triangle::Triangle4;

/// Eight rays in AVX lanes: per axis their origins and directions, and the lanes to test.
pub(crate) struct TriangleRays {
    pub origin: [__m256; 3],
    pub dir: [__m256; 3],
    pub t_min: __m256,
    /// All bits set in the lanes of the rays to test, clear in the others.
    pub active: __m256,
}

/// The lanes of `rays` as a vector mask: all bits set in lane `i` where bit `i` is.
#[inline(always)]
pub(crate) fn lane_mask(rays: u32) -> __m256 {
    // SAFETY: see the module's documentation.
    unsafe {
        let bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
        let set = _mm256_and_si256(_mm256_set1_epi32(rays as i32), bits);
        _mm256_castsi256_ps(_mm256_cmpeq_epi32(set, bits))
    }
}

/// A triangle's hits by eight rays: the mask of the rays that hit it (all bits set in their
/// lanes), and each lane's `t`, `u` and `v`.
pub(crate) struct LanesHit {
    pub mask: __m256,
    pub t: __m256,
    pub u: __m256,
    pub v: __m256,
}

impl TriangleRays {
    /// Triangle `lane` of `packet` against the active rays: those that hit it with `t` in
    /// `(t_min, t_max)` (each ray its own `t_max`), or `None` when none does.
    #[inline(always)]
    pub fn hit(&self, packet: &Triangle4, lane: usize, t_max: __m256) -> Option<LanesHit> {
        let (v0, e1, e2) = packet.vertex_and_edges(lane);
        let (o, d) = (&self.origin, &self.dir);
        // SAFETY: see the module's documentation.
        unsafe {
            let (add, sub, mul, and) = (_mm256_add_ps, _mm256_sub_ps, _mm256_mul_ps, _mm256_and_ps);
            let splat = |v: [f32; 3]| v.map(|x| _mm256_set1_ps(x));
            let (v0, e1, e2) = (splat(v0), splat(e1), splat(e2));
            let cross = |a: &[__m256; 3], b: &[__m256; 3]| {
                [
                    sub(mul(a[1], b[2]), mul(a[2], b[1])),
                    sub(mul(a[2], b[0]), mul(a[0], b[2])),
                    sub(mul(a[0], b[1]), mul(a[1], b[0])),
                ]
            };
            let dot = |a: &[__m256; 3], b: &[__m256; 3]| {
                add(add(mul(a[0], b[0]), mul(a[1], b[1])), mul(a[2], b[2]))
            };
            let (zero, one) = (_mm256_setzero_ps(), _mm256_set1_ps(1.0));
            let p = cross(d, &e2);
            let det = dot(&e1, &p);
            let inv_det = _mm256_div_ps(one, det);
            let s = [sub(o[0], v0[0]), sub(o[1], v0[1]), sub(o[2], v0[2])];
            let u = mul(dot(&s, &p), inv_det);
            // As in `Triangle4::intersect`: when no ray passes the first barycentric test,
            // stop before the second cross product.
            let u_mask = and(
                and(self.active, _mm256_cmp_ps::<_CMP_NEQ_UQ>(det, zero)),
                and(
                    _mm256_cmp_ps::<_CMP_GE_OQ>(u, zero),
                    _mm256_cmp_ps::<_CMP_LE_OQ>(u, one),
                ),
            );
            if _mm256_movemask_ps(u_mask) == 0 {
                return None;
            }
            let q = cross(&s, &e1);
            let v = mul(dot(d, &q), inv_det);
            let t = mul(dot(&e2, &q), inv_det);
            let mask = and(
                and(u_mask, _mm256_cmp_ps::<_CMP_GE_OQ>(v, zero)),
                and(
                    _mm256_cmp_ps::<_CMP_LE_OQ>(add(u, v), one),
                    and(
                        _mm256_cmp_ps::<_CMP_GT_OQ>(t, self.t_min),
                        _mm256_cmp_ps::<_CMP_LT_OQ>(t, t_max),
                    ),
                ),
            );
            (_mm256_movemask_ps(mask) != 0).then_some(LanesHit { mask, t, u, v })
        }
    }
}
