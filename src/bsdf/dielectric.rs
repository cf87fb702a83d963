//! Smooth dielectric interface (LuxRender's `glass`): specular reflection and
//! refraction weighted by the exact Fresnel reflectance (pbrt-v4 §9.5,
//! `DielectricBxDF` for a smooth surface), with the colours `Kr` and `Kt`
//! multiplying the reflected and transmitted lobes.

use super::BsdfSample;
use super::fresnel::fr_dielectric;
use glam::Vec3;

#[derive(Clone, Copy, Debug)]
pub struct Dielectric {
    pub reflectance: Vec3,
    pub transmittance: Vec3,
    /// Index inside / index outside; the normal (+z) points outside.
    pub eta: f32,
}

/// The range a relative index is clamped to (NaN becomes 1): keeps 1 / eta^2
/// finite for any input; real materials lie well inside it.
const ETA_MIN: f32 = 1e-2;
const ETA_MAX: f32 = 1e2;

/// A relative index clamped to [ETA_MIN, ETA_MAX]; NaN becomes 1.
pub(super) fn clamp_eta(eta: f32) -> f32 {
    if eta.is_nan() {
        1.0
    } else {
        eta.clamp(ETA_MIN, ETA_MAX)
    }
}

/// The refracted direction of `wo` through an interface with unit normal `n`
/// (pointing outside: +z for a smooth surface, a microfacet normal for a
/// rough one) and relative index `eta` (inside / outside), with the relative
/// index of the side `wo` is on over the other (eta if wo is outside, 1 / eta
/// inside); None under total internal reflection. Snell's law in vector form
/// (pbrt-v4 §9.3.2, `Refract`).
pub(super) fn refract(wo: Vec3, n: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let cos_i = wo.dot(n);
    let (cos_i, eta, n) = if cos_i < 0.0 {
        (-cos_i, 1.0 / eta, -n)
    } else {
        (cos_i, eta, n)
    };
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((-wo / eta + (cos_i / eta - cos_t) * n, eta))
}

/// `reflectance` and `transmittance` blended by the Fresnel reflectance at
/// normal incidence: a grey-level albedo of any dielectric interface.
pub(super) fn blend_by_normal_fresnel(reflectance: Vec3, transmittance: Vec3, eta: f32) -> Vec3 {
    let r = fr_dielectric(1.0, eta);
    reflectance * r + transmittance * (1.0 - r)
}

impl Dielectric {
    fn eta(&self) -> f32 {
        clamp_eta(self.eta)
    }

    /// Kr and Kt blended by the Fresnel reflectance at normal incidence,
    /// ((eta - 1) / (eta + 1))^2.
    pub fn albedo(&self) -> Vec3 {
        blend_by_normal_fresnel(self.reflectance, self.transmittance, self.eta())
    }

    /// Picks reflection with probability R (the Fresnel reflectance for wo)
    /// using `uc`, else refraction with probability T = 1 - R.
    ///
    /// Radiance transport: the radiance carried across the interface is
    /// scaled by 1 / eta'^2 (eta' = the relative index of the side of wi
    /// over that of wo), because the solid angle is compressed by refraction;
    /// this makes the BTDF non-symmetric (pbrt-v4 §9.5.2, Veach 1997 §5.2).
    /// The returned f is that of radiance transport: light tracing
    /// (importance transport) must multiply the transmitted f by eta'^2 again.
    pub fn sample(&self, wo: Vec3, uc: f32) -> Option<BsdfSample> {
        let eta = self.eta();
        let r = fr_dielectric(wo.z, eta);
        let t = 1.0 - r;
        if uc < r || t <= 0.0 {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return Some(BsdfSample {
                wi,
                f: self.reflectance * (r / wi.z.abs()),
                pdf: r,
                delta: true,
            });
        }
        let (wi, etap) = refract(wo, Vec3::Z, eta)?;
        Some(BsdfSample {
            wi,
            f: self.transmittance * (t / (wi.z.abs() * etap * etap)),
            pdf: t,
            delta: true,
        })
    }
}
