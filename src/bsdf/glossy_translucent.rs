//! LuxRender's `glossytranslucent` (`materials/glossytranslucent.cpp`): a glossy coating over a
//! diffuse base on each side of a thin translucent sheet, plus diffuse transmission through it.
//!
//! Reflection (`core/reflection/bxdf/schlickbrdf.cpp`, `SchlickDoubleSidedBRDF`): on the front
//! (wo and wi above the surface) LuxRender's `glossy` lobe of the front coating
//! ([`CoatedGlossy`]), on the back the same lobe of the back coating (`backface_*`) evaluated
//! with both directions mirrored through the surface. `multibounce` adds, to each coating's
//! specular term, Schlick's interreflection in the coating's creases:
//!
//!   f_mb = S clamp((1 - G(cos_i) G(cos_o)) / (4 pi cos_i cos_o), 0, 1).
//!
//! Transmission (`schlicktranslucentbtdf.cpp`, `SchlickTranslucentBTDF`): a Lambertian lobe
//! through the sheet, weighted by both coatings' Schlick Fresnel terms and absorptions:
//!
//!   f_t = Kt (1 - Kd) / pi  (1 - S1)(1 - S2) / (1 - (S1 + S2) / 2)
//!         exp(-Ka d / |cos_front| - Ka_bf d_bf / |cos_back|),
//!
//! with S1, S2 Schlick's Fresnel of the front and back coatings' Ks at u = |wi . h'|, h' the
//! normalised (wi.x + wo.x, wi.y + wo.y, wi.z - wo.z) (wo mirrored to wi's side), and
//! cos_front, cos_back the cosines of the direction on each side. Both lobes are symmetric in
//! wo and wi, so f is reciprocal. As with `glossy`, each coating has r = uroughness x
//! vroughness and Schlick's anisotropy from them, in the same tangent frame on both sides
//! (mirroring wo and wi through the surface keeps their x and y).
//!
//! Sampling: like LuxRender's `MultiBSDF` of its two components, reflection or transmission
//! with probability 1/2 each (reflection always when the transmission is black); reflection
//! samples the side's coated lobe, transmission a cosine-weighted direction on the other side.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

use super::BsdfSample;
use super::coated_glossy::CoatedGlossy;
use super::schlick_distribution::{half_vector, schlick_g};
use crate::math::normalize_or;
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};

/// One side's coating: LuxRender's `glossy` lobe and its `multibounce` switch.
#[derive(Clone, Copy, Debug)]
pub struct Coating {
    pub lobe: CoatedGlossy,
    pub multibounce: bool,
}

#[derive(Clone, Copy, Debug)]
pub struct GlossyTranslucent {
    /// The front coating (the side the normal points to) and the back one; both lobes hold the
    /// same diffuse Kd.
    pub front: Coating,
    pub back: Coating,
    /// Kt, the diffuse transmission colour.
    pub transmittance: Vec3,
}

/// `w` mirrored through the surface.
fn mirrored(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

impl Coating {
    /// The reflection lobe for wo and wi above the surface.
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let f = self.lobe.eval(wo, wi);
        if !self.multibounce || f == Vec3::ZERO {
            return f;
        }
        let Some((_, cos_wh)) = half_vector(wo, wi) else {
            return f;
        };
        let ks = self.lobe.specular;
        let s = ks + (Vec3::ONE - ks) * (1.0 - cos_wh).powi(5);
        let r = self.lobe.roughness;
        let g = schlick_g(r, wo.z) * schlick_g(r, wi.z);
        f + s * ((1.0 - g) / (4.0 * PI * wo.z * wi.z)).clamp(0.0, 1.0)
    }

    /// Schlick's Fresnel term of the coating at cosine `u`.
    fn fresnel(&self, u: f32) -> Vec3 {
        let ks = self.lobe.specular;
        ks + (Vec3::ONE - ks) * (1.0 - u).powi(5)
    }

    /// The coating's transmittance along a direction of cosine `cos` (Beer-Lambert).
    fn absorption(&self, cos: f32) -> Vec3 {
        if self.lobe.depth > 0.0 {
            (-self.lobe.absorption * (self.lobe.depth / cos)).exp()
        } else {
            Vec3::ONE
        }
    }
}

impl GlossyTranslucent {
    /// The colour transmission carries at most, Kt (1 - Kd).
    fn transmission_weight(&self) -> Vec3 {
        self.transmittance * (Vec3::ONE - self.front.lobe.diffuse)
    }

    fn transmission_probability(&self) -> f32 {
        if self.transmission_weight().max_element() > 0.0 {
            0.5
        } else {
            0.0
        }
    }

    /// The side's coating and the directions brought above it.
    fn side(&self, wo: Vec3, wi: Vec3) -> (&Coating, Vec3, Vec3) {
        if wo.z > 0.0 {
            (&self.front, wo, wi)
        } else {
            (&self.back, mirrored(wo), mirrored(wi))
        }
    }

    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let side = wo.z * wi.z;
        if side > 0.0 {
            let (coating, wo, wi) = self.side(wo, wi);
            return coating.eval(wo, wi);
        }
        if side == 0.0 {
            return Vec3::ZERO;
        }
        let h = normalize_or(Vec3::new(wi.x + wo.x, wi.y + wo.y, wi.z - wo.z), Vec3::ZERO);
        let u = wi.dot(h).abs();
        let (s1, s2) = (self.front.fresnel(u), self.back.fresnel(u));
        let s = (Vec3::ONE - s1) * (Vec3::ONE - s2) / (Vec3::ONE - (s1 + s2) * 0.5);
        let (front, back) = if wi.z > 0.0 { (wi, wo) } else { (wo, wi) };
        let absorption = self.front.absorption(front.z) * self.back.absorption(-back.z);
        self.transmission_weight() * FRAC_1_PI * s * absorption
    }

    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let p_t = self.transmission_probability();
        let side = wo.z * wi.z;
        if side > 0.0 {
            let (coating, wo, wi) = self.side(wo, wi);
            (1.0 - p_t) * coating.lobe.pdf(wo, wi)
        } else if side < 0.0 {
            p_t * cosine_hemisphere_pdf(wi.z.abs())
        } else {
            0.0
        }
    }

    /// `uc` chooses reflection or transmission, `u` the direction.
    pub fn sample(&self, wo: Vec3, u: Vec2, uc: f32) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let wi = if uc < self.transmission_probability() {
            let wi = cosine_hemisphere(u);
            if wo.z > 0.0 { mirrored(wi) } else { wi }
        } else {
            let (coating, above, _) = self.side(wo, wo);
            let wi = coating.lobe.sample(above, u)?.wi;
            if wo.z > 0.0 { wi } else { mirrored(wi) }
        };
        BsdfSample::glossy(wi, self.eval(wo, wi), self.pdf(wo, wi))
    }

    /// A grey-level estimate: the front coating's reflection plus the transmission.
    pub fn albedo(&self) -> Vec3 {
        let ks = self.front.lobe.specular;
        ks + (Vec3::ONE - ks) * self.front.lobe.diffuse + self.transmission_weight()
    }
}
