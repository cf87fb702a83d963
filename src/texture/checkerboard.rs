//! LuxRender's `checkerboard` (`textures/checkerboard.h`, pbrt-v1 §11.4.4): `tex1` where the sum
//! of the integer parts of the coordinates is even, `tex2` where it is odd.
//!
//! LuxRender filters it (a closed-form box filter or a 4x4 supersample over the pixel
//! footprint, from ray differentials); foton point-samples it, and the pixel's samples do the
//! filtering.

use glam::{Vec2, Vec3};

use crate::math::floor;

/// True where a 2D checkerboard shows `tex1`: floor(s) + floor(t) even.
pub fn checker_2d(st: Vec2) -> bool {
    parity_even(floor(st.x) as i64 + floor(st.y) as i64)
}

/// True where a 3D checkerboard shows `tex1`: floor(x) + floor(y) + floor(z) even.
pub fn checker_3d(p: Vec3) -> bool {
    parity_even(floor(p.x) as i64 + floor(p.y) as i64 + floor(p.z) as i64)
}

fn parity_even(n: i64) -> bool {
    n.rem_euclid(2) == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checks_alternate() {
        assert!(checker_2d(Vec2::new(0.5, 0.5)));
        assert!(!checker_2d(Vec2::new(1.5, 0.5)));
        assert!(checker_2d(Vec2::new(1.5, 1.5)));
        // Negative coordinates continue the pattern (floor, not truncation).
        assert!(!checker_2d(Vec2::new(-0.5, 0.5)));
        assert!(checker_2d(Vec2::new(-0.5, -0.5)));
        assert!(checker_3d(Vec3::new(0.1, 0.2, 0.3)));
        assert!(!checker_3d(Vec3::new(0.1, 0.2, 1.3)));
        assert!(checker_3d(Vec3::new(-0.1, -0.2, 0.3)));
        // Half the area of a large square is tex1.
        let n = 200;
        let even = (0..n * n)
            .filter(|i| checker_2d(Vec2::new((i % n) as f32 * 0.05, (i / n) as f32 * 0.05)))
            .count();
        assert_eq!(even, n * n / 2);
    }
}
