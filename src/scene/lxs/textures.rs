//! LuxRender's procedural and composite texture classes (`Texture "name" "float"|"color"
//! "class" ...`), read into the scene's texture graph with LuxRender 1.x's parameter names and
//! defaults (`textures/*.h`, `core/texture.cpp` for the mappings).

use glam::{Affine3A, Vec2, Vec3};

use super::params::ParamList;
use super::parser::Parser;
use crate::scene::desc::{ColorParam, SceneError};
use crate::texture::blender::{
    BlendKind, BlenderPattern, BlenderTexture, MarbleSharpness, StucciKind, VoronoiColor, Waveform,
};
use crate::texture::blender_noise::{BlenderNoise, DistanceMetric, NoiseBasis};
use crate::texture::musgrave::{Musgrave, MusgraveKind};
use crate::texture::{Mapping2D, Mapping3D, TexParam, TextureNode};

/// LuxRender's Blender texture classes (`textures/blender_*.h`).
const BLENDER_CLASSES: [&str; 10] = [
    "blender_blend",
    "blender_clouds",
    "blender_distortednoise",
    "blender_magic",
    "blender_marble",
    "blender_musgrave",
    "blender_noise",
    "blender_stucci",
    "blender_voronoi",
    "blender_wood",
];

impl Parser {
    /// The graph node for a texture of class `class`, or `None` for a class foton lacks.
    pub(super) fn procedural_texture(
        &mut self,
        class: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<Option<TextureNode>, SceneError> {
        let octaves = |p: &mut ParamList| -> Result<u32, SceneError> {
            Ok(p.int("octaves")?.unwrap_or(8).clamp(0, 64) as u32)
        };
        Ok(Some(match class {
            "scale" => TextureNode::Scale {
                tex1: self.tex_param(params, "tex1", 1.0, line)?,
                tex2: self.tex_param(params, "tex2", 1.0, line)?,
            },
            "mix" => TextureNode::Mix {
                tex1: self.tex_param(params, "tex1", 0.0, line)?,
                tex2: self.tex_param(params, "tex2", 1.0, line)?,
                amount: self.tex_param(params, "amount", 0.5, line)?,
            },
            "checkerboard" => {
                let tex1 = self.tex_param(params, "tex1", 1.0, line)?;
                let tex2 = self.tex_param(params, "tex2", 0.0, line)?;
                params.string("aamode")?;
                match params.int("dimension")?.unwrap_or(2) {
                    3 => TextureNode::Checkerboard3D {
                        mapping: self.mapping_3d(params, line, true)?,
                        tex1,
                        tex2,
                    },
                    2 => TextureNode::Checkerboard2D {
                        mapping: self.mapping_2d(params, line)?,
                        tex1,
                        tex2,
                    },
                    d => {
                        return Err(self.error(
                            line,
                            format!("checkerboard: \"dimension\" {d}, expected 2 or 3"),
                        ));
                    }
                }
            }
            // LuxRender 1.x passes `inside` and `outside` to `DotsTexture(mapping, c1, c2)`,
            // whose constructor stores them as `outsideDot = c1, insideDot = c2`
            // (`textures/dots.h`, inherited from pbrt-v1's `dots.cpp`): the dots show
            // `outside` and the ground between them `inside`. Scenes are made to look right
            // in LuxRender, so foton keeps the swap.
            "dots" => TextureNode::Dots {
                inside: self.tex_param(params, "outside", 0.0, line)?,
                outside: self.tex_param(params, "inside", 1.0, line)?,
                mapping: self.mapping_2d(params, line)?,
            },
            "bilerp" => {
                let mut corner = |name: &str, default: f32| -> Result<Vec3, SceneError> {
                    Ok(match params.color(name)? {
                        Some(super::params::ColorSource::Rgb(c)) => c,
                        Some(super::params::ColorSource::Texture(t)) => {
                            return Err(self.error(
                                line,
                                format!(
                                    "bilerp: \"{name}\" names texture \"{t}\"; expected a value"
                                ),
                            ));
                        }
                        None => Vec3::splat(default),
                    })
                };
                let v = [
                    corner("v00", 0.0)?,
                    corner("v01", 1.0)?,
                    corner("v10", 0.0)?,
                    corner("v11", 1.0)?,
                ];
                TextureNode::Bilerp {
                    mapping: self.mapping_2d(params, line)?,
                    v,
                }
            }
            "fbm" => TextureNode::Fbm {
                octaves: octaves(params)?,
                roughness: params.float("roughness")?.unwrap_or(0.5),
                mapping: self.mapping_3d(params, line, true)?,
            },
            "wrinkled" => TextureNode::Wrinkled {
                octaves: octaves(params)?,
                roughness: params.float("roughness")?.unwrap_or(0.5),
                mapping: self.mapping_3d(params, line, true)?,
            },
            "windy" => TextureNode::Windy {
                mapping: self.mapping_3d(params, line, true)?,
            },
            // Marble's own `float scale` takes the name of the mappings' `vector scale`.
            "marble" => TextureNode::Marble {
                octaves: octaves(params)?,
                roughness: params.float("roughness")?.unwrap_or(0.5),
                scale: params.float("scale")?.unwrap_or(1.0),
                variation: params.float("variation")?.unwrap_or(0.2),
                mapping: self.mapping_3d(params, line, false)?,
            },
            "blackbody" => TextureNode::blackbody(params.float("temperature")?.unwrap_or(6500.0)),
            "harlequin" => TextureNode::Harlequin,
            class if BLENDER_CLASSES.contains(&class) => {
                let pattern = self.blender_pattern(class, line, params)?;
                TextureNode::Blender {
                    texture: BlenderTexture {
                        pattern,
                        bright: params.float("bright")?.unwrap_or(1.0),
                        contrast: params.float("contrast")?.unwrap_or(1.0),
                    },
                    tex1: self.tex_param(params, "tex1", 0.0, line)?,
                    tex2: self.tex_param(params, "tex2", 1.0, line)?,
                    mapping: self.mapping_3d(params, line, true)?,
                }
            }
            _ => return Ok(None),
        }))
    }

    /// The pattern of a Blender texture, with LuxRender 1.x's parameter names and defaults
    /// (`textures/blender_*.h`, `blender_base.cpp` for the names of the types). An unknown type
    /// name is warned and read as the default, as LuxRender does.
    fn blender_pattern(
        &mut self,
        class: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<BlenderPattern, SceneError> {
        let depth = |p: &mut ParamList| -> Result<u32, SceneError> {
            Ok(p.int("noisedepth")?.unwrap_or(2).clamp(0, 30) as u32)
        };
        let float = |p: &mut ParamList, name: &str, default: f32| -> Result<f32, SceneError> {
            Ok(p.float(name)?.unwrap_or(default))
        };
        Ok(match class {
            "blender_blend" => {
                let kinds = ["lin", "quad", "ease", "diag", "sphere", "halo", "radial"];
                let kind = match self.choice(class, line, params, "type", &kinds)?.as_str() {
                    "quad" => BlendKind::Quadratic,
                    "ease" => BlendKind::Ease,
                    "diag" => BlendKind::Diagonal,
                    "sphere" => BlendKind::Sphere,
                    "halo" => BlendKind::Halo,
                    "radial" => BlendKind::Radial,
                    _ => BlendKind::Linear,
                };
                BlenderPattern::Blend {
                    kind,
                    flip_xy: params.bool("flipxy")?.unwrap_or(false),
                }
            }
            "blender_magic" => BlenderPattern::Magic {
                depth: params.int("noisedepth")?.unwrap_or(2).clamp(0, 10) as u32,
                turbulence: float(params, "turbulence", 5.0)?,
            },
            "blender_wood" => {
                let types = ["bands", "rings", "bandnoise", "ringnoise"];
                let kind = self.choice(class, line, params, "type", &types)?;
                let wave = self.waveform(class, line, params)?;
                let noise = self.blender_noise(class, line, params)?;
                BlenderPattern::Wood {
                    rings: kind.starts_with("ring"),
                    wave,
                    noise: kind.ends_with("noise").then_some(noise),
                    turbulence: float(params, "turbulence", 5.0)?,
                }
            }
            "blender_clouds" => {
                let color = self.choice(class, line, params, "type", &["default", "color"])?;
                BlenderPattern::Clouds {
                    noise: self.blender_noise(class, line, params)?,
                    depth: depth(params)?,
                    color: color == "color",
                }
            }
            "blender_marble" => {
                let kinds = ["soft", "sharp", "sharper"];
                let sharpness = match self.choice(class, line, params, "type", &kinds)?.as_str() {
                    "sharp" => MarbleSharpness::Sharp,
                    "sharper" => MarbleSharpness::Sharper,
                    _ => MarbleSharpness::Soft,
                };
                BlenderPattern::Marble {
                    noise: self.blender_noise(class, line, params)?,
                    depth: depth(params)?,
                    turbulence: float(params, "turbulence", 5.0)?,
                    wave: self.waveform(class, line, params)?,
                    sharpness,
                }
            }
            "blender_musgrave" => {
                let kinds = [
                    "multifractal",
                    "ridged_multifractal",
                    "hybrid_multifractal",
                    "hetero_terrain",
                    "fbm",
                ];
                let kind = match self.choice(class, line, params, "type", &kinds)?.as_str() {
                    "ridged_multifractal" => MusgraveKind::RidgedMultifractal,
                    "hybrid_multifractal" => MusgraveKind::HybridMultifractal,
                    "hetero_terrain" => MusgraveKind::HeteroTerrain,
                    "fbm" => MusgraveKind::Fbm,
                    _ => MusgraveKind::Multifractal,
                };
                BlenderPattern::Musgrave {
                    fractal: Musgrave {
                        kind,
                        h: float(params, "h", 1.0)?,
                        lacunarity: float(params, "lacu", 2.0)?,
                        octaves: float(params, "octs", 2.0)?.clamp(0.0, 64.0),
                        offset: float(params, "offset", 1.0)?,
                        gain: float(params, "gain", 1.0)?,
                        basis: self.noise_basis(class, line, params, "noisebasis")?,
                    },
                    size: float(params, "noisesize", 0.25)?,
                    outscale: float(params, "outscale", 1.0)?,
                }
            }
            "blender_distortednoise" => {
                // `nabla` is Blender's step for bump normals; foton's bump map differentiates
                // the texture itself.
                params.float("nabla")?;
                BlenderPattern::DistortedNoise {
                    size: float(params, "noisesize", 0.25)?,
                    amount: float(params, "distamount", 1.0)?,
                    distortion: self.noise_basis(class, line, params, "noisebasis")?,
                    basis: self.noise_basis(class, line, params, "type")?,
                }
            }
            "blender_stucci" => {
                let kinds = ["plastic", "wall_in", "wall_out"];
                let kind = match self.choice(class, line, params, "type", &kinds)?.as_str() {
                    "wall_in" => StucciKind::WallIn,
                    "wall_out" => StucciKind::WallOut,
                    _ => StucciKind::Plastic,
                };
                BlenderPattern::Stucci {
                    noise: self.blender_noise(class, line, params)?,
                    turbulence: float(params, "turbulence", 5.0)?,
                    kind,
                }
            }
            "blender_voronoi" => {
                let metrics = [
                    "actual_distance",
                    "distance_squared",
                    "manhattan",
                    "chebychev",
                    "minkovsky_half",
                    "minkovsky_four",
                    "minkovsky",
                ];
                let metric = self.choice(class, line, params, "distmetric", &metrics)?;
                let exponent = float(params, "minkovsky_exp", 2.5)?;
                let metric = match metric.as_str() {
                    "distance_squared" => DistanceMetric::Squared,
                    "manhattan" => DistanceMetric::Manhattan,
                    "chebychev" => DistanceMetric::Chebychev,
                    "minkovsky_half" => DistanceMetric::MinkowskiHalf,
                    "minkovsky_four" => DistanceMetric::MinkowskiFour,
                    "minkovsky" => DistanceMetric::Minkowski(exponent),
                    _ => DistanceMetric::Actual,
                };
                // Blender tests `coltype` as nonzero, >= 2 and == 3.
                let color = match params.int("coltype")?.unwrap_or(0) {
                    0 => VoronoiColor::Intensity,
                    3 => VoronoiColor::CellsEdgedShaded,
                    c if c >= 2 => VoronoiColor::CellsEdged,
                    _ => VoronoiColor::Cells,
                };
                params.float("nabla")?;
                BlenderPattern::Voronoi {
                    metric,
                    weights: [
                        float(params, "w1", 1.0)?,
                        float(params, "w2", 0.0)?,
                        float(params, "w3", 0.0)?,
                        float(params, "w4", 0.0)?,
                    ],
                    size: float(params, "noisesize", 0.25)?,
                    outscale: float(params, "outscale", 1.0)?,
                    color,
                }
            }
            _ => BlenderPattern::Noise {
                depth: depth(params)?,
            },
        })
    }

    /// A string parameter that must be one of `known` (the first is LuxRender's default): an
    /// unknown value is warned and read as the default.
    fn choice(
        &mut self,
        class: &str,
        line: usize,
        params: &mut ParamList,
        name: &str,
        known: &[&str],
    ) -> Result<String, SceneError> {
        let default = known[0];
        let value = params.string(name)?.unwrap_or_else(|| default.to_owned());
        Ok(if known.contains(&value.as_str()) {
            value
        } else {
            self.warn(
                line,
                format!("{class}: \"{name}\" \"{value}\" unknown: \"{default}\""),
            );
            default.to_owned()
        })
    }

    /// A noise basis named by `name` ("blender_original" when absent or unknown).
    fn noise_basis(
        &mut self,
        class: &str,
        line: usize,
        params: &mut ParamList,
        name: &str,
    ) -> Result<NoiseBasis, SceneError> {
        let value = params.string(name)?;
        let value = value.as_deref().unwrap_or("blender_original");
        Ok(NoiseBasis::from_name(value).unwrap_or_else(|| {
            self.warn(
                line,
                format!("{class}: \"{name}\" \"{value}\" unknown: \"blender_original\""),
            );
            NoiseBasis::BlenderOriginal
        }))
    }

    /// `noisebasis`, `noisesize` (0.25) and `noisetype` ("soft_noise" or "hard_noise").
    fn blender_noise(
        &mut self,
        class: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<BlenderNoise, SceneError> {
        let basis = self.noise_basis(class, line, params, "noisebasis")?;
        let hardness = self.choice(
            class,
            line,
            params,
            "noisetype",
            &["soft_noise", "hard_noise"],
        )?;
        Ok(BlenderNoise {
            basis,
            size: params.float("noisesize")?.unwrap_or(0.25),
            hard: hardness == "hard_noise",
        })
    }

    /// `noisebasis2`, the wave of wood and marble: "sin" (default), "saw", "tri".
    fn waveform(
        &mut self,
        class: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<Waveform, SceneError> {
        Ok(
            match self
                .choice(class, line, params, "noisebasis2", &["sin", "saw", "tri"])?
                .as_str()
            {
                "saw" => Waveform::Saw,
                "tri" => Waveform::Triangle,
                _ => Waveform::Sine,
            },
        )
    }

    /// A texture input: a value (one float or a colour) or the name of a texture.
    fn tex_param(
        &mut self,
        params: &mut ParamList,
        name: &str,
        default: f32,
        line: usize,
    ) -> Result<TexParam, SceneError> {
        Ok(
            match self.color_param(params, name, Vec3::splat(default), line)? {
                ColorParam::Constant(c) => TexParam::Value(c),
                ColorParam::Texture(id) => TexParam::Texture(id),
            },
        )
    }

    /// LuxRender's 2D mappings (`TextureMapping2D::Create`): `mapping` "uv" (default),
    /// "spherical", "cylindrical", "planar".
    fn mapping_2d(&mut self, params: &mut ParamList, line: usize) -> Result<Mapping2D, SceneError> {
        let mut f = |name: &str, default: f32| -> Result<f32, SceneError> {
            Ok(params.float(name)?.unwrap_or(default))
        };
        let scale = Vec2::new(f("uscale", 1.0)?, f("vscale", 1.0)?);
        let delta = Vec2::new(f("udelta", 0.0)?, f("vdelta", 0.0)?);
        let world_to_texture = Affine3A::from_mat4(self.state.ctm).inverse();
        let kind = params.string("mapping")?;
        Ok(match kind.as_deref().unwrap_or("uv") {
            "uv" => Mapping2D::Uv { scale, delta },
            "spherical" => Mapping2D::Spherical {
                world_to_texture,
                scale,
                delta,
            },
            "cylindrical" => Mapping2D::Cylindrical {
                world_to_texture,
                uscale: scale.x,
                udelta: delta.x,
            },
            "planar" => Mapping2D::Planar {
                v1: params.vec3("v1")?.unwrap_or(Vec3::X),
                v2: params.vec3("v2")?.unwrap_or(Vec3::Y),
                delta,
            },
            other => {
                self.warn(line, format!("texture mapping \"{other}\" unsupported: uv"));
                Mapping2D::Uv { scale, delta }
            }
        })
    }

    /// LuxRender's 3D mappings (`TextureMapping3D`): `coordinates` "global" (default) or "uv",
    /// with `scale` (when `vector_scale`), `rotate` (degrees) and `translate` applied in texture
    /// space.
    fn mapping_3d(
        &mut self,
        params: &mut ParamList,
        line: usize,
        vector_scale: bool,
    ) -> Result<Mapping3D, SceneError> {
        let scale = if vector_scale {
            params.vec3("scale")?.unwrap_or(Vec3::ONE)
        } else {
            Vec3::ONE
        };
        let world_to_texture = Mapping3D::world_to_texture(
            Affine3A::from_mat4(self.state.ctm),
            scale,
            params.vec3("rotate")?.unwrap_or(Vec3::ZERO),
            params.vec3("translate")?.unwrap_or(Vec3::ZERO),
        );
        let coordinates = params.string("coordinates")?;
        Ok(match coordinates.as_deref().unwrap_or("global") {
            "global" => Mapping3D::Global { world_to_texture },
            "uv" => Mapping3D::Uv { world_to_texture },
            other => {
                self.warn(
                    line,
                    format!("texture coordinates \"{other}\" unsupported: global"),
                );
                Mapping3D::Global { world_to_texture }
            }
        })
    }
}
