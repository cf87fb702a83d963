//! BSDF sampling covers every direction a BSDF scatters light into: where f(wo, wi) > 0 its
//! density is positive, so BSDF sampling alone is an unbiased estimator of the light arriving
//! from any direction. The path tracer relies on it: next-event estimation leaves a constant
//! sky to BSDF sampling (`Environment::sample_for_mis`, pbrt-v4's `allowIncompletePDF`), and
//! samples only the part of an environment map above its mean. A BSDF that missed a region
//! would lose the sky's light there: it would have to keep light sampling of the sky.
//!
//! Every kind is listed (an exhaustive match: a new kind does not compile until it is added),
//! and for each, at outgoing directions above and below the surface:
//! - pointwise, on a grid of incoming directions over the sphere: f > 0 implies pdf > 0;
//! - on average: the mean of f |cos| / pdf over the non-delta samples equals the integral of
//!   f |cos| over the sphere (by quadrature) within five standard errors of the mean plus the
//!   quadrature's error. A sampler that misses a region where f > 0 falls short by that region's
//!   share of the integral.

use foton::bsdf::coated_glossy::coating_f0;
use foton::bsdf::glossy_translucent::{Coating, GlossyTranslucent};
use foton::bsdf::lafortune::{LafortuneFit, LafortuneLobe};
use foton::bsdf::microfacet::TrowbridgeReitz;
use foton::bsdf::microfacet_distribution::{DistributionKind, Masking, Microfacet};
use foton::bsdf::oren_nayar::oren_nayar_ab;
use foton::bsdf::phong_distribution::PhongDistribution;
use foton::bsdf::plastic::internal_reflectance;
use foton::bsdf::rough_plastic::CoatingTables;
use foton::bsdf::thin_film::ThinFilm;
use foton::bsdf::{
    BlinnPlastic, Bsdf, CarPaint, CarPaintLobe, CoatedGlossy, ConductorFresnel, DiffuseTranslucent,
    FresnelBlend, Lafortune, Plastic, RoughConductor, RoughDielectric, RoughPlastic, ShinyMetal,
    SmoothConductor, ThinDielectric, Velvet,
};
use glam::{Vec2, Vec3};
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;

use crate::common::bsdf_estimates::{quadrature, uniform};

/// The number of BSDF kinds; `kind` numbers them.
const KINDS: usize = 20;

/// Each kind's number: exhaustive, so a kind added to `Bsdf` must be added here (and to `cases`).
fn kind(bsdf: &Bsdf) -> usize {
    match bsdf {
        Bsdf::Lambertian { .. } => 0,
        Bsdf::SpecularReflection { .. } => 1,
        Bsdf::Dielectric { .. } => 2,
        Bsdf::Conductor { .. } => 3,
        Bsdf::OrenNayar { .. } => 4,
        Bsdf::CoatedGlossy(_) => 5,
        Bsdf::RoughDielectric(_) => 6,
        Bsdf::ThinDielectric(_) => 7,
        Bsdf::DiffuseTranslucent(_) => 8,
        Bsdf::Plastic(_) => 9,
        Bsdf::RoughPlastic(_) => 10,
        Bsdf::RoughConductor(_) => 11,
        Bsdf::SmoothConductor(_) => 12,
        Bsdf::ShinyMetal(_) => 13,
        Bsdf::Velvet(_) => 14,
        Bsdf::CarPaint(_) => 15,
        Bsdf::GlossyTranslucent(_) => 16,
        Bsdf::BlinnPlastic(_) => 17,
        Bsdf::FresnelBlend(_) => 18,
        Bsdf::Lafortune(_) => 19,
    }
}

fn glossy(diffuse: Vec3, specular: Vec3, roughness: f32) -> CoatedGlossy {
    CoatedGlossy {
        diffuse,
        specular,
        absorption: Vec3::new(0.5, 0.2, 0.0),
        depth: 0.1,
        roughness,
        anisotropy: 0.0,
    }
}

/// At least one BSDF of every kind, with parameters where a lobe's sampling probability is
/// small (weak coatings, dark bases), where sampling is most likely to leave a gap.
fn cases() -> Vec<Bsdf> {
    let (on_a, on_b) = oren_nayar_ab(20f32.to_radians());
    let coating = |diffuse, specular, roughness, multibounce| Coating {
        lobe: glossy(Vec3::splat(diffuse), Vec3::splat(specular), roughness),
        multibounce,
    };
    vec![
        Bsdf::Lambertian {
            reflectance: Vec3::new(0.2, 0.5, 0.9),
        },
        Bsdf::SpecularReflection {
            reflectance: Vec3::ONE,
        },
        Bsdf::Dielectric {
            reflectance: Vec3::ONE,
            transmittance: Vec3::ONE,
            eta: 1.5,
        },
        Bsdf::Conductor {
            f0: Vec3::new(0.95, 0.64, 0.54),
            alpha_x: 0.3,
            alpha_y: 0.1,
        },
        Bsdf::OrenNayar {
            reflectance: Vec3::splat(0.8),
            a: on_a,
            b: on_b,
        },
        Bsdf::CoatedGlossy(glossy(Vec3::splat(0.5), Vec3::splat(0.04), 0.1)),
        Bsdf::CoatedGlossy(glossy(Vec3::splat(0.02), coating_f0(Vec3::ONE, 1.5), 0.01)),
        Bsdf::RoughDielectric(RoughDielectric {
            reflectance: Vec3::ONE,
            transmittance: Vec3::ONE,
            eta: 1.5,
            distribution: Microfacet::TrowbridgeReitz(TrowbridgeReitz::new(0.3, 0.3)),
        }),
        Bsdf::RoughDielectric(RoughDielectric {
            reflectance: Vec3::ONE,
            transmittance: Vec3::ONE,
            eta: 1.33,
            distribution: Microfacet::new(DistributionKind::Beckmann, 0.2, 0.4),
        }),
        Bsdf::ThinDielectric(ThinDielectric {
            reflectance: Vec3::ONE,
            transmittance: Vec3::ONE,
            eta: 1.5,
        }),
        Bsdf::DiffuseTranslucent(DiffuseTranslucent {
            reflectance: Vec3::new(0.3, 0.5, 0.1),
            transmittance: Vec3::new(0.6, 0.2, 0.9),
            a: on_a,
            b: on_b,
        }),
        Bsdf::Plastic(Plastic {
            diffuse: Vec3::new(0.5, 0.1, 0.05),
            specular: Vec3::ONE,
            eta: 1.5,
            internal_reflectance: internal_reflectance(1.5),
            nonlinear: false,
        }),
        Bsdf::RoughPlastic(RoughPlastic {
            diffuse: Vec3::new(0.05, 0.3, 0.5),
            specular: Vec3::ONE,
            eta: 1.5,
            distribution: TrowbridgeReitz::new(0.2, 0.2),
            nonlinear: true,
            tables: CoatingTables::of(0.2, 1.5),
        }),
        Bsdf::RoughConductor(RoughConductor {
            reflectance: Vec3::ONE,
            fresnel: ConductorFresnel::Complex {
                eta: Vec3::new(0.2, 0.9, 1.1),
                k: Vec3::new(3.9, 2.4, 2.2),
            },
            distribution: Microfacet::new(DistributionKind::Beckmann, 0.05, 0.5),
            masking: Masking::Separable,
        }),
        Bsdf::SmoothConductor(SmoothConductor {
            reflectance: Vec3::ONE,
            eta: Vec3::new(0.2, 0.9, 1.1),
            k: Vec3::new(3.9, 2.4, 2.2),
        }),
        Bsdf::ShinyMetal(ShinyMetal {
            glossy: Vec3::new(0.6, 0.5, 0.3),
            mirror: Vec3::splat(0.7),
            roughness: 0.05,
            anisotropy: 0.6,
            film: Some(ThinFilm {
                thickness: 300.0,
                index: 1.4,
            }),
        }),
        Bsdf::Velvet(Velvet {
            reflectance: Vec3::new(0.3, 0.5, 0.9),
            legendre: [-2.0, 20.0, 2.0],
            thickness: 0.1,
        }),
        Bsdf::CarPaint(CarPaint {
            base: CoatedGlossy {
                specular: Vec3::ZERO,
                roughness: 1.0,
                anisotropy: 0.0,
                ..glossy(Vec3::new(0.01, 0.02, 0.1), Vec3::ZERO, 1.0)
            },
            lobes: [(0.3, 0.15, 0.32), (0.2, 0.087, 0.11), (0.1, 0.9, 0.013)].map(
                |(ks, f0, roughness)| CarPaintLobe {
                    specular: Vec3::splat(ks),
                    f0,
                    roughness,
                },
            ),
        }),
        Bsdf::GlossyTranslucent(GlossyTranslucent {
            front: coating(0.3, 0.1, 0.05, true),
            back: coating(0.3, 0.3, 0.3, false),
            transmittance: Vec3::new(0.9, 0.6, 0.3),
        }),
        Bsdf::BlinnPlastic(BlinnPlastic {
            diffuse: Vec3::new(0.02, 0.05, 0.1),
            specular: Vec3::ONE,
            distribution: PhongDistribution::from_roughness(0.05, 0.05),
        }),
        Bsdf::FresnelBlend(FresnelBlend {
            diffuse: Vec3::new(0.03, 0.02, 0.05),
            specular: Vec3::splat(0.1),
            distribution: PhongDistribution::from_roughness(0.02, 0.1),
        }),
        Bsdf::Lafortune(Lafortune { fit: &GRAZING_FIT }),
    ]
}

/// A Lafortune fit with a dark diffuse term, a lobe towards grazing angles whose sampling axis
/// points below the surface (Cz < 0, as in LuxRender's `clay` and `skin`), a retro-reflecting
/// and a forward lobe.
const GRAZING_FIT: LafortuneFit = LafortuneFit {
    diffuse: Vec3::new(0.02, 0.02, 0.02),
    lobes: [
        LafortuneLobe {
            xy: Vec3::splat(-1.1),
            z: Vec3::splat(-1.4),
            exponent: Vec3::splat(15.0),
        },
        LafortuneLobe {
            xy: Vec3::splat(0.8),
            z: Vec3::splat(0.7),
            exponent: Vec3::splat(20.0),
        },
        LafortuneLobe {
            xy: Vec3::splat(-1.0),
            z: Vec3::splat(0.9),
            exponent: Vec3::splat(60.0),
        },
    ],
};

/// Outgoing directions above the surface, grazing, and below it (two-sided and transmitting
/// kinds scatter from there too; the others give nothing, on both sides of the comparison).
fn outgoing() -> [Vec3; 4] {
    [0.3f32, 1.3, 2.0, 2.8]
        .map(|theta| Vec3::new(theta.sin() * 0.6, theta.sin() * 0.8, theta.cos()))
}

#[test]
fn every_bsdf_kind_is_covered_by_the_cases() {
    let mut seen = [false; KINDS];
    for bsdf in cases() {
        seen[kind(&bsdf)] = true;
    }
    let missing: Vec<usize> = (0..KINDS).filter(|&k| !seen[k]).collect();
    assert!(missing.is_empty(), "kinds without a case: {missing:?}");
}

/// On a grid of 400 x 800 incoming directions (midpoints in (cos theta, phi)), wherever any
/// channel of f is positive, the density is too. Positive means above 1e-20: far in the tails
/// of a microfacet lobe D underflows to an f32 denormal, and the density, D times factors below
/// one, to 0 where f, divided by small cosines, does not; light there is below any rounding.
#[test]
fn bsdf_density_is_positive_wherever_it_scatters() {
    let (nz, nphi) = (400, 800);
    for bsdf in cases() {
        for wo in outgoing() {
            for iz in 0..nz {
                let z = -1.0 + 2.0 * (iz as f32 + 0.5) / nz as f32;
                let r = (1.0 - z * z).sqrt();
                for ip in 0..nphi {
                    let phi = 2.0 * std::f32::consts::PI * (ip as f32 + 0.5) / nphi as f32;
                    let wi = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                    if bsdf.eval(wo, wi).max_element() > 1e-20 {
                        let pdf = bsdf.pdf(wo, wi);
                        assert!(pdf > 0.0, "{bsdf:?}: f > 0 but pdf 0 at wo {wo}, wi {wi}");
                    }
                }
            }
        }
    }
}

/// BSDF sampling alone, as it estimates the light of a constant white sky: the mean of
/// f |cos| / pdf over the non-delta samples against the quadrature of f |cos| over the sphere.
#[test]
fn bsdf_sampling_alone_integrates_f_cos_over_the_sphere() {
    const N: usize = 400_000;
    for (case, bsdf) in cases().into_iter().enumerate() {
        for (i, wo) in outgoing().into_iter().enumerate() {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64((100 * case + i) as u64);
            let (mut sum, mut sum2) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
            for _ in 0..N {
                let u = Vec2::new(uniform(&mut rng), uniform(&mut rng));
                let Some(s) = bsdf.sample(wo, u, uniform(&mut rng)) else {
                    continue;
                };
                if s.delta {
                    continue;
                }
                let x = (s.f * s.wi.z.abs() / s.pdf).as_dvec3();
                sum += x;
                sum2 += x * x;
            }
            let mean = sum / N as f64;
            let standard_error =
                ((sum2 / N as f64 - mean * mean).max(glam::DVec3::ZERO) / N as f64).powf(0.5);
            let exact = quadrature(&bsdf, wo, -1.0).as_dvec3();
            // The midpoint rule's error on f |cos| (kinks at the horizon, sharp lobes): 0.5 %,
            // plus an absolute 1e-4 for kinds that scatter nothing from this side.
            let bound = 5.0 * standard_error + 0.005 * exact + glam::DVec3::splat(1e-4);
            assert!(
                ((mean - exact).abs() - bound).max_element() <= 0.0,
                "{bsdf:?} wo {wo}: sampled {mean} quadrature {exact} bound {bound}"
            );
        }
    }
}
