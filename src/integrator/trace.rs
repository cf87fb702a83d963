//! The trace stages: closest hits for the path rays, any hits for the shadow rays, each one
//! batch call into the BVH.

use bevy_ecs::prelude::*;
use rayon::prelude::*;

use super::batch::{HitBatch, PathBatch, ShadowBatch};
use crate::shape::geometry::SceneGeometry;
use crate::shared::Shared;

pub fn trace_closest_hits(
    geometry: Res<Shared<SceneGeometry>>,
    batch: Res<PathBatch>,
    mut hits: ResMut<HitBatch>,
) {
    let n = batch.len;
    let hits = &mut *hits;
    hits.grow(n);
    // A path that ended (a fisheye sample outside the image circle) gets an empty extent.
    (&batch.alive[..n], &mut hits.t_max[..n])
        .into_par_iter()
        .with_min_len(4096)
        .for_each(|(alive, t_max)| *t_max = if *alive { f32::INFINITY } else { 0.0 });
    geometry.accel.closest_hits(
        &batch.origin[..n],
        &batch.direction[..n],
        0.0,
        &hits.t_max[..n],
        &mut hits.hit[..n],
    );
}

pub fn trace_shadow_rays(geometry: Res<Shared<SceneGeometry>>, mut shadows: ResMut<ShadowBatch>) {
    let shadows = &mut *shadows;
    let accel = &geometry.accel;
    let pass_through = geometry.pass_through.as_ref();
    let slots = shadows.slots;
    let (origins, dirs) = (&shadows.origin[..slots], &shadows.direction[..slots]);
    let t_maxs = &shadows.t_max[..slots];
    // Empty slots have t_max 0 and are skipped; invisible surfaces let the light through.
    // With a slot per light, rays `rays_per_path` apart go to the same light from
    // neighbouring paths.
    let stride = shadows.slot_per_light.then_some(shadows.rays_per_path);
    let occluded = &mut shadows.occluded[..slots];
    accel.any_hits_strided(origins, dirs, 0.0, t_maxs, stride, pass_through, occluded);
}
