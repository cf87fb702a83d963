//! The microfacet distributions a rough BSDF can be built on (Mitsuba's `distribution`
//! parameter), and the two forms of Smith's masking-shadowing term.

use super::beckmann::Beckmann;
use super::microfacet::{Alphas, TrowbridgeReitz};
use glam::{Vec2, Vec3};

/// Which distribution, before its alphas are known.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DistributionKind {
    Beckmann,
    TrowbridgeReitz,
}

/// A distribution of microfacet normals with its roughness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Microfacet {
    TrowbridgeReitz(TrowbridgeReitz),
    Beckmann(Beckmann),
}

/// How G(wo, wi) is formed from the one-direction terms.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Masking {
    /// 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz 2014, eq. 99; pbrt-v4).
    HeightCorrelated,
    /// G1(wo) G1(wi) (Walter et al. 2007, eq. 23; Mitsuba 3's `G`).
    Separable,
}

impl Microfacet {
    /// `kind` with roughness `alpha_x` along the local x axis and `alpha_y` along y.
    pub fn new(kind: DistributionKind, alpha_x: f32, alpha_y: f32) -> Self {
        match kind {
            DistributionKind::Beckmann => Microfacet::Beckmann(Beckmann::new(alpha_x, alpha_y)),
            DistributionKind::TrowbridgeReitz => {
                Microfacet::TrowbridgeReitz(TrowbridgeReitz::new(alpha_x, alpha_y))
            }
        }
    }

    /// Whether the roughness differs along the local x and y axes (the frame's x axis then
    /// matters).
    pub fn is_anisotropic(&self) -> bool {
        self.alpha().is_anisotropic()
    }

    /// The roughness along the local x and y axes.
    pub fn alphas(&self) -> (f32, f32) {
        let alpha = self.alpha();
        (alpha.x, alpha.y)
    }

    fn alpha(&self) -> Alphas {
        match self {
            Microfacet::TrowbridgeReitz(d) => d.alpha,
            Microfacet::Beckmann(d) => d.alpha,
        }
    }

    /// D(wm), normalised to unit projected area.
    pub fn d(&self, wm: Vec3) -> f32 {
        match self {
            Microfacet::TrowbridgeReitz(d) => d.d(wm),
            Microfacet::Beckmann(d) => d.d(wm),
        }
    }

    /// Smith's masking G1(w).
    pub fn g1(&self, w: Vec3) -> f32 {
        match self {
            Microfacet::TrowbridgeReitz(d) => d.g1(w),
            Microfacet::Beckmann(d) => d.g1(w),
        }
    }

    /// G(wo, wi) in the form `masking`.
    pub fn g(&self, wo: Vec3, wi: Vec3, masking: Masking) -> f32 {
        match masking {
            Masking::Separable => self.g1(wo) * self.g1(wi),
            Masking::HeightCorrelated => {
                let lambda = |w| match self {
                    Microfacet::TrowbridgeReitz(d) => d.lambda(w),
                    Microfacet::Beckmann(d) => d.lambda(w),
                };
                1.0 / (1.0 + lambda(wo) + lambda(wi))
            }
        }
    }

    /// A normal for viewing direction `w` (w.z > 0): GGX draws the normals visible from `w`,
    /// Beckmann the whole distribution (see `beckmann.rs`).
    pub fn sample_wm(&self, w: Vec3, u: Vec2) -> Vec3 {
        match self {
            Microfacet::TrowbridgeReitz(d) => d.sample_wm(w, u),
            Microfacet::Beckmann(d) => d.sample_wm(u),
        }
    }

    /// The density of [`Microfacet::sample_wm`] per solid angle of wm.
    pub fn pdf_wm(&self, w: Vec3, wm: Vec3) -> f32 {
        match self {
            Microfacet::TrowbridgeReitz(d) => d.d_visible(w, wm),
            Microfacet::Beckmann(d) => d.pdf_wm(wm),
        }
    }
}
