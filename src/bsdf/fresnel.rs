//! Fresnel reflectance.

use glam::Vec3;

/// Unpolarised Fresnel reflectance of a smooth dielectric interface (pbrt-v4
/// §9.3.3, `FrDielectric`). `cos_i` is the cosine of the incident direction
/// with the normal, which points to the outside; `eta` = index inside / index
/// outside. A negative `cos_i` means the light arrives from inside, so the
/// relative index is inverted. Returns 1 under total internal reflection.
pub fn fr_dielectric(cos_i: f32, eta: f32) -> f32 {
    let (cos_i, eta) = if cos_i < 0.0 {
        ((-cos_i).min(1.0), 1.0 / eta)
    } else {
        (cos_i.min(1.0), eta)
    };
    // Snell's law: sin_t = sin_i / eta.
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    // Fresnel equations for parallel and perpendicular polarisation; the
    // denominators vanish only when cos_t = 0, handled above.
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parl * r_parl + r_perp * r_perp)
}

/// Schlick's approximation (1994, "An Inexpensive BRDF Model for
/// Physically-based Rendering", eq. 15): F = F0 + (1 - F0) (1 - cos)^5, where
/// F0 is the reflectance at normal incidence and `cos` the cosine between the
/// incident direction and the (micro)facet normal.
pub fn schlick(f0: Vec3, cos: f32) -> Vec3 {
    let m = (1.0 - cos.clamp(0.0, 1.0)).powi(5);
    f0 + (Vec3::ONE - f0) * m
}
