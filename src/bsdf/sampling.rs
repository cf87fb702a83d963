//! Warps from the unit square used by the BSDF samplers.

use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_PI_4;

/// Uniform point on the unit disk by Shirley and Chiu's concentric map
/// (1997, "A Low Distortion Map Between Disk and Square"; pbrt-v4 §A.5.1).
pub fn sample_uniform_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (o.x / o.y))
    };
    r * Vec2::new(theta.cos(), theta.sin())
}

/// Cosine-weighted direction on the upper hemisphere (pdf cos(theta) / pi),
/// by Malley's method: lift a uniform disk point (pbrt-v4 §A.5.3).
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = sample_uniform_disk_concentric(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}
