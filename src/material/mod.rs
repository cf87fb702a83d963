//! Materials: what each primitive's material index means at a hit. A material resolves, at a
//! surface point, to one BSDF (or none, for `null`).

pub mod texture;

use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};

use crate::bsdf::{Bsdf, roughness_to_alpha};
use crate::scene::desc::{ColorParam, MaterialDesc};
use texture::TextureTable;

/// Mixes nest at most this deep; deeper chains (only a cycle makes one) resolve to black matte.
const MAX_MIX_DEPTH: usize = 8;

#[derive(Resource, Clone, Debug)]
pub struct MaterialTable {
    pub materials: Vec<MaterialDesc>,
}

impl MaterialTable {
    /// Whether any material reads a texture (the geometry then keeps uvs).
    pub fn uses_textures(&self) -> bool {
        self.materials.iter().any(|m| {
            let params: &[&ColorParam] = match m {
                MaterialDesc::Matte { kd } => &[kd],
                MaterialDesc::Mirror { kr } => &[kr],
                MaterialDesc::Glass { kr, kt, .. } => &[kr, kt],
                MaterialDesc::Metal { kr, .. } => &[kr],
                MaterialDesc::Null | MaterialDesc::Mix { .. } => &[],
            };
            params.iter().any(|p| matches!(p, ColorParam::Texture(_)))
        })
    }

    /// The BSDF of material `id` at `uv`; `None` for `null` (the ray passes through).
    /// `choice` in [0,1) picks the side of each mix (and is remapped for the next one).
    pub fn bsdf_at(
        &self,
        id: u32,
        uv: Vec2,
        textures: Option<&TextureTable>,
        mut choice: f32,
    ) -> Option<Bsdf> {
        let color = |p: &ColorParam| match (p, textures) {
            (ColorParam::Constant(c), _) => *c,
            (ColorParam::Texture(t), Some(table)) => table.lookup(*t, uv),
            (ColorParam::Texture(_), None) => Vec3::splat(0.5),
        };
        let mut id = id as usize;
        for _ in 0..MAX_MIX_DEPTH {
            return match self.materials.get(id)? {
                MaterialDesc::Matte { kd } => Some(Bsdf::Lambertian {
                    reflectance: color(kd),
                }),
                MaterialDesc::Mirror { kr } => Some(Bsdf::SpecularReflection {
                    reflectance: color(kr),
                }),
                MaterialDesc::Glass { kr, kt, index } => Some(Bsdf::Dielectric {
                    reflectance: color(kr),
                    transmittance: color(kt),
                    eta: *index,
                }),
                MaterialDesc::Metal {
                    kr,
                    u_roughness,
                    v_roughness,
                } => Some(Bsdf::Conductor {
                    f0: color(kr),
                    alpha_x: roughness_to_alpha(*u_roughness),
                    alpha_y: roughness_to_alpha(*v_roughness),
                }),
                MaterialDesc::Null => None,
                MaterialDesc::Mix {
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
            };
        }
        Some(Bsdf::Lambertian {
            reflectance: Vec3::ZERO,
        })
    }
}
