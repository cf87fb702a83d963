//! foton: a physically based, wavefront path tracer on bevy_ecs.

pub mod scene;
