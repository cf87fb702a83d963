//! Smooth glass finished eight at a time: the shading frame, the Fresnel choice between the
//! mirror and the refracted direction, and the throughput update, with one lane per path.
//!
//! Smooth glass is a pair of delta lobes: no light sample, no MIS, no Russian roulette after it
//! (`shade_scattering`), so a vertex needs its one lobe sample `u` and the glass. Every lane
//! performs the operations of `Dielectric::sample`, `fr_dielectric` and `refract` in their
//! order, both sides of each branch computed and one selected, so the image is the same to the
//! bit as one vertex at a time (tested).

use super::diffuse_lanes::NextRays;
use super::lanes::{
    F8, LANES, LaneFrame, QueuedSurface, SurfaceLanes, V8, canonical, offset_ray_origin,
    unit_direction,
};
use super::shading::PathBlock;
use crate::accel::vex;
use crate::bsdf::SmoothGlass;

/// What finishing a glass vertex needs: the surface (normals as `face_forward` left them),
/// the path's throughput, the glass and the lobe sample.
#[derive(Clone, Copy, Debug)]
pub struct GlassVertex {
    pub surface: QueuedSurface,
    pub glass: SmoothGlass,
    pub u: f32,
}

/// The queued vertices, one lane each.
#[derive(Clone, Copy, Default)]
struct Inputs {
    surface: SurfaceLanes,
    reflectance: V8,
    transmittance: V8,
    eta: F8,
    u: F8,
}

/// A block's glass vertices waiting to be finished, with their slots in the block.
#[derive(Default)]
pub struct GlassQueue {
    len: usize,
    slots: [usize; LANES],
    inputs: Inputs,
    outputs: NextRays,
}

impl GlassQueue {
    pub fn is_full(&self) -> bool {
        self.len == LANES
    }

    /// Queues the vertex of the block's path `slot`.
    #[inline(always)]
    pub fn push(&mut self, slot: usize, vertex: GlassVertex) {
        let (lane, inputs) = (self.len, &mut self.inputs);
        self.slots[lane] = slot;
        inputs.surface.set(lane, &vertex.surface);
        inputs.reflectance.set(lane, vertex.glass.reflectance);
        inputs.transmittance.set(lane, vertex.glass.transmittance);
        inputs.eta.0[lane] = vertex.glass.eta;
        inputs.u.0[lane] = vertex.u;
        self.len += 1;
    }

    /// Finishes the queued vertices into their paths' slots in `block` (the next ray; a delta
    /// bounce: its density 0 for MIS, no roulette) and empties the queue.
    pub fn finish(&mut self, block: &mut PathBlock) {
        if self.len == 0 {
            return;
        }
        let (inputs, out) = (&self.inputs, &mut self.outputs);
        vex::run(
            #[inline(always)]
            || glass_lanes(inputs, out),
        );
        let carrying = out.carrying();
        for (lane, &slot) in self.slots[..self.len].iter().enumerate() {
            let mut path = block.paths.slots(slot);
            let vertex = self.inputs.surface.position.get(lane);
            out.continue_path(lane, &mut path, vertex, 0.0, carrying);
        }
        self.len = 0;
    }
}

/// The lanes of [`GlassQueue::finish`]: `shade_scattering`'s operations on smooth glass
/// (`Bsdf::sample_unit_wo`, `Dielectric::sample`, `checked_sample`, `PathSlots::scatter`).
#[inline(always)]
fn glass_lanes(inputs: &Inputs, out: &mut NextRays) {
    let (zero, one) = (F8::splat(0.0), F8::splat(1.0));
    let (ng, p, wo) = (
        inputs.surface.geometric_normal,
        inputs.surface.position,
        inputs.surface.wo,
    );
    let frame = LaneFrame::from_z(inputs.surface.shading_normal);
    let (wo, sound) = unit_direction(frame.to_local(wo));
    let uc = canonical(inputs.u);
    let eta = inputs.eta;

    // `fr_dielectric(wo.z, eta)`: seen from inside, the relative index inverted.
    let inside = wo.z.lt(zero);
    let cos_i = inside.select(-wo.z, wo.z).min(one);
    let eta_i = inside.select(1.0 / eta, eta);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta_i * eta_i);
    let cos_t = (1.0 - sin2_t).max(zero).sqrt();
    let r_parl = (eta_i * cos_i - cos_t) / (eta_i * cos_i + cos_t);
    let r_perp = (cos_i - eta_i * cos_t) / (cos_i + eta_i * cos_t);
    let r = sin2_t
        .ge(one)
        .select(one, 0.5 * (r_parl * r_parl + r_perp * r_perp));
    let t = 1.0 - r;

    // The mirror direction, f = R r / |cos|, chosen with probability r.
    let mirror = uc.lt(r) | t.le(zero);
    let reflected = V8 {
        x: -wo.x,
        y: -wo.y,
        z: wo.z,
    };
    let f_reflected = inputs.reflectance.scale(r / reflected.z.abs());

    // `refract(wo, Vec3::Z, eta)`: the normal turned to wo's side, the index inverted.
    let cos_n = wo.x * 0.0 + wo.y * 0.0 + wo.z * 1.0;
    let below = cos_n.lt(zero);
    let (cos_n, etap) = (below.select(-cos_n, cos_n), below.select(1.0 / eta, eta));
    let (n_xy, n_z) = (below.select(F8::splat(-0.0), zero), below.select(-one, one));
    let sin2 = (1.0 - cos_n * cos_n).max(zero) / (etap * etap);
    let refracts = !sin2.ge(one);
    let k = cos_n / etap - (1.0 - sin2).sqrt();
    let refracted = V8 {
        x: -wo.x / etap + k * n_xy,
        y: -wo.y / etap + k * n_xy,
        z: -wo.z / etap + k * n_z,
    };
    let f_refracted = inputs
        .transmittance
        .scale(t / (refracted.z.abs() * etap * etap));

    let wi = mirror.select_v(reflected, refracted);
    let f = mirror.select_v(f_reflected, f_refracted);
    let pdf = mirror.select(r, t);
    // `checked_sample`, `math::is_positive_finite`.
    let sampled = (mirror | refracts) & wi.is_finite() & f.is_finite() & pdf.is_positive_finite();
    out.scattered = sound & sampled;
    let cos = wi.z.abs();
    out.throughput = inputs.surface.throughput.mul(V8 {
        x: f.x * cos / pdf,
        y: f.y * cos / pdf,
        z: f.z * cos / pdf,
    });
    let direction = frame.to_world(wi);
    out.origin = offset_ray_origin(p, ng, direction);
    out.direction = direction;
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;
    use crate::bsdf::frame::Frame;
    use crate::bsdf::{Bsdf, unit_direction};
    use crate::math::offset_ray_origin;
    use crate::sampling::PathRng;
    use crate::sampling::warp::uniform_sphere;

    fn bits(v: Vec3) -> [u32; 3] {
        v.to_array().map(f32::to_bits)
    }

    /// A vertex with random normals and directions (now and then a zero or tiny `wo`, or one
    /// in the surface), random glass (now and then an index of 1, below 1 or out of range) and
    /// a random lobe sample (now and then NaN, negative or 1).
    fn random_vertex(rng: &mut PathRng, i: usize) -> (GlassVertex, Bsdf) {
        let n = uniform_sphere(rng.next_2d());
        let geometric_normal = (n + 0.4 * uniform_sphere(rng.next_2d())).normalize();
        let wo = match i % 13 {
            0 => Vec3::ZERO,
            6 => uniform_sphere(rng.next_2d()) * 1e-25,
            9 => Frame::from_z(n).to_world(Vec3::new(0.6, -0.8, 0.0)),
            _ => uniform_sphere(rng.next_2d()) * (0.5 + rng.next_f32()),
        };
        let eta = match i % 11 {
            0 => 1.0,
            1 => 0.7,
            2 => 1e3,
            3 => f32::NAN,
            _ => 1.0 + 1.5 * rng.next_f32(),
        };
        let mut colour = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let bsdf = Bsdf::Dielectric {
            reflectance: colour(),
            transmittance: colour(),
            eta,
        };
        let u = match i % 17 {
            0 => f32::NAN,
            1 => -0.25,
            2 => 1.0,
            _ => rng.next_f32(),
        };
        let vertex = GlassVertex {
            surface: QueuedSurface {
                position: 20.0 * (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5),
                geometric_normal,
                shading_normal: n,
                wo,
                throughput: Vec3::new(rng.next_f32(), 1.0, 3.0 * rng.next_f32()),
            },
            glass: bsdf.smooth_glass().expect("smooth glass"),
            u,
        };
        (vertex, bsdf)
    }

    /// The scalar path's operations on one glass vertex (as `shade_scattering` does them)
    /// against the lanes, bit for bit, in both compilations of the kernel.
    #[test]
    fn lanes_match_the_scalar_vertex_bit_for_bit() {
        let mut rng = PathRng::new(9, 0, 0);
        let (mut reflected, mut refracted, mut ended) = (0, 0, 0);
        for group in 0..1000 {
            let vertices: Vec<(GlassVertex, Bsdf)> = (0..LANES)
                .map(|lane| random_vertex(&mut rng, group * LANES + lane))
                .collect();
            let mut queue = GlassQueue::default();
            for (lane, (vertex, _)) in vertices.iter().enumerate() {
                queue.push(lane, *vertex);
            }
            let (mut baseline, mut dispatched) = (NextRays::default(), NextRays::default());
            glass_lanes(&queue.inputs, &mut baseline);
            vex::run(|| glass_lanes(&queue.inputs, &mut dispatched));
            for (lane, (v, bsdf)) in vertices.iter().enumerate() {
                for out in [&baseline, &dispatched] {
                    let frame = Frame::from_z(v.surface.shading_normal);
                    let next = unit_direction(frame.to_local(v.surface.wo))
                        .and_then(|wo| bsdf.sample_unit_wo(wo, Vec2::splat(0.5), v.u))
                        .filter(|s| s.pdf > 0.0);
                    assert_eq!(out.scattered.lane(lane), next.is_some(), "lane {lane}");
                    let Some(s) = next else {
                        ended += 1;
                        continue;
                    };
                    assert!(s.delta);
                    let wi = frame.to_world(s.wi);
                    let throughput = v.surface.throughput * (s.f * s.wi.z.abs() / s.pdf);
                    assert_eq!(bits(out.throughput.get(lane)), bits(throughput));
                    assert_eq!(bits(out.direction.get(lane)), bits(wi));
                    let origin =
                        offset_ray_origin(v.surface.position, v.surface.geometric_normal, wi);
                    assert_eq!(bits(out.origin.get(lane)), bits(origin));
                    if wi.dot(v.surface.geometric_normal)
                        * v.surface.wo.dot(v.surface.geometric_normal)
                        > 0.0
                    {
                        reflected += 1;
                    } else {
                        refracted += 1;
                    }
                }
            }
        }
        // Every outcome common, so the comparisons were exercised.
        assert!(
            reflected > 1000 && refracted > 1000 && ended > 1000,
            "{reflected} {refracted} {ended}"
        );
    }
}
