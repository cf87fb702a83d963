//! foton: a physically based, wavefront path tracer on bevy_ecs.

pub mod accel;
pub mod bsdf;
pub mod camera;
pub mod cli;
pub mod film;
pub mod integrator;
pub mod light;
pub mod material;
pub mod math;
pub mod sampling;
pub mod scene;
pub mod settings;
pub mod shape;
pub mod shared;
pub mod texture;
