//! Cameras as components. Each camera file declares a [`CameraType`]: its names, how it is built
//! from the scene's camera and the command line, and the system that turns the batch's film
//! positions into rays (run only when its component exists). [`CAMERAS`] lists them all, one
//! line each; the loaders, `--camera` and `scene::build` read it. The lens stage after ray
//! generation does not know which camera made the rays, and nothing after it does either.
//!
//! Ray generation writes directions whose length places the focus surface: a point at distance
//! `f` in focus lies at `origin + f * direction`. Planar projections write `z = 1` (a focal plane),
//! spherical ones unit vectors (a focal sphere). The thin lens relies only on that.

use std::fmt;

use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::{ScheduleSystem, SystemParam};
use glam::{Affine3A, Vec2, Vec3};
use rayon::prelude::*;

use crate::integrator::batch::PathBatch;
use crate::integrator::lanes::F8;
use crate::scene::build::RenderOptions;
use crate::scene::desc::CameraDesc;

/// Declares each camera's module and lists its `CAMERA` in [`CAMERAS`].
macro_rules! cameras {
    ($($camera:ident),* $(,)?) => {
        $(pub mod $camera;)*

        /// Every camera, in the order `--camera` lists them.
        pub static CAMERAS: &[&CameraType] = &[$(&$camera::CAMERA),*];
    };
}

mod lanes;
use lanes::{LANES, Lanes3, load_vec2, load_vec3, short_group, store_vec3};

// The registry: one line per camera.
cameras! {
    pinhole,
    thin_lens,
    fisheye,
    orthographic,
    equirectangular,
}

/// One kind of camera, as the registry knows it.
pub struct CameraType {
    /// The first is foton's name (the `--camera` value); the others are names scene formats
    /// give it. Matched in any case.
    pub names: &'static [&'static str],
    /// The field of view a scene may give it, if it takes one.
    pub fov: Option<FovRange>,
    /// Adds the camera's components to the camera entity.
    pub build: fn(&CameraSetup, &mut EntityWorldMut, &mut Vec<String>),
    /// Adds its systems to the pass schedule, each only when its component exists.
    pub register: fn(&mut Schedule, &mut World),
}

impl CameraType {
    pub fn name(&self) -> &'static str {
        self.names[0]
    }
}

impl PartialEq for CameraType {
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name()
    }
}

impl fmt::Debug for CameraType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A field of view in degrees: what it is when the scene gives none, and the largest allowed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FovRange {
    pub default: f32,
    pub max: f32,
}

/// What a camera is built from.
pub struct CameraSetup<'a> {
    /// The scene's camera.
    pub scene: &'a CameraDesc,
    /// Whether the scene's camera is of this type (the command line may choose another).
    pub scene_names_it: bool,
    pub options: &'a RenderOptions,
    /// [xmin, xmax, ymin, ymax], fitted to the image's aspect ratio.
    pub screen_window: [f32; 4],
}

/// The camera type called `name` (any of its names, in any case).
pub fn find(name: &str) -> Option<&'static CameraType> {
    CAMERAS
        .iter()
        .copied()
        .find(|camera| camera.names.iter().any(|n| n.eq_ignore_ascii_case(name)))
}

/// foton's name of every camera, in registry order.
pub fn names() -> impl Iterator<Item = &'static str> {
    CAMERAS.iter().map(|camera| camera.name())
}

/// Camera space to world space (x right, y up, z forward in camera space).
#[derive(Component, Clone, Copy, Debug)]
pub struct CameraPose(pub Affine3A);

/// The order of the camera stages within a pass.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CameraStage {
    /// One projection's ray generation.
    Generate,
    /// Optional optics applied to any projection's camera-space rays; it leaves them in world
    /// space.
    Lens,
}

/// Registers the camera systems in the pass schedule. Each camera adds its system only when the
/// world has its component, so the schedule holds only what the scene uses. Without a lens
/// stage, ray generation writes world-space rays itself; with one, it writes camera-space rays
/// and the lens moves them to world space (each ray is written in world space by the last
/// stage that touches it, with no pass of its own for the move).
pub fn register_cameras(pass: &mut Schedule, world: &mut World) {
    pass.configure_sets((CameraStage::Generate, CameraStage::Lens).chain());
    world.insert_resource(GeneratedRaySpace::World);
    world.insert_resource(CameraCopies(vec![copy_component::<CameraPose>]));
    for camera in CAMERAS {
        (camera.register)(pass, world);
    }
}

/// Adds `system` to `stage` when the world has a camera component `C`, to run while it does.
/// A lens stage makes ray generation leave its rays in camera space. `C` is cloned into the
/// worlds of the chunks traced at once ([`copy_camera`]).
pub fn register_for<C: Component + Clone, M>(
    pass: &mut Schedule,
    world: &mut World,
    stage: CameraStage,
    system: impl IntoScheduleConfigs<ScheduleSystem, M>,
) {
    if world
        .query_filtered::<(), With<C>>()
        .iter(world)
        .next()
        .is_some()
    {
        let configs: ScheduleConfigs<ScheduleSystem> =
            system.run_if(any_with_component::<C>).in_set(stage);
        pass.add_systems(configs);
        if stage == CameraStage::Lens {
            world.insert_resource(GeneratedRaySpace::Camera);
        }
        world
            .resource_mut::<CameraCopies>()
            .0
            .push(copy_component::<C>);
    }
}

/// How to copy each component of the camera entity that [`register_cameras`] found (its pose
/// and those a camera registered systems for) to another world's camera entity.
#[derive(Resource, Clone)]
struct CameraCopies(Vec<fn(EntityRef, &mut EntityWorldMut)>);

/// Gives `to` a camera entity with the components of `from`'s that [`register_cameras`] found,
/// for the camera systems of a pass schedule of its own.
pub fn copy_camera(from: &World, to: &mut World) {
    let mut cameras = from.try_query_filtered::<Entity, With<CameraPose>>();
    let camera = cameras.as_mut().and_then(|query| query.iter(from).next());
    let (Some(copies), Some(camera)) = (from.get_resource::<CameraCopies>(), camera) else {
        return;
    };
    let camera = from.entity(camera);
    let mut entity = to.spawn_empty();
    for copy in &copies.0 {
        copy(camera, &mut entity);
    }
}

/// Copies `camera`'s component `C` to `to`.
fn copy_component<C: Component + Clone>(camera: EntityRef, to: &mut EntityWorldMut) {
    if let Some(component) = camera.get::<C>() {
        to.insert(component.clone());
    }
}

/// The space ray generation writes its rays in: camera space when a lens stage follows (optics
/// are defined in camera space; the lens writes world-space rays), else world space.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeneratedRaySpace {
    Camera,
    World,
}

/// What a ray generation system writes: the batch's rays, in the space the schedule wants.
#[derive(SystemParam)]
pub struct CameraRays<'w, 's> {
    batch: ResMut<'w, PathBatch>,
    pose: Single<'w, 's, &'static CameraPose>,
    space: Res<'w, GeneratedRaySpace>,
}

impl CameraRays<'_, '_> {
    /// Fills every path's ray from its film position: `project` maps a raster position to a
    /// camera-space (origin, direction), or to `None` where the camera sees nothing (a black
    /// sample that costs no ray). Moved to world space here ([`to_world`]) unless a lens stage
    /// follows.
    pub fn generate(&mut self, project: impl Fn(Vec2) -> Option<(Vec3, Vec3)> + Sync) {
        match *self.space {
            GeneratedRaySpace::Camera => write_camera_rays(&mut self.batch, project),
            GeneratedRaySpace::World => {
                let pose = self.pose.0;
                write_camera_rays(&mut self.batch, |film| {
                    project(film).map(|(origin, direction)| to_world(pose, origin, direction))
                })
            }
        }
    }

    /// As [`CameraRays::generate`] for a camera whose rays all start at its centre (camera-space
    /// origin 0): `directions` maps `LANES` raster positions to their camera-space directions,
    /// one array per component, so that the projection too runs in the lanes of vector
    /// registers. In world space every origin is the pose's translation, taken as it is rather
    /// than transformed per ray (the same value: the linear part times 0 adds only zeros).
    pub fn generate_from_centre(&mut self, directions: impl Fn([F8; 2]) -> [F8; 3] + Sync) {
        let camera_lanes = |films: &[Vec2; LANES]| {
            let [x, y] = load_vec2(films);
            let [x, y, z] = directions([F8(x), F8(y)]);
            [x.0, y.0, z.0]
        };
        let batch = &mut self.batch;
        match *self.space {
            GeneratedRaySpace::Camera => {
                write_rays_from_centre(batch, Vec3::ZERO, |films, rays| {
                    store_vec3(&camera_lanes(films), rays)
                })
            }
            GeneratedRaySpace::World => {
                let pose = self.pose.0;
                write_rays_from_centre(batch, pose.translation.into(), |films, rays| {
                    store_vec3(&lanes_to_world(pose, &camera_lanes(films)), rays)
                })
            }
        }
    }
}

/// Rays traced from the camera's centre `origin`, `directions` writing their directions for
/// `LANES` film positions at a time. The origins are stored with the directions rather than
/// filled beforehand: one pass over the columns.
fn write_rays_from_centre(
    batch: &mut PathBatch,
    origin: Vec3,
    directions: impl Fn(&[Vec2; LANES], &mut [Vec3; LANES]) + Sync,
) {
    let n = batch.len;
    let rays = (&mut batch.origin[..n], &mut batch.direction[..n]);
    for_each_ray_group(&batch.film_position[..n], rays, |films, origins, rays| {
        *origins = [origin; LANES];
        directions(films, rays);
    });
}

/// Runs `rays` on the batch's paths `LANES` at a time, in parallel: each group's values of a
/// per-path column `inputs` and its origins and directions, which it may change. The batch's
/// last group, short, is filled out by [`short_group`] and its extra lanes' results dropped.
pub(super) fn for_each_ray_group<T: Copy + Default + Sync>(
    inputs: &[T],
    (origins, directions): (&mut [Vec3], &mut [Vec3]),
    rays: impl Fn(&[T; LANES], &mut [Vec3; LANES], &mut [Vec3; LANES]) + Sync,
) {
    (
        inputs.par_chunks(LANES),
        origins.par_chunks_mut(LANES),
        directions.par_chunks_mut(LANES),
    )
        .into_par_iter()
        .with_min_len(1024 / LANES)
        .for_each(|(inputs, origins, directions)| {
            let group = (inputs.try_into(), origins.try_into(), directions.try_into());
            if let (Ok(inputs), Ok(origins), Ok(directions)) = group {
                rays(inputs, origins, directions);
            } else {
                let len = inputs.len();
                let (mut lane_origins, mut lane_directions) =
                    (short_group(origins), short_group(directions));
                rays(
                    &short_group(inputs),
                    &mut lane_origins,
                    &mut lane_directions,
                );
                origins.copy_from_slice(&lane_origins[..len]);
                directions.copy_from_slice(&lane_directions[..len]);
            }
        });
}

/// [`direction_to_world`] of `LANES` camera-space directions, each step done for all of them
/// before the next, so that the compiler takes it across the lanes of vector registers (the
/// same operations in the same order, so the same values): glam's `transform_vector3` is
/// x_axis d.x + y_axis d.y + z_axis d.z summed left to right, and `normalize_or_zero`
/// multiplies by 1 / sqrt((x x + y y) + z z) when that is finite and positive, else gives zero.
#[inline(always)]
pub(super) fn lanes_to_world(pose: Affine3A, direction: &Lanes3) -> Lanes3 {
    let [dx, dy, dz] = direction;
    let m = pose.matrix3;
    let (mut x, mut y, mut z) = ([0.0f32; LANES], [0.0f32; LANES], [0.0f32; LANES]);
    for k in 0..LANES {
        x[k] = m.x_axis.x * dx[k] + m.y_axis.x * dy[k] + m.z_axis.x * dz[k];
        y[k] = m.x_axis.y * dx[k] + m.y_axis.y * dy[k] + m.z_axis.y * dz[k];
        z[k] = m.x_axis.z * dx[k] + m.y_axis.z * dy[k] + m.z_axis.z * dz[k];
    }
    for k in 0..LANES {
        let rcp = 1.0 / (x[k] * x[k] + y[k] * y[k] + z[k] * z[k]).sqrt();
        // Finite and positive, 0 < rcp < inf (false for NaN): as an i32, the bits of such a
        // float lie in 1..=0x7f7f_ffff (the sign bit clear, the exponent not all ones). Two
        // integer compares and a bit mask (all ones or +0) rather than float compares and a
        // choice, so that the lanes stay in vector registers.
        let bits = rcp.to_bits() as i32;
        let normal = (bits > 0) & (bits < f32::INFINITY.to_bits() as i32);
        let mask = u32::from(normal).wrapping_neg();
        x[k] = f32::from_bits((x[k] * rcp).to_bits() & mask);
        y[k] = f32::from_bits((y[k] * rcp).to_bits() & mask);
        z[k] = f32::from_bits((z[k] * rcp).to_bits() & mask);
    }
    [x, y, z]
}

/// `pose.transform_point3` of `LANES` camera-space points, component by component (the same
/// values): glam sums ((x_axis p.x + y_axis p.y) + z_axis p.z) + translation.
#[inline(always)]
pub(super) fn points_to_world(pose: Affine3A, point: &Lanes3) -> Lanes3 {
    let [px, py, pz] = point;
    let (m, t) = (pose.matrix3, pose.translation);
    let (mut x, mut y, mut z) = ([0.0f32; LANES], [0.0f32; LANES], [0.0f32; LANES]);
    for k in 0..LANES {
        x[k] = m.x_axis.x * px[k] + m.y_axis.x * py[k] + m.z_axis.x * pz[k] + t.x;
        y[k] = m.x_axis.y * px[k] + m.y_axis.y * py[k] + m.z_axis.y * pz[k] + t.y;
        z[k] = m.x_axis.z * px[k] + m.y_axis.z * py[k] + m.z_axis.z * pz[k] + t.z;
    }
    [x, y, z]
}

/// Fills every path's ray from its film position with `project`; ends the path where it gives
/// `None`.
fn write_camera_rays(batch: &mut PathBatch, project: impl Fn(Vec2) -> Option<(Vec3, Vec3)> + Sync) {
    let n = batch.len;
    (
        &batch.film_position[..n],
        &mut batch.origin[..n],
        &mut batch.direction[..n],
        &mut batch.alive[..n],
    )
        .into_par_iter()
        .with_min_len(1024)
        .for_each(|(film, origin, direction, alive)| match project(*film) {
            Some((o, d)) => {
                *origin = o;
                *direction = d;
            }
            None => *alive = false,
        });
}

/// A camera-space ray in world space: the direction normalised (a lens's focus-scaled direction
/// becomes a unit one).
#[inline(always)]
pub fn to_world(pose: Affine3A, origin: Vec3, direction: Vec3) -> (Vec3, Vec3) {
    (
        pose.transform_point3(origin),
        direction_to_world(pose, direction),
    )
}

/// A camera-space direction in world space, normalised.
#[inline(always)]
fn direction_to_world(pose: Affine3A, direction: Vec3) -> Vec3 {
    pose.transform_vector3(direction).normalize_or_zero()
}

/// Maps a raster position (pixels, y down) to the screen window [xmin, xmax, ymin, ymax] (y up).
pub fn raster_to_screen(raster: Vec2, width: u32, height: u32, window: [f32; 4]) -> Vec2 {
    let [x_min, x_max, y_min, y_max] = window;
    Vec2::new(
        x_min + raster.x / width as f32 * (x_max - x_min),
        y_max - raster.y / height as f32 * (y_max - y_min),
    )
}

/// [`raster_to_screen`] of `LANES` raster positions given by their x and y: the same
/// operations lane by lane (vector registers), so the same values.
#[inline(always)]
pub(super) fn raster_to_screen_lanes(
    [x, y]: [F8; 2],
    width: u32,
    height: u32,
    window: [f32; 4],
) -> [F8; 2] {
    let [x_min, x_max, y_min, y_max] = window;
    [
        x_min + x / width as f32 * (x_max - x_min),
        y_max - y / height as f32 * (y_max - y_min),
    ]
}

/// The default screen window: the shorter image axis spans [-1, 1].
pub fn default_screen_window(width: u32, height: u32) -> [f32; 4] {
    let aspect = width as f32 / height as f32;
    if aspect >= 1.0 {
        [-aspect, aspect, -1.0, 1.0]
    } else {
        [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Eight directions at once give each one's own world direction to the bit, including the
    /// cases `normalize_or_zero` sends to zero (zero, infinite and NaN directions).
    #[test]
    fn directions_in_lanes_match_one_at_a_time() {
        let rotation = glam::Quat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0);
        let pose = Affine3A::from_rotation_translation(rotation, Vec3::new(0.3, -4.0, 1.2));
        let films: [Vec2; LANES] =
            std::array::from_fn(|k| Vec2::new(k as f32 * 17.0 - 40.0, 0.7 - k as f32 * 0.11));
        let direction = |film: Vec2| match film.x as i32 {
            -40 => Vec3::ZERO,
            -23 => Vec3::new(f32::INFINITY, 0.0, 1.0),
            -6 => Vec3::new(0.0, f32::NAN, 1.0),
            _ => film.extend(1.0),
        };
        let mut camera: Lanes3 = [[0.0; LANES]; 3];
        for (k, &film) in films.iter().enumerate() {
            [camera[0][k], camera[1][k], camera[2][k]] = direction(film).to_array();
        }
        let mut lanes = [Vec3::ZERO; LANES];
        store_vec3(&lanes_to_world(pose, &camera), &mut lanes);
        let mut zeros = 0;
        for (film, lane) in films.iter().zip(lanes) {
            let one = direction_to_world(pose, direction(*film));
            assert_eq!(
                lane.to_array().map(f32::to_bits),
                one.to_array().map(f32::to_bits)
            );
            zeros += usize::from(one == Vec3::ZERO);
        }
        assert_eq!(zeros, 3, "the zero, infinite and NaN directions");
    }
}
