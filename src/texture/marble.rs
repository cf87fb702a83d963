//! LuxRender's `marble` (`textures/marble.h`, pbrt-v1 §11.6.4): bands along y perturbed by
//! fractional Brownian motion, coloured by a cubic Bezier spline through nine greys and a blue.

use glam::Vec3;

use super::noise::fbm;

/// The spline's control colours (LuxRender's table).
const COLOURS: [[f32; 3]; 9] = [
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.5, 0.5, 0.5],
    [0.6, 0.59, 0.58],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.2, 0.2, 0.33],
    [0.58, 0.58, 0.6],
];

/// The marble colour at texture-space point `p`:
/// t = 1/2 + sin(scale p.y + variation fbm(scale p)) / 2, then the spline at t, times 1.5.
pub fn marble(p: Vec3, octaves: u32, roughness: f32, scale: f32, variation: f32) -> Vec3 {
    let p = p * scale;
    let t = 0.5 + 0.5 * (p.y + variation * fbm(p, roughness, octaves)).sin();
    1.5 * spline(t)
}

/// The cubic Bezier segment of the control polygon at t in [0, 1], by de Casteljau. There are
/// NSEG = 9 - 3 = 6 segments, each using four consecutive colours; LuxRender would read past
/// the table at t = 1, so the last segment is clamped.
fn spline(t: f32) -> Vec3 {
    let segments = COLOURS.len() - 3;
    let x = t.clamp(0.0, 1.0) * segments as f32;
    let first = (x.floor() as usize).min(segments - 1);
    let t = x - first as f32;
    let c = |i: usize| Vec3::from_array(COLOURS[first + i]);
    let (s0, s1, s2) = (c(0).lerp(c(1), t), c(1).lerp(c(2), t), c(2).lerp(c(3), t));
    let (s0, s1) = (s0.lerp(s1, t), s1.lerp(s2, t));
    s0.lerp(s1, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spline_interpolates_segment_ends() {
        // A cubic Bezier passes through its first and last control points: at the start of
        // segment k (t = k / 6) the value is colour k; at t = 1, colour 8.
        for (k, c) in COLOURS.iter().enumerate().take(6) {
            let v = spline(k as f32 / 6.0);
            assert!((v - Vec3::from_array(*c)).length() < 1e-6, "{k}: {v}");
        }
        assert!((spline(1.0) - Vec3::from_array(COLOURS[8])).length() < 1e-6);
        // Midpoint of segment 4 (colours 4..7): (c4 + 3 c5 + 3 c6 + c7) / 8.
        let c = |i: usize| Vec3::from_array(COLOURS[i]);
        let mid = (c(4) + 3.0 * c(5) + 3.0 * c(6) + c(7)) / 8.0;
        assert!((spline(4.5 / 6.0) - mid).length() < 1e-6);
    }

    /// LuxRender 1.x's `MarbleTexture::Evaluate` (`textures/marble.h`) at two points, from an
    /// independent float64 transcription (Python) of it and of `FBm`: t = 1/2 + sin(scale y +
    /// variation FBm(scale p, roughness, octaves)) / 2, the Bezier segment Floor(6 t), times 1.5.
    #[test]
    fn marble_matches_luxrenders_formula() {
        let a = marble(Vec3::new(0.4, 2.0, -1.3), 8, 0.5, 1.0, 0.2);
        let expected = Vec3::new(0.619_555_4, 0.619_555_4, 0.722_052_5);
        assert!((a - expected).abs().max_element() < 1e-5, "{a}");
        // texture-examples' marble: roughness 1, scale 0.1.
        let b = marble(Vec3::new(3.1, -7.5, 2.2), 8, 1.0, 0.1, 0.2);
        let expected = Vec3::new(0.755_536_8, 0.755_536_8, 0.756_921);
        assert!((b - expected).abs().max_element() < 1e-5, "{b}");
    }

    #[test]
    fn marble_without_variation_is_bands_along_y() {
        // variation 0: t = 1/2 + sin(scale y) / 2; y = 0 gives t = 1/2, y = pi/2 gives t = 1.
        let at = |y: f32| marble(Vec3::new(0.37, y, -1.3), 8, 0.5, 1.0, 0.0);
        assert!((at(0.0) - 1.5 * spline(0.5)).length() < 1e-6);
        assert!((at(std::f32::consts::FRAC_PI_2) - 1.5 * spline(1.0)).length() < 1e-5);
        // With variation the bands move: the fbm term changes the colour somewhere.
        let moved = (0..100).any(|i| {
            let p = Vec3::new(i as f32 * 0.37, 0.2, i as f32 * 0.11);
            (marble(p, 8, 0.5, 1.0, 0.2) - marble(p, 8, 0.5, 1.0, 0.0)).length() > 1e-3
        });
        assert!(moved);
    }
}
