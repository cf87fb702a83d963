//! `Material`, `MakeNamedMaterial` and `Texture`.

use glam::{Vec2, Vec3};

use super::measured::measured_material;
use super::params::{ColorSource, ParamList};
use super::parser::Parser;
use super::{car_paint, nk, paths};
use crate::bsdf::coated_glossy::coating_f0;
use crate::bsdf::phong_distribution::PhongDistribution;
use crate::material::bump::DEFAULT_SAMPLE_DISTANCE;
use crate::scene::desc::{
    CarPaintLobeDesc, ColorParam, ImageTexture, Location, MaterialDesc, MicrofacetDistribution,
    Roughness, SceneError, Wrap,
};
use crate::scene::io::image;
use crate::texture::{Mapping2D, TextureNode};

/// LuxRender's default diffuse grey, also what unknown materials become.
const GREY: Vec3 = Vec3::splat(0.5);

/// metal2's (and roughglass's) `uroughness`/`vroughness` as GGX alpha.
///
/// LuxRender 1.x's metal2 (`materials/metal2.cpp`, LuxRender/Lux on GitHub) builds
/// `SchlickDistribution(u * v, anisotropy)`, and
/// `core/reflection/microfacetdistribution/schlickdistribution.h` defines
/// D = Z(cos) A(phi) / pi with Z(t) = r / (1 + (r - 1) t^2)^2, r = u v.
/// Isotropic GGX is D = alpha^2 / (pi (1 + (alpha^2 - 1) cos^2)^2) (Walter et al. 2007, eq. 33
/// rewritten in cos): the same function with r = alpha^2. So alpha = roughness exactly for
/// u = v, and alpha_u = u, alpha_v = v keeps alpha_u alpha_v = r and the wider lobe along the
/// larger roughness (Schlick's A(phi) shapes the anisotropy differently).
///
/// (The Blinn mapping exponent = 1 / roughness is that of LuxRender's older `metal`,
/// `shinymetal`, `plastic`, `roughglass` (pbrt-v1 heritage), whose GGX/Beckmann match would be
/// alpha = sqrt(2 / (e + 2)), Walter et al. 2007; it does not apply to metal2.)
fn metal2_alpha(roughness: f32) -> f32 {
    roughness
}

/// Schlick's anisotropy of LuxRender's `uroughness` u and `vroughness` v (`shinymetal.cpp`,
/// `glossy2.cpp`, `glossytranslucent.cpp`): 1 - u^2 / v^2 when u < v, else v^2 / u^2 - 1; 0 for
/// u = v, positive when the lobe is wider along v.
pub(super) fn schlick_anisotropy(u: f32, v: f32) -> f32 {
    let (u2, v2) = (u * u, v * v);
    let anisotropy = if u2 < v2 {
        1.0 - u2 / v2
    } else {
        v2 / u2 - 1.0
    };
    if anisotropy.is_finite() {
        anisotropy
    } else {
        0.0
    }
}

impl Parser {
    pub(super) fn material(
        &mut self,
        kind: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<MaterialDesc, SceneError> {
        // Every material may carry a bump map (`core/material.cpp`: `Material::Bump`); a
        // constant displacement bends nothing.
        let bump = match self.color_param(params, "bumpmap", Vec3::ZERO, line)? {
            ColorParam::Texture(height) => Some(height),
            ColorParam::Constant(_) => None,
        };
        let sample_distance = params
            .float("bumpmapsampledistance")?
            .unwrap_or(DEFAULT_SAMPLE_DISTANCE);
        let material = self.unbumped_material(kind, line, params)?;
        Ok(match bump {
            Some(height) => {
                self.scene.materials.push(material);
                MaterialDesc::Bump {
                    material: self.scene.materials.len() - 1,
                    height,
                    sample_distance,
                }
            }
            None => material,
        })
    }

    fn unbumped_material(
        &mut self,
        kind: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<MaterialDesc, SceneError> {
        if let Some(fit) = measured_material(kind) {
            return Ok(MaterialDesc::Lafortune(fit));
        }
        Ok(match kind {
            // `materials/matte.cpp`: Kd 0.9, sigma 0 (Lambertian) in degrees, clamped to [0, 90].
            "matte" => {
                let reflectance = self.color_param(params, "Kd", Vec3::splat(0.9), line)?;
                match self.color_param(params, "sigma", Vec3::ZERO, line)? {
                    ColorParam::Constant(sigma) if sigma.max_element() <= 0.0 => {
                        MaterialDesc::Diffuse { reflectance }
                    }
                    sigma_degrees => MaterialDesc::RoughDiffuse {
                        reflectance,
                        sigma_degrees,
                    },
                }
            }
            // `materials/glossy2.cpp`: Kd 1, Ks 1 (times ((n - 1) / (n + 1))^2 when `index` > 0),
            // Ka 0, d 0, uroughness = vroughness = 0.1 clamped to [1e-4, 1], Schlick's
            // r = u v and anisotropy of the clamped u and v.
            "glossy" => {
                let diffuse = self.color_param(params, "Kd", Vec3::ONE, line)?;
                let index = self.constant_float(params, "index", 0.0, line)?;
                let specular = match self.color_param(params, "Ks", Vec3::ONE, line)? {
                    ColorParam::Constant(ks) => ColorParam::Constant(coating_f0(ks, index)),
                    texture => texture,
                };
                let absorption = self.color_param(params, "Ka", Vec3::ZERO, line)?;
                let depth = self.constant_float(params, "d", 0.0, line)?;
                let u = self.constant_float(params, "uroughness", 0.1, line)?;
                let v = self.constant_float(params, "vroughness", 0.1, line)?;
                let clamp = |r: f32| r.clamp(1e-4, 1.0);
                params.string("multibounce")?;
                MaterialDesc::CoatedDiffuse {
                    diffuse,
                    specular,
                    absorption,
                    depth,
                    roughness: clamp(u) * clamp(v),
                    anisotropy: schlick_anisotropy(clamp(u), clamp(v)),
                }
            }
            "mirror" => MaterialDesc::Mirror {
                reflectance: self.color_param(params, "Kr", Vec3::ONE, line)?,
            },
            "glass" => {
                self.warn_unrendered_glass_options(params, line, "glass")?;
                MaterialDesc::Dielectric {
                    reflectance: self.color_param(params, "Kr", Vec3::ONE, line)?,
                    transmittance: self.color_param(params, "Kt", Vec3::ONE, line)?,
                    ior: self.constant_float(params, "index", 1.5, line)?,
                }
            }
            // `materials/glass2.cpp`: a smooth interface (`architectural`: a thin sheet) whose
            // index the shape's volumes give (`volumes.rs`); 1 until then, as with no volumes.
            "glass2" => {
                if params.bool("dispersion")?.unwrap_or(false) {
                    self.warn(
                        line,
                        "glass2: \"dispersion\" is not rendered (foton is RGB)",
                    );
                }
                let (reflectance, transmittance) = (
                    ColorParam::Constant(Vec3::ONE),
                    ColorParam::Constant(Vec3::ONE),
                );
                if params.bool("architectural")?.unwrap_or(false) {
                    MaterialDesc::ThinDielectric {
                        reflectance,
                        transmittance,
                        ior: 1.0,
                    }
                } else {
                    MaterialDesc::Dielectric {
                        reflectance,
                        transmittance,
                        ior: 1.0,
                    }
                }
            }
            // `materials/roughglass.cpp` (LuxRender 1.x): Kr, Kt 1, index 1.5, uroughness and
            // vroughness 0.001 clamped to [6e-3, 1], the same Schlick distribution of r = u v
            // as metal2, so the same GGX alphas. (`cauchyb`, dispersion: not modelled.)
            "roughglass" => {
                let clamp = |r: f32| metal2_alpha(r.clamp(6e-3, 1.0));
                let u = self.constant_float(params, "uroughness", 0.001, line)?;
                let v = self.constant_float(params, "vroughness", 0.001, line)?;
                self.warn_unrendered_glass_options(params, line, "roughglass")?;
                MaterialDesc::RoughDielectric {
                    reflectance: self.color_param(params, "Kr", Vec3::ONE, line)?,
                    transmittance: self.color_param(params, "Kt", Vec3::ONE, line)?,
                    ior: self.constant_float(params, "index", 1.5, line)?,
                    roughness: Roughness {
                        distribution: MicrofacetDistribution::Ggx,
                        alpha_u: clamp(u),
                        alpha_v: clamp(v),
                    },
                }
            }
            "metal2" => {
                let kr = self.color_param(params, "Kr", Vec3::ONE, line)?;
                // The course's `roughness` sets both, unless LuxRender's own are given.
                let both = params.float("roughness")?;
                let (u, v) = (params.float("uroughness")?, params.float("vroughness")?);
                if both.is_some() && u.is_some() && v.is_some() {
                    self.warn(
                        line,
                        "metal2: \"roughness\" ignored: uroughness and vroughness given",
                    );
                }
                let default = both.unwrap_or(0.1);
                MaterialDesc::RoughConductor {
                    specular: kr,
                    alpha_u: metal2_alpha(u.unwrap_or(default)),
                    alpha_v: metal2_alpha(v.unwrap_or(default)),
                }
            }
            "metal" => self.metal(line, params)?,
            "mattetranslucent" => self.matte_translucent(line, params)?,
            "glossytranslucent" => self.glossy_translucent(line, params)?,
            "shinymetal" => self.shiny_metal(line, params)?,
            // `materials/velvet.cpp` (1.x): Kd 0.3, p1 -2, p2 20, p3 2 (each clamped to
            // [-100, 100]), thickness 0.1 (clamped to [0, 1]).
            "velvet" => {
                let reflectance = self.color_param(params, "Kd", Vec3::splat(0.3), line)?;
                let mut coefficient = |name: &str, default: f32| {
                    self.constant_float(params, name, default, line)
                        .map(|a| a.clamp(-100.0, 100.0))
                };
                let legendre = [
                    coefficient("p1", -2.0)?,
                    coefficient("p2", 20.0)?,
                    coefficient("p3", 2.0)?,
                ];
                let thickness = self.constant_float(params, "thickness", 0.1, line)?;
                MaterialDesc::Velvet {
                    reflectance,
                    legendre,
                    thickness: thickness.clamp(0.0, 1.0),
                }
            }
            "carpaint" => self.car_paint(line, params)?,
            // LuxRender 0.x's (pbrt-v1's) `materials/plastic.cpp`: Kd 1, Ks 1, roughness 0.1,
            // Blinn's exponent 1 / roughness (clamped as `PhongDistribution` says).
            "plastic" => {
                let diffuse = self.color_param(params, "Kd", Vec3::ONE, line)?;
                let specular = self.color_param(params, "Ks", Vec3::ONE, line)?;
                let roughness = self.constant_float(params, "roughness", 0.1, line)?;
                MaterialDesc::BlinnPlastic {
                    diffuse,
                    specular,
                    exponent: PhongDistribution::from_roughness(roughness, roughness).ex,
                }
            }
            // LuxRender 0.x's `materials/substrate.cpp`: Kd 0.5, Ks 0.5, uroughness and
            // vroughness 0.1, the exponents their inverses.
            "substrate" => {
                let diffuse = self.color_param(params, "Kd", Vec3::splat(0.5), line)?;
                let specular = self.color_param(params, "Ks", Vec3::splat(0.5), line)?;
                let u = self.constant_float(params, "uroughness", 0.1, line)?;
                let v = self.constant_float(params, "vroughness", 0.1, line)?;
                let PhongDistribution { ex, ey } = PhongDistribution::from_roughness(u, v);
                MaterialDesc::FresnelBlend {
                    diffuse,
                    specular,
                    exponents: (ex, ey),
                }
            }
            // `materials/scattermaterial.cpp` scatters by a volume's phase function at the
            // surface; foton has no media.
            "scatter" => {
                self.warn(
                    line,
                    "material \"scatter\" (a phase function at the surface) is not rendered: grey matte",
                );
                params.ignore_all();
                MaterialDesc::Diffuse {
                    reflectance: ColorParam::Constant(GREY),
                }
            }
            "null" => MaterialDesc::Null,
            "mix" => {
                let mut named = |key: &str| -> Result<usize, SceneError> {
                    let name = params
                        .string(key)?
                        .ok_or_else(|| self.error(line, format!("mix: \"{key}\" missing")))?;
                    self.named_materials.get(&name).copied().ok_or_else(|| {
                        self.error(line, format!("mix: \"{key}\" \"{name}\": no such material"))
                    })
                };
                let first = named("namedmaterial1")?;
                let second = named("namedmaterial2")?;
                let amount = self.color_param(params, "amount", Vec3::splat(0.5), line)?;
                MaterialDesc::Mix {
                    first,
                    second,
                    amount,
                }
            }
            _ => {
                self.warn(
                    line,
                    format!("material type \"{kind}\" unsupported: grey matte"),
                );
                params.ignore_all();
                MaterialDesc::Diffuse {
                    reflectance: ColorParam::Constant(GREY),
                }
            }
        })
    }

    /// `metal` (LuxRender 1.x `materials/metal.cpp`): `name` is tried first as a file of n/k data
    /// (`.nk`), then as one of the built-in tables; an unknown name gets a warning and
    /// aluminium, as in LuxRender. `uroughness`, `vroughness` (0.1; older scenes write one
    /// `roughness`) are the inverse exponents of Blinn's distribution, e = 1 / r, which matches
    /// the Beckmann alpha = sqrt(2 / (e + 2)) (Walter et al. 2007, section 5.2); foton's lobe is
    /// GGX of that alpha.
    fn metal(&mut self, line: usize, params: &mut ParamList) -> Result<MaterialDesc, SceneError> {
        let name = params
            .string("name")?
            .unwrap_or_else(|| nk::DEFAULT_METAL.to_string());
        let samples = match nk::named_metal(&name) {
            Some(samples) => samples,
            None => match paths::resolve(&name, &self.dir, &self.main_dir) {
                Ok(found) => nk::read_nk_file(&found.path).map_err(|e| SceneError {
                    location: Location::line(&found.path, e.line),
                    message: format!("metal \"name\" \"{name}\": {}", e.message),
                })?,
                Err(_) => {
                    self.warn(
                        line,
                        format!(
                            "metal \"{name}\": neither a built-in metal nor a file: {}",
                            nk::DEFAULT_METAL
                        ),
                    );
                    nk::named_metal(nk::DEFAULT_METAL).unwrap_or_default()
                }
            },
        };
        let (eta, k) = nk::nk_to_rgb(&samples);
        let roughness = self.constant_float(params, "roughness", 0.1, line)?;
        let u = self.constant_float(params, "uroughness", roughness, line)?;
        let v = self.constant_float(params, "vroughness", roughness, line)?;
        let blinn_alpha = |r: f32| (2.0 / (1.0 / r.max(1e-6) + 2.0)).sqrt();
        Ok(MaterialDesc::Conductor {
            reflectance: ColorParam::Constant(Vec3::ONE),
            eta,
            k,
            roughness: Some(Roughness {
                distribution: MicrofacetDistribution::Ggx,
                alpha_u: blinn_alpha(u),
                alpha_v: blinn_alpha(v),
            }),
        })
    }

    /// LuxRender 1.x's glass and roughglass take Cauchy's B (`cauchyb`, in um^2: the index
    /// n(lambda) = A + B / lambda^2, i.e. dispersion) and glass a thin film on its interface
    /// (`film` thickness in nm, `filmindex`); foton renders neither (it is RGB, its glass one
    /// index), so a non-zero value gets a warning rather than a silently different image.
    fn warn_unrendered_glass_options(
        &mut self,
        params: &mut ParamList,
        line: usize,
        kind: &str,
    ) -> Result<(), SceneError> {
        if self.constant_float(params, "cauchyb", 0.0, line)? != 0.0 {
            self.warn(
                line,
                format!("{kind}: dispersion (\"cauchyb\") is not rendered (foton is RGB)"),
            );
        }
        if kind == "glass" {
            if self.constant_float(params, "film", 0.0, line)? > 0.0 {
                self.warn(line, "glass: the thin film (\"film\") is not rendered");
            }
            params.ignore("filmindex");
        }
        Ok(())
    }

    /// `shinymetal` (LuxRender 1.x `materials/shinymetal.cpp`): `Ks`, `Kr` (1), `uroughness`,
    /// `vroughness` (0.1; Schlick's r = u v and anisotropy from u and v), `film` (thin-film
    /// thickness in nm, 0: none) and `filmindex` (1.5) on the mirror.
    fn shiny_metal(
        &mut self,
        line: usize,
        params: &mut ParamList,
    ) -> Result<MaterialDesc, SceneError> {
        // LuxRender 0.x's `roughness` was Blinn's exponent 1 / roughness (`shinymetal.cpp`
        // of 2007-8, pbrt-v1's); Blinn's distribution is not Schlick's for any r, so no value
        // of 1.x's parameters draws the same lobe.
        if params.ignore("roughness") {
            self.warn(
                line,
                "shinymetal: LuxRender 0.x's \"roughness\" (a Blinn exponent) has no exact \
                 counterpart in 1.x's Schlick uroughness, vroughness: ignored",
            );
        }
        let glossy = self.color_param(params, "Ks", Vec3::ONE, line)?;
        let mirror = self.color_param(params, "Kr", Vec3::ONE, line)?;
        let u = self.constant_float(params, "uroughness", 0.1, line)?;
        let v = self.constant_float(params, "vroughness", 0.1, line)?;
        let thickness = self.constant_float(params, "film", 0.0, line)?;
        let index = self.constant_float(params, "filmindex", 1.5, line)?;
        Ok(MaterialDesc::FittedConductor {
            glossy,
            mirror,
            roughness: u * v,
            anisotropy: schlick_anisotropy(u, v),
            film: (thickness > 0.0).then_some((thickness, index)),
        })
    }

    /// `carpaint` (LuxRender 1.x `materials/carpaint.cpp`): a `name` picks a preset (every
    /// parameter but `Ka` and `d` then ignored, as in LuxRender; an unknown name gets a warning
    /// and the first preset, "ford f8"); without one, `Kd`, `Ks1`..`Ks3`, `R1`..`R3`, `M1`..`M3`
    /// default to that preset's values. `Ka` (0) and `d` (0) are the clear coat's absorption.
    fn car_paint(
        &mut self,
        line: usize,
        params: &mut ParamList,
    ) -> Result<MaterialDesc, SceneError> {
        let absorption = self.color_param(params, "Ka", Vec3::ZERO, line)?;
        let depth = self.constant_float(params, "d", 0.0, line)?;
        let name = params.string("name")?.unwrap_or_default();
        let default = &car_paint::PRESETS[0];
        let (diffuse, lobes) = if name.is_empty() {
            let diffuse = self.color_param(params, "Kd", default.kd, line)?;
            let mut lobes = Vec::with_capacity(3);
            for k in 0..3 {
                let n = k + 1;
                lobes.push(CarPaintLobeDesc {
                    specular: self.color_param(params, &format!("Ks{n}"), default.ks[k], line)?,
                    f0: self.constant_float(params, &format!("R{n}"), default.r[k], line)?,
                    roughness: self.constant_float(params, &format!("M{n}"), default.m[k], line)?,
                });
            }
            (diffuse, lobes)
        } else {
            let paint = car_paint::preset(&name).unwrap_or_else(|| {
                self.warn(
                    line,
                    format!("carpaint \"{name}\": no such preset: {}", default.name),
                );
                default
            });
            params.ignore_all();
            let lobes = (0..3)
                .map(|k| CarPaintLobeDesc {
                    specular: ColorParam::Constant(paint.ks[k]),
                    f0: paint.r[k],
                    roughness: paint.m[k],
                })
                .collect();
            (ColorParam::Constant(paint.kd), lobes)
        };
        let lobes: [CarPaintLobeDesc; 3] = lobes
            .try_into()
            .map_err(|_| self.error(line, "carpaint: three lobes expected"))?;
        Ok(MaterialDesc::CarPaint {
            diffuse,
            absorption,
            depth,
            lobes,
        })
    }

    /// `mattetranslucent` (LuxRender 1.x `materials/mattetranslucent.cpp`): Lambertian
    /// reflection of `Kr` and transmission of `Kt` (both 1, clamped to [0, 1]); with
    /// `energyconserving` (false) LuxRender scales T by 1 - R so that R + T <= 1. `sigma` (0,
    /// in degrees, a float texture too) makes both lobes Oren-Nayar, as in LuxRender.
    fn matte_translucent(
        &mut self,
        line: usize,
        params: &mut ParamList,
    ) -> Result<MaterialDesc, SceneError> {
        let reflectance = self.color_param(params, "Kr", Vec3::ONE, line)?;
        let mut transmittance = self.color_param(params, "Kt", Vec3::ONE, line)?;
        if params.bool("energyconserving")?.unwrap_or(false) {
            match (reflectance, transmittance) {
                (ColorParam::Constant(r), ColorParam::Constant(t)) => {
                    let clamp = |c: Vec3| c.clamp(Vec3::ZERO, Vec3::ONE);
                    transmittance = ColorParam::Constant(clamp(t) * (Vec3::ONE - clamp(r)));
                }
                _ => self.warn(
                    line,
                    "mattetranslucent: \"energyconserving\" with textured Kr or Kt unsupported: ignored",
                ),
            }
        }
        let sigma_degrees = self.color_param(params, "sigma", Vec3::ZERO, line)?;
        Ok(MaterialDesc::DiffuseTranslucent {
            reflectance,
            transmittance,
            sigma_degrees,
        })
    }

    /// A float parameter that may name a texture: a number or a `constant` texture gives its
    /// value; a varying texture is not evaluated per hit for these parameters (a warning, then
    /// the default).
    pub(super) fn constant_float(
        &mut self,
        params: &mut ParamList,
        name: &str,
        default: f32,
        line: usize,
    ) -> Result<f32, SceneError> {
        match self.color_param(params, name, Vec3::splat(default), line)? {
            ColorParam::Constant(c) => Ok((c.x + c.y + c.z) / 3.0),
            ColorParam::Texture(_) => {
                self.warn(
                    line,
                    format!(
                        "\"{name}\": a varying texture for this parameter is unsupported: {default}"
                    ),
                );
                Ok(default)
            }
        }
    }

    /// A colour or a reference to a texture defined earlier.
    pub(super) fn color_param(
        &self,
        params: &mut ParamList,
        name: &str,
        default: Vec3,
        line: usize,
    ) -> Result<ColorParam, SceneError> {
        match params.color(name)? {
            None => Ok(ColorParam::Constant(default)),
            Some(ColorSource::Rgb(rgb)) => Ok(ColorParam::Constant(rgb)),
            Some(ColorSource::Texture(texture)) => {
                self.named_textures.get(&texture).copied().ok_or_else(|| {
                    self.error(
                        line,
                        format!("\"{name}\" names texture \"{texture}\", which is not defined"),
                    )
                })
            }
        }
    }

    /// `Texture "name" "color" "class" ...`, or the course's `Texture "name" "string filename"`.
    pub(super) fn texture(
        &mut self,
        strings: &[String],
        line: usize,
        params: &mut ParamList,
    ) -> Result<(), SceneError> {
        let name = strings[0].clone();
        let class = match strings {
            [_, _, class] => class.as_str(),
            [_] => {
                self.warn(
                    line,
                    format!("Texture \"{name}\" has no type and class: read as an imagemap"),
                );
                "imagemap"
            }
            _ => {
                return Err(self.error(
                    line,
                    format!("Texture \"{name}\": expected a type and a class"),
                ));
            }
        };
        let texture = match class {
            "imagemap" => {
                let image = self.image_texture(&name, line, params)?;
                ColorParam::Texture(self.scene.texture_graph.push(TextureNode::Image {
                    image,
                    mapping: Mapping2D::default(),
                }))
            }
            "constant" => match params.color("value")? {
                Some(ColorSource::Rgb(rgb)) => ColorParam::Constant(rgb),
                _ => {
                    return Err(self.error(
                        line,
                        format!("Texture \"{name}\": constant without a \"value\""),
                    ));
                }
            },
            _ => match self.procedural_texture(class, line, params)? {
                Some(node) => ColorParam::Texture(self.scene.texture_graph.push(node)),
                None => {
                    self.warn(
                        line,
                        format!("Texture \"{name}\": class \"{class}\" unsupported: constant grey"),
                    );
                    params.ignore_all();
                    ColorParam::Constant(GREY)
                }
            },
        };
        self.named_textures.insert(name, texture);
        Ok(())
    }

    /// Decodes an image map into `textures`: texel = (value/255)^gamma * gain.
    fn image_texture(
        &mut self,
        name: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<usize, SceneError> {
        let filename = params
            .string("filename")?
            .ok_or_else(|| self.error(line, format!("Texture \"{name}\": \"filename\" missing")))?;
        let gamma = params.float("gamma")?.unwrap_or(2.2);
        let gain = params.float("gain")?.unwrap_or(1.0);
        let scale = Vec2::new(
            params.float("uscale")?.unwrap_or(1.0),
            params.float("vscale")?.unwrap_or(1.0),
        );
        let delta = Vec2::new(
            params.float("udelta")?.unwrap_or(0.0),
            params.float("vdelta")?.unwrap_or(0.0),
        );
        // LuxRender 1.x's `wrap` (textures/imagemap.cpp): repeat (the default), black, white,
        // clamp.
        let wrap = match params.string("wrap")?.as_deref() {
            None | Some("repeat") => Wrap::Repeat,
            Some("black") => Wrap::Black,
            Some("white") => Wrap::White,
            Some("clamp") => Wrap::Clamp,
            Some(other) => {
                self.warn(
                    line,
                    format!("Texture \"{name}\": unknown wrap \"{other}\": repeat used"),
                );
                Wrap::Repeat
            }
        };
        let what = format!("Texture \"{name}\" \"{filename}\"");
        let id = self.load_image(name, &filename, gamma, gain, line, &what)?;
        self.scene.textures[id].scale = scale;
        self.scene.textures[id].delta = delta;
        self.scene.textures[id].wrap = wrap;
        Ok(id)
    }

    /// Finds and decodes an image, appending it to `textures` with the identity uv mapping.
    pub(super) fn load_image(
        &mut self,
        name: &str,
        filename: &str,
        gamma: f32,
        gain: f32,
        line: usize,
        what: &str,
    ) -> Result<usize, SceneError> {
        let path = self.resolve(filename, line, what)?;
        let decoded = image::decode_texture(&path, gamma, gain).map_err(|e| {
            self.error(
                line,
                format!("{what}: cannot decode {}: {e}", path.display()),
            )
        })?;
        self.scene.textures.push(ImageTexture {
            name: name.to_string(),
            path,
            width: decoded.width,
            height: decoded.height,
            texels: decoded.texels,
            scale: Vec2::ONE,
            delta: Vec2::ZERO,
            wrap: Wrap::Repeat,
        });
        Ok(self.scene.textures.len() - 1)
    }
}
