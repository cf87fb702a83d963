//! Rough conductors on isotropic GGX finished eight at a time, as the Lambertian's vertices are
//! ([`super::diffuse_lanes`]): next-event estimation's BSDF value and density, the sample of
//! visible normals (Heitz 2018), the Fresnel term (Schlick's or a complex index's) and the
//! throughput update, with one lane per path.
//!
//! The vertices wait in a [`DiffuseQueue`] (their light samples and random numbers drawn as a
//! Lambertian vertex's are), beside each lane's lobe: roughness, Fresnel term and masking.
//! Every lane performs the operations of `RoughConductor::sample` and
//! `RoughConductor::eval_and_pdf` (and of the functions they call) in their order, both sides
//! of each branch computed and one selected, so the image is the same to the bit as one vertex
//! at a time (tested).

use std::f32::consts::PI;

use super::diffuse_lanes::{
    DiffuseQueue, DiffuseVertex, Inputs, Outputs, Sampled, light_lanes, scatter_lanes,
};
use super::lanes::{F8, LANES, LaneFrame, M8, V8, canonical, concentric_disk, unit_direction};
use super::shading::PathBlock;
use crate::bsdf::microfacet_distribution::Masking;
use crate::bsdf::{ConductorFresnel, RoughConductor};

/// The queued conductors' lobes, one lane each.
#[derive(Clone, Copy, Default)]
struct Lobes {
    /// GGX's alpha (the same along x and y).
    alpha: F8,
    /// Schlick's Fresnel term of reflectance `f0` at normal incidence, else the exact one of
    /// the complex index `eta` + i `k`.
    schlick: [bool; LANES],
    f0: V8,
    eta: V8,
    k: V8,
    /// Smith's G as G1(wo) G1(wi), else height-correlated.
    separable: [bool; LANES],
}

/// A block's isotropic GGX conductor vertices waiting to be finished.
#[derive(Default)]
pub struct ConductorQueue<'a> {
    vertices: DiffuseQueue<'a>,
    lobes: Lobes,
}

impl<'a> ConductorQueue<'a> {
    pub fn is_full(&self) -> bool {
        self.vertices.is_full()
    }

    /// Queues the vertex of the block's path `slot` at the conductor `conductor`, an
    /// isotropic GGX one (`Bsdf::isotropic_ggx_conductor`); `vertex.reflectance` is the
    /// conductor's factor on its lobe.
    #[inline(always)]
    pub fn push(&mut self, slot: usize, vertex: DiffuseVertex<'a>, conductor: &RoughConductor) {
        let (lane, lobes) = (self.vertices.len(), &mut self.lobes);
        lobes.alpha.0[lane] = conductor.distribution.alphas().0;
        match conductor.fresnel {
            ConductorFresnel::Schlick(f0) => {
                lobes.schlick[lane] = true;
                lobes.f0.set(lane, f0);
            }
            ConductorFresnel::Complex { eta, k } => {
                lobes.schlick[lane] = false;
                lobes.eta.set(lane, eta);
                lobes.k.set(lane, k);
            }
        }
        lobes.separable[lane] = conductor.masking == Masking::Separable;
        self.vertices.push(slot, vertex);
    }

    /// Finishes the queued vertices as [`DiffuseQueue::finish`] does the Lambertian ones.
    pub fn finish(&mut self, block: &mut PathBlock, rr_depth: u32) {
        let len = self.vertices.len();
        if len == 0 {
            return;
        }
        let lobes = &self.lobes;
        // Each Fresnel term only where some queued lane has it.
        let fresnel = (
            lobes.schlick[..len].contains(&true),
            lobes.schlick[..len].contains(&false),
        );
        self.vertices.finish_with(
            block,
            rr_depth,
            #[inline(always)]
            |inputs, out| conductor_lanes(inputs, lobes, fresnel, out),
        );
    }
}

/// The lanes of [`ConductorQueue::finish`]: `shade_scattering`'s operations on a rough
/// conductor (`Bsdf::eval_and_pdf_unit_wo`, `Bsdf::sample_unit_wo`, `checked_sample`), both
/// sides of each branch computed and one selected. `fresnel`: whether any lane has Schlick's
/// term, and whether any has a complex index's.
#[inline(always)]
fn conductor_lanes(inputs: &Inputs, lobes: &Lobes, fresnel: (bool, bool), out: &mut Outputs) {
    let (n, wo) = (inputs.surface.shading_normal, inputs.surface.wo);
    let zero = F8::splat(0.0);
    let frame = LaneFrame::from_z(n);
    let wo_local = frame.to_local(wo);
    let (wo_unit, sound) = unit_direction(wo_local);
    let lobe = Lobe {
        alpha: lobes.alpha,
        reflectance: inputs.reflectance,
        lobes,
        fresnel,
    };

    // Next-event estimation (`finite_or_zero`, `density_or_zero`).
    if inputs.has_light.contains(&true) {
        let eval = |wi_unit: V8, wi_sound: M8| {
            let (f, pdf) = lobe.eval_and_pdf(wo_unit, wi_unit);
            (
                (wi_sound & f.is_finite()).select_v(f, V8::default()),
                (wi_sound & pdf.is_positive_finite()).select(pdf, zero),
            )
        };
        light_lanes(inputs, out, &frame, eval);
        out.has_shadow = out.has_shadow & sound;
    } else {
        out.has_shadow = M8::default();
    }

    // The next ray (`RoughConductor::sample`: a visible normal, wo reflected about it).
    let wh = lobe.sample_wm(wo_unit, inputs.u.map(canonical));
    let two_cos = 2.0 * wo_unit.dot(wh);
    let wi = V8 {
        x: two_cos * wh.x - wo_unit.x,
        y: two_cos * wh.y - wo_unit.y,
        z: two_cos * wh.z - wo_unit.z,
    };
    let (f, pdf) = lobe.eval_and_pdf(wo_unit, wi);
    // `BsdfSample::glossy` and `checked_sample`.
    let sampled = wo_unit.z.gt(zero) & wi.is_finite() & f.is_finite() & pdf.is_positive_finite();
    let sample = Sampled {
        wi_local_z: wi.z,
        wi: frame.to_world(wi),
        f,
        pdf,
    };
    scatter_lanes(inputs, out, wo_local.z, sound & sampled, sample);
}

/// `f32::clamp(x, 0, 1)` per lane (NaN stays NaN).
#[inline(always)]
fn clamp_unit(x: F8) -> F8 {
    let (zero, one) = (F8::splat(0.0), F8::splat(1.0));
    let x = x.lt(zero).select(zero, x);
    x.gt(one).select(one, x)
}

/// glam's `Vec3::normalize`: v times 1 / |v|.
#[inline(always)]
fn normalize(v: V8) -> V8 {
    v.scale(1.0 / v.dot(v).sqrt())
}

/// glam's `Vec3::cross`.
#[inline(always)]
fn cross(a: V8, b: V8) -> V8 {
    V8 {
        x: a.y * b.z - b.y * a.z,
        y: a.z * b.x - b.z * a.x,
        z: a.x * b.y - b.x * a.y,
    }
}

/// The lanes' rough conductors.
struct Lobe<'l> {
    alpha: F8,
    reflectance: V8,
    lobes: &'l Lobes,
    fresnel: (bool, bool),
}

impl Lobe<'_> {
    /// `RoughConductor::eval_and_pdf` with `Microfacet::d_g_pdf_wm` for GGX.
    #[inline(always)]
    fn eval_and_pdf(&self, wo: V8, wi: V8) -> (V8, F8) {
        let zero = F8::splat(0.0);
        let a = self.alpha;
        // `half_vector`.
        let (wh, wh_sound) = unit_direction(V8 {
            x: wo.x + wi.x,
            y: wo.y + wi.y,
            z: wo.z + wi.z,
        });
        let valid = wo.z.gt(zero) & wi.z.gt(zero) & wh_sound;
        // `TrowbridgeReitz::d`; `powi(2)` is a product.
        let (sx, sy) = (wh.x / a, wh.y / a);
        let s = sx * sx + sy * sy + wh.z * wh.z;
        let d = wh.z.le(zero).select(zero, 1.0 / (PI * a * a * s * s));
        let lambda_o = self.lambda(wo);
        let g1_o = 1.0 / (1.0 + lambda_o);
        let lambda_i = self.lambda(wi);
        let g = M8::from(self.lobes.separable).select(
            g1_o * (1.0 / (1.0 + lambda_i)),
            1.0 / (1.0 + lambda_o + lambda_i),
        );
        let pdf_wm =
            wo.z.le(zero)
                .select(zero, g1_o * wo.dot(wh).max(zero) * d / wo.z);
        let cos_oh = wo.dot(wh);
        let denom = 4.0 * wo.z * wi.z;
        let fresnel = self.fresnel_term(cos_oh);
        let dg = d * g / denom;
        let f = V8 {
            x: self.reflectance.x * fresnel.x * dg,
            y: self.reflectance.y * fresnel.y * dg,
            z: self.reflectance.z * fresnel.z * dg,
        };
        let f = (valid & !denom.le(zero)).select_v(f, V8::default());
        let pdf = (valid & !cos_oh.le(zero)).select(pdf_wm / (4.0 * cos_oh), zero);
        (f, pdf)
    }

    /// `TrowbridgeReitz::lambda`.
    #[inline(always)]
    fn lambda(&self, w: V8) -> F8 {
        let a = self.alpha;
        let z2 = w.z * w.z;
        let (ax, ay) = (a * w.x, a * w.y);
        let a2_tan2 = (ax * ax + ay * ay) / z2;
        let lambda = a2_tan2 / (2.0 * ((1.0 + a2_tan2).sqrt() + 1.0));
        z2.eq(F8::splat(0.0))
            .select(F8::splat(f32::INFINITY), lambda)
    }

    /// `ConductorFresnel::eval`: `schlick` or `fr_conductor`, each computed only where some
    /// lane has it.
    #[inline(always)]
    fn fresnel_term(&self, cos: F8) -> V8 {
        let (any_schlick, any_complex) = self.fresnel;
        let lobes = self.lobes;
        let schlick = if any_schlick {
            let m = 1.0 - clamp_unit(cos);
            let m2 = m * m;
            // `powi(5)` as LLVM expands it: m (m^2)^2.
            let m5 = m * (m2 * m2);
            let f0 = lobes.f0;
            V8 {
                x: f0.x + (1.0 - f0.x) * m5,
                y: f0.y + (1.0 - f0.y) * m5,
                z: f0.z + (1.0 - f0.z) * m5,
            }
        } else {
            V8::default()
        };
        if !any_complex {
            return schlick;
        }
        let complex = fr_conductor(cos, lobes.eta, lobes.k);
        if !any_schlick {
            return complex;
        }
        M8::from(lobes.schlick).select_v(schlick, complex)
    }

    /// `TrowbridgeReitz::sample_wm` (Heitz 2018, Listing 1) for isotropic alpha.
    #[inline(always)]
    fn sample_wm(&self, w: V8, u: [F8; 2]) -> V8 {
        let (zero, one) = (F8::splat(0.0), F8::splat(1.0));
        let a = self.alpha;
        let wh = normalize(V8 {
            x: a * w.x,
            y: a * w.y,
            z: w.z,
        });
        let z_axis = V8 {
            x: zero,
            y: zero,
            z: one,
        };
        let x_axis = V8 {
            x: one,
            y: zero,
            z: zero,
        };
        let t1 =
            wh.z.lt(F8::splat(0.99999))
                .select_v(normalize(cross(z_axis, wh)), x_axis);
        let t2 = cross(wh, t1);
        let (px, py) = concentric_disk(u);
        let h = (1.0 - px * px).max(zero).sqrt();
        let s = 0.5 * (1.0 + wh.z);
        let py = (1.0 - s) * h + s * py;
        let pz = (1.0 - (px * px + py * py)).max(zero).sqrt();
        let nh = V8 {
            x: px * t1.x + py * t2.x + pz * wh.x,
            y: px * t1.y + py * t2.y + pz * wh.y,
            z: px * t1.z + py * t2.z + pz * wh.z,
        };
        normalize(V8 {
            x: a * nh.x,
            y: a * nh.y,
            z: nh.z.max(zero),
        })
    }
}

/// `fresnel::fr_conductor` per lane and channel.
#[inline(always)]
fn fr_conductor(cos_i: F8, eta: V8, k: V8) -> V8 {
    let zero = F8::splat(0.0);
    let cos = clamp_unit(cos_i);
    let (cos2, sin2) = (cos * cos, 1.0 - cos * cos);
    let channel = |eta: F8, k: F8| {
        let (eta2, k2) = (eta * eta, k * k);
        let t0 = eta2 - k2 - sin2;
        // `powf(0.5)`, which LLVM compiles to a square root.
        let a2_plus_b2 = (t0 * t0 + 4.0 * eta2 * k2).max(zero).sqrt();
        let t1 = a2_plus_b2 + cos2;
        let a = (0.5 * (a2_plus_b2 + t0)).max(zero).sqrt();
        let t2 = 2.0 * cos * a;
        let rs = (t1 - t2) / (t1 + t2);
        let t3 = cos2 * a2_plus_b2 + sin2 * sin2;
        let t4 = t2 * sin2;
        let rp = rs * (t3 - t4) / (t3 + t4);
        0.5 * (rp + rs)
    };
    V8 {
        x: channel(eta.x, k.x),
        y: channel(eta.y, k.y),
        z: channel(eta.z, k.z),
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::bsdf::Bsdf;
    use crate::bsdf::microfacet::TrowbridgeReitz;
    use crate::bsdf::microfacet_distribution::Microfacet;
    use crate::integrator::diffuse_lanes::tests::assert_lanes_match_scalar;
    use crate::sampling::PathRng;

    /// A random isotropic GGX conductor: Schlick's Fresnel with height-correlated masking
    /// (`Bsdf::Conductor`) or a complex index with separable masking (`Bsdf::RoughConductor`),
    /// now and then the other pairings; random alphas, now and then the smallest or the largest. Groups of
    /// eight of one Fresnel term alone come now and then, for the kernel's shortcuts.
    fn random_conductor(rng: &mut PathRng, vertex: &mut DiffuseVertex, i: usize) -> Bsdf {
        let alpha = match i % 5 {
            0 => 1e-3,
            1 => 1.0,
            _ => rng.next_f32(),
        };
        let colour = |rng: &mut PathRng, scale: f32| {
            scale * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32())
        };
        let kind = match (i / LANES) % 4 {
            0 => 0,
            1 => 1,
            _ => (i * 7 / 3) % 4,
        };
        let bsdf = match kind {
            0 => Bsdf::Conductor {
                f0: colour(rng, 1.0),
                alpha_x: alpha,
                alpha_y: alpha,
            },
            _ => Bsdf::RoughConductor(RoughConductor {
                reflectance: colour(rng, 1.0),
                fresnel: if kind == 2 {
                    ConductorFresnel::Schlick(colour(rng, 1.0))
                } else {
                    ConductorFresnel::Complex {
                        eta: colour(rng, 3.0),
                        k: colour(rng, 5.0),
                    }
                },
                distribution: Microfacet::TrowbridgeReitz(TrowbridgeReitz::new(alpha, alpha)),
                masking: if kind == 3 {
                    Masking::HeightCorrelated
                } else {
                    Masking::Separable
                },
            }),
        };
        vertex.reflectance = bsdf
            .isotropic_ggx_conductor()
            .expect("an isotropic GGX conductor")
            .reflectance;
        bsdf
    }

    /// The scalar path's operations on one conductor vertex against the lanes, bit for bit, in
    /// both compilations of the kernel.
    #[test]
    fn lanes_match_the_scalar_vertex_bit_for_bit() {
        let mut i = 0;
        let [shadows, lamp_shadows, scattered, unsound] = assert_lanes_match_scalar(
            |rng, vertex| {
                i += 1;
                random_conductor(rng, vertex, i)
            },
            |vertices, bsdfs| {
                let mut queue = ConductorQueue::default();
                for (lane, (vertex, bsdf)) in vertices.iter().zip(bsdfs).enumerate() {
                    let conductor = bsdf.isotropic_ggx_conductor().unwrap();
                    queue.push(lane, *vertex, &conductor);
                }
                let lobes = queue.lobes;
                let fresnel = (
                    lobes.schlick.contains(&true),
                    lobes.schlick.contains(&false),
                );
                queue
                    .vertices
                    .kernel_outputs(|inputs, out| conductor_lanes(inputs, &lobes, fresnel, out))
            },
        );
        // Both outcomes common, so the comparisons were exercised.
        assert!(
            shadows > 1000 && lamp_shadows > 100 && scattered > 1000 && unsound > 100,
            "{shadows} {lamp_shadows} {scattered} {unsound}"
        );
    }
}
