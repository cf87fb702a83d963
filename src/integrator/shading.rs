//! What both shading stages share: the scene they read, a path's slots, its shadow ray.

use glam::Vec3;

use crate::bsdf::Bsdf;
use crate::light::LightTable;
use crate::material::MaterialTable;
use crate::material::texture::TextureTable;
use crate::math::offset_ray_origin;
use crate::sampling::PathRng;
use crate::shape::geometry::SceneGeometry;
use crate::shape::surface::SurfacePoint;

/// Chains of pass-through (null material) surfaces longer than this end the path.
pub const MAX_PASS_THROUGH: u32 = 64;

/// The read-only scene a shading stage sees.
pub struct Scene<'a> {
    pub geometry: &'a SceneGeometry,
    pub materials: &'a MaterialTable,
    pub textures: Option<&'a TextureTable>,
    pub lights: &'a LightTable,
    pub max_depth: u32,
}

/// One path's slots in the batch.
pub struct PathSlots<'a> {
    pub origin: &'a mut Vec3,
    pub direction: &'a mut Vec3,
    pub throughput: &'a mut Vec3,
    pub radiance: &'a mut Vec3,
    pub depth: &'a mut u32,
    pub pass_through: &'a mut u32,
    pub rng: &'a mut PathRng,
    pub scatter_pdf: &'a mut f32,
    pub alive: &'a mut bool,
}

impl PathSlots<'_> {
    /// Adds `light` to the path's radiance; a non-finite value (a bug, never a feature of the
    /// scene) is dropped rather than let through to the film.
    pub fn add_radiance(&mut self, light: Vec3) {
        if light.is_finite() {
            *self.radiance += light;
        }
    }

    /// Continues the ray straight through a null-material surface.
    pub fn pass_through(&mut self, surface: &SurfacePoint) {
        *self.origin =
            offset_ray_origin(surface.position, surface.geometric_normal, *self.direction);
        *self.pass_through += 1;
        if *self.pass_through > MAX_PASS_THROUGH {
            *self.alive = false;
        }
    }

    /// Follows `direction` from `surface` with the throughput scaled by `weight`.
    pub fn scatter(&mut self, surface: &SurfacePoint, direction: Vec3, weight: Vec3) {
        *self.throughput *= weight;
        *self.origin = offset_ray_origin(surface.position, surface.geometric_normal, direction);
        *self.direction = direction;
        *self.depth += 1;
        if !self.throughput.is_finite() || *self.throughput == Vec3::ZERO {
            *self.alive = false;
        }
    }
}

/// A shadow ray to test and the radiance it carries if unoccluded.
#[derive(Clone, Copy, Debug)]
pub struct ShadowRay {
    pub origin: Vec3,
    pub direction: Vec3,
    pub t_max: f32,
    pub contribution: Vec3,
}

impl ShadowRay {
    /// A ray from `surface` towards a light `distance` away along `wi`, stopping just short of it.
    pub fn towards(surface: &SurfacePoint, wi: Vec3, distance: f32, contribution: Vec3) -> Self {
        let origin = offset_ray_origin(surface.position, surface.geometric_normal, wi);
        // Stop short of the light's own surface (an emitter must not shadow itself).
        let t_max = distance * (1.0 - 1e-3);
        Self {
            origin,
            direction: wi,
            t_max,
            contribution,
        }
    }
}

/// Turns the surface's normals to face `wo` when the BSDF only reflects, so one-sided meshes
/// shade the same from both sides; a dielectric keeps them, as their side tells in from out.
pub fn face_forward(surface: &mut SurfacePoint, bsdf: &Bsdf, wo: Vec3) {
    let transmits = matches!(bsdf, Bsdf::Dielectric { .. });
    if !transmits && surface.geometric_normal.dot(wo) < 0.0 {
        surface.geometric_normal = -surface.geometric_normal;
        surface.shading_normal = -surface.shading_normal;
    }
}
