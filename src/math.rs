//! Small numeric and geometric helpers shared by the stages.

use std::ops::{Add, Mul, Sub};

use glam::{BVec4A, Vec3, Vec3A, Vec4};

/// `x.floor()` to the bit, without the call to libm's `floorf` that baseline x86-64 (no SSE4.1
/// `roundss`) compiles `f32::floor` to (about 25 instructions a call, four per bilinear texture
/// lookup): below 2^23 in magnitude, truncation through i32 (with x's sign, so that -0.0 stays
/// -0.0) and one step down where that rounded a negative number up; from 2^23 on every float
/// is an integer, and NaN stays NaN.
pub fn floor(x: f32) -> f32 {
    if x.abs() < 8_388_608.0 {
        let truncated = (x as i32 as f32).copysign(x);
        if truncated > x {
            truncated - 1.0
        } else {
            truncated
        }
    } else {
        x
    }
}

/// atan2(y, x) in [-pi, pi] within 5e-7 of libm's, two units in the last place at pi (tested):
/// the octant reduction to a ratio r in [0, 1], then Cephes' `atanf` (its reduction of r above tan(pi/8) by
/// atan r = pi/4 + atan((r - 1) / (r + 1)), and its minimax polynomial on |z| <= tan(pi/8),
/// relative error 1.9e-7 there). atan2(0, 0) is 0, as libm's (for x = +0).
pub fn atan2(y: f32, x: f32) -> f32 {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let (ay, ax) = (y.abs(), x.abs());
    let swapped = ay > ax;
    let (num, den) = if swapped { (ax, ay) } else { (ay, ax) };
    if den == 0.0 {
        return if x < 0.0 {
            PI.copysign(y)
        } else {
            0.0f32.copysign(y)
        };
    }
    let r = num / den;
    let (base, z) = if r > TAN_PI_8 {
        (FRAC_PI_4, (r - 1.0) / (r + 1.0))
    } else {
        (0.0, r)
    };
    let poly = atan_reduced(z);
    let mut angle = base + poly;
    if swapped {
        angle = FRAC_PI_2 - angle;
    }
    if x < 0.0 {
        angle = PI - angle;
    }
    angle.copysign(y)
}

/// tan(pi/8): above it [`atan2`] reduces r to (r - 1) / (r + 1), whose angle is pi/4 less.
const TAN_PI_8: f32 = 0.414_213_57;

/// atan z for |z| <= tan(pi/8), the odd minimax polynomial of [`atan2`]'s reduced argument;
/// generic so that [`atan2_lanes`] evaluates the very same operations in each lane.
#[inline(always)]
fn atan_reduced<T>(z: T) -> T
where
    T: Copy + Mul<Output = T> + Mul<f32, Output = T> + Add<Output = T> + Add<f32, Output = T>,
    T: Sub<f32, Output = T>,
{
    let z2 = z * z;
    (((z2 * 8.053_744_5e-2 - 1.387_768_6e-1) * z2 + 1.997_771_1e-1) * z2 - 3.333_295e-1) * z2 * z
        + z
}

/// [`atan2`] of each lane, to the bit: the same operations, with its branches as selects,
/// so that two or more independent angles (an escaped ray's phi and theta) cost one
/// evaluation in SSE registers instead of one each (whose branches were half the work).
pub fn atan2_lanes(y: Vec4, x: Vec4) -> Vec4 {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let (ay, ax) = (y.abs(), x.abs());
    let swapped = ay.cmpgt(ax);
    let (num, den) = (select_lanes(swapped, ax, ay), select_lanes(swapped, ay, ax));
    // 0 / 0 gives NaN in the lanes that `atan2` returns early from; the last select drops it.
    let r = num / den;
    let reduced = r.cmpgt(Vec4::splat(TAN_PI_8));
    let base = select_lanes(reduced, Vec4::splat(FRAC_PI_4), Vec4::ZERO);
    let z = select_lanes(reduced, (r - 1.0) / (r + 1.0), r);
    let poly = atan_reduced(z);
    let angle = base + poly;
    let angle = select_lanes(swapped, FRAC_PI_2 - angle, angle);
    let negative_x = x.cmplt(Vec4::ZERO);
    let angle = select_lanes(negative_x, PI - angle, angle);
    let on_axis = select_lanes(negative_x, Vec4::splat(PI), Vec4::ZERO);
    select_lanes(den.cmpeq(Vec4::ZERO), on_axis, angle).copysign(y)
}

/// `Vec4::select` (the lanes of `if_true` where `mask` is set): one `blendvps` where the build
/// has SSE4.1 (the x86-64-v3 and native builds), where glam's and, and-not and or stay three
/// instructions; the same lanes for masks from comparisons (each lane's bits all set or none).
#[inline]
pub(crate) fn select_lanes(mask: BVec4A, if_true: Vec4, if_false: Vec4) -> Vec4 {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse4.1"))]
    {
        // SAFETY: the build enables SSE4.1.
        Vec4::from(unsafe {
            std::arch::x86_64::_mm_blendv_ps(if_false.into(), if_true.into(), mask.into())
        })
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse4.1")))]
    Vec4::select(mask, if_true, if_false)
}

/// sin x and cos x for |x| <= pi/4 without range reduction: the minimax polynomials of Cephes'
/// `sinf.c` (S. L. Moshier), which Dr.Jit's `sincos` also evaluates, good to about 1 ulp there.
/// Generic over the number type so that the shading stage's eight-lane kernel and the
/// environment map's four-lane light samples (glam's `Vec4`) evaluate the very same operations
/// on each lane (a constant's product with x^2 is the same either way round).
pub fn sin_cos_eighth_turn<T>(x: T) -> (T, T)
where
    T: Copy + Add<Output = T> + Sub<Output = T> + Mul<Output = T> + Mul<f32, Output = T>,
    f32: Add<T, Output = T> + Sub<T, Output = T>,
{
    let x2 = x * x;
    let sin = x + x * x2 * (-1.666_665_5e-1 + x2 * (8.332_161e-3 + x2 * -1.951_529_6e-4));
    let cos =
        1.0 - x2 * 0.5 + x2 * x2 * (4.166_664_6e-2 + x2 * (-1.388_731_6e-3 + x2 * 2.443_315_7e-5));
    (sin, cos)
}

/// (sin(pi x), cos(pi x)) within 1.2e-7 (an ulp of 1) of the exact values (tested on [-2, 2]),
/// without libm's `sincosf` (about 50 instructions a call) and the rounding of pi x before it
/// (up to 4e-7 there): x = q / 2 + r with q the integer nearest 2x and |r| <= 1/4, exactly (r
/// is a multiple of x's ulp no larger than x, for |x| < 2^22), then [`sin_cos_eighth_turn`] of
/// t = pi r in [-pi/4, pi/4], and the quadrant q mod 4 swapping and negating them. sin and cos are exactly 0 and +-1 at multiples of 1/2.
pub fn sin_cos_pi(x: f32) -> (f32, f32) {
    let q = floor(2.0 * x + 0.5);
    let r = x - 0.5 * q;
    let (sin, cos) = sin_cos_eighth_turn(std::f32::consts::PI * r);
    match (q as i32) & 3 {
        0 => (sin, cos),
        1 => (cos, -sin),
        2 => (-sin, -cos),
        _ => (-cos, sin),
    }
}

/// `v` scaled to unit length, or `fallback` when that is not finite and positive (`v` zero or
/// not finite): glam's `Vec3::normalize_or` to the bit (the same reciprocal length and product),
/// with its test `rcp.is_finite() && rcp > 0.0` as two float comparisons, which LLVM folds
/// into a class test of two dozen integer instructions on x86-64 (`rcp <= f32::MAX` is not
/// folded).
pub fn normalize_or(v: Vec3, fallback: Vec3) -> Vec3 {
    let rcp = 1.0 / v.length();
    if is_positive_finite(rcp) {
        v * rcp
    } else {
        fallback
    }
}

/// glam's `Vec3::try_normalize` to the bit (the same reciprocal length and product), its test
/// written as comparisons as in [`normalize_or`]: None when `v` is zero or not finite.
pub fn try_normalize(v: Vec3) -> Option<Vec3> {
    let rcp = 1.0 / v.length();
    is_positive_finite(rcp).then(|| v * rcp)
}

/// `x.is_finite() && x > 0.0` for every input (false for NaN), as two float comparisons where
/// LLVM folds `is_finite` with the other test into integer ones (see [`normalize_or`]).
pub fn is_positive_finite(x: f32) -> bool {
    x > 0.0 && x <= f32::MAX
}

/// `x.is_finite()` for every input (NaN compares false, and |x| <= f32::MAX excludes exactly
/// the infinities), as a float comparison where LLVM folds `is_finite` into integer tests.
pub fn is_finite(x: f32) -> bool {
    x.abs() <= f32::MAX
}

/// glam's `Vec3::is_finite` (every component finite): [`is_finite`] on the three lanes in one
/// vector compare, where the components one by one compiled to two branches and a scalar test
/// (this is the check on every radiance a path adds).
pub fn is_finite_vec3(v: Vec3) -> bool {
    Vec3A::from(v).abs().cmple(Vec3A::splat(f32::MAX)).all()
}

/// Moves a ray origin off a surface along its geometric normal, to the side `w` leaves on,
/// so the new ray does not hit the surface it starts on. The offset scales with the point's
/// magnitude, as float error does (pbrt-v4 §6.8.6 bounds it the same way, per component).
pub fn offset_ray_origin(p: Vec3, geometric_normal: Vec3, w: Vec3) -> Vec3 {
    let scale = 1e-4 * (1.0 + p.abs().max_element());
    let offset = geometric_normal * scale;
    if w.dot(geometric_normal) < 0.0 {
        p - offset
    } else {
        p + offset
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    /// The fast atan2 against libm's over directions all around the circle, the axes and the
    /// diagonals (where the octant and Cephes reductions switch) included.
    #[test]
    fn atan2_is_libm_atan2_within_its_error_bound() {
        let mut worst = 0.0f32;
        let mut check = |y: f32, x: f32| {
            worst = worst.max((atan2(y, x) - y.atan2(x)).abs());
        };
        for k in 0..200_000 {
            let angle = k as f32 / 200_000.0 * 2.0 * PI - PI;
            let (s, c) = angle.sin_cos();
            check(s, c);
            check(s * 1e-3, c * 1e-3);
        }
        for (y, x) in [
            (0.0, 1.0),
            (1.0, 0.0),
            (0.0, -1.0),
            (-1.0, 0.0),
            (1.0, 1.0),
            (1.0, -1.0),
        ] {
            check(y, x);
            let t = 0.414_213_57f32;
            check(t * y, x);
            check(y, t * x);
        }
        // Two ulps of pi: the polynomial's error plus the roundings of pi/4 + p and pi - a.
        assert!(worst <= 5e-7, "largest difference {worst:e}");
        assert_eq!(atan2(0.0, 0.0), 0.0);
        assert_eq!(atan2(-0.0, -1.0), -PI);
    }

    /// `atan2_lanes` is `atan2` in every lane to the bit: around the circle at several scales,
    /// on and beside the axes, the diagonals and the reduction's switch at tan(pi/8), with
    /// signed zeros, infinities and subnormals, each pair in a different lane.
    #[test]
    fn atan2_lanes_is_atan2_to_the_bit() {
        let mut pairs: Vec<(f32, f32)> = (0..100_000)
            .flat_map(|k| {
                let (s, c) = (k as f32 / 100_000.0 * 2.0 * PI - PI).sin_cos();
                [(s, c), (s * 1e-3, c * 1e-3), (s * 3e4, c)]
            })
            .collect();
        let specials = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.414_213_57,
            -0.414_213_57,
            0.414_213_57f32.next_up(),
            1e-45,
            -1e-45,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        for y in specials {
            for x in specials {
                pairs.push((y, x));
            }
        }
        for (k, lanes) in pairs.chunks(4).enumerate() {
            let rotated: Vec<(f32, f32)> = (0..4).map(|i| lanes[(i + k) % lanes.len()]).collect();
            let y = Vec4::from_array(std::array::from_fn(|i| rotated[i].0));
            let x = Vec4::from_array(std::array::from_fn(|i| rotated[i].1));
            let got = atan2_lanes(y, x).to_array();
            for (i, &(y, x)) in rotated.iter().enumerate() {
                assert_eq!(
                    got[i].to_bits(),
                    atan2(y, x).to_bits(),
                    "atan2({y:e}, {x:e})"
                );
            }
        }
    }

    /// Against f64's sin and cos of pi x, over [-2, 2] densely and beside every multiple of 1/8
    /// (where the quadrant changes or the reduction's r is largest), and the exact values at the
    /// multiples of 1/2.
    #[test]
    fn sin_cos_pi_is_within_an_ulp_of_one() {
        let mut xs: Vec<f32> = (-2_000_000..=2_000_000)
            .map(|k| k as f32 / 1_000_000.0)
            .collect();
        for k in -16..=16 {
            let x = k as f32 / 8.0;
            xs.extend([x, x.next_up(), x.next_down()]);
        }
        let mut worst = 0.0f64;
        for x in xs {
            let (sin, cos) = sin_cos_pi(x);
            let exact = std::f64::consts::PI * f64::from(x);
            worst = worst
                .max((f64::from(sin) - exact.sin()).abs())
                .max((f64::from(cos) - exact.cos()).abs());
        }
        assert!(worst <= 1.2e-7, "largest error {worst:e}");
        for (x, sin, cos) in [
            (0.0, 0.0, 1.0),
            (0.5, 1.0, 0.0),
            (1.0, 0.0, -1.0),
            (1.5, -1.0, 0.0),
        ] {
            assert_eq!(sin_cos_pi(x), (sin, cos), "at {x}");
        }
    }

    /// glam's `normalize_or` to the bit, on vectors of every scale, zero, tiny (whose length
    /// underflows), huge (whose length overflows), infinite and NaN.
    #[test]
    fn normalize_or_is_glams() {
        let fallback = Vec3::new(0.0, 0.0, 1.0);
        let mut vectors = vec![
            Vec3::ZERO,
            Vec3::splat(1e-30),
            Vec3::new(1e-45, 0.0, 0.0),
            Vec3::splat(3e38),
            Vec3::new(f32::INFINITY, 0.0, 0.0),
            Vec3::new(f32::NAN, 1.0, 0.0),
            Vec3::new(-0.0, -0.0, -0.0),
        ];
        vectors.extend(vectors_of_every_scale());
        for v in vectors {
            let (got, expected) = (normalize_or(v, fallback), v.normalize_or(fallback));
            assert!(
                got.to_array().map(f32::to_bits) == expected.to_array().map(f32::to_bits),
                "{v}: {got} against {expected}"
            );
        }
    }

    /// `is_finite`, `is_positive_finite` and `is_finite_vec3` agree with std and glam on NaN,
    /// the infinities, the largest finite values, zeros, subnormals and ordinary values;
    /// `try_normalize` is glam's to the bit on them and on vectors of every scale.
    #[test]
    fn finiteness_tests_are_stds() {
        let values = [
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            f32::MIN,
            0.0,
            -0.0,
            f32::MIN_POSITIVE,
            1e-45,
            -1e-45,
            1.0,
            -3.5,
        ];
        for x in values {
            assert_eq!(is_finite(x), x.is_finite(), "{x}");
            assert_eq!(is_positive_finite(x), x.is_finite() && x > 0.0, "{x}");
            for y in values {
                let v = Vec3::new(x, y, 1.0);
                assert_eq!(is_finite_vec3(v), v.is_finite(), "{v}");
                let w = Vec3::new(1.0, x, y);
                assert_eq!(is_finite_vec3(w), w.is_finite(), "{w}");
                let bits = |v: Option<Vec3>| v.map(|v| v.to_array().map(f32::to_bits));
                assert_eq!(bits(try_normalize(v)), bits(v.try_normalize()), "{v}");
            }
        }
        for v in vectors_of_every_scale() {
            let bits = |v: Option<Vec3>| v.map(|v| v.to_array().map(f32::to_bits));
            assert_eq!(bits(try_normalize(v)), bits(v.try_normalize()), "{v}");
        }
    }

    /// 10,000 vectors in all directions at scales from 1e-40 (lengths that underflow) to 1e39
    /// (lengths that overflow).
    fn vectors_of_every_scale() -> impl Iterator<Item = Vec3> {
        (0..10_000).map(|k| {
            let t = k as f32 * 0.618_034;
            let scale = 10f32.powi(k % 80 - 40);
            Vec3::new(t.sin(), (1.3 * t).cos(), (0.7 * t).sin() - 0.2) * scale
        })
    }

    #[test]
    fn floor_is_std_floor_to_the_bit() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            8_388_607.5,
            -8_388_607.5,
            8_388_608.0,
            -8_388_609.0,
            3e9,
            -3e9,
            f32::MAX,
            f32::MIN,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        // Every float's neighbours around the integers of [-300, 300], and a sweep.
        for k in -300..=300 {
            let k = k as f32;
            values.extend([k, k.next_down(), k.next_up()]);
        }
        values.extend((-20_000..20_000).map(|k| k as f32 * 0.013_7));
        for x in values {
            assert_eq!(floor(x).to_bits(), x.floor().to_bits(), "{x:e}");
        }
        assert!(floor(f32::NAN).is_nan());
    }
}
