//! Volumes as far as foton renders them: `MakeNamedVolume "name" "clear"|"homogeneous"|...`,
//! and `Interior "name"` / `Exterior "name"`, which the graphics state carries to the shapes
//! that follow (saved and restored by `AttributeBegin`/`AttributeEnd`, as in LuxRender 1.x's
//! `core/api.cpp`).
//!
//! What a volume gives foton is its index of refraction, `fresnel` (a float, or a constant
//! texture; 1.5 by default in `volumes/clear.cpp` and `homogeneous.cpp`), which `glass2` reads
//! (`materials/glass2.cpp`): the interface's relative index is interior / exterior; with no
//! exterior volume it is the interior's index, with no interior 1 / the exterior's, with
//! neither 1 (the glass is invisible). So a `glass2` material becomes, per combination of
//! interior and exterior it is used with, a smooth dielectric of that index (`architectural`:
//! a thin sheet, `ThinDielectric`).
//!
//! foton renders no participating media: `clear`'s `absorption` (Beer-Lambert attenuation
//! inside), `homogeneous`'s scattering and the other volume types are warned once per kind and
//! not drawn.

use std::collections::HashMap;

use super::params::{ColorSource, ParamList};
use super::parser::Parser;
use crate::scene::desc::{ColorParam, MaterialDesc, MaterialId, SceneError};

/// LuxRender's default `fresnel` of a volume.
const DEFAULT_VOLUME_IOR: f32 = 1.5;

/// The volumes and `glass2` materials read so far.
#[derive(Default)]
pub(super) struct Volumes {
    /// Each named volume's index of refraction.
    ior: HashMap<String, f32>,
    /// The `glass2` materials (their placeholder, the no-volume interface), and the interface
    /// made for each (material, interior, exterior) met at a shape.
    glass2: Vec<MaterialId>,
    interfaces: HashMap<(MaterialId, Option<String>, Option<String>), MaterialId>,
}

/// `glass2`'s relative index from the interior's and exterior's indices.
fn relative_ior(interior: Option<f32>, exterior: Option<f32>) -> f32 {
    interior.unwrap_or(1.0) / exterior.unwrap_or(1.0)
}

impl Parser {
    /// `MakeNamedVolume "name" "type" params`.
    pub(super) fn make_named_volume(
        &mut self,
        strings: &[String],
        line: usize,
        params: &mut ParamList,
    ) -> Result<(), SceneError> {
        let (name, kind) = match strings {
            [name, kind, ..] => (name.clone(), kind.clone()),
            _ => {
                return Err(self.error(line, "MakeNamedVolume: expected a name and a type"));
            }
        };
        let ior = self.volume_ior(params, line)?;
        match kind.as_str() {
            "clear" => {
                if let Some(absorption) = params.color("absorption")?
                    && absorption != ColorSource::Rgb(glam::Vec3::ZERO)
                {
                    self.warn(
                        line,
                        "volume \"clear\": \"absorption\" is not rendered (foton has no media): \
                         the glass inside is clear",
                    );
                }
            }
            "homogeneous" | "heterogeneous" | "exponential" | "cloud" => {
                params.ignore_all();
                self.warn(
                    line,
                    format!(
                        "volume \"{kind}\": absorption and scattering are not rendered (foton \
                         has no media); only its \"fresnel\" index is used, by glass2"
                    ),
                );
            }
            _ => {
                params.ignore_all();
                self.warn(
                    line,
                    format!("unknown volume type \"{kind}\": only its \"fresnel\" index is used"),
                );
            }
        }
        if self.volumes.ior.insert(name.clone(), ior).is_some() {
            self.warn(line, format!("MakeNamedVolume \"{name}\" redefined"));
        }
        Ok(())
    }

    /// A volume's `fresnel`: a number or a constant texture; a varying texture (a dispersion
    /// curve, e.g. `cauchy`) is warned and read as the default.
    fn volume_ior(&mut self, params: &mut ParamList, line: usize) -> Result<f32, SceneError> {
        let constant = match params.color("fresnel")? {
            None => return Ok(DEFAULT_VOLUME_IOR),
            Some(ColorSource::Rgb(rgb)) => Some(rgb.x),
            Some(ColorSource::Texture(name)) => match self.named_textures.get(&name) {
                Some(ColorParam::Constant(c)) => Some((c.x + c.y + c.z) / 3.0),
                _ => None,
            },
        };
        match constant {
            Some(ior) if ior > 0.0 && ior.is_finite() => Ok(ior),
            Some(ior) => {
                Err(self.error(line, format!("volume \"fresnel\" {ior} must be positive")))
            }
            None => {
                self.warn(
                    line,
                    format!(
                        "volume \"fresnel\": only a number or a constant texture is read: \
                         {DEFAULT_VOLUME_IOR}"
                    ),
                );
                Ok(DEFAULT_VOLUME_IOR)
            }
        }
    }

    /// `Interior "name"` or `Exterior "name"`: the volume of the shapes that follow (an
    /// unknown name is warned and leaves none).
    pub(super) fn set_volume(&mut self, directive: &str, name: &str, line: usize) {
        let volume = if name.is_empty() || self.volumes.ior.contains_key(name) {
            (!name.is_empty()).then(|| name.to_string())
        } else {
            self.warn(
                line,
                format!("{directive} \"{name}\": no such volume (MakeNamedVolume): none"),
            );
            None
        };
        if directive == "Interior" {
            self.state.interior = volume;
        } else {
            self.state.exterior = volume;
        }
    }

    /// Records the material just added as a `glass2`.
    pub(super) fn note_glass2(&mut self, material: MaterialId) {
        self.volumes.glass2.push(material);
    }

    /// The material a shape wears: a `glass2` becomes the dielectric interface of the current
    /// interior and exterior volumes (made once per combination); any other is unchanged.
    pub(super) fn material_between_volumes(
        &mut self,
        material: Option<MaterialId>,
    ) -> Option<MaterialId> {
        let id = material?;
        if !self.volumes.glass2.contains(&id) {
            return Some(id);
        }
        let key = (id, self.state.interior.clone(), self.state.exterior.clone());
        if let Some(&made) = self.volumes.interfaces.get(&key) {
            return Some(made);
        }
        let index = |volume: &Option<String>| {
            volume
                .as_ref()
                .and_then(|name| self.volumes.ior.get(name).copied())
        };
        let ior = relative_ior(index(&key.1), index(&key.2));
        // A bumped glass2 (LuxRender 1.x bumps any material, `core/material.cpp`) keeps its
        // bump map over the interface of the volumes' index.
        let interface = match self.scene.materials[id].clone() {
            MaterialDesc::Bump {
                material,
                height,
                sample_distance,
            } => {
                let inner = with_ior(self.scene.materials[material].clone(), ior);
                self.scene.materials.push(inner);
                MaterialDesc::Bump {
                    material: self.scene.materials.len() - 1,
                    height,
                    sample_distance,
                }
            }
            other => with_ior(other, ior),
        };
        self.scene.materials.push(interface);
        let made = self.scene.materials.len() - 1;
        self.volumes.interfaces.insert(key, made);
        Some(made)
    }
}

/// A smooth (or thin) dielectric `material` with its index replaced by `ior`.
fn with_ior(material: MaterialDesc, ior: f32) -> MaterialDesc {
    match material {
        MaterialDesc::Dielectric {
            reflectance,
            transmittance,
            ..
        } => MaterialDesc::Dielectric {
            reflectance,
            transmittance,
            ior,
        },
        MaterialDesc::ThinDielectric {
            reflectance,
            transmittance,
            ..
        } => MaterialDesc::ThinDielectric {
            reflectance,
            transmittance,
            ior,
        },
        other => other,
    }
}
