//! Scene loading: one loader per format, each producing a [`desc::SceneDesc`].

pub mod desc;
