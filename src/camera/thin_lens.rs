//! The thin lens: depth of field for any projection.
//!
//! A ray through the lens centre reaches its point of sharp focus at `origin + f * direction`
//! (see the module notes in `camera`); every other ray of that pixel sample starts on the lens
//! disk and passes through the same point (pbrt-v4 §5.2.3, the thin lens model). The lens is the
//! last camera stage: it leaves the rays in world space.

use bevy_ecs::prelude::*;
use rayon::prelude::*;

use super::pinhole::{PERSPECTIVE_FOV, Pinhole};
use super::{CameraPose, CameraSetup, CameraStage, CameraType, register_for, to_world};
use crate::integrator::batch::PathBatch;
use crate::integrator::start_pass::{CameraSampling, LENS_DIMENSION, PassIndex};
use crate::sampling::warp::concentric_disk;

#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ThinLens {
    pub lens_radius: f32,
    pub focal_distance: f32,
}

/// The perspective camera through a thin lens of the scene's radius (or `--lens-radius`).
pub static CAMERA: CameraType = CameraType {
    names: &["thin-lens", "thinlens"],
    fov: Some(PERSPECTIVE_FOV),
    build: |setup, entity, notes| {
        entity.insert(Pinhole::new(setup));
        let lens = ThinLens::new(setup);
        if lens.lens_radius > 0.0 {
            entity.insert(lens);
        } else {
            notes.push("thin-lens camera with lens radius 0: rendered as a pinhole".into());
        }
    },
    register,
};

impl ThinLens {
    /// The command line's radius and focal distance, else the scene's.
    fn new(setup: &CameraSetup) -> Self {
        let options = setup.options;
        Self {
            lens_radius: options
                .lens_radius
                .unwrap_or(setup.scene.lens_radius)
                .max(0.0),
            focal_distance: options
                .focal_distance
                .unwrap_or(setup.scene.focal_distance)
                .max(1e-4),
        }
    }

    /// Puts the lens in front of any camera: when `--lens-radius` is given, or when the scene's
    /// own camera is used and has a lens. Radius 0 is exactly no lens, so no stage then.
    pub fn compose(setup: &CameraSetup, entity: &mut EntityWorldMut) {
        let options = setup.options;
        let wanted = options.lens_radius.is_some()
            || (options.camera.is_none() && setup.scene.lens_radius > 0.0);
        let lens = Self::new(setup);
        if wanted && lens.lens_radius > 0.0 {
            entity.insert(lens);
        }
    }
}

fn register(pass: &mut Schedule, world: &mut World) {
    register_for::<ThinLens, _>(pass, world, CameraStage::Lens, focus_through_thin_lens);
}

fn focus_through_thin_lens(
    lens: Single<&ThinLens>,
    pose: Single<&CameraPose>,
    pass: Res<PassIndex>,
    sampling: Res<CameraSampling>,
    mut batch: ResMut<PathBatch>,
) {
    let lens = **lens;
    let pose = pose.0;
    let pass_sampler = sampling.sampler.pass(pass.0);
    let sampler = pass_sampler.dimension(LENS_DIMENSION);
    let batch = &mut *batch;
    let n = batch.len;
    (
        &batch.pixel[..n],
        &mut batch.origin[..n],
        &mut batch.direction[..n],
    )
        .into_par_iter()
        .with_min_len(1024)
        .for_each(|(pixel, origin, direction)| {
            let focus = *origin + *direction * lens.focal_distance;
            let sample = sampler.sample(*pixel);
            // Shirley-Chiu's concentric map keeps the sampler's stratification on the disk.
            let on_lens = concentric_disk(sample) * lens.lens_radius;
            let lens_point = *origin + on_lens.extend(0.0);
            (*origin, *direction) = to_world(pose, lens_point, focus - lens_point);
        });
}
