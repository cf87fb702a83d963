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
    for camera in CAMERAS {
        (camera.register)(pass, world);
    }
}

/// Adds `system` to `stage` when the world has a camera component `C`, to run while it does.
/// A lens stage makes ray generation leave its rays in camera space.
pub fn register_for<C: Component, M>(
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
    /// origin 0): `direction` maps a raster position to a camera-space direction. In world space
    /// every origin is the pose's translation, taken as it is rather than transformed per ray
    /// (the same value: the linear part times 0 adds only zeros).
    pub fn generate_from_centre(&mut self, direction: impl Fn(Vec2) -> Vec3 + Sync) {
        match *self.space {
            GeneratedRaySpace::Camera => {
                write_camera_rays(&mut self.batch, |film| Some((Vec3::ZERO, direction(film))))
            }
            GeneratedRaySpace::World => {
                let pose = self.pose.0;
                let centre = Vec3::from(pose.translation);
                write_camera_rays(&mut self.batch, |film| {
                    Some((centre, direction_to_world(pose, direction(film))))
                })
            }
        }
    }
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

/// The default screen window: the shorter image axis spans [-1, 1].
pub fn default_screen_window(width: u32, height: u32) -> [f32; 4] {
    let aspect = width as f32 / height as f32;
    if aspect >= 1.0 {
        [-aspect, aspect, -1.0, 1.0]
    } else {
        [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]
    }
}
