//! The thin lens: depth of field for any projection.
//!
//! A ray through the lens centre reaches its point of sharp focus at `origin + f * direction`
//! (see the module notes in `camera`); every other ray of that pixel sample starts on the lens
//! disk and passes through the same point (pbrt-v4 §5.2.3, the thin lens model). The lens is the
//! last camera stage: it leaves the rays in world space.

use bevy_ecs::prelude::*;
use glam::{Affine3A, Vec2, Vec3};

use super::pinhole::{PERSPECTIVE_FOV, Pinhole};
use super::{
    CameraPose, CameraSetup, CameraStage, CameraType, LANES, Lanes3, for_each_ray_group,
    lanes_to_world, load_vec2, load_vec3, points_to_world, register_for, store_vec3,
};
use crate::integrator::batch::PathBatch;
use crate::integrator::lanes::{F8, concentric_disk};
use crate::integrator::start_pass::{CameraSampling, LENS_DIMENSION, PassIndex};
use crate::sampling::{DimensionLanes, SampleLanes};

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
    match sampler.lanes() {
        DimensionLanes::Sobol(lanes) => lens.focus_batch(pose, &lanes, &mut batch),
        DimensionLanes::Plain(lanes) => lens.focus_batch(pose, &lanes, &mut batch),
    }
}

impl ThinLens {
    /// Moves the batch's camera rays onto the lens, their lens points sampled by `lanes`
    /// [`LANES`] paths at a time. Generic over the sampler's kind, matched once per batch (see
    /// `DimensionSampler::lanes`).
    fn focus_batch<S: SampleLanes>(self, pose: Affine3A, lanes: &S, batch: &mut PathBatch) {
        let n = batch.len;
        let rays = (&mut batch.origin[..n], &mut batch.direction[..n]);
        for_each_ray_group(&batch.pixel[..n], rays, |pixels, origins, directions| {
            self.focus_group(pose, lanes.sample_lanes(*pixels), origins, directions)
        });
    }

    /// [`ThinLens::focus`] of a group of `LANES` camera-space rays in the batch's columns,
    /// written back in world space.
    #[inline(always)]
    fn focus_group(
        self,
        pose: Affine3A,
        samples: [Vec2; LANES],
        origins: &mut [Vec3; LANES],
        directions: &mut [Vec3; LANES],
    ) {
        let [sample_x, sample_y] = load_vec2(&samples);
        let samples = [F8(sample_x), F8(sample_y)];
        let (origin, direction) = (load_vec3(origins), load_vec3(directions));
        let (world_origin, world_direction) = self.focus(pose, &samples, &origin, &direction);
        store_vec3(&world_origin, origins);
        store_vec3(&world_direction, directions);
    }

    /// The world-space rays through the lens of `LANES` camera-space rays, `samples` their
    /// lens samples: each ray's focus point `origin + focal_distance direction`, the lens
    /// point `origin + lens_radius concentric_disk(sample)`, and the ray from the lens point
    /// to the focus, each step done for all lanes before the next (vector registers).
    #[inline(always)]
    fn focus(
        self,
        pose: Affine3A,
        samples: &[F8; 2],
        origin: &Lanes3,
        direction: &Lanes3,
    ) -> (Lanes3, Lanes3) {
        // Shirley-Chiu's concentric map keeps the sampler's stratification on the disk; in
        // lanes (its choices as selects), where the scalar map, called lane after lane, took
        // branches.
        let (disk_x, disk_y) = concentric_disk(*samples);
        let on_lens: Lanes3 = [
            (disk_x * self.lens_radius).0,
            (disk_y * self.lens_radius).0,
            [0.0; LANES],
        ];
        let (mut lens_point, mut to_focus): (Lanes3, Lanes3) = Default::default();
        for axis in 0..3 {
            for k in 0..LANES {
                let focus = origin[axis][k] + direction[axis][k] * self.focal_distance;
                lens_point[axis][k] = origin[axis][k] + on_lens[axis][k];
                to_focus[axis][k] = focus - lens_point[axis][k];
            }
        }
        (
            points_to_world(pose, &lens_point),
            lanes_to_world(pose, &to_focus),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::to_world;
    use crate::sampling::warp;

    /// `LANES` rays at once give each ray's own world-space ray to the bit: the thin lens one
    /// ray at a time as pbrt-v4 writes it (focus point, lens point, the ray between them), on
    /// film samples that include the disk's centre and its diagonals and a camera-space origin
    /// off the centre (an orthographic camera's).
    #[test]
    fn rays_in_lanes_match_one_at_a_time() {
        let rotation = glam::Quat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0);
        let pose = Affine3A::from_rotation_translation(rotation, Vec3::new(0.3, -4.0, 1.2));
        let lens = ThinLens {
            lens_radius: 0.37,
            focal_distance: 4.5,
        };
        let samples: [Vec2; LANES] = [
            Vec2::splat(0.5),
            Vec2::new(0.1, 0.9),
            Vec2::new(0.75, 0.75),
            Vec2::new(0.93, 0.12),
            Vec2::new(0.0, 0.6),
            Vec2::new(0.4, 0.0),
            Vec2::new(0.31, 0.58),
            Vec2::new(0.999, 0.999),
        ];
        let rays: [(Vec3, Vec3); LANES] = std::array::from_fn(|k| {
            let origin = Vec3::new(k as f32 * 0.1 - 0.3, 0.2 - k as f32 * 0.05, 0.0);
            (origin, Vec3::new(0.4 - k as f32 * 0.13, k as f32 * 0.07 - 0.2, 1.0))
        });
        let components = |of: fn(&(Vec3, Vec3)) -> Vec3| -> Lanes3 {
            std::array::from_fn(|axis| std::array::from_fn(|k| of(&rays[k])[axis]))
        };
        let origin = components(|ray| ray.0);
        let direction = components(|ray| ray.1);
        let lanes = [0, 1].map(|axis| F8(samples.map(|u| u[axis])));
        let (origin, direction) = lens.focus(pose, &lanes, &origin, &direction);
        let (mut origins, mut directions) = ([Vec3::ZERO; LANES], [Vec3::ZERO; LANES]);
        store_vec3(&origin, &mut origins);
        store_vec3(&direction, &mut directions);
        for k in 0..LANES {
            let (o, d) = rays[k];
            let focus = o + d * lens.focal_distance;
            let on_disk = warp::concentric_disk(samples[k]);
            let lens_point = o + (on_disk * lens.lens_radius).extend(0.0);
            let (one_origin, one_direction) = to_world(pose, lens_point, focus - lens_point);
            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
            assert_eq!(bits(origins[k]), bits(one_origin), "origin {k}");
            assert_eq!(bits(directions[k]), bits(one_direction), "direction {k}");
        }
    }
}
