//! Materials: what each primitive's material index means at a hit. A material resolves, at a
//! surface point, to one BSDF (or none, for `null`).

pub mod texture;

use bevy_ecs::prelude::*;
use glam::Vec3;

use crate::bsdf::microfacet::TrowbridgeReitz;
use crate::bsdf::rough_plastic::CoatingTables;
use crate::bsdf::{Bsdf, CoatedGlossy, Plastic, RoughDielectric, RoughPlastic, ThinDielectric};
use crate::texture::ShadingPoint;
use texture::TextureTable;

/// Mixes nest at most this deep; deeper chains (only a cycle makes one) resolve to black matte.
const MAX_MIX_DEPTH: usize = 8;

/// A colour input: a constant, or a texture of the [`TextureTable`] looked up at the hit's uv.
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
    /// Oren-Nayar's A and B (see `bsdf::oren_nayar`).
    OrenNayar {
        reflectance: Color,
        a: f32,
        b: f32,
    },
    CoatedGlossy {
        diffuse: Color,
        specular: Color,
        absorption: Color,
        depth: f32,
        roughness: f32,
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
    /// GGX reflection and refraction; `eta` = index inside / index outside.
    RoughDielectric {
        reflectance: Color,
        transmittance: Color,
        eta: f32,
        alpha_x: f32,
        alpha_y: f32,
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
    /// Rays pass through.
    Null,
    /// `amount` of material `second`, `1 - amount` of `first`.
    Mix {
        first: usize,
        second: usize,
        amount: f32,
    },
    /// Material `material` from the front, black from the back (see [`MaterialTable::is_one_sided`]).
    OneSided {
        material: usize,
    },
}

#[derive(Resource, Clone, Debug)]
pub struct MaterialTable {
    pub materials: Vec<Material>,
}

impl MaterialTable {
    /// Whether any material reads a texture (the geometry then keeps uvs).
    pub fn uses_textures(&self) -> bool {
        self.materials.iter().any(|m| {
            let inputs: &[&Color] = match m {
                Material::Lambertian { reflectance } => &[reflectance],
                Material::OrenNayar { reflectance, .. } => &[reflectance],
                Material::CoatedGlossy {
                    diffuse,
                    specular,
                    absorption,
                    ..
                } => &[diffuse, specular, absorption],
                Material::SpecularReflection { reflectance } => &[reflectance],
                Material::Dielectric {
                    reflectance,
                    transmittance,
                    ..
                } => &[reflectance, transmittance],
                Material::Conductor { f0, .. } => &[f0],
                Material::RoughDielectric {
                    reflectance,
                    transmittance,
                    ..
                }
                | Material::ThinDielectric {
                    reflectance,
                    transmittance,
                    ..
                } => &[reflectance, transmittance],
                Material::Plastic {
                    diffuse, specular, ..
                }
                | Material::RoughPlastic {
                    diffuse, specular, ..
                } => &[diffuse, specular],
                Material::Null | Material::Mix { .. } | Material::OneSided { .. } => &[],
            };
            inputs.iter().any(|c| matches!(c, Color::Texture(_)))
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

    /// The BSDF of material `id` at `sp`; `None` for `null` (the ray passes through).
    /// `choice` in [0,1) picks the side of each mix (and is remapped for the next one).
    pub fn bsdf_at(
        &self,
        id: u32,
        sp: &ShadingPoint,
        textures: Option<&TextureTable>,
        mut choice: f32,
    ) -> Option<Bsdf> {
        // Colours are clamped to [0, 1], as LuxRender's materials clamp their textures'
        // values (`materials/matte.cpp`, `glossy2.cpp`: `Kd->Evaluate(...).Clamp(0, 1)`): an
        // unclamped `mix` driven by fbm can go negative.
        let color = |c: &Color| {
            match (c, textures) {
                (Color::Constant(c), _) => *c,
                (Color::Texture(t), Some(table)) => table.lookup(*t, sp),
                (Color::Texture(_), None) => Vec3::splat(0.5),
            }
            .clamp(Vec3::ZERO, Vec3::ONE)
        };
        let mut id = id as usize;
        for _ in 0..MAX_MIX_DEPTH {
            return match self.materials.get(id)? {
                Material::Lambertian { reflectance } => Some(Bsdf::Lambertian {
                    reflectance: color(reflectance),
                }),
                Material::OrenNayar { reflectance, a, b } => Some(Bsdf::OrenNayar {
                    reflectance: color(reflectance),
                    a: *a,
                    b: *b,
                }),
                Material::CoatedGlossy {
                    diffuse,
                    specular,
                    absorption,
                    depth,
                    roughness,
                } => Some(Bsdf::CoatedGlossy(CoatedGlossy {
                    diffuse: color(diffuse),
                    specular: color(specular),
                    absorption: color(absorption),
                    depth: *depth,
                    roughness: *roughness,
                })),
                Material::SpecularReflection { reflectance } => Some(Bsdf::SpecularReflection {
                    reflectance: color(reflectance),
                }),
                Material::Dielectric {
                    reflectance,
                    transmittance,
                    eta,
                } => Some(Bsdf::Dielectric {
                    reflectance: color(reflectance),
                    transmittance: color(transmittance),
                    eta: *eta,
                }),
                Material::Conductor {
                    f0,
                    alpha_x,
                    alpha_y,
                } => Some(Bsdf::Conductor {
                    f0: color(f0),
                    alpha_x: *alpha_x,
                    alpha_y: *alpha_y,
                }),
                Material::RoughDielectric {
                    reflectance,
                    transmittance,
                    eta,
                    alpha_x,
                    alpha_y,
                } => Some(Bsdf::RoughDielectric(RoughDielectric {
                    reflectance: color(reflectance),
                    transmittance: color(transmittance),
                    eta: *eta,
                    distribution: TrowbridgeReitz::new(*alpha_x, *alpha_y),
                })),
                Material::ThinDielectric {
                    reflectance,
                    transmittance,
                    eta,
                } => Some(Bsdf::ThinDielectric(ThinDielectric {
                    reflectance: color(reflectance),
                    transmittance: color(transmittance),
                    eta: *eta,
                })),
                Material::Plastic {
                    diffuse,
                    specular,
                    eta,
                    internal_reflectance,
                    nonlinear,
                } => Some(Bsdf::Plastic(Plastic {
                    diffuse: color(diffuse),
                    specular: color(specular),
                    eta: *eta,
                    internal_reflectance: *internal_reflectance,
                    nonlinear: *nonlinear,
                })),
                Material::RoughPlastic {
                    diffuse,
                    specular,
                    eta,
                    alpha,
                    nonlinear,
                    tables,
                } => Some(Bsdf::RoughPlastic(RoughPlastic {
                    diffuse: color(diffuse),
                    specular: color(specular),
                    eta: *eta,
                    distribution: TrowbridgeReitz::new(*alpha, *alpha),
                    nonlinear: *nonlinear,
                    tables,
                })),
                Material::Null => None,
                Material::Mix {
                    first,
                    second,
                    amount,
                } => {
                    let amount = amount.clamp(0.0, 1.0);
                    if choice < amount {
                        choice /= amount;
                        id = *second;
                    } else {
                        choice = (choice - amount) / (1.0 - amount);
                        id = *first;
                    }
                    continue;
                }
                Material::OneSided { material } => {
                    id = *material;
                    continue;
                }
            };
        }
        Some(Bsdf::Lambertian {
            reflectance: Vec3::ZERO,
        })
    }
}
