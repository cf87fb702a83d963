//! Bump mapping: the shading normal of a surface displaced along its normal by a float
//! texture, without moving the surface (Blinn 1978; pbrt-v3 §9.3 `Material::Bump`).
//!
//! The displaced surface is p'(u, v) = p(u, v) + h(u, v) n, so to first order
//! dp'/du = dp/du + (dh/du) n and dp'/dv = dp/dv + (dh/dv) n (the h dn/du terms dropped, as
//! LuxRender 1.x drops them: `core/material.cpp`, "displace*dgs.dndu creates artefacts"), and
//! the bumped normal is their cross product, kept on the side of the original normal.
//!
//! dh/du and dh/dv are forward differences over a step of `sample_distance` in world units
//! (LuxRender's `bumpmapsampledistance`, default 0.001): du = distance / |dp/du|, the point
//! moved by du dp/du and u by du (LuxRender's generic `Texture::GetDuv`).

use glam::{Vec2, Vec3};

use crate::texture::ShadingPoint;

/// LuxRender's default `bumpmapsampledistance`.
pub const DEFAULT_SAMPLE_DISTANCE: f32 = 0.001;

/// A material's bump map: a node of the texture graph read as a float (the displacement in
/// world units) and the finite-difference step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BumpMap {
    pub height: usize,
    pub sample_distance: f32,
}

/// The bumped shading normal at `sp` (whose `n` is the unit normal to perturb) for the
/// surface's `dpdu`, `dpdv` and the displacement `height` evaluated at shading points.
pub fn bumped_normal(
    sp: &ShadingPoint,
    dpdu: Vec3,
    dpdv: Vec3,
    sample_distance: f32,
    height: impl Fn(&ShadingPoint) -> f32,
) -> Vec3 {
    let n = sp.n;
    // Tangents in the shading plane (an interpolated normal need not be perpendicular to the
    // true surface's dp/du, dp/dv): their components along n removed.
    let dpdu = dpdu - n * n.dot(dpdu);
    let dpdv = dpdv - n * n.dot(dpdv);
    let base = height(sp);
    let slope = |dpd: Vec3, duv: Vec2| {
        let step = sample_distance / dpd.length();
        if !(step.is_finite() && step > 0.0) {
            return 0.0;
        }
        let moved = ShadingPoint {
            p: sp.p + step * dpd,
            uv: sp.uv + step * duv,
            ..*sp
        };
        (height(&moved) - base) / step
    };
    let (dhdu, dhdv) = (slope(dpdu, Vec2::X), slope(dpdv, Vec2::Y));
    let bumped = (dpdu + dhdu * n).cross(dpdv + dhdv * n);
    match bumped.try_normalize() {
        Some(b) if b.dot(n) < 0.0 => -b,
        Some(b) => b,
        None => n,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(uv: Vec2) -> ShadingPoint {
        ShadingPoint {
            p: uv.extend(0.0),
            uv,
            n: Vec3::Z,
            object: 0,
        }
    }

    /// A ramp h = a u + b v on the plane z = 0 (p = (u, v, 0)): the displaced surface
    /// (u, v, a u + b v) has the normal (-a, -b, 1) / sqrt(1 + a^2 + b^2).
    #[test]
    fn a_ramp_tilts_the_normal_by_its_slope() {
        let (a, b) = (0.3, -0.7);
        let height = |sp: &ShadingPoint| a * sp.uv.x + b * sp.uv.y;
        let expected = Vec3::new(-a, -b, 1.0).normalize();
        let n = bumped_normal(&at(Vec2::new(0.4, 0.6)), Vec3::X, Vec3::Y, 1e-3, height);
        assert!((n - expected).length() < 1e-3, "{n} vs {expected}");
        // A left-handed parameterisation (dp/du, dp/dv swapped) gives the same surface and
        // normal: the flip keeps it on the side of the original.
        let n = bumped_normal(&at(Vec2::new(0.4, 0.6)), Vec3::Y, Vec3::X, 1e-3, |sp| {
            a * sp.uv.y + b * sp.uv.x
        });
        assert!((n - expected).length() < 1e-3, "{n} vs {expected}");
    }

    /// A constant displacement leaves the normal as it was.
    #[test]
    fn a_flat_height_keeps_the_normal() {
        let n = bumped_normal(&at(Vec2::ZERO), Vec3::X, 2.0 * Vec3::Y, 1e-3, |_| 0.25);
        assert_eq!(n, Vec3::Z);
    }
}
