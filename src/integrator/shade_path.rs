//! The path tracer's shading stage: at each path vertex, emitted light (MIS-weighted against
//! light sampling), one light sample (next-event estimation), one BSDF sample for the next ray,
//! Russian roulette. Veach 1997 ch. 9 for the MIS, pbrt-v4 §13.4 for the structure.

use crate::math;
use bevy_ecs::prelude::*;
use glam::Vec3;

use super::batch::{PathBatch, ShadowBatch};
use super::conductor_lanes::ConductorQueue;
use super::diffuse_lanes::{
    DiffuseQueue, DiffuseVertex, LampPoint, LightPoint, SkyPoint, VertexLight,
};
use super::escaped_lanes::EscapedQueue;
use super::glass_lanes::{GlassQueue, GlassVertex};
use super::lanes::QueuedSurface;
use super::shading::{
    PathColumns, PathSlots, Scene, ShadingInputs, ShadowRay, face_forward, shade_live_blocks,
};
use crate::accel::Hit;
use crate::bsdf::{Bsdf, unit_direction};
use crate::light::infinite::{Environment, SkyLookup};
use crate::light::{EscapedLight, Light, LightTable};
use crate::sampling::warp::power_heuristic;
use crate::shape::geometry::NO_EMITTER;
use crate::shape::surface::SurfacePoint;

pub fn shade_path_vertices(
    inputs: ShadingInputs,
    mut batch: ResMut<PathBatch>,
    mut shadows: ResMut<ShadowBatch>,
) {
    let scene = inputs.scene();
    shade_live_blocks(&inputs, &mut batch, &mut shadows, |mut block| {
        // The block's diffuse, rough conductor and glass vertices and its rays that escaped
        // under an environment map wait in queues, in block order, and are finished eight at a
        // time; every other vertex is shaded where it stands. Each path's result depends on its
        // own slots only, so the order of the work changes no bit.
        let mut queues = Queues::default();
        let hits = block.hits;
        for (i, hit) in hits.iter().enumerate() {
            if !block.is_alive(i) {
                continue;
            }
            match hit {
                None => match scene.lights.escaped_light() {
                    EscapedLight::Uniform(radiance) => {
                        shade_uniform_miss(&scene, &mut block.paths.slots(i), radiance)
                    }
                    _ => shade_miss(&scene, &mut block.paths, &mut queues.escaped, i),
                },
                Some(hit) => {
                    if let Some(ray) = shade_vertex(&scene, hit, &mut block.paths, &mut queues, i) {
                        block.shadows.emit_first(i, ray);
                    }
                }
            }
            if queues.diffuse.is_full() {
                queues.diffuse.finish(&mut block.reborrow(), scene.rr_depth);
            }
            if queues.conductor.is_full() {
                queues
                    .conductor
                    .finish(&mut block.reborrow(), scene.rr_depth);
            }
            if queues.glass.is_full() {
                queues.glass.finish(&mut block.reborrow());
            }
            if queues.escaped.is_full() {
                queues.escaped.finish(&scene, &mut block.paths);
            }
        }
        queues.diffuse.finish(&mut block, scene.rr_depth);
        queues.conductor.finish(&mut block, scene.rr_depth);
        queues.glass.finish(&mut block);
        queues.escaped.finish(&scene, &mut block.paths);
    });
}

/// The vertices of a block waiting to be finished in lanes, by BSDF, and its escaped rays.
#[derive(Default)]
struct Queues<'a> {
    diffuse: DiffuseQueue<'a>,
    conductor: ConductorQueue<'a>,
    glass: GlassQueue,
    escaped: EscapedQueue,
}

/// Shades the vertex of the block's path `slot` (of `paths`) at `hit` where it stands
/// (returning its shadow ray, if any), or, at a Lambertian surface, an isotropic GGX conductor
/// or smooth glass, draws its random numbers (and light sample) and queues it in `queues`, for
/// [`DiffuseQueue::finish`], [`ConductorQueue::finish`] or [`GlassQueue::finish`] (a ray that
/// escaped is [`shade_miss`]'s). Kept out of
/// line: the build that LLVM inlined it into the block's loop (with a third queue; and
/// `finish_lanes` passed as a function, not a closure) took 3 to 4 % more instructions. Takes
/// the columns, not the path's slots: the loop stored the slots' eleven references to the
/// stack for each call.
#[inline(never)]
fn shade_vertex<'a>(
    scene: &Scene<'a>,
    hit: &Hit,
    paths: &mut PathColumns,
    queues: &mut Queues<'a>,
    slot: usize,
) -> Option<ShadowRay> {
    let mut path = paths.slots(slot);
    let lights = scene.lights;
    let hidden = hides_emitters(scene, &path);
    let mut surface = scene
        .geometry
        .surface_point(hit, path.origin, path.direction);
    let wo = -*path.direction;
    if hidden && surface.emitter != NO_EMITTER {
        *path.alive = false;
        return None;
    }

    if surface.emitter != NO_EMITTER
        && surface.geometric_normal.dot(wo) > 0.0
        && let Some((index, area)) = lights.area_light(surface.emitter)
    {
        // Light sampling would have sampled from the last scattering vertex, which is not the
        // ray's origin after a pass through a null surface.
        let weight = emission_weight(lights, (*path.scatter_pdf, path.vertex), index, || {
            area.pdf(*path.vertex, surface.position, surface.geometric_normal)
        });
        path.add_radiance(*path.throughput * area.radiance() * weight);
    }

    let mut built = None;
    let Some(bsdf) = scene.bsdf_at(&mut surface, &mut path.rng, &mut built) else {
        path.pass_through(&surface);
        return None;
    };
    if *path.depth >= scene.max_depth {
        *path.alive = false;
        return None;
    }
    let one_sided = scene.materials.is_one_sided(surface.material);
    if !face_forward(&mut surface, bsdf, wo, one_sided) {
        *path.alive = false;
        return None;
    }
    if let Bsdf::Lambertian { reflectance } = *bsdf {
        let vertex = queued_vertex(scene, &surface, reflectance, wo, &mut path);
        queues.diffuse.push(slot, vertex);
        return None;
    }
    if let Some(conductor) = bsdf.isotropic_ggx_conductor() {
        let vertex = queued_vertex(scene, &surface, conductor.reflectance, wo, &mut path);
        queues.conductor.push(slot, vertex, &conductor);
        return None;
    }
    if let Some(glass) = bsdf.smooth_glass() {
        // A delta BSDF: no light sample; the lobe's draw picks reflection or refraction, the
        // direction's is counted, not made.
        let u = path.rng.next_f32();
        path.rng.skip();
        queues.glass.push(
            slot,
            GlassVertex {
                surface: queued_surface(&surface, wo, &path),
                glass,
                u,
            },
        );
        return None;
    }
    shade_scattering(scene, &surface, bsdf, wo, path)
}

/// Mitsuba 3.9 with `hide_emitters` drops a camera path whose first surface (past null ones)
/// is an emitter, its reflection included, and one that leaves the scene unscattered.
#[inline(always)]
fn hides_emitters(scene: &Scene, path: &PathSlots) -> bool {
    scene.hide_emitters && *path.depth == 0
}

/// A path whose ray escaped under a constant sky (`radiance`): `shade_escaped`'s sum, with
/// its MIS weight of 1 left out. Inlined into the block's loop, a multiply-add of the
/// throughput and the radiance, where [`shade_miss`] is out of line.
#[inline(always)]
fn shade_uniform_miss(scene: &Scene, path: &mut PathSlots, radiance: Vec3) {
    if !hides_emitters(scene, path) {
        path.add_radiance(*path.throughput * radiance);
    }
    *path.alive = false;
}

/// The block's path `slot` (of `paths`), whose ray escaped: shaded where it stands, or queued
/// in `escaped` (for [`EscapedQueue::finish`]) under an environment map (the block's loop
/// shades those under a constant sky itself, [`shade_uniform_miss`]). Apart from
/// [`shade_vertex`], whose saves and restores of registers it does without: 1 % to 1.7 % fewer
/// instructions on the furnace, dof-sky, textured and envmap, where rays escape.
#[inline(never)]
fn shade_miss(scene: &Scene, paths: &mut PathColumns, escaped: &mut EscapedQueue, slot: usize) {
    let mut path = paths.slots(slot);
    let lights = scene.lights;
    let hidden = hides_emitters(scene, &path);
    match lights.escaped_light() {
        EscapedLight::Dark => *path.alive = false,
        EscapedLight::Uniform(radiance) => shade_uniform_miss(scene, &mut path, radiance),
        EscapedLight::Map if !hidden => escaped.push(slot, *path.direction),
        EscapedLight::Map | EscapedLight::SunDiscs => {
            let sky = lights
                .environment()
                .filter(|_| !hidden)
                .map(|(index, environment)| {
                    (index, environment, environment.look_up(*path.direction))
                });
            shade_escaped(lights, &mut path, sky, hidden);
        }
    }
}

/// A path whose ray escaped: the environment's light `sky` (its index, the light and its
/// lookup along the ray), then the sun discs' unless `hidden`, each MIS-weighted against
/// light sampling; the path ends.
#[inline(always)]
pub(super) fn shade_escaped(
    lights: &LightTable,
    path: &mut PathSlots,
    sky: Option<(usize, &Environment, SkyLookup)>,
    hidden: bool,
) {
    if let Some((index, environment, sky)) = sky {
        let from = (*path.scatter_pdf, &*path.vertex);
        let weight = emission_weight(lights, from, index, || environment.pdf_for_mis_of(&sky));
        path.add_radiance(*path.throughput * sky.radiance * weight);
    }
    for (index, sun) in lights.sun_discs().filter(|_| !hidden) {
        let light = sun.radiance_towards(*path.direction);
        if light != Vec3::ZERO {
            let from = (*path.scatter_pdf, &*path.vertex);
            let weight = emission_weight(lights, from, index, || sun.pdf());
            path.add_radiance(*path.throughput * light * weight);
        }
    }
    *path.alive = false;
}

/// The light sample and the BSDF sample at a scattering vertex, Russian roulette after.
fn shade_scattering(
    scene: &Scene,
    surface: &SurfacePoint,
    bsdf: &Bsdf,
    wo: Vec3,
    mut path: PathSlots,
) -> Option<ShadowRay> {
    let lights = scene.lights;
    let frame = scene.shading_frame(surface, bsdf);
    let wo_local = frame.to_local(wo);
    // Normalised once here for both the light sample's evaluation and the BSDF sample (each
    // normalised it before, to the same bits); a degenerate one ends the path as they did.
    let Some(wo_unit) = unit_direction(wo_local) else {
        *path.alive = false;
        return None;
    };

    // Next-event estimation: one light, chosen by power.
    let mut shadow = None;
    if !bsdf.is_delta() {
        let u_choose = path.rng.next_f32_if(lights.has_choice());
        let u_light = path.rng.next_2d();
        if let Some((index, probability)) = lights.choose(u_choose, surface.position) {
            shadow = lights.lights[index]
                .sample_for_mis(surface.position, u_light)
                .filter(|sample| sample.pdf > 0.0 && sample.radiance != Vec3::ZERO)
                .and_then(|sample| {
                    // Light on the other side of the true surface than the shading frame
                    // puts it would leak through it.
                    let wi_local = frame.to_local(sample.wi);
                    if sample.wi.dot(surface.geometric_normal) * wi_local.z <= 0.0 {
                        return None;
                    }
                    let (f, bsdf_pdf) = bsdf.eval_and_pdf_unit_wo(wo_unit, wi_local);
                    let f = f * wi_local.z.abs();
                    if f == Vec3::ZERO {
                        return None;
                    }
                    let light_pdf = probability * sample.pdf;
                    let weight = if sample.delta {
                        1.0
                    } else {
                        power_heuristic(1, light_pdf, 1, bsdf_pdf)
                    };
                    let contribution = *path.throughput * f * sample.radiance * weight / light_pdf;
                    math::is_finite_vec3(contribution).then(|| {
                        ShadowRay::towards(surface, sample.wi, sample.distance, contribution)
                    })
                });
        }
    }

    // The next ray, by BSDF sampling.
    let (u_lobe, u_direction) = (path.rng.next_f32(), path.rng.next_2d());
    let delta = match bsdf.sample_unit_wo(wo_unit, u_direction, u_lobe) {
        Some(sample) if sample.pdf > 0.0 => {
            let wi = frame.to_world(sample.wi);
            let reflects = sample.wi.z * wo_local.z > 0.0;
            // A reflection (or refraction) the shading normal allows but the true surface
            // does not.
            let stays = wi.dot(surface.geometric_normal) * wo.dot(surface.geometric_normal) > 0.0;
            if !sample.delta && reflects != stays {
                *path.alive = false;
                return shadow;
            }
            *path.scatter_pdf = if sample.delta { 0.0 } else { sample.pdf };
            path.scatter(surface, wi, sample.f * sample.wi.z.abs() / sample.pdf);
            sample.delta
        }
        _ => {
            *path.alive = false;
            return shadow;
        }
    };

    if !delta {
        russian_roulette(&mut path, scene.rr_depth);
    }
    shadow
}

/// The surface a queued vertex starts from: `surface`, the direction `wo` and the path's
/// throughput.
fn queued_surface(surface: &SurfacePoint, wo: Vec3, path: &PathSlots) -> QueuedSurface {
    QueuedSurface {
        position: surface.position,
        geometric_normal: surface.geometric_normal,
        shading_normal: surface.shading_normal,
        wo,
        throughput: *path.throughput,
    }
}

/// Whether [`shade_vertex`] queues a vertex with this BSDF for the diffuse or the conductor
/// kernels, which have one lobe: [`queued_vertex`] counts its lobe's draw without making it.
pub(super) fn draws_no_lobe(bsdf: &Bsdf) -> bool {
    matches!(bsdf, Bsdf::Lambertian { .. }) || bsdf.isotropic_ggx_conductor().is_some()
}

/// A queued vertex's random numbers and light sample, drawn in the order the scalar path draws
/// them (light choice, light point, lobe, direction; the choice where there is none to make,
/// and the lobe, which neither BSDF reads, counted and not made), for the lanes that finish it; a
/// rectangle lamp sampled by area is left for the kernel to sample, eight vertices at once, and
/// an environment map for the group's sample of it.
/// `reflectance`: the Lambertian's, or the factor on a conductor's lobe.
#[inline(always)]
fn queued_vertex<'a>(
    scene: &Scene<'a>,
    surface: &SurfacePoint,
    reflectance: Vec3,
    wo: Vec3,
    path: &mut PathSlots,
) -> DiffuseVertex<'a> {
    let lights = scene.lights;
    let u_choose = path.rng.next_f32_if(lights.has_choice());
    let u_light = path.rng.next_2d();
    let light = match lights.choose(u_choose, surface.position) {
        None => VertexLight::None,
        Some((index, probability)) => {
            let light = &lights.lights[index];
            let lamp = match light {
                Light::Area(area) => area.uniform_parallelogram().map(|lamp| (lamp, area)),
                _ => None,
            };
            if let Some((lamp, area)) = lamp {
                VertexLight::Lamp(LampPoint {
                    lamp,
                    radiance: area.radiance(),
                    probability,
                    u: u_light,
                })
            } else if let Light::Environment(environment) = light
                && !environment.is_constant()
            {
                VertexLight::Sky(SkyPoint {
                    environment,
                    probability,
                    u: u_light,
                })
            } else {
                let sample = light.sample_for_mis(surface.position, u_light);
                LightPoint::chosen(sample, probability)
                    .map_or(VertexLight::None, VertexLight::Point)
            }
        }
    };
    path.rng.skip();
    let u_direction = path.rng.next_2d();
    DiffuseVertex {
        surface: queued_surface(surface, wo, path),
        reflectance,
        light,
        u: u_direction,
    }
}

/// Russian roulette (pbrt-v4 §13.4.3): a path whose throughput (the product of the BSDF
/// weights f cos / pdf, each the surface's albedo in the sampled direction) fell to t < 1
/// survives with probability min(t, 0.95) and is reweighted by its inverse: unbiased, and a dim
/// path's expected cost falls with its contribution (Mitsuba 3's rule). Called only after a
/// non-delta bounce: the throughput inside a dielectric carries 1 / eta^2, which leaving
/// undoes, so a specular chain is judged where it ends. Always inline: called out of line
/// from the queues' write-back (as plain `#[inline]` left it), each path's slots were stored
/// to the stack for the call.
#[inline(always)]
pub fn russian_roulette(path: &mut PathSlots, rr_depth: u32) {
    let max_throughput = path.throughput.max_element();
    if *path.depth > rr_depth && max_throughput < 1.0 {
        let q = (1.0 - max_throughput).max(0.05);
        if path.rng.next_f32() < q {
            *path.alive = false;
        } else {
            *path.throughput /= 1.0 - q;
        }
    }
}

/// The MIS weight of light found by BSDF sampling, by a ray sampled with density `scatter_pdf`
/// from the scattering vertex `vertex`: 1 after a camera ray or a delta lobe (light sampling
/// could not have made it), else the power heuristic against light sampling from `vertex`.
fn emission_weight(
    lights: &LightTable,
    (scatter_pdf, vertex): (f32, &Vec3),
    light: usize,
    light_pdf: impl FnOnce() -> f32,
) -> f32 {
    if scatter_pdf <= 0.0 {
        return 1.0;
    }
    let light_pdf = lights.selection_probability(light, vertex) * light_pdf();
    power_heuristic(1, scatter_pdf, 1, light_pdf)
}
