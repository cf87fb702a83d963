//! The ray caster's shading stage (Whitted 1980, as the course's first assignment asks): direct
//! light from every light with one shadow ray each, Lambert for matte surfaces and a normalised
//! Phong lobe for metals, and mirror reflection and refraction continuing the ray up to the
//! maximum depth. Area and environment lights take one sample per pass, so soft shadows
//! converge with the samples per pixel.

use std::f32::consts::PI;

use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};

use super::batch::{PathBatch, ShadowBatch};
use super::shading::{
    PathBlock, PathColumns, PathSlots, Scene, ShadingInputs, ShadowRay, face_forward,
    shade_live_blocks,
};
use crate::accel::Hit;
use crate::bsdf::Bsdf;
use crate::light::{Light, LightSample, LightTable};
use crate::shape::geometry::NO_EMITTER;
use crate::shape::surface::SurfacePoint;

/// The ray caster's first draws computed at the chunk's first bounce (`FirstDrawsTable`): the BSDF
/// choice, the one draw every shaded hit makes. A mirror's or glass's bounce and an area or
/// environment light's point, which fewer hits draw, are drawn where they are made (the same
/// values: the table's are the scalar draws bit for bit).
pub const DRAWS_AHEAD: u32 = 1;

/// The ray caster needs one shadow ray per light at each shaded point.
pub fn shadow_rays_per_path(lights: &LightTable) -> usize {
    lights.lights.len().max(1)
}

pub fn shade_raycast_hits(
    inputs: ShadingInputs,
    mut batch: ResMut<PathBatch>,
    mut shadows: ResMut<ShadowBatch>,
) {
    assert!(
        DRAWS_AHEAD <= inputs.draws_ahead(),
        "first draws not computed"
    );
    let scene = inputs.scene();
    shade_live_blocks(&inputs, &mut batch, &mut shadows, |mut block| {
        shade_block(&scene, &mut block);
    });
}

/// A path's shading point whose direct light is still to gather: its slot in the block, the
/// surface (normals facing the viewer), the lobe and the path's throughput.
struct LitPoint {
    path: usize,
    surface: SurfacePoint,
    lobe: Lobe,
    throughput: Vec3,
}

/// Shades a block in two passes: each live path's hit first (its surface and lobe, or its
/// end), then each light over all the block's shading points, so that the light's kind is
/// matched once per block, not once per point. A path draws its random numbers in the same
/// order as one shaded alone (its BSDF choice, then one 2D sample per area-like light in the
/// table's order), so the image is the same to the bit.
fn shade_block(scene: &Scene, block: &mut PathBlock) {
    let hits = block.hits;
    let mut lit = Vec::with_capacity(hits.len());
    for (i, hit) in hits.iter().enumerate() {
        if block.is_alive(i)
            && let Some((surface, lobe, throughput)) =
                shade_hit(scene, hit.as_ref(), block.paths.slots_reading(i))
        {
            lit.push(LitPoint {
                path: i,
                surface,
                lobe,
                throughput,
            });
        }
    }
    for (slot, light) in scene.lights.lights.iter().enumerate() {
        // A point light, the ray caster's usual one, gets its own loop with its sample inlined.
        match light {
            Light::Point(point) => gather(block, &lit, slot, |surface, _, _| {
                point.sample(surface.position)
            }),
            _ => gather(block, &lit, slot, |surface, paths, i| {
                // A point, spot or distant light has one direction to sample: no random
                // numbers drawn for it (the path ends here, so nothing later depends on the
                // stream's position).
                let u = if light.is_delta() {
                    Vec2::ZERO
                } else {
                    paths.slots_reading::<DRAWS_AHEAD>(i).rng.next_2d()
                };
                light.sample(surface.position, u)
            }),
        }
    }
}

/// One light's shadow rays in `slot` for each of the block's shading points: `sample` gives
/// the light's sample at a point (it may draw from the stream of the block's path `i`; the
/// path's slots are formed only then).
#[inline(always)]
fn gather(
    block: &mut PathBlock,
    lit: &[LitPoint],
    slot: usize,
    mut sample: impl FnMut(&SurfacePoint, &mut PathColumns, usize) -> Option<LightSample>,
) {
    for point in lit {
        let surface = &point.surface;
        let Some(sample) = sample(surface, &mut block.paths, point.path) else {
            continue;
        };
        let cos = sample.wi.dot(surface.shading_normal);
        if sample.pdf <= 0.0 || cos <= 0.0 || sample.wi.dot(surface.geometric_normal) <= 0.0 {
            continue;
        }
        let contribution =
            point.throughput * point.lobe.eval(sample.wi) * cos * sample.radiance / sample.pdf;
        if contribution.is_finite() && contribution != Vec3::ZERO {
            block.shadows.slots(point.path).emit(
                slot,
                ShadowRay::towards(surface, sample.wi, sample.distance, contribution),
            );
        }
    }
}

/// Shades one path's hit: light seen directly, a miss, a pass-through surface or a mirror or
/// glass bounce are settled here; a surface to light by the ray caster's lobes is returned
/// with its lobe and the path's throughput (the path ends there: its shadow rays carry the
/// rest).
fn shade_hit(
    scene: &Scene,
    hit: Option<&Hit>,
    mut path: PathSlots<'_, DRAWS_AHEAD>,
) -> Option<(SurfacePoint, Lobe, Vec3)> {
    let Some(hit) = hit else {
        if let Some((_, environment)) = scene.lights.environment() {
            path.add_radiance(*path.throughput * environment.radiance(*path.direction));
        }
        for (_, sun) in scene.lights.sun_discs() {
            path.add_radiance(*path.throughput * sun.radiance_towards(*path.direction));
        }
        *path.alive = false;
        return None;
    };
    let mut surface = scene
        .geometry
        .surface_point(hit, path.origin, path.direction);
    let wo = -*path.direction;
    if surface.emitter != NO_EMITTER
        && surface.geometric_normal.dot(wo) > 0.0
        && let Some((_, area)) = scene.lights.area_light(surface.emitter)
    {
        path.add_radiance(*path.throughput * area.radiance());
    }
    let mut built = None;
    let Some(bsdf) = scene.bsdf_at(&mut surface, &mut path.rng, &mut built) else {
        path.pass_through(&surface);
        return None;
    };
    let one_sided = scene.materials.is_one_sided(surface.material);
    if !face_forward(&mut surface, bsdf, wo, one_sided) {
        *path.alive = false;
        return None;
    }

    if bsdf.is_delta() {
        // Mirror and glass: follow the reflected or refracted ray (glass picks one by Fresnel).
        if *path.depth >= scene.max_depth {
            *path.alive = false;
            return None;
        }
        let frame = crate::bsdf::frame::Frame::from_z(surface.shading_normal);
        let (u_lobe, u_direction) = (path.rng.next_f32(), path.rng.next_2d());
        match bsdf.sample(frame.to_local(wo), u_direction, u_lobe) {
            Some(sample) if sample.pdf > 0.0 => {
                let wi = frame.to_world(sample.wi);
                path.scatter(&surface, wi, sample.f * sample.wi.z.abs() / sample.pdf);
            }
            _ => *path.alive = false,
        }
        return None;
    }

    let lobe = Lobe::new(bsdf, surface.shading_normal, wo);
    *path.alive = false;
    Some((surface, lobe, *path.throughput))
}

/// The ray caster's reflection models: Lambert, and for metals a normalised Phong lobe
/// (Lafortune & Willems 1994: (n + 2) / 2pi cos^n of the angle to the mirror direction) with
/// the exponent that matches the GGX alpha, n = 2 / alpha^2 - 2 (Walter et al. 2007). Prepared
/// once per shading point (the BSDF's dispatch, albedo and mirror direction), then evaluated
/// for each light.
enum Lobe {
    /// albedo / pi.
    Lambert(Vec3),
    Phong {
        /// albedo (n + 2) / 2pi.
        scale: Vec3,
        exponent: f32,
        mirror: Vec3,
    },
}

impl Lobe {
    fn new(bsdf: &Bsdf, normal: Vec3, wo: Vec3) -> Self {
        let alphas = match bsdf {
            Bsdf::Conductor {
                alpha_x, alpha_y, ..
            } => Some((*alpha_x, *alpha_y)),
            Bsdf::RoughConductor(c) => Some(c.distribution.alphas()),
            _ => None,
        };
        match alphas {
            Some((alpha_x, alpha_y)) => {
                let alpha = (alpha_x * alpha_y).sqrt().max(1e-3);
                let exponent = (2.0 / (alpha * alpha) - 2.0).max(1.0);
                Lobe::Phong {
                    scale: bsdf.albedo() * (exponent + 2.0) / (2.0 * PI),
                    exponent,
                    mirror: 2.0 * wo.dot(normal) * normal - wo,
                }
            }
            None => Lobe::Lambert(bsdf.albedo() / PI),
        }
    }

    /// The lobe's value towards the light direction `wi`.
    fn eval(&self, wi: Vec3) -> Vec3 {
        match *self {
            Lobe::Lambert(f) => f,
            Lobe::Phong {
                scale,
                exponent,
                mirror,
            } => scale * mirror.dot(wi).max(0.0).powf(exponent),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::microfacet_distribution::{DistributionKind, Masking, Microfacet};
    use crate::bsdf::{ConductorFresnel, RoughConductor};

    /// Every rough conductor gets the Phong lobe (LuxRender's `metal` and Mitsuba's conductors
    /// are `RoughConductor`s): far brighter towards the mirror direction than 60 degrees off it,
    /// where a Lambertian stand-in would be the same.
    #[test]
    fn rough_conductors_shade_with_the_phong_lobe() {
        let bsdf = Bsdf::RoughConductor(RoughConductor {
            reflectance: Vec3::ONE,
            fresnel: ConductorFresnel::Complex {
                eta: Vec3::splat(0.2),
                k: Vec3::splat(3.0),
            },
            distribution: Microfacet::new(DistributionKind::Beckmann, 0.1, 0.1),
            masking: Masking::Separable,
        });
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let mirror = Vec3::new(-0.6, 0.0, 0.8);
        let off = Vec3::new(0.3, 0.0, 1.0).normalize();
        let lobe = Lobe::new(&bsdf, Vec3::Z, wo);
        let towards = lobe.eval(mirror).x;
        let away = lobe.eval(off).x;
        assert!(towards > 100.0 * away, "{towards} vs {away}");
    }
}
