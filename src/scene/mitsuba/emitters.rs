//! Mitsuba emitters in foton's lights, in Mitsuba's units: `area` radiance, `point` and `spot`
//! radiant intensity, `directional` irradiance, `constant` radiance, `envmap` a latitude-longitude
//! map times `scale`, with y up and u = 0 toward -z as Mitsuba orients it.

use glam::{DMat4, Mat3, Mat4, Vec3};

use super::convert::Converter;
use super::tree::Object;
use crate::scene::desc::{AreaLightDesc, ImageTexture, LightDesc, SceneError, SpotFalloff, Wrap};
use crate::scene::io::image as images;
use std::sync::Arc;

/// The area light of a shape's `<emitter type="area">`.
pub fn area(cx: &mut Converter, emitter: &Object) -> Option<AreaLightDesc> {
    if emitter.plugin != "area" {
        cx.warn(
            &emitter.loc,
            format!(
                "emitter \"{}\" inside a shape not supported",
                emitter.plugin
            ),
        );
        return None;
    }
    let radiance = cx.rgb(emitter, "radiance", Vec3::ONE);
    if emitter.named_child(cx.tree, "radiance").is_some() {
        cx.warn(
            &emitter.loc,
            "textured radiance not supported: 1 used".into(),
        );
    }
    cx.report_unused(emitter);
    Some(AreaLightDesc { radiance })
}

/// A scene-level emitter.
pub fn emitter(cx: &mut Converter, object: &Object) -> Result<(), SceneError> {
    let loc = object.loc.clone();
    let to_world = cx.transform(object, "to_world");
    let light = match object.plugin.as_str() {
        "point" => {
            let position = match object.prop("position") {
                Some(_) => cx.vec3(object, "position", Vec3::ZERO),
                None => to_world.transform_point3(glam::DVec3::ZERO).as_vec3(),
            };
            LightDesc::Point {
                position,
                intensity: cx.rgb(object, "intensity", Vec3::ONE),
            }
        }
        "spot" => {
            let cutoff = cx.float(object, "cutoff_angle", 20.0);
            let beam = cx.float(object, "beam_width", cutoff * 0.75).min(cutoff);
            LightDesc::Spot {
                position: to_world.transform_point3(glam::DVec3::ZERO).as_vec3(),
                direction: to_world
                    .transform_vector3(glam::DVec3::Z)
                    .as_vec3()
                    .normalize_or(Vec3::Z),
                intensity: cx.rgb(object, "intensity", Vec3::ONE),
                cone_angle: cutoff,
                cone_delta_angle: cutoff - beam,
                falloff: SpotFalloff::LinearAngle,
            }
        }
        "directional" => {
            let direction = match object.prop("direction") {
                Some(_) => cx.vec3(object, "direction", Vec3::Z),
                None => to_world.transform_vector3(glam::DVec3::Z).as_vec3(),
            };
            LightDesc::Distant {
                direction_to_light: -direction.normalize_or(Vec3::Z),
                radiance: cx.rgb(object, "irradiance", Vec3::ONE),
            }
        }
        "constant" => LightDesc::Infinite {
            radiance: cx.rgb(object, "radiance", Vec3::ONE),
            map: None,
            light_to_world: Mat4::IDENTITY,
        },
        "envmap" => {
            let name = cx
                .string(object, "filename")
                .ok_or_else(|| cx.error(&loc, "envmap needs a filename".into()))?;
            let path = cx.tree.resolve(&name);
            let image = images::decode(&path, 2.2, 1.0).map_err(|e| {
                cx.error(
                    &loc,
                    format!("cannot read envmap \"{}\": {e}", path.display()),
                )
            })?;
            cx.desc.textures.push(ImageTexture {
                name: name.clone(),
                path,
                width: image.width,
                height: image.height,
                texels: Arc::new(image.texels).into(),
                scale: glam::Vec2::ONE,
                delta: glam::Vec2::ZERO,
                wrap: Wrap::Repeat,
            });
            object.prop("filter_type");
            LightDesc::Infinite {
                radiance: Vec3::splat(cx.float(object, "scale", 1.0)),
                map: Some(cx.desc.textures.len() - 1),
                light_to_world: (to_world * mitsuba_from_foton_envmap()).as_mat4(),
            }
        }
        other => {
            let other = other.to_string();
            cx.warn(&loc, format!("emitter \"{other}\" not supported, skipped"));
            return Ok(());
        }
    };
    cx.report_unused(object);
    cx.desc.lights.push(light);
    Ok(())
}

/// foton's map has z up and u = atan2(y, x) / 2 pi; Mitsuba's has y up and
/// u = atan2(x, -z) / 2 pi. A direction d in foton's frame is (d.y, d.z, -d.x) in Mitsuba's
/// (so that d.z is Mitsuba's up, and atan2(d.y, d.x) = atan2(x, -z)).
fn mitsuba_from_foton_envmap() -> DMat4 {
    let m = Mat3::from_cols(
        Vec3::new(0.0, 0.0, -1.0), // foton x -> Mitsuba -z
        Vec3::new(1.0, 0.0, 0.0),  // foton y -> Mitsuba x
        Vec3::new(0.0, 1.0, 0.0),  // foton z -> Mitsuba y
    );
    DMat4::from_mat3(m.as_dmat3())
}
