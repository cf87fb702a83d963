//! Small geometric helpers shared by the stages.

use glam::Vec3;

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
