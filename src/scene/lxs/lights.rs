//! `LightSource` and `AreaLightSource`: positions and directions go through the CTM.

use std::f32::consts::PI;
use std::sync::Arc;

use glam::Vec3;

use super::params::ParamList;
use super::parser::Parser;
use super::sky::PreethamSky;
use super::sun::{sun_radiance, sun_sin_theta_max};
use crate::film::luminance;
use crate::scene::desc::{
    AreaLightDesc, ColorParam, ImageTexture, LightDesc, SceneError, ShapeDesc, SpotFalloff, Wrap,
};
use crate::texture::{ShadingPoint, TexParam, TextureNode};

/// `AreaLightSource "area"` as written; it becomes a radiance once the shape's area is known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct AreaLight {
    l: Vec3,
    gain: f32,
    power: f32,
    efficacy: f32,
    /// The parser's `film_units`, for when `power` does not apply.
    film_units: f32,
}

impl AreaLight {
    /// The radiance L * gain, where `power` (W) and `efficacy` (lm/W) scale the gain so that the
    /// emitter's luminous flux is power * efficacy: a one-sided Lambertian emitter of radiance L
    /// and area A emits pi A Y(L), so gain *= power * efficacy / (pi A Y(L)) (LuxRender 1.x
    /// `lights/area.cpp`).
    pub(super) fn radiance(&self, shape: &ShapeDesc) -> AreaLightDesc {
        let flux_per_gain = PI * shape.surface_area() * luminance(self.l);
        AreaLightDesc {
            radiance: self.l
                * (self.gain
                    * power_factor(self.power, self.efficacy, flux_per_gain, self.film_units)),
        }
    }
}

/// LuxRender's gain factor from `power` and `efficacy`: the luminous flux asked for over the
/// flux the light emits at gain 1. When that is not positive and finite, as when either is 0
/// (what LuxBlend writes when no power is set), the gain stands alone: `film_units` (1, or
/// LuxRender 0.x's film units, `version.rs`).
fn power_factor(power: f32, efficacy: f32, flux_per_gain: f32, film_units: f32) -> f32 {
    let factor = power * efficacy / flux_per_gain;
    if factor > 0.0 && factor.is_finite() {
        factor
    } else {
        film_units
    }
}

impl Parser {
    pub(super) fn light(
        &mut self,
        kind: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<(), SceneError> {
        let ctm = self.state.ctm;
        let l = self.light_color(params, line)?;
        let gain = params.float("gain")?.unwrap_or(1.0);
        let film_units = self.film_units;
        let scale = l * gain * film_units;
        let from = params.vec3("from")?.unwrap_or(Vec3::ZERO);
        let to = params.vec3("to")?.unwrap_or(Vec3::Z);
        let direction = |from: Vec3, to: Vec3| {
            ctm.transform_vector3(to - from)
                .try_normalize()
                .ok_or_else(|| {
                    self.error(
                        line,
                        format!("LightSource \"{kind}\": \"from\" and \"to\" give no direction"),
                    )
                })
        };
        let power = params.float("power")?.unwrap_or(0.0);
        let efficacy = params.float("efficacy")?.unwrap_or(0.0);
        let light = match kind {
            // An isotropic point light of intensity I emits 4 pi I; power * efficacy asks for a
            // luminous flux, so gain *= power * efficacy / (4 pi Y(L)) (LuxRender 1.x
            // `lights/pointlight.cpp`).
            "point" => LightDesc::Point {
                position: ctm.transform_point3(from),
                intensity: l
                    * (gain * power_factor(power, efficacy, 4.0 * PI * luminance(l), film_units)),
            },
            "spot" => {
                let cone_angle = params.float("coneangle")?.unwrap_or(30.0);
                let cone_delta_angle = params.float("conedeltaangle")?.unwrap_or(5.0);
                // LuxRender 1.x `lights/spot.cpp` counts the flux of intensity I as
                // 2 pi I (1 - (cos(fall) + cos(width)) / 2), with width = coneangle and
                // fall = coneangle - conedeltaangle: the cone's solid angle, the falloff band
                // counted half.
                let (cos_width, cos_fall) = (
                    cone_angle.to_radians().cos(),
                    (cone_angle - cone_delta_angle).to_radians().cos(),
                );
                let flux_per_gain = 2.0 * PI * luminance(l) * (1.0 - 0.5 * (cos_fall + cos_width));
                LightDesc::Spot {
                    position: ctm.transform_point3(from),
                    direction: direction(from, to)?,
                    intensity: l
                        * (gain * power_factor(power, efficacy, flux_per_gain, film_units)),
                    cone_angle,
                    cone_delta_angle,
                    falloff: SpotFalloff::SmoothCosine,
                }
            }
            "distant" => LightDesc::Distant {
                direction_to_light: direction(to, from)?,
                radiance: scale,
            },
            "infinite" => {
                let map = match params.string("mapname")? {
                    Some(mapname) => {
                        let gamma = params.float("gamma")?.unwrap_or(2.2);
                        let what = format!("LightSource \"infinite\" \"mapname\" \"{mapname}\"");
                        Some(self.load_image(&mapname, &mapname, gamma, 1.0, line, &what)?)
                    }
                    None => None,
                };
                LightDesc::Infinite {
                    radiance: scale,
                    map,
                    light_to_world: ctm,
                }
            }
            "sun" | "sunsky" => {
                // LuxRender 1.x makes `sunsky` a `sun` and a `sky` from the same parameters.
                if let Some(sun) = self.sun(line, gain, params)? {
                    self.scene.lights.push(sun);
                }
                if kind == "sun" {
                    return Ok(());
                }
                self.sky(kind, gain, params)?
            }
            "sky" => self.sky(kind, gain, params)?,
            _ => {
                self.warn(line, format!("LightSource \"{kind}\" unsupported: skipped"));
                params.ignore_all();
                return Ok(());
            }
        };
        self.scene.lights.push(light);
        Ok(())
    }

    /// `sun` (LuxRender 1.x `lights/sun.cpp`: `sundir` (0 0 -1) through the CTM, `turbidity`
    /// 2, `relsize` 1, `gain` 1): the attenuated solar spectrum of the sun's zenith angle in the
    /// world ([`sun_radiance`]) times `gain`, seen within the cone of the disc `relsize` times
    /// the sun's size ([`LightDesc::SunDisc`]). `relsize` 0 is LuxRender's old delta sun, a
    /// distant light whose irradiance is the radiance itself. `None` when the sun is below the
    /// horizon (dark).
    fn sun(
        &mut self,
        line: usize,
        gain: f32,
        params: &mut ParamList,
    ) -> Result<Option<LightDesc>, SceneError> {
        let turbidity = params.float("turbidity")?.unwrap_or(2.0);
        let relsize = params.float("relsize")?.unwrap_or(1.0);
        params.int("nsamples")?;
        let sundir = params.vec3("sundir")?.unwrap_or(Vec3::NEG_Z);
        let Some(direction) = self.state.ctm.transform_vector3(sundir).try_normalize() else {
            return Err(self.error(line, "LightSource \"sun\": \"sundir\" is zero"));
        };
        let radiance = sun_radiance(direction.z.clamp(-1.0, 1.0).acos(), turbidity) * gain;
        if radiance == Vec3::ZERO {
            return Ok(None);
        }
        if relsize == 0.0 {
            return Ok(Some(LightDesc::Distant {
                direction_to_light: direction,
                radiance,
            }));
        }
        let sin_theta_max = sun_sin_theta_max(relsize).unwrap_or_else(|| {
            self.warn(
                line,
                format!("LightSource \"sun\": \"relsize\" {relsize} exceeds a hemisphere: reduced to one"),
            );
            1.0
        });
        Ok(Some(LightDesc::SunDisc {
            direction_to_light: direction,
            radiance,
            sin_theta_max,
        }))
    }

    /// `sky` (LuxRender 1.x `lights/sky.cpp`: `turbidity` 2, `sundir` (0 0 1) in light space,
    /// `aconst` .. `econst` 1, `gain` 1) as an environment map of the Preetham sky
    /// ([`PreethamSky`]), importance-sampled like any other. `sunsky` gives the same sky.
    fn sky(
        &mut self,
        kind: &str,
        gain: f32,
        params: &mut ParamList,
    ) -> Result<LightDesc, SceneError> {
        /// The map's size: the sky varies smoothly except near the sun (its circumsolar term
        /// spans several degrees), which 0.7-degree texels resolve.
        const WIDTH: usize = 512;
        const HEIGHT: usize = 256;
        let turbidity = params.float("turbidity")?.unwrap_or(2.0);
        let sun = params.vec3("sundir")?.unwrap_or(Vec3::Z);
        let mut constants = [1.0; 5];
        for (c, name) in constants
            .iter_mut()
            .zip(["aconst", "bconst", "cconst", "dconst", "econst"])
        {
            *c = params.float(name)?.unwrap_or(1.0);
        }
        params.int("nsamples")?;
        let texels = PreethamSky::new(sun, turbidity, constants).tabulate(WIDTH, HEIGHT);
        self.scene.textures.push(ImageTexture {
            name: format!("LightSource \"{kind}\" (Preetham sky, turbidity {turbidity})"),
            path: self.file.clone(),
            width: WIDTH as u32,
            height: HEIGHT as u32,
            texels: Arc::new(texels).into(),
            scale: glam::Vec2::ONE,
            delta: glam::Vec2::ZERO,
            wrap: Wrap::Repeat,
        });
        Ok(LightDesc::Infinite {
            radiance: Vec3::splat(gain),
            map: Some(self.scene.textures.len() - 1),
            light_to_world: self.state.ctm,
        })
    }

    /// Makes the shapes that follow in this attribute block emitters.
    pub(super) fn area_light(
        &mut self,
        kind: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<(), SceneError> {
        if kind != "area" {
            self.warn(
                line,
                format!("AreaLightSource \"{kind}\" unsupported: read as \"area\""),
            );
        }
        self.state.area_light = Some(AreaLight {
            l: self.light_color(params, line)?,
            gain: params.float("gain")?.unwrap_or(1.0),
            // LuxRender 1.x's defaults (`lights/area.cpp`, `CreateAreaLight`): 100 W at
            // 17 lm/W, so an area light without `power` is normalised to 1700 lm too.
            power: params.float("power")?.unwrap_or(100.0),
            efficacy: params.float("efficacy")?.unwrap_or(17.0),
            film_units: self.film_units,
        });
        Ok(())
    }

    /// A light's `L`: a colour, or a texture (LuxBlend writes `"texture L"` naming a
    /// `blackbody` or `constant` texture). Emission is one colour per light in foton, so the
    /// texture is evaluated once; a texture that varies over the surface gets a warning.
    fn light_color(&mut self, params: &mut ParamList, line: usize) -> Result<Vec3, SceneError> {
        let id = match self.color_param(params, "L", Vec3::ONE, line)? {
            ColorParam::Constant(c) => return Ok(c),
            ColorParam::Texture(id) => id,
        };
        let graph = &self.scene.texture_graph;
        if !matches!(
            graph.nodes.get(id),
            Some(TextureNode::Blackbody { .. } | TextureNode::Constant(_))
        ) {
            self.warn(
                line,
                "\"texture L\": a texture varying over the light is unsupported: its value at uv (0, 0)",
            );
        }
        let at = ShadingPoint {
            p: Vec3::ZERO,
            uv: glam::Vec2::ZERO,
            n: Vec3::Z,
            object: 0,
        };
        Ok(self
            .scene
            .texture_graph
            .eval(TexParam::Texture(id), &at, &|_, _| Vec3::ONE))
    }
}
