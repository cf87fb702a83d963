//! The thin lens: depth of field for any projection.
//!
//! A ray through the lens centre reaches its point of sharp focus at `origin + f * direction`
//! (see the module notes in `camera`); every other ray of that pixel sample starts on the lens
//! disk and passes through the same point (pbrt-v4 §5.2.3, the thin lens model). The lens is the
//! last camera stage: it leaves the rays in world space.

use bevy_ecs::prelude::*;
use glam::{Affine3A, Vec2, Vec3};
use rayon::prelude::*;

use super::pinhole::{PERSPECTIVE_FOV, Pinhole};
use super::{
    CameraPose, CameraSetup, CameraStage, CameraType, LANES, Lanes3, lanes_to_world, points_to_world,
    register_for,
};
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
        batch.pixel[..n].par_chunks(LANES),
        batch.origin[..n].par_chunks_mut(LANES),
        batch.direction[..n].par_chunks_mut(LANES),
    )
        .into_par_iter()
        .with_min_len(1024 / LANES)
        .for_each(|(pixels, origins, directions)| {
            // The batch's last group may be short: its missing lanes are computed from pixel
            // 0's sample and a zero ray, and dropped.
            let mut lane_pixels = [0; LANES];
            lane_pixels[..pixels.len()].copy_from_slice(pixels);
            let (mut origin, mut direction) = ([[0.0; LANES]; 3], [[0.0; LANES]; 3]);
            for (k, (o, d)) in origins.iter().zip(directions.iter()).enumerate() {
                [origin[0][k], origin[1][k], origin[2][k]] = o.to_array();
                [direction[0][k], direction[1][k], direction[2][k]] = d.to_array();
            }
            let samples = sampler.sample_lanes(lane_pixels);
            let (world_origins, world_directions) =
                lens.focus(pose, &samples, &origin, &direction);
            let len = origins.len();
            origins.copy_from_slice(&world_origins[..len]);
            directions.copy_from_slice(&world_directions[..len]);
        });
}

impl ThinLens {
    /// The world-space rays through the lens of `LANES` camera-space rays, `samples` their
    /// lens samples: each ray's focus point `origin + focal_distance direction`, the lens
    /// point `origin + lens_radius concentric_disk(sample)`, and the ray from the lens point
    /// to the focus, each step done for all lanes before the next (vector registers).
    #[inline(always)]
    fn focus(
        self,
        pose: Affine3A,
        samples: &[Vec2; LANES],
        origin: &Lanes3,
        direction: &Lanes3,
    ) -> ([Vec3; LANES], [Vec3; LANES]) {
        // Shirley-Chiu's concentric map keeps the sampler's stratification on the disk.
        let on_disk = samples.map(concentric_disk);
        let mut on_lens: Lanes3 = [[0.0; LANES]; 3];
        for k in 0..LANES {
            on_lens[0][k] = on_disk[k].x * self.lens_radius;
            on_lens[1][k] = on_disk[k].y * self.lens_radius;
        }
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
        let (origins, directions) = lens.focus(pose, &samples, &origin, &direction);
        for k in 0..LANES {
            let (o, d) = rays[k];
            let focus = o + d * lens.focal_distance;
            let lens_point = o + (concentric_disk(samples[k]) * lens.lens_radius).extend(0.0);
            let (one_origin, one_direction) = to_world(pose, lens_point, focus - lens_point);
            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
            assert_eq!(bits(origins[k]), bits(one_origin), "origin {k}");
            assert_eq!(bits(directions[k]), bits(one_direction), "direction {k}");
        }
    }
}
