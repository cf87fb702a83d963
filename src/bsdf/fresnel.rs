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

/// Unpolarised Fresnel reflectance of a conductor of complex relative index eta + i k, per
/// channel (pbrt-v3 §8.2.1, `FrConductor`, after Born and Wolf): with s = sin^2, c = cos^2,
/// a^2 + b^2 = sqrt((eta^2 - k^2 - s)^2 + 4 eta^2 k^2) and a = sqrt((a^2 + b^2 + eta^2 - k^2 - s)/2),
///   Rs = (a^2 + b^2 + c - 2 a cos) / (a^2 + b^2 + c + 2 a cos),
///   Rp = Rs (c (a^2 + b^2) + s^2 - 2 a cos s) / (c (a^2 + b^2) + s^2 + 2 a cos s),
/// and F = (Rs + Rp) / 2. At normal incidence it is ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2).
pub fn fr_conductor(cos_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    let cos = cos_i.clamp(0.0, 1.0);
    let (cos2, sin2) = (cos * cos, 1.0 - cos * cos);
    let (eta2, k2) = (eta * eta, k * k);
    let t0 = eta2 - k2 - Vec3::splat(sin2);
    let a2_plus_b2 = (t0 * t0 + 4.0 * eta2 * k2).max(Vec3::ZERO).powf(0.5);
    let t1 = a2_plus_b2 + Vec3::splat(cos2);
    let a = (0.5 * (a2_plus_b2 + t0)).max(Vec3::ZERO).powf(0.5);
    let t2 = 2.0 * cos * a;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = cos2 * a2_plus_b2 + Vec3::splat(sin2 * sin2);
    let t4 = t2 * sin2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    0.5 * (rp + rs)
}

/// pbrt-v1's `FresnelApproxEta`: the real index whose normal-incidence reflectance
/// ((eta - 1) / (eta + 1))^2 is `reflectance`, eta = (1 + sqrt(R)) / (1 - sqrt(R)), with R
/// clamped to [0, 0.999] as pbrt-v1 does, so that eta stays finite.
pub fn approx_eta(reflectance: Vec3) -> Vec3 {
    let root = reflectance.clamp(Vec3::ZERO, Vec3::splat(0.999)).powf(0.5);
    (Vec3::ONE + root) / (Vec3::ONE - root)
}

/// pbrt-v1's `FresnelApproxK`: the absorption 2 sqrt(R / (1 - R)) paired with
/// [`approx_eta`] (R clamped to [0, 0.999]).
pub fn approx_k(reflectance: Vec3) -> Vec3 {
    let r = reflectance.clamp(Vec3::ZERO, Vec3::splat(0.999));
    2.0 * (r / (Vec3::ONE - r)).powf(0.5)
}

/// LuxRender's `FresnelGeneral` of a real part `eta` and absorption `k` (`fresnelgeneral.cpp`
/// with `FrFull` of `core/reflection/fresnel.cpp`): the refracted cosine cos_t = sqrt(1 -
/// (sin_i / eta)^2) (clamped) of Snell's law on the real part, then
///   R_parl^2 = ((eta^2 + k^2) c_i^2 + c_t^2 - 2 eta c_i c_t) / (... + 2 eta c_i c_t),
///   R_perp^2 = ((eta^2 + k^2) c_t^2 + c_i^2 - 2 eta c_i c_t) / (... + 2 eta c_i c_t),
/// F = (R_parl^2 + R_perp^2) / 2: ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2) at normal
/// incidence, 1 at grazing incidence.
pub fn fr_general(cos_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    let c_i = cos_i.abs().min(1.0);
    let sin_i = (1.0 - c_i * c_i).max(0.0).sqrt();
    let sin_t = (Vec3::splat(sin_i) / eta).clamp(Vec3::ZERO, Vec3::ONE);
    let c_t = (Vec3::ONE - sin_t * sin_t).powf(0.5);
    let norm2 = eta * eta + k * k;
    let cross = 2.0 * c_i * c_t * eta;
    let parl = norm2 * (c_i * c_i) + c_t * c_t;
    let perp = norm2 * c_t * c_t + Vec3::splat(c_i * c_i);
    // Both sums vanish only at grazing incidence on a matched index (eta = 1, k = 0), whose
    // limit is total reflection, as for any other index.
    let ratio = |sum: Vec3| {
        let r = (sum - cross) / (sum + cross);
        Vec3::select((sum + cross).cmpgt(Vec3::ZERO), r, Vec3::ONE)
    };
    0.5 * (ratio(parl) + ratio(perp))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At normal incidence the closed form; at grazing incidence total reflection; with k = 0 the
    /// dielectric's reflectance.
    #[test]
    fn conductor_fresnel_known_values() {
        let (eta, k) = (Vec3::new(0.2, 1.1, 1.5), Vec3::new(3.0, 2.0, 0.0));
        let normal = fr_conductor(1.0, eta, k);
        let expected = ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
        assert!(
            (normal - expected).abs().max_element() < 1e-5,
            "{normal} {expected}"
        );
        assert!((fr_conductor(0.0, eta, k) - Vec3::ONE).abs().max_element() < 1e-5);
        for cos in [0.1, 0.4, 0.8] {
            let f = fr_conductor(cos, Vec3::splat(1.5), Vec3::ZERO);
            assert!((f.x - fr_dielectric(cos, 1.5)).abs() < 1e-5, "{cos}: {f}");
        }
    }
}
