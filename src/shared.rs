//! A resource several worlds hold at once: the scene's large read-only tables (its geometry and
//! its lights), which the worlds of the chunks traced at once (`integrator::in_flight`) share
//! rather than copy.

use std::ops::Deref;
use std::sync::Arc;

use bevy_ecs::prelude::Resource;

/// A value shared by the worlds that hold it: a clone is another handle to the same value.
#[derive(Resource, Debug)]
pub struct Shared<T: Send + Sync + 'static>(Arc<T>);

impl<T: Send + Sync + 'static> Shared<T> {
    pub fn new(value: T) -> Self {
        Self(Arc::new(value))
    }
}

impl<T: Send + Sync + 'static> Clone for Shared<T> {
    fn clone(&self) -> Self {
        Self(Arc::clone(&self.0))
    }
}

impl<T: Send + Sync + 'static> Deref for Shared<T> {
    type Target = T;

    fn deref(&self) -> &T {
        &self.0
    }
}
