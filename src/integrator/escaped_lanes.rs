//! Escaped rays under an environment map, looked up eight at a time: the block's paths whose
//! ray left the scene wait in a queue (as pbrt-v4's wavefront integrator gathers them in its
//! `EscapedRayQueue`), and the map's lookup (the rotation into its frame, the two angles, the
//! cell) runs in lanes ([`Environment::look_up_lanes`]); each path's radiance is then added
//! where it stands, in the order the scalar vertex adds it (so the same bits).

use super::shade_path::shade_escaped;
use super::shading::{PathColumns, Scene};
#[cfg(doc)]
use crate::light::infinite::Environment;
use crate::light::infinite::{DirectionLanes, LANES};

/// A block's paths whose ray escaped, waiting for the environment map's lookup, with their
/// directions.
#[derive(Default)]
pub struct EscapedQueue {
    len: usize,
    slots: [usize; LANES],
    directions: DirectionLanes,
}

impl EscapedQueue {
    pub fn is_full(&self) -> bool {
        self.len == LANES
    }

    /// Queues the block's path `slot`, whose ray along `direction` escaped.
    #[inline(always)]
    pub fn push(&mut self, slot: usize, direction: glam::Vec3) {
        self.slots[self.len] = slot;
        let (n, d) = (self.len, &mut self.directions);
        (d[0][n], d[1][n], d[2][n]) = (direction.x, direction.y, direction.z);
        self.len += 1;
    }

    /// Adds the sky's light to the queued paths in `paths`, ends them and empties the queue.
    /// The lanes past the queue's length hold earlier directions (or none, which the lookup
    /// takes for +z): looked up, and dropped.
    pub fn finish(&mut self, scene: &Scene, paths: &mut PathColumns) {
        if self.len == 0 {
            return;
        }
        let lights = scene.lights;
        let sky = lights.environment().and_then(|(index, environment)| {
            Some((
                index,
                environment,
                environment.look_up_lanes(&self.directions)?,
            ))
        });
        let Some((index, environment, lookups)) = sky else {
            unreachable!("escaped rays queued without an environment map")
        };
        for (lane, &slot) in self.slots[..self.len].iter().enumerate() {
            let mut path = paths.slots(slot);
            let sky = (index, environment, lookups.look_up(lane));
            shade_escaped(lights, &mut path, Some(sky), false);
        }
        self.len = 0;
    }
}
