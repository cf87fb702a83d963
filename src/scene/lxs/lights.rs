//! `LightSource` and `AreaLightSource`: positions and directions go through the CTM.

use glam::Vec3;

use super::params::ParamList;
use super::parser::Parser;
use crate::scene::desc::{AreaLightDesc, LightDesc, SceneError};

impl Parser {
    pub(super) fn light(
        &mut self,
        kind: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<(), SceneError> {
        let ctm = self.state.ctm;
        let scale = params.vec3("L")?.unwrap_or(Vec3::ONE) * params.float("gain")?.unwrap_or(1.0);
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
        let light = match kind {
            "point" => LightDesc::Point {
                position: ctm.transform_point3(from),
                intensity: scale,
            },
            "spot" => LightDesc::Spot {
                position: ctm.transform_point3(from),
                direction: direction(from, to)?,
                intensity: scale,
                cone_angle: params.float("coneangle")?.unwrap_or(30.0),
                cone_delta_angle: params.float("conedeltaangle")?.unwrap_or(5.0),
            },
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
            _ => {
                self.warn(line, format!("LightSource \"{kind}\" unsupported: skipped"));
                params.ignore_all();
                return Ok(());
            }
        };
        // LuxBlend writes "power" and "efficacy" 0 for point lights; they only matter for area lights.
        params.float("power")?;
        params.float("efficacy")?;
        self.scene.lights.push(light);
        Ok(())
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
        self.state.area_light = Some(AreaLightDesc {
            l: params.vec3("L")?.unwrap_or(Vec3::ONE),
            gain: params.float("gain")?.unwrap_or(1.0),
            power: params.float("power")?.unwrap_or(0.0),
            efficacy: params.float("efficacy")?.unwrap_or(0.0),
        });
        Ok(())
    }
}
