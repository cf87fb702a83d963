//! The integration tests, one module to a file beside this one, built as one test binary: one
//! link, and one copy of foton and its dependencies on disk, rather than one for each file.
//! `cargo test --release --test integration MODULE::` runs one file's tests.

mod common;

mod accel;
mod bsdf;
mod bsdf_glossy_translucent;
mod bsdf_layered;
mod bsdf_lux_materials;
mod bsdf_sampling_coverage;
mod bsdf_translucent;
mod cameras;
mod cli;
mod constant_sky;
mod course_scenes;
mod disk;
mod error_per_sample;
mod fuzz_corpus;
mod integrator;
mod luxrender_scenes;
mod lxs_instances;
mod lxs_legacy;
mod lxs_materials;
mod lxs_parser;
mod lxs_versions;
mod mitsuba_format;
mod mitsuba_references;
mod mitsuba_scenes;
mod registries;
mod slurm;
mod sobol10;
mod split_merge;
mod sun_disc;
