//! The orthographic camera: parallel rays along the view axis, starting across the screen
//! window (in camera-space units).

use bevy_ecs::prelude::*;
use glam::Vec3;

use super::{CameraRays, CameraStage, CameraType, raster_to_screen, register_for};
use crate::settings::RenderSettings;

#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Orthographic {
    /// [xmin, xmax, ymin, ymax] in camera-space units.
    pub screen_window: [f32; 4],
}

pub static CAMERA: CameraType = CameraType {
    names: &["orthographic"],
    fov: None,
    build: |setup, entity, _| {
        entity.insert(Orthographic {
            screen_window: setup.screen_window,
        });
    },
    register,
};

fn register(pass: &mut Schedule, world: &mut World) {
    register_for::<Orthographic, _>(
        pass,
        world,
        CameraStage::Generate,
        generate_orthographic_rays,
    );
}

fn generate_orthographic_rays(
    camera: Single<&Orthographic>,
    settings: Res<RenderSettings>,
    mut rays: CameraRays,
) {
    let window = camera.screen_window;
    let (width, height) = (settings.width, settings.height);
    // z = 1: the focal plane, for a lens, is at the focal distance.
    rays.generate(|film| {
        let origin = raster_to_screen(film, width, height, window).extend(0.0);
        Some((origin, Vec3::Z))
    });
}
