//! Chunks in flight: with several threads, the renderer traces as many chunks at once, each in a
//! world of its own, so that a thread that finishes its share of one chunk's stage takes up
//! work of another chunk rather than waiting for the stage's last task (the joins that end the
//! stages left about 7.5 % of two threads idle, docs/speed.md, stop 35). Thread k traces world
//! k's chunks, so a chunk's batches stay with the thread that traces it from its camera rays to
//! its last bounce, and a world's from chunk to chunk.
//!
//! The worlds share the scene's geometry and lights ([`Shared`]), copy the small tables and
//! the camera entity, and run schedules of their own (a system keeps state for the world it
//! runs in). The film takes the chunks' samples in chunk order whichever finishes first, so
//! the image is the same at any number of chunks in flight and threads.

use bevy_ecs::prelude::*;

use super::start_pass::CameraSampling;
use super::{Stage, StageTime, WorldStages, bounce_stages, chunk_schedule, insert_chunk_state};
use crate::camera::copy_camera;
use crate::light::LightTable;
use crate::material::MaterialTable;
use crate::material::texture::TextureTable;
use crate::settings::{RenderSettings, Techniques};
use crate::shape::geometry::SceneGeometry;
use crate::shared::Shared;

/// The most chunks traced at once, whatever the threads: each holds its batches (a few
/// megabytes at the default chunk size).
pub const MAX_IN_FLIGHT: usize = 8;

/// A world that traces one chunk at a time, beside the main world.
pub(super) struct ChunkWorld {
    pub world: World,
    /// Its chunk start: fresh paths and the camera's rays.
    pub chunk: Schedule,
    /// Its bounce stages.
    pub bounce: Vec<Stage>,
    /// Time and items of its stages, laid out as the main world's, when stages are timed.
    pub times: Option<Vec<StageTime>>,
}

impl ChunkWorld {
    /// A world with what the stages read of `main` (the render's world, after its startup
    /// systems), batches and schedules of its own.
    pub fn new(main: &World) -> Self {
        let mut world = World::new();
        copy_camera(main, &mut world);
        world.insert_resource(main.resource::<CameraSampling>().clone());
        world.insert_resource(main.resource::<Shared<SceneGeometry>>().clone());
        world.insert_resource(main.resource::<Shared<LightTable>>().clone());
        world.insert_resource(main.resource::<MaterialTable>().clone());
        if let Some(textures) = main.get_resource::<TextureTable>() {
            world.insert_resource(textures.clone());
        }
        world.insert_resource(main.resource::<RenderSettings>().clone());
        world.insert_resource(*main.resource::<Techniques>());
        insert_chunk_state(&mut world);
        let chunk = chunk_schedule(&mut world);
        let bounce = bounce_stages(world.resource::<RenderSettings>().integrator);
        Self {
            world,
            chunk,
            bounce,
            times: None,
        }
    }

    /// The world with its schedules and stage times, as a chunk is traced.
    pub fn stages(&mut self) -> WorldStages<'_> {
        (
            &mut self.world,
            &mut self.chunk,
            &mut self.bounce,
            self.times.as_deref_mut(),
        )
    }
}
