//! `Camera` and `PixelFilter`.

use glam::Vec2;

use super::params::ParamList;
use super::parser::Parser;
use crate::camera::{self, pinhole};
use crate::scene::desc::{CameraDesc, DEFAULT_FOV_DEGREES, FilterDesc, FilterKind, SceneError};

impl Parser {
    /// Camera space is the CTM's space: camera_to_world = CTM^-1; the world starts afresh.
    pub(super) fn camera(
        &mut self,
        kind: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<(), SceneError> {
        // LuxRender's cameras (perspective, orthographic, environment) and foton's, by any of
        // their registered names.
        let camera = camera::find(kind).unwrap_or_else(|| {
            self.warn(
                line,
                format!("Camera \"{kind}\" unknown: using \"perspective\""),
            );
            &pinhole::CAMERA
        });
        let fov = params.float("fov")?;
        let fov_degrees = match camera.fov {
            Some(range) => {
                let fov = fov.unwrap_or(range.default);
                if !(fov > 0.0 && fov <= range.max) {
                    return Err(self.error(
                        line,
                        format!("Camera \"{kind}\": fov {fov} is not in (0, {}]", range.max),
                    ));
                }
                fov
            }
            None => DEFAULT_FOV_DEGREES,
        };
        let lens_radius = params.float("lensradius")?.unwrap_or(0.0);
        let focal_distance = params.float("focaldistance")?.unwrap_or(1e6);
        // LuxBlend writes lensradius 0 and focaldistance 0 when depth of field is off: a pinhole,
        // whose focal distance means nothing.
        let focal_distance = if lens_radius == 0.0 && focal_distance == 0.0 {
            1e6
        } else {
            focal_distance
        };
        if lens_radius < 0.0 || focal_distance <= 0.0 {
            return Err(self.error(
                line,
                format!("Camera: lensradius {lens_radius} or focaldistance {focal_distance} out of range"),
            ));
        }
        if self.state.ctm.determinant().abs() < 1e-12 {
            return Err(self.error(line, "Camera: the current transformation is not invertible"));
        }
        self.scene.camera = CameraDesc {
            kind: camera,
            fov_degrees,
            camera_to_world: self.state.ctm.inverse(),
            screen_window: params.array::<4>("screenwindow")?,
            lens_radius,
            focal_distance,
            location: self.location(line),
        };
        self.state.ctm = glam::Mat4::IDENTITY;
        Ok(())
    }

    /// `xwidth`/`ywidth` are radii; defaults as LuxRender's (box 0.5, others 2).
    pub(super) fn pixel_filter(
        &mut self,
        kind: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<(), SceneError> {
        let kind = match kind {
            "box" => FilterKind::Box,
            "gaussian" => FilterKind::Gaussian {
                alpha: params.float("alpha")?.unwrap_or(2.0),
            },
            "blackmanharris" => FilterKind::BlackmanHarris,
            // `filters/mitchell.cpp`: B and C default 1/3 (the `supersample` option is not read).
            "mitchell" => {
                params.string("supersample")?;
                FilterKind::Mitchell {
                    b: params.float("B")?.unwrap_or(1.0 / 3.0),
                    c: params.float("C")?.unwrap_or(1.0 / 3.0),
                }
            }
            "triangle" => FilterKind::Triangle,
            "sinc" => FilterKind::Sinc {
                tau: params.float("tau")?.unwrap_or(3.0),
            },
            _ => {
                self.warn(
                    line,
                    format!("PixelFilter \"{kind}\" unsupported: box of radius 0.5"),
                );
                params.ignore_all();
                self.scene.filter = FilterDesc {
                    kind: FilterKind::Box,
                    radius: Vec2::splat(0.5),
                };
                return Ok(());
            }
        };
        let default = if kind == FilterKind::Box { 0.5 } else { 2.0 };
        let radius = Vec2::new(
            params.float("xwidth")?.unwrap_or(default),
            params.float("ywidth")?.unwrap_or(default),
        );
        if radius.min_element() <= 0.0 {
            return Err(self.error(
                line,
                format!("PixelFilter: width {radius} must be positive"),
            ));
        }
        self.scene.filter = FilterDesc { kind, radius };
        Ok(())
    }
}
