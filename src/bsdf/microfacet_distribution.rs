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

    /// D(wm), G(wo, wi) in the form `masking` and the density of [`Microfacet::sample_wm`] from
    /// `wo` at `wm`, as `d`, `g` and `pdf_wm` give them (the same bits), with D(wm) and Smith's
    /// term for `wo` computed once for all three: a rough BSDF's eval and pdf at one pair of
    /// directions (next-event estimation, a sample's weight) need all three.
    pub fn d_g_pdf_wm(&self, wo: Vec3, wi: Vec3, wm: Vec3, masking: Masking) -> (f32, f32, f32) {
        match self {
            Microfacet::TrowbridgeReitz(d) => {
                let dm = d.d(wm);
                let lambda_o = d.lambda(wo);
                let g1_o = 1.0 / (1.0 + lambda_o);
                let g = match masking {
                    Masking::HeightCorrelated => 1.0 / (1.0 + lambda_o + d.lambda(wi)),
                    Masking::Separable => g1_o * d.g1(wi),
                };
                // `TrowbridgeReitz::d_visible` with G1(wo) and D(wm) known.
                let pdf_wm = if wo.z <= 0.0 {
                    0.0
                } else {
                    g1_o * wo.dot(wm).max(0.0) * dm / wo.z
                };
                (dm, g, pdf_wm)
            }
            Microfacet::Beckmann(d) => {
                let dm = d.d(wm);
                let g1_o = d.g1(wo);
                let g = match masking {
                    // Beckmann's Lambda is 1 / G1 - 1.
                    Masking::HeightCorrelated => 1.0 / (1.0 + (1.0 / g1_o - 1.0) + d.lambda(wi)),
                    Masking::Separable => g1_o * d.g1(wi),
                };
                // `Beckmann::pdf_wm` with D(wm) known.
                (dm, g, dm * wm.z.max(0.0))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::warp::uniform_sphere;

    /// The shared terms are the separate ones to the bit, for both distributions, both forms of
    /// G, anisotropic roughness and directions on both sides (wm from the half vector).
    #[test]
    fn shared_terms_match_separate_ones_to_the_bit() {
        let grid = |k: u32, n: u32| (k as f32 + 0.5) / n as f32;
        let directions: Vec<Vec3> = (0..12)
            .flat_map(|i| (0..12).map(move |j| uniform_sphere(Vec2::new(grid(i, 12), grid(j, 12)))))
            .collect();
        for kind in [
            DistributionKind::TrowbridgeReitz,
            DistributionKind::Beckmann,
        ] {
            for (ax, ay) in [(0.08, 0.08), (0.3, 0.05), (0.9, 0.6)] {
                let distribution = Microfacet::new(kind, ax, ay);
                for masking in [Masking::HeightCorrelated, Masking::Separable] {
                    for &wo in &directions {
                        for &wi in &directions {
                            let wm = (wo + wi).normalize_or(Vec3::Z);
                            let shared = distribution.d_g_pdf_wm(wo, wi, wm, masking);
                            let separate = (
                                distribution.d(wm),
                                distribution.g(wo, wi, masking),
                                distribution.pdf_wm(wo, wm),
                            );
                            let bits = |(a, b, c): (f32, f32, f32)| {
                                [a.to_bits(), b.to_bits(), c.to_bits()]
                            };
                            assert_eq!(bits(shared), bits(separate), "{kind:?} {masking:?}");
                        }
                    }
                }
            }
        }
    }
}
