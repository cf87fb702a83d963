//! Small geometric helpers shared by the stages.

use glam::Vec3;

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
