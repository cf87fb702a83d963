//! The trace stages: closest hits for the path rays, any hits for the shadow rays.

use bevy_ecs::prelude::*;
use rayon::prelude::*;

use super::batch::{HitBatch, PathBatch, ShadowBatch};
use crate::shape::geometry::SceneGeometry;

pub fn trace_closest_hits(
    geometry: Res<SceneGeometry>,
    batch: Res<PathBatch>,
    mut hits: ResMut<HitBatch>,
) {
    let n = batch.len;
    hits.hit.resize(n, None);
    let accel = &geometry.accel;
    (
        &batch.origin[..n],
        &batch.direction[..n],
        &batch.alive[..n],
        &mut hits.hit[..n],
    )
        .into_par_iter()
        .with_min_len(256)
        .for_each(|(origin, direction, alive, hit)| {
            *hit = if *alive {
                accel.closest_hit(*origin, *direction, 0.0, f32::INFINITY)
            } else {
                None
            };
        });
}

pub fn trace_shadow_rays(geometry: Res<SceneGeometry>, mut shadows: ResMut<ShadowBatch>) {
    let accel = &geometry.accel;
    let shadows = &mut *shadows;
    (
        &shadows.origin[..],
        &shadows.direction[..],
        &shadows.t_max[..],
        &mut shadows.occluded[..],
    )
        .into_par_iter()
        .with_min_len(256)
        .for_each(|(origin, direction, t_max, occluded)| {
            *occluded = *t_max > 0.0 && accel.any_hit(*origin, *direction, 0.0, *t_max);
        });
}
