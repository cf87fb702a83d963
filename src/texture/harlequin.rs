//! LuxRender's `harlequin` colour texture (`textures/harlequin.h`): a different colour per
//! object, from a palette of 31 colours whose channels are the radical inverses of 3i + 1 in
//! bases 2, 3 and 5. LuxRender picks the entry from the object's memory address; foton from
//! its object index, so the colours differ from LuxRender's but stay fixed from run to run.

use glam::Vec3;

const PALETTE_SIZE: u32 = 31;

/// The radical inverse of `n` in `base`: its digits mirrored about the radix point.
fn radical_inverse(mut n: u32, base: u32) -> f32 {
    let (mut inv, mut scale) = (0.0f64, 1.0f64 / f64::from(base));
    while n > 0 {
        inv += f64::from(n % base) * scale;
        n /= base;
        scale /= f64::from(base);
    }
    inv as f32
}

/// The colour of object `object`.
pub fn harlequin(object: u32) -> Vec3 {
    let i = 3 * (object % PALETTE_SIZE) + 1;
    Vec3::new(
        radical_inverse(i, 2),
        radical_inverse(i, 3),
        radical_inverse(i, 5),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn palette() {
        // Entry 0: i = 1, radical inverse 1/2, 1/3, 1/5. Entry 1: i = 4 = 100b, 11 (base 3),
        // 4 (base 5): 1/8, 1/3 + 1/9, 4/5.
        assert!((harlequin(0) - Vec3::new(0.5, 1.0 / 3.0, 0.2)).length() < 1e-6);
        let c = harlequin(1);
        assert!(
            (c - Vec3::new(0.125, 4.0 / 9.0, 0.8)).length() < 1e-6,
            "{c}"
        );
        assert_eq!(harlequin(31), harlequin(0));
        // Distinct colours for neighbouring objects.
        for i in 0..30 {
            assert_ne!(harlequin(i), harlequin(i + 1));
        }
    }
}
