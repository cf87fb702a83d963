//! Materials: what each primitive's material index means at a hit. A material resolves, at a
//! surface point, to one BSDF (or none, for `null`).

pub mod bump;
pub mod texels;
pub mod texture;

use std::cell::Cell;

use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};

use crate::bsdf::glossy_translucent::Coating;
use crate::bsdf::lafortune::LafortuneFit;
use crate::bsdf::microfacet::TrowbridgeReitz;
use crate::bsdf::microfacet_distribution::{Masking, Microfacet};
use crate::bsdf::oren_nayar::oren_nayar_ab;
use crate::bsdf::phong_distribution::PhongDistribution;
use crate::bsdf::rough_plastic::CoatingTables;
use crate::bsdf::thin_film::ThinFilm;
use crate::bsdf::{
    BlinnPlastic, Bsdf, CarPaint, CarPaintLobe, CoatedGlossy, ConductorFresnel, DiffuseTranslucent,
    FresnelBlend, GlossyTranslucent, Lafortune, Plastic, RoughConductor, RoughDielectric,
    RoughPlastic, ShinyMetal, SmoothConductor, ThinDielectric, Velvet,
};
use crate::texture::ShadingPoint;
use bump::BumpMap;
use texture::TextureTable;

/// Mixes nest at most this deep; deeper chains (only a cycle makes one) resolve to black matte.
const MAX_MIX_DEPTH: usize = 8;

/// A colour input: a constant, or a texture of the [`TextureTable`] looked up at the hit's uv.
/// A float input is one too, read as the mean of its channels (the texture graph's rule).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Color {
    Constant(Vec3),
    Texture(usize),
}

/// One material: a BSDF with its inputs, or a rule choosing another material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Material {
    Lambertian {
        reflectance: Color,
    },
    /// Oren-Nayar with the facet slope deviation in degrees (a float input).
    OrenNayar {
        reflectance: Color,
        sigma_degrees: Color,
    },
    CoatedGlossy {
        diffuse: Color,
        specular: Color,
        absorption: Color,
        depth: f32,
        roughness: f32,
        anisotropy: f32,
    },
    SpecularReflection {
        reflectance: Color,
    },
    /// `eta` = index inside / index outside.
    Dielectric {
        reflectance: Color,
        transmittance: Color,
        eta: f32,
    },
    /// GGX alphas (clamped by the BSDF) and Schlick's reflectance at normal incidence.
    Conductor {
        f0: Color,
        alpha_x: f32,
        alpha_y: f32,
    },
    /// Diffuse reflection of `reflectance` and diffuse transmission of `transmittance`, both
    /// Oren-Nayar of the slope deviation in degrees (a float input).
    DiffuseTranslucent {
        reflectance: Color,
        transmittance: Color,
        sigma_degrees: Color,
    },
    /// A conductor of complex index `eta` + i `k` with the exact Fresnel term, scaled by
    /// `reflectance`: a mirror for `distribution` None, else rough (Mitsuba's separable masking).
    ComplexConductor {
        reflectance: Color,
        eta: Vec3,
        k: Vec3,
        distribution: Option<Microfacet>,
    },
    /// Microfacet reflection and refraction; `eta` = index inside / index outside.
    RoughDielectric {
        reflectance: Color,
        transmittance: Color,
        eta: f32,
        distribution: Microfacet,
    },
    /// A thin sheet of relative index `eta`.
    ThinDielectric {
        reflectance: Color,
        transmittance: Color,
        eta: f32,
    },
    /// A diffuse base under a smooth coating of relative index `eta`; `internal_reflectance`
    /// from `bsdf::plastic::internal_reflectance`.
    Plastic {
        diffuse: Color,
        specular: Color,
        eta: f32,
        internal_reflectance: f32,
        nonlinear: bool,
    },
    /// A diffuse base under a GGX coating of roughness `alpha` and relative index `eta`.
    RoughPlastic {
        diffuse: Color,
        specular: Color,
        eta: f32,
        alpha: f32,
        nonlinear: bool,
        tables: &'static CoatingTables,
    },
    /// LuxRender's `shinymetal`: a mirror and a Schlick lobe of roughness r, their Fresnel
    /// terms fitted to `mirror` and `glossy`.
    FittedConductor {
        glossy: Color,
        mirror: Color,
        roughness: f32,
        anisotropy: f32,
        film: Option<ThinFilm>,
    },
    /// Asperity scattering: Legendre coefficients of the phase function, optical thickness.
    Velvet {
        reflectance: Color,
        legendre: [f32; 3],
        thickness: f32,
    },
    /// Three Schlick lobes over a diffuse base under an absorbing clear coat.
    CarPaint {
        diffuse: Color,
        absorption: Color,
        depth: f32,
        lobes: [PaintLobe; 3],
    },
    /// LuxRender's `glossytranslucent`: a coating on each side of a diffusely transmitting
    /// sheet over the diffuse base `diffuse`.
    GlossyTranslucent {
        diffuse: Color,
        transmittance: Color,
        front: GlossyCoating,
        back: GlossyCoating,
    },
    /// LuxRender 0.x's `plastic`: Lambertian plus a Blinn lobe.
    BlinnPlastic {
        diffuse: Color,
        specular: Color,
        distribution: PhongDistribution,
    },
    /// LuxRender 0.x's `substrate`: Ashikhmin and Shirley's diffuse and glossy BRDF.
    FresnelBlend {
        diffuse: Color,
        specular: Color,
        distribution: PhongDistribution,
    },
    /// A measured BRDF of generalized cosine lobes.
    Lafortune(&'static LafortuneFit),
    /// Rays pass through.
    Null,
    /// `amount` (a float input) of material `second`, `1 - amount` of `first`.
    Mix {
        first: usize,
        second: usize,
        amount: Color,
    },
    /// Material `material` with its shading normal perturbed by a bump map.
    Bump {
        material: usize,
        bump: BumpMap,
    },
    /// Material `material` from the front, black from the back (see [`MaterialTable::is_one_sided`]).
    OneSided {
        material: usize,
    },
}

/// One side's coating of [`Material::GlossyTranslucent`]: as [`Material::CoatedGlossy`]'s, and
/// its `multibounce` switch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlossyCoating {
    pub specular: Color,
    pub absorption: Color,
    pub depth: f32,
    pub roughness: f32,
    pub anisotropy: f32,
    pub multibounce: bool,
}

/// One specular lobe of [`Material::CarPaint`]: its colour, normal-incidence Fresnel
/// reflectance and roughness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaintLobe {
    pub specular: Color,
    pub f0: f32,
    pub roughness: f32,
}

#[derive(Resource, Clone, Debug)]
pub struct MaterialTable {
    pub materials: Vec<Material>,
    /// Per material, its BSDF when that is the same at every point (a scattering material
    /// whose inputs are all constants, or a one-sided wrapper of one), built once here rather
    /// than at every hit.
    fixed: Vec<Option<Bsdf>>,
}

/// The BSDF of `m` when it is the same at every point: a scattering material that reads no
/// texture while its BSDF is built (so every input the BSDF depends on is a constant).
fn constant_bsdf(m: &Material) -> Option<Bsdf> {
    let constants = Inputs {
        textures: None,
        read_texture: Cell::new(false),
    };
    let anywhere = ShadingPoint {
        p: Vec3::ZERO,
        uv: Vec2::ZERO,
        n: Vec3::Z,
        object: 0,
    };
    let bsdf = constants.bsdf(m, &anywhere)?;
    (!constants.read_texture.get()).then_some(bsdf)
}

impl MaterialTable {
    pub fn new(materials: Vec<Material>) -> Self {
        let constant: Vec<Option<Bsdf>> = materials.iter().map(constant_bsdf).collect();
        // A one-sided material scatters as the one it wraps (its side is checked apart, by
        // `is_one_sided`); chains are followed as far as `bsdf_at` follows them.
        let fixed = (0..materials.len())
            .map(|mut id| {
                for _ in 0..MAX_MIX_DEPTH {
                    match materials[id] {
                        Material::OneSided { material } if material < materials.len() => {
                            id = material;
                        }
                        _ => return constant[id],
                    }
                }
                None
            })
            .collect();
        Self { materials, fixed }
    }

    /// Whether any material is a mix: the only reader of `bsdf_at`'s `choice`.
    pub fn has_mix(&self) -> bool {
        (self.materials.iter()).any(|m| matches!(m, Material::Mix { .. }))
    }

    /// Whether every material has a BSDF that is the same everywhere (no null material among
    /// them) and `holds` for it.
    pub fn every_bsdf(&self, holds: impl Fn(&Bsdf) -> bool) -> bool {
        (self.fixed.iter()).all(|bsdf| bsdf.as_ref().is_some_and(&holds))
    }

    /// Whether any material reads a texture (the geometry then keeps uvs): a bump map, a mix
    /// of textured amount, or a scattering material whose BSDF is not constant.
    pub fn uses_textures(&self) -> bool {
        (self.materials.iter().zip(&self.fixed)).any(|(m, fixed)| match m {
            Material::Bump { .. } => true,
            Material::Mix { amount, .. } => matches!(amount, Color::Texture(_)),
            Material::Null | Material::OneSided { .. } => false,
            _ => fixed.is_none(),
        })
    }

    /// Whether the geometry must keep uvs: a material reads a texture, or orients anisotropic
    /// roughness along dp/du.
    pub fn needs_uvs(&self) -> bool {
        self.uses_textures()
            || self.materials.iter().any(|m| match m {
                Material::Conductor {
                    alpha_x, alpha_y, ..
                } => alpha_x != alpha_y,
                Material::ComplexConductor {
                    distribution: Some(d),
                    ..
                }
                | Material::RoughDielectric {
                    distribution: d, ..
                } => d.is_anisotropic(),
                Material::FresnelBlend { distribution, .. } => distribution.ex != distribution.ey,
                _ => false,
            })
    }

    /// Whether material `id` is `null`: rays, shadow rays included, pass through it.
    pub fn is_null(&self, id: u32) -> bool {
        matches!(self.materials.get(id as usize), Some(Material::Null))
    }

    /// Whether material `id` scatters only toward the side its surface's normal faces (a
    /// [`Material::OneSided`]; one inside a mix counts as its material, two-sided).
    pub fn is_one_sided(&self, id: u32) -> bool {
        matches!(
            self.materials.get(id as usize),
            Some(Material::OneSided { .. })
        )
    }

    /// The BSDF of material `id` when it is the same at every point (see `fixed`).
    pub fn fixed_bsdf(&self, id: u32) -> Option<&Bsdf> {
        self.fixed.get(id as usize)?.as_ref()
    }

    /// The BSDF of material `id` at `sp`; `None` for `null` (the ray passes through).
    /// `choice` in [0,1) picks the side of each mix (and is remapped for the next one);
    /// `bump` is called with each bump map met on the way, outermost first, and may change the
    /// normal of `sp` (which the BSDF's textures then see).
    pub fn bsdf_at(
        &self,
        id: u32,
        sp: &mut ShadingPoint,
        textures: Option<&TextureTable>,
        mut choice: f32,
        mut bump: impl FnMut(&BumpMap, &mut ShadingPoint),
    ) -> Option<Bsdf> {
        let inputs = Inputs {
            textures,
            read_texture: Cell::new(false),
        };
        if let Some(bsdf) = self.fixed_bsdf(id) {
            return Some(*bsdf);
        }
        let mut id = id as usize;
        // A textured Lambertian, the common varying material: the loop's first step (a leaf,
        // not fixed) and `Inputs::bsdf`'s first arm, without the general match.
        if let Some(Material::Lambertian { reflectance }) = self.materials.get(id) {
            return Some(Bsdf::Lambertian {
                reflectance: inputs.color(reflectance, sp),
            });
        }
        for _ in 0..MAX_MIX_DEPTH {
            match self.materials.get(id)? {
                Material::Mix {
                    first,
                    second,
                    amount,
                } => {
                    let amount = inputs.float(amount, sp).clamp(0.0, 1.0);
                    if choice < amount {
                        choice /= amount;
                        id = *second;
                    } else {
                        choice = (choice - amount) / (1.0 - amount);
                        id = *first;
                    }
                }
                Material::OneSided { material } => {
                    id = *material;
                }
                Material::Bump {
                    material,
                    bump: map,
                } => {
                    bump(map, sp);
                    id = *material;
                }
                leaf => return self.fixed[id].or_else(|| inputs.bsdf(leaf, sp)),
            }
        }
        Some(Bsdf::Lambertian {
            reflectance: Vec3::ZERO,
        })
    }
}

/// Reads a material's inputs at a shading point.
struct Inputs<'a> {
    textures: Option<&'a TextureTable>,
    /// Set when an input named a texture: the BSDF built then varies over the surface.
    read_texture: Cell<bool>,
}

impl Inputs<'_> {
    fn raw(&self, c: &Color, sp: &ShadingPoint) -> Vec3 {
        if matches!(c, Color::Texture(_)) {
            self.read_texture.set(true);
        }
        match (c, self.textures) {
            (Color::Constant(c), _) => *c,
            (Color::Texture(t), Some(table)) => table.lookup(*t, sp),
            (Color::Texture(_), None) => Vec3::splat(0.5),
        }
    }

    /// Colours are clamped to [0, 1], as LuxRender's materials clamp their textures' values
    /// (`materials/matte.cpp`, `glossy2.cpp`: `Kd->Evaluate(...).Clamp(0, 1)`): an unclamped
    /// `mix` driven by fbm can go negative.
    fn color(&self, c: &Color, sp: &ShadingPoint) -> Vec3 {
        self.raw(c, sp).clamp(Vec3::ZERO, Vec3::ONE)
    }

    /// A float input: the mean of the channels, unclamped (each material clamps its own).
    fn float(&self, c: &Color, sp: &ShadingPoint) -> f32 {
        let v = self.raw(c, sp);
        (v.x + v.y + v.z) / 3.0
    }

    /// The BSDF of a material that scatters (`None` for `null`, and for the mixes and bumps
    /// [`MaterialTable::bsdf_at`] resolves before).
    fn bsdf(&self, material: &Material, sp: &ShadingPoint) -> Option<Bsdf> {
        let color = |c: &Color| self.color(c, sp);
        Some(match material {
            Material::Lambertian { reflectance } => Bsdf::Lambertian {
                reflectance: color(reflectance),
            },
            Material::OrenNayar {
                reflectance,
                sigma_degrees,
            } => {
                // `materials/matte.cpp` clamps sigma to [0, 90] degrees.
                let (a, b) = oren_nayar_ab(self.float(sigma_degrees, sp).clamp(0.0, 90.0));
                Bsdf::OrenNayar {
                    reflectance: color(reflectance),
                    a,
                    b,
                }
            }
            Material::CoatedGlossy {
                diffuse,
                specular,
                absorption,
                depth,
                roughness,
                anisotropy,
            } => Bsdf::CoatedGlossy(CoatedGlossy {
                diffuse: color(diffuse),
                specular: color(specular),
                absorption: color(absorption),
                depth: *depth,
                roughness: *roughness,
                anisotropy: *anisotropy,
            }),
            Material::SpecularReflection { reflectance } => Bsdf::SpecularReflection {
                reflectance: color(reflectance),
            },
            Material::Dielectric {
                reflectance,
                transmittance,
                eta,
            } => Bsdf::Dielectric {
                reflectance: color(reflectance),
                transmittance: color(transmittance),
                eta: *eta,
            },
            Material::Conductor {
                f0,
                alpha_x,
                alpha_y,
            } => Bsdf::Conductor {
                f0: color(f0),
                alpha_x: *alpha_x,
                alpha_y: *alpha_y,
            },
            Material::GlossyTranslucent {
                diffuse,
                transmittance,
                front,
                back,
            } => {
                let coating = |c: &GlossyCoating| Coating {
                    lobe: CoatedGlossy {
                        diffuse: color(diffuse),
                        specular: color(&c.specular),
                        absorption: color(&c.absorption),
                        depth: c.depth,
                        roughness: c.roughness,
                        anisotropy: c.anisotropy,
                    },
                    multibounce: c.multibounce,
                };
                Bsdf::GlossyTranslucent(GlossyTranslucent {
                    front: coating(front),
                    back: coating(back),
                    transmittance: color(transmittance),
                })
            }
            Material::DiffuseTranslucent {
                reflectance,
                transmittance,
                sigma_degrees,
            } => {
                // `materials/mattetranslucent.cpp` clamps sigma to [0, 90] degrees.
                let (a, b) = oren_nayar_ab(self.float(sigma_degrees, sp).clamp(0.0, 90.0));
                Bsdf::DiffuseTranslucent(DiffuseTranslucent {
                    reflectance: color(reflectance),
                    transmittance: color(transmittance),
                    a,
                    b,
                })
            }
            Material::ComplexConductor {
                reflectance,
                eta,
                k,
                distribution: None,
            } => Bsdf::SmoothConductor(SmoothConductor {
                reflectance: color(reflectance),
                eta: *eta,
                k: *k,
            }),
            Material::ComplexConductor {
                reflectance,
                eta,
                k,
                distribution: Some(distribution),
            } => Bsdf::RoughConductor(RoughConductor {
                reflectance: color(reflectance),
                fresnel: ConductorFresnel::Complex { eta: *eta, k: *k },
                distribution: *distribution,
                masking: Masking::Separable,
            }),
            Material::RoughDielectric {
                reflectance,
                transmittance,
                eta,
                distribution,
            } => Bsdf::RoughDielectric(RoughDielectric {
                reflectance: color(reflectance),
                transmittance: color(transmittance),
                eta: *eta,
                distribution: *distribution,
            }),
            Material::ThinDielectric {
                reflectance,
                transmittance,
                eta,
            } => Bsdf::ThinDielectric(ThinDielectric {
                reflectance: color(reflectance),
                transmittance: color(transmittance),
                eta: *eta,
            }),
            Material::Plastic {
                diffuse,
                specular,
                eta,
                internal_reflectance,
                nonlinear,
            } => Bsdf::Plastic(Plastic {
                diffuse: color(diffuse),
                specular: color(specular),
                eta: *eta,
                internal_reflectance: *internal_reflectance,
                nonlinear: *nonlinear,
            }),
            Material::RoughPlastic {
                diffuse,
                specular,
                eta,
                alpha,
                nonlinear,
                tables,
            } => Bsdf::RoughPlastic(RoughPlastic {
                diffuse: color(diffuse),
                specular: color(specular),
                eta: *eta,
                distribution: TrowbridgeReitz::new(*alpha, *alpha),
                nonlinear: *nonlinear,
                tables,
            }),
            Material::FittedConductor {
                glossy,
                mirror,
                roughness,
                anisotropy,
                film,
            } => Bsdf::ShinyMetal(ShinyMetal {
                glossy: color(glossy),
                mirror: color(mirror),
                roughness: *roughness,
                anisotropy: *anisotropy,
                film: *film,
            }),
            Material::Velvet {
                reflectance,
                legendre,
                thickness,
            } => Bsdf::Velvet(Velvet {
                reflectance: color(reflectance),
                legendre: *legendre,
                thickness: *thickness,
            }),
            Material::CarPaint {
                diffuse,
                absorption,
                depth,
                lobes,
            } => Bsdf::CarPaint(CarPaint {
                base: CoatedGlossy {
                    diffuse: color(diffuse),
                    specular: Vec3::ZERO,
                    absorption: color(absorption),
                    depth: *depth,
                    roughness: 1.0,
                    anisotropy: 0.0,
                },
                lobes: lobes.map(|l| CarPaintLobe {
                    specular: color(&l.specular),
                    f0: l.f0,
                    roughness: l.roughness,
                }),
            }),
            Material::BlinnPlastic {
                diffuse,
                specular,
                distribution,
            } => Bsdf::BlinnPlastic(BlinnPlastic {
                diffuse: color(diffuse),
                specular: color(specular),
                distribution: *distribution,
            }),
            Material::FresnelBlend {
                diffuse,
                specular,
                distribution,
            } => Bsdf::FresnelBlend(FresnelBlend {
                diffuse: color(diffuse),
                specular: color(specular),
                distribution: *distribution,
            }),
            Material::Lafortune(fit) => Bsdf::Lafortune(Lafortune { fit }),
            Material::Null
            | Material::Mix { .. }
            | Material::Bump { .. }
            | Material::OneSided { .. } => return None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{TextureGraph, TextureNode};

    #[test]
    fn constant_materials_keep_their_bsdf_and_textured_ones_read_their_texture() {
        let textures = TextureTable {
            textures: Vec::new(),
            graph: TextureGraph {
                nodes: vec![TextureNode::Constant(Vec3::splat(0.75))],
            },
        };
        let table = MaterialTable::new(vec![
            Material::Lambertian {
                reflectance: Color::Constant(Vec3::splat(0.25)),
            },
            Material::Lambertian {
                reflectance: Color::Texture(0),
            },
            Material::Mix {
                first: 0,
                second: 1,
                amount: Color::Constant(Vec3::splat(0.5)),
            },
            Material::Null,
            Material::OneSided { material: 0 },
            Material::OneSided { material: 1 },
        ]);
        // A one-sided wrapper lends its constant material's BSDF, and only a constant one.
        let fixed_albedo = |id: u32| table.fixed_bsdf(id).map(|bsdf| bsdf.albedo().x);
        assert_eq!(fixed_albedo(0), Some(0.25));
        assert_eq!(fixed_albedo(4), Some(0.25));
        assert_eq!(
            (fixed_albedo(1), fixed_albedo(2), fixed_albedo(5)),
            (None, None, None)
        );
        let albedo = |id: u32, choice: f32| {
            let mut point = ShadingPoint {
                p: Vec3::ONE,
                uv: Vec2::new(0.3, 0.6),
                n: Vec3::Z,
                object: id,
            };
            (table.bsdf_at(id, &mut point, Some(&textures), choice, |_, _| {}))
                .map(|bsdf| bsdf.albedo().x)
        };
        assert_eq!(albedo(0, 0.5), Some(0.25));
        // A texture looked up at the point, not the grey a table built without textures gives.
        assert_eq!(albedo(1, 0.5), Some(0.75));
        assert_eq!(albedo(2, 0.25), Some(0.75));
        assert_eq!(albedo(2, 0.75), Some(0.25));
        assert_eq!(albedo(3, 0.5), None);
        assert_eq!(albedo(4, 0.5), Some(0.25));
        assert_eq!(albedo(5, 0.5), Some(0.75));
    }
}
