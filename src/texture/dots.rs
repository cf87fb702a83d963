//! LuxRender's `dots` (`textures/dots.h`, pbrt-v1 §11.5.1): polka dots, one per unit cell of
//! (s, t) in about half of the cells (where Perlin noise at the cell is positive), of radius 0.35,
//! each shifted from the cell centre by up to 0.15 along s and t by further noise lookups.

use glam::{Vec2, Vec3};

use super::noise::noise;

/// True inside a dot.
pub fn inside_dot(st: Vec2) -> bool {
    let cell = (st + Vec2::splat(0.5)).floor();
    let n = |ds: f32, dt: f32| noise(Vec3::new(cell.x + ds, cell.y + dt, 0.5));
    if n(0.5, 0.5) <= 0.0 {
        return false;
    }
    const RADIUS: f32 = 0.35;
    let max_shift = 0.5 - RADIUS;
    let centre = cell + max_shift * Vec2::new(n(1.5, 2.8), n(4.5, 9.8));
    (st - centre).length_squared() < RADIUS * RADIUS
}

#[cfg(test)]
mod tests {
    use super::*;

    /// LuxRender's jitter (`textures/dots.h`) in cell (2, 3): noise(2.5, 3.5, 0.5) = 3/8 > 0
    /// (the mean of that cell centre's corner terms), so the cell has a dot; its centre is
    /// (2 + 0.15 noise(3.5, 5.8, 0.5), 3 + 0.15 noise(6.5, 12.8, 0.5)) = (2.050922, 2.901082),
    /// the two noises (0.33948, -0.659456) from an independent float64 transcription (Python)
    /// of LuxRender's `Noise`. The disc of radius 0.35 about it: in at 0.34 and 0.345 from the
    /// centre, out at 0.355 and 0.36.
    #[test]
    fn dot_centre_is_luxrenders_jittered_centre() {
        let centre = Vec2::new(2.050_922, 2.901_081_6);
        assert!(inside_dot(centre + Vec2::new(0.34, 0.0)));
        assert!(!inside_dot(centre + Vec2::new(0.36, 0.0)));
        assert!(inside_dot(centre - Vec2::new(0.0, 0.345)));
        assert!(!inside_dot(centre - Vec2::new(0.0, 0.355)));
        // Cell (0, 0) has no dot: noise at its centre is -1/8.
        assert!(!inside_dot(Vec2::ZERO));
    }

    /// Each dot is a disc of radius 0.35 within its cell: the area inside dots over many cells
    /// is pi 0.35^2 times the fraction of cells with a dot, and a cell's centre is inside its
    /// dot exactly when the cell has one (the shift, at most 0.15 per axis, is below 0.35).
    #[test]
    fn dots_are_discs_in_cells() {
        let cells = 40;
        let grid = 50;
        let (mut inside, mut with_dot) = (0usize, 0usize);
        for cs in 0..cells {
            for ct in 0..cells {
                let centre = Vec2::new(cs as f32, ct as f32);
                let has = noise(Vec3::new(centre.x + 0.5, centre.y + 0.5, 0.5)) > 0.0;
                assert_eq!(inside_dot(centre), has, "{centre}");
                with_dot += usize::from(has);
                for i in 0..grid * grid {
                    let off = Vec2::new(
                        ((i % grid) as f32 + 0.5) / grid as f32 - 0.5,
                        ((i / grid) as f32 + 0.5) / grid as f32 - 0.5,
                    );
                    inside += usize::from(inside_dot(centre + off));
                }
            }
        }
        assert!(with_dot > 0 && with_dot < cells * cells);
        let area = inside as f64 / (grid * grid) as f64;
        let expected = with_dot as f64 * std::f64::consts::PI * 0.35 * 0.35;
        assert!((area / expected - 1.0).abs() < 0.01, "{area} {expected}");
    }
}
