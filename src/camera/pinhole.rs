//! The pinhole perspective camera.

use bevy_ecs::prelude::*;

use super::{
    CameraRays, CameraSetup, CameraStage, CameraType, FovRange, raster_to_screen_lanes,
    register_for,
};
use crate::integrator::lanes::F8;
use crate::settings::RenderSettings;

/// A perspective projection: screen coordinate 1 is at `tan(fov / 2)` on the plane z = 1.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Pinhole {
    pub fov_degrees: f32,
    /// [xmin, xmax, ymin, ymax] in screen coordinates.
    pub screen_window: [f32; 4],
}

/// The perspective field of view: the shorter image axis spans `fov`, up to 179 degrees.
pub const PERSPECTIVE_FOV: FovRange = FovRange {
    default: 90.0,
    max: 179.0,
};

pub static CAMERA: CameraType = CameraType {
    names: &["pinhole", "perspective"],
    fov: Some(PERSPECTIVE_FOV),
    build: |setup, entity, _| {
        entity.insert(Pinhole::new(setup));
    },
    register,
};

impl Pinhole {
    /// With the scene's field of view, whichever camera the scene has.
    pub fn new(setup: &CameraSetup) -> Self {
        Self {
            fov_degrees: setup.scene.fov_degrees,
            screen_window: setup.screen_window,
        }
    }
}

fn register(pass: &mut Schedule, world: &mut World) {
    register_for::<Pinhole, _>(pass, world, CameraStage::Generate, generate_pinhole_rays);
}

fn generate_pinhole_rays(
    camera: Single<&Pinhole>,
    settings: Res<RenderSettings>,
    mut rays: CameraRays,
) {
    let camera = **camera;
    let tan_half_fov = (camera.fov_degrees.to_radians() * 0.5).tan();
    let (width, height) = (settings.width, settings.height);
    rays.generate_from_centre(|film| {
        let [x, y] = raster_to_screen_lanes(film, width, height, camera.screen_window);
        [x * tan_half_fov, y * tan_half_fov, F8::splat(1.0)]
    });
}
