//! Lambertian path vertices finished eight at a time: the shading frame, next-event
//! estimation's BSDF value, density and MIS weight, the cosine-weighted sample of the next
//! direction and the throughput update, with one lane per path.
//!
//! pbrt-v4 sorts a wavefront's hits into one queue per material kind and runs each kind's
//! kernel over its queue (`WavefrontPathIntegrator::EvaluateMaterialsAndBSDFs`); here a block of
//! paths queues its Lambertian vertices, in order, once their light sample and random numbers
//! are drawn (per path: they depend on the light and on the path's stream), and this module
//! finishes them in groups of [`LANES`]. The kernel is a loop over the lanes whose body has no
//! branches (both sides of each choice computed, one selected), so the compiler turns it into
//! eight-wide vector instructions; it is compiled a second time for AVX2 and picked at run time
//! ([`crate::accel::vex::run`]). Every lane performs the scalar path's operations in the same
//! order (IEEE sums, products, quotients and square roots, no fused multiply-add), so the
//! image is the same to the bit as one vertex at a time, at any width (tested).
//!
//! The queue, the lamps' lanes and next-event estimation's lanes serve the rough conductor's
//! vertices too ([`super::conductor_lanes`]), its kernel in the Lambertian's place
//! ([`DiffuseQueue::finish_with`]).

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::lanes::{
    F8, LANES, LaneFrame, M8, QueuedSurface, SurfaceLanes, V8, canonical, concentric_disk,
    offset_ray_origin, power_heuristic, unit_direction,
};
use super::shade_path::russian_roulette;
use super::shading::{PathBlock, PathSlots, ShadowRay};
use crate::accel::vex;
use crate::light::LightSample;
use crate::light::area::EmitterParallelogram;
use crate::light::infinite::Environment;

/// A light sample for a vertex: the direction and distance to the light point, its radiance
/// and the density of choosing it (light selection times the light's own density).
#[derive(Clone, Copy, Debug)]
pub struct LightPoint {
    pub wi: Vec3,
    pub distance: f32,
    pub radiance: Vec3,
    pub pdf: f32,
    /// A point or directional light: weight 1, no MIS.
    pub delta: bool,
}

impl LightPoint {
    /// A light's `sample`, the light chosen with `probability`: none unless it carries light
    /// (a positive density and radiance), and its density times the probability.
    pub fn chosen(sample: Option<LightSample>, probability: f32) -> Option<LightPoint> {
        sample
            .filter(|sample| sample.pdf > 0.0 && sample.radiance != Vec3::ZERO)
            .map(|sample| LightPoint {
                wi: sample.wi,
                distance: sample.distance,
                radiance: sample.radiance,
                pdf: probability * sample.pdf,
                delta: sample.delta,
            })
    }
}

/// A rectangle lamp chosen for a vertex, to be sampled uniformly by area in the kernel
/// ([`EmitterParallelogram::sample`] without its solid-angle case): the lamp, its radiance,
/// the probability of choosing it and the 2D sample for its point.
#[derive(Clone, Copy, Debug)]
pub struct LampPoint<'a> {
    pub lamp: &'a EmitterParallelogram,
    pub radiance: Vec3,
    pub probability: f32,
    pub u: Vec2,
}

/// An environment map chosen for a vertex, to be sampled with the group's other such vertices
/// ([`Environment::sample_for_mis_lanes`]): the light, the probability of choosing it and the
/// 2D sample for its direction.
#[derive(Clone, Copy, Debug)]
pub struct SkyPoint<'a> {
    pub environment: &'a Environment,
    pub probability: f32,
    pub u: Vec2,
}

/// A vertex's next-event estimation: no light sample, one drawn, or a lamp or an environment
/// map for the group to sample.
#[derive(Clone, Copy, Debug)]
pub enum VertexLight<'a> {
    None,
    Point(LightPoint),
    Lamp(LampPoint<'a>),
    Sky(SkyPoint<'a>),
}

/// What finishing a Lambertian vertex needs: the surface (normals turned to face `wo`), the
/// reflectance, the path's throughput, its light sample and its 2D sample for the direction.
#[derive(Clone, Copy, Debug)]
pub struct DiffuseVertex<'a> {
    pub surface: QueuedSurface,
    pub reflectance: Vec3,
    pub light: VertexLight<'a>,
    pub u: Vec2,
}

/// The light fields of a lane without a light sample.
const NO_LIGHT: LightPoint = LightPoint {
    wi: Vec3::Z,
    distance: 0.0,
    radiance: Vec3::ZERO,
    pdf: 1.0,
    delta: false,
};

/// The queued vertices, one lane each (structure of arrays).
#[derive(Clone, Copy, Default)]
pub(super) struct Inputs {
    pub(super) surface: SurfaceLanes,
    /// The Lambertian's reflectance, or the factor on a conductor's lobe.
    pub(super) reflectance: V8,
    /// The light sample's fields; `has_light` false where there is none (the other fields
    /// then hold harmless values). A lamp lane has none yet: its `light_radiance` is the
    /// lamp's and its `light_pdf` the probability of choosing it.
    pub(super) has_light: [bool; LANES],
    light_wi: V8,
    light_distance: F8,
    light_radiance: V8,
    light_pdf: F8,
    light_delta: [bool; LANES],
    /// The lanes whose lamp the kernel samples, the lamps and the 2D samples for their
    /// points (stale values elsewhere); `light_u` holds the sky lanes' samples too.
    lamp: [bool; LANES],
    lamp_corner: V8,
    lamp_edge1: V8,
    lamp_edge2: V8,
    lamp_normal: V8,
    lamp_area: F8,
    light_u: [F8; 2],
    /// The lanes whose environment map [`sample_sky`] samples.
    sky: [bool; LANES],
    pub(super) u: [F8; 2],
}

/// The kernel's results, one lane each.
#[derive(Clone, Copy, Default)]
pub(super) struct Outputs {
    /// A shadow ray, where the vertex's frame and `wo` were sound (else the path ends with
    /// nothing: no shadow ray, no next ray).
    pub(super) has_shadow: M8,
    pub(super) shadow_origin: V8,
    pub(super) shadow_direction: V8,
    pub(super) shadow_t_max: F8,
    pub(super) contribution: V8,
    /// Where the vertex was sound and the BSDF sample made a next ray (else the path ends,
    /// keeping its shadow ray).
    pub(super) next: NextRays,
    pub(super) pdf: F8,
}

/// The next rays a kernel made, one lane each: where `scattered`, the path goes on from
/// `origin` along `direction` with `throughput`; elsewhere it ends.
#[derive(Clone, Copy, Default)]
pub(super) struct NextRays {
    pub(super) scattered: M8,
    pub(super) throughput: V8,
    pub(super) origin: V8,
    pub(super) direction: V8,
}

impl NextRays {
    /// The lanes whose throughput is finite and not zero: [`PathSlots::continue_from`]'s test,
    /// eight at once, for [`NextRays::continue_path`].
    #[inline(always)]
    pub(super) fn carrying(&self) -> M8 {
        self.throughput.is_finite() & !self.throughput.is_zero()
    }

    /// Lane `lane`'s next ray into `path` from the vertex at `vertex` (`PathSlots::scatter`,
    /// with `scatter_pdf` for MIS), or the path's end; whether the path was scattered.
    /// `carrying`: [`NextRays::carrying`].
    #[inline(always)]
    pub(super) fn continue_path(
        &self,
        lane: usize,
        path: &mut PathSlots,
        vertex: Vec3,
        scatter_pdf: f32,
        carrying: M8,
    ) -> bool {
        if !self.scattered.lane(lane) {
            *path.alive = false;
            return false;
        }
        *path.scatter_pdf = scatter_pdf;
        path.continue_carrying(
            vertex,
            self.origin.get(lane),
            self.direction.get(lane),
            self.throughput.get(lane),
            carrying.lane(lane),
        );
        true
    }
}

/// A block's Lambertian vertices waiting to be finished, with their slots in the block (and,
/// inside a [`super::conductor_lanes::ConductorQueue`], its conductor vertices).
#[derive(Default)]
pub struct DiffuseQueue<'a> {
    len: usize,
    slots: [usize; LANES],
    inputs: Inputs,
    lamps: QueuedLamps<'a>,
    /// The lamp whose fields fill every lane's lamp fields, left by an earlier group's
    /// [`DiffuseQueue::fill_lamps`] (a group of the same lamp then writes none of them).
    filled_lamp: Option<&'a EmitterParallelogram>,
    /// The environment map of the queued sky lanes (a scene has one at most).
    sky: Option<&'a Environment>,
    /// Where the kernel writes, kept from group to group (the kernel sets every field it
    /// reads back; clearing them for each group cost a tenth of the write-back).
    outputs: Outputs,
}

/// The lamps of the queued lamp lanes. Most scenes have one lamp, so its fields are written
/// once per group, into every lane, when the group is finished ([`DiffuseQueue::fill_lamps`]),
/// not at each push: 13 stores a vertex.
#[derive(Clone, Copy, Default)]
enum QueuedLamps<'a> {
    #[default]
    None,
    /// All lamp lanes so far have this lamp; no lane's lamp fields are written yet.
    Shared(&'a EmitterParallelogram),
    /// Two lamps or more: each lamp lane's fields are written.
    Mixed,
}

/// Which of the group's samplers draws a lane's light sample: [`sample_lamps`] in the kernel,
/// or [`sample_sky`] for the group before it.
#[derive(Clone, Copy, PartialEq, Eq)]
enum GroupLight {
    Lamp,
    Sky,
}

impl Inputs {
    /// Lane `lane`'s light sample, `light` (`has_light` false: none, `light` harmless values).
    #[inline(always)]
    fn set_light(&mut self, lane: usize, has_light: bool, light: &LightPoint) {
        self.set_light_but_ray(lane, has_light, None, light);
        self.light_wi.set(lane, light.wi);
        self.light_distance.0[lane] = light.distance;
    }

    /// Lane `lane`'s light fields but the direction and distance to the light: all of them a
    /// lamp or sky lane (`sampled_by` the kernel's lamp or the group's sky) has before
    /// [`sample_lamps`] or [`sample_sky`] samples its light, which writes those two.
    #[inline(always)]
    fn set_light_but_ray(
        &mut self,
        lane: usize,
        has_light: bool,
        sampled_by: Option<GroupLight>,
        light: &LightPoint,
    ) {
        self.has_light[lane] = has_light;
        self.lamp[lane] = sampled_by == Some(GroupLight::Lamp);
        self.sky[lane] = sampled_by == Some(GroupLight::Sky);
        self.light_radiance.set(lane, light.radiance);
        self.light_pdf.0[lane] = light.pdf;
        self.light_delta[lane] = light.delta;
    }

    /// Lane `lane`'s lamp fields.
    #[inline(always)]
    fn set_lamp(&mut self, lane: usize, lamp: &EmitterParallelogram) {
        self.lamp_corner.set(lane, lamp.corner);
        self.lamp_edge1.set(lane, lamp.edge1);
        self.lamp_edge2.set(lane, lamp.edge2);
        self.lamp_normal.set(lane, lamp.normal);
        self.lamp_area.0[lane] = lamp.area;
    }
}

impl<'a> DiffuseQueue<'a> {
    pub fn is_full(&self) -> bool {
        self.len == LANES
    }

    /// The number of queued vertices (the next one's lane).
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// Queues the vertex of the block's path `slot`.
    #[inline(always)]
    pub fn push(&mut self, slot: usize, vertex: DiffuseVertex<'a>) {
        let (lane, inputs) = (self.len, &mut self.inputs);
        self.slots[lane] = slot;
        inputs.surface.set(lane, &vertex.surface);
        inputs.reflectance.set(lane, vertex.reflectance);
        match vertex.light {
            VertexLight::Point(light) => inputs.set_light(lane, true, &light),
            VertexLight::None => inputs.set_light(lane, false, &NO_LIGHT),
            VertexLight::Lamp(lamp) => {
                match self.lamps {
                    QueuedLamps::None => self.lamps = QueuedLamps::Shared(lamp.lamp),
                    QueuedLamps::Shared(shared) if std::ptr::eq(shared, lamp.lamp) => {}
                    QueuedLamps::Shared(shared) => {
                        // A second lamp: the lamp lanes queued so far get the first one's
                        // fields now.
                        self.filled_lamp = None;
                        for earlier in 0..lane {
                            if inputs.lamp[earlier] {
                                inputs.set_lamp(earlier, shared);
                            }
                        }
                        inputs.set_lamp(lane, lamp.lamp);
                        self.lamps = QueuedLamps::Mixed;
                    }
                    QueuedLamps::Mixed => {
                        self.filled_lamp = None;
                        inputs.set_lamp(lane, lamp.lamp);
                    }
                }
                inputs.light_u[0].0[lane] = lamp.u.x;
                inputs.light_u[1].0[lane] = lamp.u.y;
                // No light sample yet; the density is the probability of choosing the lamp,
                // which `sample_lamps` multiplies by its point's.
                let light = LightPoint {
                    radiance: lamp.radiance,
                    pdf: lamp.probability,
                    ..NO_LIGHT
                };
                inputs.set_light_but_ray(lane, false, Some(GroupLight::Lamp), &light);
            }
            VertexLight::Sky(sky) => {
                self.sky = Some(sky.environment);
                inputs.light_u[0].0[lane] = sky.u.x;
                inputs.light_u[1].0[lane] = sky.u.y;
                // The density is the probability of choosing the sky, as for a lamp.
                let light = LightPoint {
                    pdf: sky.probability,
                    ..NO_LIGHT
                };
                inputs.set_light_but_ray(lane, false, Some(GroupLight::Sky), &light);
            }
        }
        inputs.u[0].0[lane] = vertex.u.x;
        inputs.u[1].0[lane] = vertex.u.y;
        self.len += 1;
    }

    /// Finishes the queued vertices into their paths' slots in `block` (shadow ray, next ray,
    /// Russian roulette after `rr_depth` bounces) and empties the queue. Lanes past the
    /// queue's length compute on stale inputs and are not read.
    pub fn finish(&mut self, block: &mut PathBlock, rr_depth: u32) {
        // A closure forced inline, as `run_kernels`' are (not the function through `FnOnce`'s
        // shim), so that both compilations of `vex::run` hold the kernel.
        #[allow(clippy::redundant_closure)]
        self.finish_with(
            block,
            rr_depth,
            #[inline(always)]
            |inputs, out| finish_lanes(inputs, out),
        );
    }

    /// [`DiffuseQueue::finish`] with the BSDF's lanes `bsdf_lanes` in place of the
    /// Lambertian's: they write the lanes' shadow rays and next rays from the inputs (lamps
    /// sampled already), as [`finish_lanes`] does. Must be `#[inline(always)]`, for
    /// [`vex::run`].
    pub(super) fn finish_with(
        &mut self,
        block: &mut PathBlock,
        rr_depth: u32,
        bsdf_lanes: impl FnOnce(&Inputs, &mut Outputs),
    ) {
        self.fill_lamps();
        self.sample_sky();
        let out = &mut self.outputs;
        run_kernels(&mut self.inputs, out, bsdf_lanes);
        let carrying = out.next.carrying();
        let mut shadows = block.shadows.cut_to_one_length();
        for (lane, &slot) in self.slots[..self.len].iter().enumerate() {
            if out.has_shadow.lane(lane) {
                shadows.emit_first(
                    slot,
                    ShadowRay {
                        origin: out.shadow_origin.get(lane),
                        direction: out.shadow_direction.get(lane),
                        t_max: out.shadow_t_max.0[lane],
                        contribution: out.contribution.get(lane),
                    },
                );
            }
            let mut path = block.paths.slots(slot);
            let vertex = self.inputs.surface.position.get(lane);
            if out
                .next
                .continue_path(lane, &mut path, vertex, out.pdf.0[lane], carrying)
            {
                russian_roulette(&mut path, rr_depth);
            }
        }
        self.len = 0;
    }

    /// Writes the shared lamp's fields into every lane (those of lanes without a lamp are not
    /// read), unless they hold them already, and starts the next group's record of lamps.
    fn fill_lamps(&mut self) {
        if let QueuedLamps::Shared(lamp) = self.lamps
            && !self
                .filled_lamp
                .is_some_and(|filled| std::ptr::eq(filled, lamp))
        {
            let inputs = &mut self.inputs;
            inputs.lamp_corner = V8::splat(lamp.corner);
            inputs.lamp_edge1 = V8::splat(lamp.edge1);
            inputs.lamp_edge2 = V8::splat(lamp.edge2);
            inputs.lamp_normal = V8::splat(lamp.normal);
            inputs.lamp_area = F8::splat(lamp.area);
            self.filled_lamp = Some(lamp);
        }
        self.lamps = QueuedLamps::None;
    }
}

/// [`sample_lamps`] where a lane has a lamp, then the BSDF's lanes (such as [`finish_lanes`]),
/// each compiled for AVX2 where the CPU has it: as one kernel they were too large for the
/// compiler to inline into `vex::run`'s AVX2 version, and ran as baseline code in twice the
/// instructions.
fn run_kernels(
    inputs: &mut Inputs,
    out: &mut Outputs,
    bsdf_lanes: impl FnOnce(&Inputs, &mut Outputs),
) {
    // The closures are forced inline, so that both compilations of `vex::run` hold the lanes'
    // code: left to LLVM, a closure was once compiled out of line for the baseline only.
    if inputs.lamp.contains(&true) {
        vex::run(
            #[inline(always)]
            || sample_lamps(inputs),
        );
    }
    vex::run(
        #[inline(always)]
        || bsdf_lanes(inputs, out),
    );
}

/// The lanes of [`DiffuseQueue::finish`]: for each, the operations of `shade_scattering` on a
/// `Bsdf::Lambertian` (and of the functions it calls, named at each step) in their order, both
/// sides of each branch computed and one selected (lamps sampled already). Inlined into both
/// compilations of [`vex::run`].
#[inline(always)]
fn finish_lanes(inputs: &Inputs, out: &mut Outputs) {
    let (n, wo) = (inputs.surface.shading_normal, inputs.surface.wo);
    let zero = F8::splat(0.0);
    let frame = LaneFrame::from_z(n);
    let wo_local = frame.to_local(wo);
    let (wo_unit, sound) = unit_direction(wo_local);
    // `Lambertian::eval`: R / pi where both directions are above the surface.
    let above = |wi_z: F8| wo_unit.z.gt(zero) & wi_z.gt(zero);
    let f_lambert = inputs.reflectance.scale(F8::splat(FRAC_1_PI));

    // Next-event estimation (`Bsdf::eval_and_pdf_unit_wo`, `finite_or_zero`,
    // `density_or_zero`), unless no lane has a light sample (a scene lit by a constant sky
    // alone); `has_shadow` is then false.
    if inputs.has_light.contains(&true) {
        let eval = |wi_unit: V8, wi_sound: M8| {
            let lit = wi_sound & above(wi_unit.z);
            let f = (lit & f_lambert.is_finite()).select_v(f_lambert, V8::default());
            let pdf = wi_unit.z.max(zero) * FRAC_1_PI;
            (f, (lit & pdf.is_positive_finite()).select(pdf, zero))
        };
        light_lanes(inputs, out, &frame, eval);
        out.has_shadow = out.has_shadow & sound;
    } else {
        out.has_shadow = M8::default();
    }

    // The next ray (`Bsdf::sample_unit_wo`: `canonical`, `sample_cosine_lobe`,
    // `cosine_hemisphere`, `concentric_disk`).
    let (dx, dy) = concentric_disk(inputs.u.map(canonical));
    let s = V8 {
        x: dx,
        y: dy,
        z: (1.0 - (dx * dx + dy * dy)).max(zero).sqrt(),
    };
    let sample_above = above(s.z);
    let sample_f = sample_above.select_v(f_lambert, V8::default());
    let sample_pdf = sample_above.select(s.z.max(zero) * FRAC_1_PI, zero);
    let sampled_ok = wo_unit.z.gt(zero) & sample_pdf.gt(zero) & sample_f.is_finite();
    let wi = frame.to_world(s);
    let sampled = Sampled {
        wi_local_z: s.z,
        wi,
        f: sample_f,
        pdf: sample_pdf,
    };
    scatter_lanes(inputs, out, wo_local.z, sound & sampled_ok, sampled);
}

/// A BSDF sample in lanes: its direction's local z and world direction, value and density.
pub(super) struct Sampled {
    pub(super) wi_local_z: F8,
    pub(super) wi: V8,
    pub(super) f: V8,
    pub(super) pdf: F8,
}

/// `PathSlots::scatter`'s values for the `accepted` lanes' sample (`shade_scattering`'s
/// checks passed): the path goes on only where `wi` leaves on the side of the geometric
/// surface that the shading frame says (a reflection stays, a transmission crosses), carrying
/// throughput f |cos θi| / pdf from an origin offset off the surface.
#[inline(always)]
pub(super) fn scatter_lanes(
    inputs: &Inputs,
    out: &mut Outputs,
    wo_local_z: F8,
    accepted: M8,
    sample: Sampled,
) {
    let zero = F8::splat(0.0);
    let (ng, wo) = (inputs.surface.geometric_normal, inputs.surface.wo);
    let Sampled {
        wi_local_z,
        wi,
        f,
        pdf,
    } = sample;
    let reflects = (wi_local_z * wo_local_z).gt(zero);
    let stays = (wi.dot(ng) * wo.dot(ng)).gt(zero);
    out.next.scattered = accepted & reflects.eq(stays);
    out.pdf = pdf;
    let cos = wi_local_z.abs();
    out.next.throughput = inputs.surface.throughput.mul(V8 {
        x: f.x * cos / pdf,
        y: f.y * cos / pdf,
        z: f.z * cos / pdf,
    });
    out.next.origin = offset_ray_origin(inputs.surface.position, ng, wi);
    out.next.direction = wi;
}

/// The lamp lanes' light samples, written where the queued ones are: [`EmitterParallelogram::sample`]
/// by area (`sample_towards`) with `diffuse_vertex`'s checks of its density and radiance, in
/// their order.
#[inline(always)]
fn sample_lamps(inputs: &mut Inputs) {
    let zero = F8::splat(0.0);
    let (p, corner, normal) = (
        inputs.surface.position,
        inputs.lamp_corner,
        inputs.lamp_normal,
    );
    let (e1, e2, [ux, uy]) = (inputs.lamp_edge1, inputs.lamp_edge2, inputs.light_u);
    let lit = !(p - corner).dot(normal).le(zero);
    let point = V8 {
        x: corner.x + e1.x * ux + e2.x * uy,
        y: corner.y + e1.y * ux + e2.y * uy,
        z: corner.z + e1.z * ux + e2.z * uy,
    };
    let to_light = point - p;
    let distance = to_light.dot(to_light).sqrt();
    let wi = V8 {
        x: to_light.x / distance,
        y: to_light.y / distance,
        z: to_light.z / distance,
    };
    let cos_light = -wi.dot(normal);
    let pdf = distance * distance / (cos_light * inputs.lamp_area);
    let sampled = lit
        & !distance.le(zero)
        & !cos_light.le(zero)
        & pdf.gt(zero)
        & !inputs.light_radiance.is_zero();
    let lamp = M8::from(inputs.lamp);
    for (lane, has_light) in inputs.has_light.iter_mut().enumerate() {
        *has_light |= lamp.lane(lane) && sampled.lane(lane);
    }
    inputs.light_wi = lamp.select_v(wi, inputs.light_wi);
    inputs.light_distance = lamp.select(distance, inputs.light_distance);
    // `probability * sample.pdf`.
    inputs.light_pdf = lamp.select(inputs.light_pdf * pdf, inputs.light_pdf);
}

impl DiffuseQueue<'_> {
    /// The sky lanes' light samples, if there are any ([`sample_sky`]).
    fn sample_sky(&mut self) {
        if let Some(environment) = self.sky
            && self.inputs.sky.contains(&true)
        {
            sample_sky(&mut self.inputs, environment);
        }
    }
}

/// The sky lanes' light samples, written where the queued ones are: the environment map's
/// [`Environment::sample_for_mis_lanes`] with `queued_vertex`'s checks of the density and the
/// radiance, and the density times the probability of choosing the sky, in their order.
fn sample_sky(inputs: &mut Inputs, environment: &Environment) {
    let samples = environment.sample_for_mis_lanes(&inputs.light_u.map(|u| u.0));
    let lanes = |axes: [[f32; LANES]; 3]| V8 {
        x: F8(axes[0]),
        y: F8(axes[1]),
        z: F8(axes[2]),
    };
    let (wi, radiance, pdf) = (lanes(samples.wi), lanes(samples.radiance), F8(samples.pdf));
    let sampled = M8::from(samples.sampled) & pdf.gt(F8::splat(0.0)) & !radiance.is_zero();
    let sky = M8::from(inputs.sky);
    for (lane, has_light) in inputs.has_light.iter_mut().enumerate() {
        *has_light |= sky.lane(lane) && sampled.lane(lane);
    }
    inputs.light_wi = sky.select_v(wi, inputs.light_wi);
    inputs.light_distance = sky.select(F8::splat(f32::INFINITY), inputs.light_distance);
    inputs.light_radiance = sky.select_v(radiance, inputs.light_radiance);
    // `probability * sample.pdf`.
    inputs.light_pdf = sky.select(inputs.light_pdf * pdf, inputs.light_pdf);
}

/// Next-event estimation's lanes (`Bsdf::eval_and_pdf_unit_wo`, `finite_or_zero`,
/// `density_or_zero`, the power heuristic, `ShadowRay::towards`).
/// `eval` gives the BSDF's value and density (`Bsdf::eval_and_pdf_unit_wo`) at the unit
/// `wi_local` where `wi_sound` holds, zeros elsewhere.
#[inline(always)]
pub(super) fn light_lanes(
    inputs: &Inputs,
    out: &mut Outputs,
    frame: &LaneFrame,
    eval: impl FnOnce(V8, M8) -> (V8, F8),
) {
    let (ng, p) = (inputs.surface.geometric_normal, inputs.surface.position);
    let zero = F8::splat(0.0);
    let wi = inputs.light_wi;
    let wi_local = frame.to_local(wi);
    let leaks = (wi.dot(ng) * wi_local.z).le(zero);
    let (wi_unit, wi_sound) = unit_direction(wi_local);
    let (f, bsdf_pdf) = eval(wi_unit, wi_sound);
    let f = f.scale(wi_local.z.abs());
    let light_pdf = inputs.light_pdf;
    let weight =
        M8::from(inputs.light_delta).select(F8::splat(1.0), power_heuristic(light_pdf, bsdf_pdf));
    let contribution = inputs
        .surface
        .throughput
        .mul(f)
        .mul(inputs.light_radiance)
        .scale(weight);
    let contribution = V8 {
        x: contribution.x / light_pdf,
        y: contribution.y / light_pdf,
        z: contribution.z / light_pdf,
    };
    out.has_shadow = M8::from(inputs.has_light) & !leaks & !f.is_zero() & contribution.is_finite();
    out.contribution = contribution;
    // `ShadowRay::towards`.
    out.shadow_origin = offset_ray_origin(p, ng, wi);
    out.shadow_direction = wi;
    out.shadow_t_max = inputs.light_distance * (1.0 - 1e-3);
}

#[cfg(test)]
pub(super) mod tests {
    use glam::{Vec2, Vec3};

    use super::*;
    use crate::bsdf::frame::Frame;
    use crate::bsdf::{Bsdf, unit_direction};
    use crate::light::infinite::InfiniteLight;
    use crate::material::texture::ImageTexture;
    use crate::math::offset_ray_origin;
    use crate::sampling::PathRng;
    use crate::sampling::warp::{power_heuristic, uniform_sphere};

    /// Lamps around the origin, of random corners, edges and radiance (one black).
    fn random_lamps(rng: &mut PathRng) -> Vec<EmitterParallelogram> {
        let mut point =
            |scale: f32| scale * (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5);
        (0..5)
            .map(|_| {
                let (corner, edge1, edge2) = (point(20.0), point(4.0), point(4.0));
                EmitterParallelogram {
                    corner,
                    edge1,
                    edge2,
                    normal: edge1.cross(edge2).normalize(),
                    area: edge1.cross(edge2).length(),
                    rectangle: None,
                }
            })
            .collect()
    }

    /// A vertex with random normals, directions, light and sample, and now and then what the
    /// scalar path treats as a special case: no light, a delta light, a lamp (seen from
    /// either side), a zero or tiny `wo`, the disk's centre, a NaN or out-of-range sample.
    /// A sky of distinct texels (some black), rotated.
    fn test_sky() -> Environment {
        let (w, h) = (32, 16);
        let texels = (0..w * h)
            .map(|i| {
                let v = ((i * 7919) % 13) as f32;
                Vec3::new(if v < 3.0 { 0.0 } else { v }, (i % w) as f32, 1.0)
            })
            .collect();
        Environment::new(&InfiniteLight {
            radiance: Vec3::new(1.5, 1.0, 0.5),
            map: Some(ImageTexture {
                width: w as u32,
                height: h as u32,
                texels: std::sync::Arc::new(texels),
                scale: Vec2::ONE,
                delta: Vec2::ZERO,
                wrap: Default::default(),
            }),
            light_to_world: glam::Mat3::from_rotation_y(0.6) * glam::Mat3::from_rotation_x(0.3),
        })
    }

    fn random_vertex<'a>(
        rng: &mut PathRng,
        i: usize,
        lamps: &'a [EmitterParallelogram],
        sky: &'a Environment,
    ) -> DiffuseVertex<'a> {
        let n = uniform_sphere(rng.next_2d());
        let geometric_normal = (n + 0.4 * uniform_sphere(rng.next_2d())).normalize();
        let wo = match i % 13 {
            0 => Vec3::ZERO,
            // Its squared length underflows to zero: normalising gives infinities, not NaNs.
            6 => uniform_sphere(rng.next_2d()) * 1e-25,
            _ => uniform_sphere(rng.next_2d()) * (0.5 + rng.next_f32()),
        };
        let radiance = Vec3::new(rng.next_f32(), rng.next_f32(), 2.0 * rng.next_f32());
        let light = match i % 5 {
            0 => VertexLight::None,
            // Odd groups' lamp lanes have one lamp, even groups' two (kept apart in the queue).
            1 | 2 => VertexLight::Lamp(LampPoint {
                lamp: &lamps[if (i / LANES) % 2 == 1 {
                    (i / LANES) % lamps.len()
                } else {
                    i % lamps.len()
                }],
                radiance: if i % 11 == 1 { Vec3::ZERO } else { radiance },
                probability: rng.next_f32(),
                u: rng.next_2d(),
            }),
            4 if i % 10 == 4 => VertexLight::Sky(SkyPoint {
                environment: sky,
                probability: rng.next_f32(),
                u: rng.next_2d(),
            }),
            _ => VertexLight::Point(LightPoint {
                wi: uniform_sphere(rng.next_2d()),
                distance: 10.0 * rng.next_f32(),
                radiance,
                pdf: 2.0 * rng.next_f32(),
                delta: i.is_multiple_of(7),
            }),
        };
        let u = match i % 17 {
            0 => Vec2::splat(0.5),
            1 => Vec2::new(f32::NAN, 1.0),
            2 => Vec2::new(-0.25, 0.75),
            _ => rng.next_2d(),
        };
        let position = 20.0 * (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5);
        let reflectance = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        DiffuseVertex {
            surface: QueuedSurface {
                position,
                geometric_normal,
                shading_normal: n,
                wo,
                throughput: Vec3::new(rng.next_f32(), 1.0, 3.0 * rng.next_f32()),
            },
            reflectance,
            light,
            u,
        }
    }

    fn bits(v: Vec3) -> [u32; 3] {
        v.to_array().map(f32::to_bits)
    }

    /// A vertex's light sample as the scalar path draws it: `diffuse_vertex` with the lamp's
    /// `EmitterParallelogram::sample`.
    fn scalar_light(vertex: &DiffuseVertex) -> Option<LightPoint> {
        match vertex.light {
            VertexLight::None => None,
            VertexLight::Point(light) => Some(light),
            VertexLight::Lamp(lamp) => LightPoint::chosen(
                (lamp.lamp).sample(vertex.surface.position, lamp.u, lamp.radiance),
                lamp.probability,
            ),
            VertexLight::Sky(sky) => {
                LightPoint::chosen(sky.environment.sample_for_mis(sky.u), sky.probability)
            }
        }
    }

    /// The scalar path's operations on one Lambertian vertex (as `shade_scattering` does them)
    /// against the lanes, bit for bit, in both compilations of the kernel.
    #[test]
    fn lanes_match_the_scalar_vertex_bit_for_bit() {
        let [shadows, lamp_shadows, scattered, unsound] = assert_lanes_match_scalar(
            |_, vertex| Bsdf::Lambertian {
                reflectance: vertex.reflectance,
            },
            |vertices, _| {
                let mut queue = DiffuseQueue::default();
                for (lane, vertex) in vertices.iter().enumerate() {
                    queue.push(lane, *vertex);
                }
                queue.kernel_outputs(finish_lanes)
            },
        );
        // Both outcomes common, so the comparisons were exercised.
        assert!(
            shadows > 1000 && lamp_shadows > 300 && scattered > 1000 && unsound > 100,
            "{shadows} {lamp_shadows} {scattered} {unsound}"
        );
    }

    /// A queue kept from group to group (as a block's is) finishes each group as a new queue
    /// does, whatever lamps the groups before it had: the lamp fields that a group of one lamp
    /// leaves in every lane (and a later group of the same lamp reuses) are written again
    /// after a group of two lamps has overwritten some lanes' with the second lamp's.
    #[test]
    fn a_kept_queue_finishes_groups_as_a_new_one_does() {
        let mut rng = PathRng::new(10, 0, 0);
        let lamps = random_lamps(&mut rng);
        let sky = test_sky();
        // Each group's lamp per lane: one lamp, two, the first alone again, then the second;
        // sixteen times.
        let groups = [[0; LANES], [0, 1, 0, 1, 0, 1, 0, 1], [0; LANES], [1; LANES]];
        let mut kept = DiffuseQueue::default();
        let mut lamp_shadows = 0;
        for group in groups.into_iter().cycle().take(16 * groups.len()) {
            let vertices: Vec<DiffuseVertex> = (group.iter())
                .map(|&lamp| DiffuseVertex {
                    light: VertexLight::Lamp(LampPoint {
                        lamp: &lamps[lamp],
                        radiance: Vec3::ONE,
                        probability: 0.5,
                        u: rng.next_2d(),
                    }),
                    ..random_vertex(&mut rng, 3, &lamps, &sky)
                })
                .collect();
            let mut new = DiffuseQueue::default();
            for (lane, vertex) in vertices.iter().enumerate() {
                kept.push(lane, *vertex);
                new.push(lane, *vertex);
            }
            let [from_kept, _] = kept.kernel_outputs(finish_lanes);
            let [from_new, _] = new.kernel_outputs(finish_lanes);
            kept.len = 0;
            assert_eq!(from_kept.has_shadow, from_new.has_shadow);
            for lane in (0..LANES).filter(|&lane| from_new.has_shadow.lane(lane)) {
                let out = [&from_kept, &from_new].map(|out| {
                    (
                        bits(out.shadow_direction.get(lane)),
                        bits(out.contribution.get(lane)),
                        out.shadow_t_max.0[lane].to_bits(),
                    )
                });
                assert_eq!(out[0], out[1], "lane {lane}");
                lamp_shadows += 1;
            }
        }
        assert!(lamp_shadows > 24, "{lamp_shadows}");
    }

    impl DiffuseQueue<'_> {
        /// The queued group's outputs from `bsdf_lanes` (after the lamps' lanes) compiled for
        /// the baseline, and as [`DiffuseQueue::finish_with`] runs them.
        pub(in crate::integrator) fn kernel_outputs(
            &mut self,
            bsdf_lanes: impl Fn(&Inputs, &mut Outputs),
        ) -> [Outputs; 2] {
            let (mut baseline, mut dispatched) = (Outputs::default(), Outputs::default());
            self.fill_lamps();
            self.sample_sky();
            let mut inputs = self.inputs;
            sample_lamps(&mut inputs);
            bsdf_lanes(&inputs, &mut baseline);
            run_kernels(&mut self.inputs, &mut dispatched, &bsdf_lanes);
            [baseline, dispatched]
        }
    }

    /// Groups of random vertices (`random_vertex`), each given its BSDF by `bsdf_of` (which
    /// may set the vertex's reflectance to match), finished by `lanes` (the baseline and the
    /// dispatched outputs, [`DiffuseQueue::kernel_outputs`]), against the scalar path's
    /// operations on each vertex (as `shade_scattering` does them), bit for bit. Returns the
    /// counts of shadow rays, of those from lamps, of next rays and of unsound vertices.
    pub(in crate::integrator) fn assert_lanes_match_scalar(
        mut bsdf_of: impl FnMut(&mut PathRng, &mut DiffuseVertex) -> Bsdf,
        mut lanes: impl FnMut(&[DiffuseVertex], &[Bsdf]) -> [Outputs; 2],
    ) -> [usize; 4] {
        let mut rng = PathRng::new(8, 0, 0);
        let lamps = random_lamps(&mut rng);
        let sky = test_sky();
        let (mut shadows, mut lamp_shadows, mut scattered, mut unsound) = (0, 0, 0, 0);
        let mut sky_shadows = 0;
        for group in 0..1000 {
            let mut vertices: Vec<DiffuseVertex> = (0..LANES)
                .map(|lane| random_vertex(&mut rng, group * LANES + lane, &lamps, &sky))
                .collect();
            let bsdfs: Vec<Bsdf> = (vertices.iter_mut())
                .map(|vertex| bsdf_of(&mut rng, vertex))
                .collect();
            let [baseline, dispatched] = lanes(&vertices, &bsdfs);
            for (lane, v) in vertices.iter().enumerate() {
                for out in [&baseline, &dispatched] {
                    let frame = Frame::from_z(v.surface.shading_normal);
                    let wo_local = frame.to_local(v.surface.wo);
                    let wo_unit = unit_direction(wo_local);
                    let Some(wo_unit) = wo_unit else {
                        assert!(!out.has_shadow.lane(lane) && !out.next.scattered.lane(lane));
                        unsound += 1;
                        continue;
                    };
                    let bsdf = bsdfs[lane];
                    let shadow = scalar_light(v).and_then(|light| {
                        let wi_local = frame.to_local(light.wi);
                        if light.wi.dot(v.surface.geometric_normal) * wi_local.z <= 0.0 {
                            return None;
                        }
                        let (f, bsdf_pdf) = bsdf.eval_and_pdf_unit_wo(wo_unit, wi_local);
                        let f = f * wi_local.z.abs();
                        if f == Vec3::ZERO {
                            return None;
                        }
                        let weight = if light.delta {
                            1.0
                        } else {
                            power_heuristic(1, light.pdf, 1, bsdf_pdf)
                        };
                        let contribution =
                            v.surface.throughput * f * light.radiance * weight / light.pdf;
                        contribution.is_finite().then(|| {
                            let origin = offset_ray_origin(
                                v.surface.position,
                                v.surface.geometric_normal,
                                light.wi,
                            );
                            (
                                origin,
                                light.wi,
                                light.distance * (1.0 - 1e-3),
                                contribution,
                            )
                        })
                    });
                    assert_eq!(out.has_shadow.lane(lane), shadow.is_some(), "lane {lane}");
                    if let Some((origin, direction, t_max, contribution)) = shadow {
                        assert_eq!(bits(out.shadow_origin.get(lane)), bits(origin));
                        assert_eq!(bits(out.shadow_direction.get(lane)), bits(direction));
                        assert_eq!(out.shadow_t_max.0[lane].to_bits(), t_max.to_bits());
                        assert_eq!(bits(out.contribution.get(lane)), bits(contribution));
                        shadows += 1;
                        match v.light {
                            VertexLight::Lamp(_) => lamp_shadows += 1,
                            VertexLight::Sky(_) => sky_shadows += 1,
                            _ => {}
                        }
                    }
                    let next = bsdf
                        .sample_unit_wo(wo_unit, v.u, 0.5)
                        .filter(|s| s.pdf > 0.0)
                        .and_then(|s| {
                            let wi = frame.to_world(s.wi);
                            let reflects = s.wi.z * wo_local.z > 0.0;
                            let ng = v.surface.geometric_normal;
                            let stays = wi.dot(ng) * v.surface.wo.dot(ng) > 0.0;
                            (reflects == stays).then_some((s, wi))
                        });
                    assert_eq!(out.next.scattered.lane(lane), next.is_some(), "lane {lane}");
                    if let Some((s, wi)) = next {
                        let throughput = v.surface.throughput * (s.f * s.wi.z.abs() / s.pdf);
                        assert_eq!(out.pdf.0[lane].to_bits(), s.pdf.to_bits());
                        assert_eq!(bits(out.next.throughput.get(lane)), bits(throughput));
                        assert_eq!(bits(out.next.direction.get(lane)), bits(wi));
                        let origin =
                            offset_ray_origin(v.surface.position, v.surface.geometric_normal, wi);
                        assert_eq!(bits(out.next.origin.get(lane)), bits(origin));
                        scattered += 1;
                    }
                }
            }
        }
        // The sky lanes were exercised too.
        assert!(sky_shadows > 100, "{sky_shadows}");
        [shadows, lamp_shadows, scattered, unsound]
    }
}
