//! Shadow rays through invisible surfaces: a primitive whose material is `null` does not block
//! light, as it does not stop a camera ray (the shading stages continue those through it).
//!
//! The set of such primitives is known when the scene is built, so it is a bit per primitive
//! id, and it exists only in a scene that has one (the builder passes `None` otherwise, and
//! shadow rays keep the plain any-hit query). With it, a shadow ray first asks the cheap
//! question, whether anything at all lies on the segment (any hit); only if something does, it
//! walks the segment's surfaces nearest first (closest hit, then closest hit beyond it) until
//! one that blocks. A surface is passed by raising `t_min` to its hit distance on the same ray:
//! the same ray gives the same `t` for the same primitive, so the strict `t > t_min` test never
//! finds it again, and no origin offset is needed.

use glam::Vec3;

use super::Accel;

/// After this many invisible surfaces in a row a shadow ray counts as blocked, as a camera ray
/// ends after as many (`integrator::shading::MAX_PASS_THROUGH`).
pub(super) const MAX_LAYERS: u32 = 64;

/// The primitive ids a shadow ray passes through, one bit each.
#[derive(Clone, Debug, PartialEq)]
pub struct PassThrough {
    bits: Vec<u64>,
}

impl PassThrough {
    /// The set of the ids `0..count` for which `passes(id)` holds; `None` when there is none,
    /// so that a scene without invisible surfaces pays nothing.
    pub fn new(count: usize, passes: impl Fn(u32) -> bool) -> Option<PassThrough> {
        let mut bits = vec![0u64; count.div_ceil(64)];
        let mut any = false;
        for id in (0..count as u32).filter(|&id| passes(id)) {
            bits[id as usize / 64] |= 1 << (id % 64);
            any = true;
        }
        any.then_some(PassThrough { bits })
    }

    pub fn contains(&self, id: u32) -> bool {
        (self.bits.get(id as usize / 64)).is_some_and(|word| word & (1 << (id % 64)) != 0)
    }
}

impl Accel {
    /// Whether a primitive not in `pass_through` is hit with t in (t_min, t_max).
    pub fn any_opaque_hit(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        pass_through: &PassThrough,
    ) -> bool {
        self.find_any_opaque(origin, dir, t_min, t_max, pass_through)
    }

    /// [`Accel::any_opaque_hit`], inlined into the batch loop: the cheap question's traversal
    /// inlined, the walk past invisible surfaces (rarer) calls out.
    #[inline(always)]
    pub(super) fn find_any_opaque(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        pass_through: &PassThrough,
    ) -> bool {
        self.find_any(origin, dir, t_min, t_max)
            && self.blocked_past_pass_through(origin, dir, t_min, t_max, pass_through)
    }

    /// For a ray known to hit something with t in (t_min, t_max): whether a primitive not in
    /// `pass_through` is hit, walking the surfaces nearest first.
    pub(super) fn blocked_past_pass_through(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        pass_through: &PassThrough,
    ) -> bool {
        let mut t_min = t_min;
        for _ in 0..MAX_LAYERS {
            match self.closest_hit(origin, dir, t_min, t_max) {
                None => return false,
                Some(hit) if pass_through.contains(hit.prim) => t_min = hit.t,
                Some(_) => return true,
            }
        }
        true
    }
}
