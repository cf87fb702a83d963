//! Scattering functions sampled by the path tracer at each hit, in the local
//! shading frame (z = shading normal; see [`frame::Frame`]).
//!
//! LuxRender materials map to them: matte -> Lambertian (Oren-Nayar with
//! `sigma`), mirror -> specular reflection, glass -> smooth dielectric,
//! roughglass -> rough dielectric, metal2 -> microfacet conductor, glossy ->
//! coated glossy. Mitsuba's roughdielectric, thindielectric, plastic and
//! roughplastic have BSDFs of their own.
//! Directions point away from the surface; the dispatch here sanitises
//! inputs (non-finite or unnormalised directions, samples outside [0, 1)) and
//! outputs, so that no NaN or infinity escapes.

pub mod beckmann;
pub mod blinn_plastic;
pub mod car_paint;
pub mod coated_glossy;
mod conductor;
mod dielectric;
pub mod diffuse_translucent;
pub mod frame;
pub mod fresnel;
pub mod fresnel_blend;
pub mod glossy_translucent;
pub mod lafortune;
mod lambertian;
pub mod microfacet;
pub mod microfacet_distribution;
pub mod oren_nayar;
pub mod phong_distribution;
pub mod plastic;
pub mod rough_dielectric;
pub mod rough_plastic;
mod schlick_distribution;
pub mod shiny_metal;
mod smooth_conductor;
mod specular_reflection;
pub mod thin_dielectric;
pub mod thin_film;
pub mod velvet;

use crate::math;
use crate::sampling::ONE_MINUS_EPSILON;
pub use blinn_plastic::BlinnPlastic;
pub use car_paint::{CarPaint, CarPaintLobe};
pub use coated_glossy::CoatedGlossy;
pub use conductor::{ConductorFresnel, RoughConductor};
use dielectric::Dielectric;
pub use diffuse_translucent::DiffuseTranslucent;
pub use fresnel_blend::FresnelBlend;
use glam::{Vec2, Vec3};
pub use glossy_translucent::GlossyTranslucent;
pub use lafortune::Lafortune;
use lambertian::Lambertian;
use microfacet::TrowbridgeReitz;
use microfacet_distribution::{Masking, Microfacet};
use oren_nayar::OrenNayar;
pub use plastic::Plastic;
pub use rough_dielectric::RoughDielectric;
pub use rough_plastic::RoughPlastic;
pub use shiny_metal::ShinyMetal;
pub use smooth_conductor::SmoothConductor;
use specular_reflection::SpecularReflection;
pub use thin_dielectric::ThinDielectric;
pub use velvet::Velvet;

#[derive(Clone, Copy, Debug)]
pub enum Bsdf {
    Lambertian {
        reflectance: Vec3,
    },
    SpecularReflection {
        reflectance: Vec3,
    },
    /// `eta` = index inside / index outside; the normal points outside.
    Dielectric {
        reflectance: Vec3,
        transmittance: Vec3,
        eta: f32,
    },
    /// GGX roughness along the local x and y axes (clamped by
    /// [`microfacet::clamp_alpha`]).
    Conductor {
        f0: Vec3,
        alpha_x: f32,
        alpha_y: f32,
    },
    /// Rough diffuse; `a`, `b` from [`oren_nayar::oren_nayar_ab`].
    OrenNayar {
        reflectance: Vec3,
        a: f32,
        b: f32,
    },
    /// A diffuse base under a glossy coating (LuxRender's `glossy`).
    CoatedGlossy(CoatedGlossy),
    /// GGX microfacet reflection and refraction (Mitsuba's `roughdielectric`).
    RoughDielectric(RoughDielectric),
    /// A thin sheet: mirror reflection, straight transmission (Mitsuba's `thindielectric`).
    ThinDielectric(ThinDielectric),
    /// Diffuse reflection and diffuse transmission (LuxRender's `mattetranslucent`).
    DiffuseTranslucent(DiffuseTranslucent),
    /// A diffuse base under a smooth dielectric coating (Mitsuba's `plastic`).
    Plastic(Plastic),
    /// A diffuse base under a GGX dielectric coating (Mitsuba's `roughplastic`).
    RoughPlastic(RoughPlastic),
    /// A microfacet conductor of any Fresnel term, distribution and masking (Mitsuba's
    /// `roughconductor`).
    RoughConductor(RoughConductor),
    /// A smooth conductor: mirror reflection weighted by the exact Fresnel of a complex index
    /// (Mitsuba's `conductor`).
    SmoothConductor(SmoothConductor),
    /// A mirror plus a Schlick microfacet lobe, each with a conductor Fresnel term fitted to a
    /// reflectance (LuxRender's `shinymetal`).
    ShinyMetal(ShinyMetal),
    /// Asperity scattering (LuxRender's `velvet`).
    Velvet(Velvet),
    /// Three Schlick microfacet lobes over a diffuse base (LuxRender's `carpaint`).
    CarPaint(CarPaint),
    /// Glossy coatings on both sides of a diffusely transmitting sheet (LuxRender's
    /// `glossytranslucent`).
    GlossyTranslucent(GlossyTranslucent),
    /// A Lambertian base plus a Blinn microfacet lobe (LuxRender 0.x's `plastic`).
    BlinnPlastic(BlinnPlastic),
    /// Ashikhmin and Shirley's coupled diffuse and glossy BRDF (LuxRender 0.x's `substrate`).
    FresnelBlend(FresnelBlend),
    /// A diffuse term plus generalized cosine lobes of a measured material (LuxRender 0.x's
    /// `primer`, `felt`, `clay`, `bluepaint`, `skin`).
    Lafortune(Lafortune),
}

#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    pub wi: Vec3,
    /// f(wo, wi) (for a delta lobe: the lobe's weight divided by |cos wi| so
    /// that f*|cos|/pdf is right)
    pub f: Vec3,
    pub pdf: f32,
    /// a delta lobe: pdf is a probability, not a density; skip MIS and light
    /// sampling
    pub delta: bool,
}

impl BsdfSample {
    /// A sample of a non-delta lobe: `wi` with f(wo, wi) = `f` and density `pdf`, or None where
    /// the density is 0 (the direction cannot be sampled).
    pub fn glossy(wi: Vec3, f: Vec3, pdf: f32) -> Option<Self> {
        (pdf > 0.0).then_some(Self {
            wi,
            f,
            pdf,
            delta: false,
        })
    }

    /// The mirror direction (-x, -y, z) about the normal with probability 1, reflecting the
    /// fraction `weight`: f = weight / cos(theta_i), so that f |cos| / pdf = weight. None for
    /// `wo` below the surface.
    pub fn mirror(wo: Vec3, weight: Vec3) -> Option<Self> {
        (wo.z > 0.0).then(|| Self {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            f: weight / wo.z,
            pdf: 1.0,
            delta: true,
        })
    }
}

/// Smooth glass as its sampling uses it (the relative index clamped), for the shading stage's
/// lanes.
#[derive(Clone, Copy, Debug)]
pub struct SmoothGlass {
    pub reflectance: Vec3,
    pub transmittance: Vec3,
    pub eta: f32,
}

/// A sample coordinate clamped to [0, 1); NaN becomes 0.
fn canonical(x: f32) -> f32 {
    if x >= 0.0 {
        x.min(ONE_MINUS_EPSILON)
    } else {
        0.0
    }
}

/// A unit direction, or None for zero or non-finite input: how every entry point here takes
/// its directions.
pub fn unit_direction(w: Vec3) -> Option<Vec3> {
    math::try_normalize(w)
}

/// A BSDF value as returned: non-finite ones (never meant) become 0.
fn finite_or_zero(f: Vec3) -> Vec3 {
    if math::is_finite_vec3(f) {
        f
    } else {
        Vec3::ZERO
    }
}

/// A density as returned: 0 unless finite and positive.
fn density_or_zero(pdf: f32) -> f32 {
    if math::is_positive_finite(pdf) {
        pdf
    } else {
        0.0
    }
}

impl Bsdf {
    /// f(wo, wi) for non-delta lobes (0 for delta ones); both in the local
    /// frame, pointing away from the surface.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match (unit_direction(wo), unit_direction(wi)) {
            (Some(wo), Some(wi)) => self.eval_unit(wo, wi),
            _ => Vec3::ZERO,
        }
    }

    /// The density (per solid angle) with which [`Bsdf::sample`] returns
    /// `wi`; 0 for delta lobes.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match (unit_direction(wo), unit_direction(wi)) {
            (Some(wo), Some(wi)) => self.pdf_unit(wo, wi),
            _ => 0.0,
        }
    }

    /// [`Bsdf::eval`] and [`Bsdf::pdf`] together, as next-event estimation needs both: the
    /// directions are checked and normalised once.
    pub fn eval_and_pdf(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        match unit_direction(wo) {
            Some(wo) => self.eval_and_pdf_unit_wo(wo, wi),
            None => (Vec3::ZERO, 0.0),
        }
    }

    /// [`Bsdf::eval_and_pdf`] for a `wo` already made a unit vector by [`unit_direction`] (a
    /// path vertex normalises its `wo` once for this and [`Bsdf::sample_unit_wo`]). Inlined
    /// into the caller, so that the commonest BSDF costs no call (and no spill of the
    /// caller's vector registers around it).
    #[inline(always)]
    pub fn eval_and_pdf_unit_wo(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let Some(wi) = unit_direction(wi) else {
            return (Vec3::ZERO, 0.0);
        };
        // The commonest BSDF without the two dispatches (and calls) of `eval_unit` and
        // `pdf_unit`: the same values, a third of the instructions.
        if let Bsdf::Lambertian { reflectance } = *self {
            let lambertian = Lambertian { reflectance };
            return (
                finite_or_zero(lambertian.eval(wo, wi)),
                density_or_zero(lambertian.pdf(wo, wi)),
            );
        }
        self.eval_and_pdf_unit(wo, wi)
    }

    /// [`Bsdf::eval_and_pdf`] for unit directions, behind one call: a microfacet conductor's
    /// terms shared between its value and its density ([`RoughConductor::eval_and_pdf`]), the
    /// rest as `eval_unit` and `pdf_unit` give them.
    #[inline(never)]
    fn eval_and_pdf_unit(&self, wo: Vec3, wi: Vec3) -> (Vec3, f32) {
        let (f, pdf) = match *self {
            Bsdf::Conductor {
                f0,
                alpha_x,
                alpha_y,
            } => conductor(ConductorFresnel::Schlick(f0), alpha_x, alpha_y).eval_and_pdf(wo, wi),
            Bsdf::RoughConductor(c) => c.eval_and_pdf(wo, wi),
            _ => return (self.eval_unit(wo, wi), self.pdf_unit(wo, wi)),
        };
        (finite_or_zero(f), density_or_zero(pdf))
    }

    /// `eval` for unit directions.
    fn eval_unit(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let f = match *self {
            Bsdf::Lambertian { reflectance } => Lambertian { reflectance }.eval(wo, wi),
            Bsdf::Conductor {
                f0,
                alpha_x,
                alpha_y,
            } => conductor(ConductorFresnel::Schlick(f0), alpha_x, alpha_y).eval(wo, wi),
            Bsdf::OrenNayar { reflectance, a, b } => OrenNayar { reflectance, a, b }.eval(wo, wi),
            Bsdf::CoatedGlossy(c) => c.eval(wo, wi),
            Bsdf::RoughDielectric(d) => d.eval(wo, wi),
            Bsdf::DiffuseTranslucent(d) => d.eval(wo, wi),
            Bsdf::Plastic(p) => p.eval(wo, wi),
            Bsdf::RoughPlastic(p) => p.eval(wo, wi),
            Bsdf::RoughConductor(c) => c.eval(wo, wi),
            Bsdf::ShinyMetal(m) => m.eval(wo, wi),
            Bsdf::Velvet(v) => v.eval(wo, wi),
            Bsdf::CarPaint(c) => c.eval(wo, wi),
            Bsdf::GlossyTranslucent(g) => g.eval(wo, wi),
            Bsdf::BlinnPlastic(p) => p.eval(wo, wi),
            Bsdf::FresnelBlend(b) => b.eval(wo, wi),
            Bsdf::Lafortune(l) => l.eval(wo, wi),
            Bsdf::SpecularReflection { .. }
            | Bsdf::Dielectric { .. }
            | Bsdf::ThinDielectric(_)
            | Bsdf::SmoothConductor(_) => Vec3::ZERO,
        };
        finite_or_zero(f)
    }

    /// `pdf` for unit directions.
    fn pdf_unit(&self, wo: Vec3, wi: Vec3) -> f32 {
        let pdf = match *self {
            Bsdf::Lambertian { reflectance } => Lambertian { reflectance }.pdf(wo, wi),
            Bsdf::Conductor {
                f0,
                alpha_x,
                alpha_y,
            } => conductor(ConductorFresnel::Schlick(f0), alpha_x, alpha_y).pdf(wo, wi),
            Bsdf::OrenNayar { reflectance, a, b } => OrenNayar { reflectance, a, b }.pdf(wo, wi),
            Bsdf::CoatedGlossy(c) => c.pdf(wo, wi),
            Bsdf::RoughDielectric(d) => d.pdf(wo, wi),
            Bsdf::DiffuseTranslucent(d) => d.pdf(wo, wi),
            Bsdf::Plastic(p) => p.pdf(wo, wi),
            Bsdf::RoughPlastic(p) => p.pdf(wo, wi),
            Bsdf::RoughConductor(c) => c.pdf(wo, wi),
            Bsdf::ShinyMetal(m) => m.pdf(wo, wi),
            Bsdf::Velvet(v) => v.pdf(wo, wi),
            Bsdf::CarPaint(c) => c.pdf(wo, wi),
            Bsdf::GlossyTranslucent(g) => g.pdf(wo, wi),
            Bsdf::BlinnPlastic(p) => p.pdf(wo, wi),
            Bsdf::FresnelBlend(b) => b.pdf(wo, wi),
            Bsdf::Lafortune(l) => l.pdf(wo, wi),
            Bsdf::SpecularReflection { .. }
            | Bsdf::Dielectric { .. }
            | Bsdf::ThinDielectric(_)
            | Bsdf::SmoothConductor(_) => 0.0,
        };
        density_or_zero(pdf)
    }

    /// `u`: a 2D sample, `uc`: a 1D sample (to choose reflection or
    /// transmission).
    pub fn sample(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        self.sample_unit_wo(unit_direction(wo)?, u, uc)
    }

    /// [`Bsdf::sample`] for a `wo` already made a unit vector by [`unit_direction`]. A
    /// Lambertian BSDF and smooth glass are sampled inline in the caller (no call, no spill of
    /// its vector registers, no sample through memory), every other behind one call.
    #[inline(always)]
    pub fn sample_unit_wo(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        let u = Vec2::new(canonical(u.x), canonical(u.y));
        match *self {
            Bsdf::Lambertian { reflectance } => sample_lambertian(reflectance, wo, u),
            Bsdf::Dielectric {
                reflectance,
                transmittance,
                eta,
            } => sample_dielectric(reflectance, transmittance, eta, wo, uc),
            _ => self.sample_canonical(wo, u, uc),
        }
    }

    /// [`Bsdf::sample_unit_wo`] for a canonical `u`, by the BSDF's own sampling routine.
    #[inline(never)]
    fn sample_canonical(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        let sample = match *self {
            Bsdf::Lambertian { reflectance } => return sample_lambertian(reflectance, wo, u),
            Bsdf::SpecularReflection { reflectance } => {
                SpecularReflection { reflectance }.sample(wo)
            }
            Bsdf::Dielectric {
                reflectance,
                transmittance,
                eta,
            } => return sample_dielectric(reflectance, transmittance, eta, wo, uc),
            Bsdf::Conductor {
                f0,
                alpha_x,
                alpha_y,
            } => conductor(ConductorFresnel::Schlick(f0), alpha_x, alpha_y).sample(wo, u),
            Bsdf::OrenNayar { reflectance, a, b } => OrenNayar { reflectance, a, b }.sample(wo, u),
            Bsdf::CoatedGlossy(c) => c.sample(wo, u),
            Bsdf::RoughDielectric(d) => d.sample(wo, u, canonical(uc)),
            Bsdf::DiffuseTranslucent(d) => d.sample(wo, u, canonical(uc)),
            Bsdf::ThinDielectric(t) => t.sample(wo, canonical(uc)),
            Bsdf::Plastic(p) => p.sample(wo, u, canonical(uc)),
            Bsdf::RoughPlastic(p) => p.sample(wo, u, canonical(uc)),
            Bsdf::RoughConductor(c) => c.sample(wo, u),
            Bsdf::SmoothConductor(c) => c.sample(wo),
            Bsdf::ShinyMetal(m) => m.sample(wo, u, canonical(uc)),
            Bsdf::Velvet(v) => v.sample(wo, u),
            Bsdf::CarPaint(c) => c.sample(wo, u),
            Bsdf::GlossyTranslucent(g) => g.sample(wo, u, canonical(uc)),
            Bsdf::BlinnPlastic(p) => p.sample(wo, u, canonical(uc)),
            Bsdf::FresnelBlend(b) => b.sample(wo, u, canonical(uc)),
            Bsdf::Lafortune(l) => l.sample(wo, u, canonical(uc)),
        };
        checked_sample(sample)
    }

    /// The BSDF as smooth glass, if it is (`Bsdf::Dielectric`): the shading stage finishes
    /// those eight at a time.
    pub fn smooth_glass(&self) -> Option<SmoothGlass> {
        match *self {
            Bsdf::Dielectric {
                reflectance,
                transmittance,
                eta,
            } => Some(SmoothGlass {
                reflectance,
                transmittance,
                eta: dielectric::clamp_eta(eta),
            }),
            _ => None,
        }
    }

    /// The BSDF as a microfacet conductor on isotropic GGX, if it is one (LuxRender's metals,
    /// Mitsuba's `roughconductor` and metallic `principled`): the shading stage finishes those
    /// eight at a time.
    pub fn isotropic_ggx_conductor(&self) -> Option<RoughConductor> {
        let conductor = match *self {
            Bsdf::Conductor {
                f0,
                alpha_x,
                alpha_y,
            } => conductor(ConductorFresnel::Schlick(f0), alpha_x, alpha_y),
            Bsdf::RoughConductor(c) => c,
            _ => return None,
        };
        let ggx = matches!(conductor.distribution, Microfacet::TrowbridgeReitz(_));
        (ggx && !conductor.distribution.is_anisotropic()).then_some(conductor)
    }

    /// True when every lobe is a delta (mirror, smooth glass): no light
    /// sampling.
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Bsdf::SpecularReflection { .. }
                | Bsdf::Dielectric { .. }
                | Bsdf::ThinDielectric(_)
                | Bsdf::SmoothConductor(_)
        )
    }

    /// True when the lobes depend on the azimuth about the normal (anisotropic roughness): the
    /// shading frame's x axis must then follow the surface's dp/du.
    pub fn is_anisotropic(&self) -> bool {
        match self {
            Bsdf::Conductor {
                alpha_x, alpha_y, ..
            } => alpha_x != alpha_y,
            Bsdf::RoughConductor(c) => c.distribution.is_anisotropic(),
            Bsdf::RoughDielectric(d) => d.distribution.is_anisotropic(),
            Bsdf::ShinyMetal(m) => m.is_anisotropic(),
            Bsdf::CoatedGlossy(c) => c.anisotropy != 0.0,
            Bsdf::GlossyTranslucent(g) => {
                g.front.lobe.anisotropy != 0.0 || g.back.lobe.anisotropy != 0.0
            }
            Bsdf::FresnelBlend(b) => b.distribution.ex != b.distribution.ey,
            _ => false,
        }
    }

    /// True for an interface between an inside and an outside, whose lobes depend on the side
    /// `wo` is on: the shading normal must not be turned towards the viewer.
    pub fn has_inside(&self) -> bool {
        matches!(
            self,
            Bsdf::Dielectric { .. } | Bsdf::RoughDielectric(_) | Bsdf::GlossyTranslucent(_)
        )
    }

    /// A grey-level estimate of reflectance, for Russian roulette and for the
    /// ray caster: the albedo colour (for glass, see `Dielectric::albedo`).
    pub fn albedo(&self) -> Vec3 {
        match *self {
            Bsdf::Lambertian { reflectance } | Bsdf::SpecularReflection { reflectance } => {
                reflectance
            }
            Bsdf::Dielectric {
                reflectance,
                transmittance,
                eta,
            } => Dielectric {
                reflectance,
                transmittance,
                eta,
            }
            .albedo(),
            Bsdf::Conductor { f0, .. } => f0,
            Bsdf::OrenNayar { reflectance, .. } => reflectance,
            // The coating reflects about Ks; the base shows through the rest.
            Bsdf::CoatedGlossy(c) => c.specular + (Vec3::ONE - c.specular) * c.diffuse,
            Bsdf::RoughDielectric(d) => d.albedo(),
            Bsdf::DiffuseTranslucent(d) => d.albedo(),
            Bsdf::ThinDielectric(t) => t.albedo(),
            Bsdf::Plastic(p) => p.albedo(),
            Bsdf::RoughPlastic(p) => p.albedo(),
            Bsdf::RoughConductor(c) => c.reflectance * c.fresnel.eval(1.0),
            Bsdf::SmoothConductor(c) => c.reflectance * fresnel::fr_conductor(1.0, c.eta, c.k),
            Bsdf::ShinyMetal(m) => m.albedo(),
            Bsdf::Velvet(v) => v.reflectance,
            Bsdf::CarPaint(c) => c.albedo(),
            Bsdf::GlossyTranslucent(g) => g.albedo(),
            Bsdf::BlinnPlastic(p) => p.albedo(),
            Bsdf::FresnelBlend(b) => b.albedo(),
            Bsdf::Lafortune(l) => l.albedo(),
        }
    }
}

/// A sample as returned: none unless its direction, value and density are finite and the
/// density positive.
#[inline(always)]
fn checked_sample(sample: Option<BsdfSample>) -> Option<BsdfSample> {
    let s = sample?;
    (math::is_finite_vec3(s.wi) & math::is_finite_vec3(s.f) & math::is_positive_finite(s.pdf))
        .then_some(s)
}

/// A Lambertian BSDF's sample for a canonical `u`. The cosine warp of a canonical `u` gives a
/// finite direction and a positive finite density: only f (a texture's reflectance) needs the
/// check that [`Bsdf::sample`] makes of every other sample.
#[inline(always)]
fn sample_lambertian(reflectance: Vec3, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
    Lambertian { reflectance }
        .sample(wo, u)
        .filter(|s| math::is_finite_vec3(s.f))
}

/// Smooth glass's sample, checked as [`Bsdf::sample`] checks every sample but the Lambertian's.
#[inline(always)]
fn sample_dielectric(
    reflectance: Vec3,
    transmittance: Vec3,
    eta: f32,
    wo: Vec3,
    uc: f32,
) -> Option<BsdfSample> {
    let glass = Dielectric {
        reflectance,
        transmittance,
        eta,
    };
    checked_sample(glass.sample(wo, canonical(uc)))
}

/// LuxRender's metals: GGX with height-correlated masking.
fn conductor(fresnel: ConductorFresnel, alpha_x: f32, alpha_y: f32) -> RoughConductor {
    RoughConductor {
        reflectance: Vec3::ONE,
        fresnel,
        distribution: Microfacet::TrowbridgeReitz(TrowbridgeReitz::new(alpha_x, alpha_y)),
        masking: Masking::HeightCorrelated,
    }
}
