//! Scene loading: one loader per format, each producing a [`desc::SceneDesc`].

pub mod build;
pub mod desc;
pub mod io;
pub mod lxs;
pub mod mitsuba;
