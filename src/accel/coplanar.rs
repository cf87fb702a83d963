//! Runs of consecutive coplanar triangles (a rectangle's two halves, a flat face's fan) and the
//! lane test that skips a run when no ray of a group can reach its plane.
//!
//! A group of rays is tested against every triangle of a flat scene (see `flat.rs`); a
//! closed room's walls are in every group's way, but a group of shadow rays on their way from
//! the walls to a lamp never crosses a wall's plane. One plane test for a run replaces its
//! triangle tests when every ray of the group stays on one side of the plane over its whole
//! range, by more than the test's rounding could hide: then no triangle of the run can report
//! a hit, and the hits are the same as without the test, bit for bit.
//!
//! The bound. A ray `o + t d` is at signed distance `f(t) = n · (o - v0) + t (n · d)` from a
//! triangle's plane (unit normal `n`), linear in `t`. Möller–Trumbore's `t` is `N / det`
//! with `N = (o - v0) · (e1 × e2)` and `det = -d · (e1 × e2)`; each is a cross and a dot
//! product, computed within `γ5 |o - v0| |e1| |e2|` and `γ5 |d| |e1| |e2|` (Higham, §3.1),
//! and to first order the exact point at the computed `t` is then within
//! `γ5 (|o - v0| + t |d|) / sin α` of the plane, `α` the angle between `e1` and `e2`. Where
//! the computed `t` is in `(0, t_max)`, some `t` there has `|f(t)|` within that bound. The
//! test below evaluates `f` at 0 and `t_max` against a margin of [`ROUNDING`] `/ sin α`
//! times `1 + |o|_1 + |v0|_1 + t |d|_1` (`|o - v0| <= |o|_1 + |v0|_1`) plus the run's
//! thickness (its vertices' largest distance from the plane it uses): `32 ε / sin α` covers
//! Möller–Trumbore's `5 ε / sin α` and the rounding of `f` itself (`4 ε (|o|_1 + |offset|)`,
//! and the `f32` normal's length within `2 ε` of 1) with room to spare. As `f` and the margin
//! are both linear in `t`, a lane clear of the margin at both ends is clear over the whole
//! range.
//!
//! Only well-shaped triangles (`sin α` at least [`MIN_SIN`]) join a run, so that the margin
//! stays far below the offset `math::offset_ray_origin` puts between a new ray and its
//! surface (`1e-4 (1 + |p|_∞)`): the rays leaving a wall are clear of that wall's plane.

#![cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]

use std::ops::Range;

use glam::DVec3;

#[cfg(target_arch = "x86_64")]
use super::lanes::Lanes;

/// `32 ε` (`2^-18`): the margin's factor over `1 / sin α` (see the module's documentation).
const ROUNDING: f64 = 1.0 / (1u32 << 18) as f64;

/// The smallest `sin α` of a triangle in a run: the margin grows as `1 / sin α`.
const MIN_SIN: f64 = 0.125;

/// A triangle as the flat tests store it: a vertex and the two edges from it.
pub(crate) type VertexEdges = ([f32; 3], [f32; 3], [f32; 3]);

/// The plane `normal · x = offset` of a run (unit normal), within `margin` of its triangles'
/// vertices and of the rounding at a ray's origin, and the margin's growth per unit of
/// `|o|_1` and of `t |d|_1`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RunPlane {
    normal: [f32; 3],
    offset: f32,
    margin: f32,
    growth: f32,
}

/// Consecutive triangles of a flat scene (by index in its list), with their common plane
/// where there are two or more.
#[derive(Clone, Debug)]
pub(crate) struct TriangleRun {
    pub triangles: Range<usize>,
    pub plane: Option<RunPlane>,
}

/// A group's rays' magnitudes, for [`RunPlane::clear_lanes`]: `|o|_1` and `|d|_1` by lane.
#[cfg(target_arch = "x86_64")]
pub(crate) struct RayScale<S: Lanes> {
    origin: S,
    dir: S,
}

#[cfg(target_arch = "x86_64")]
impl<S: Lanes> RayScale<S> {
    #[inline(always)]
    pub fn new(o: &[S; 3], d: &[S; 3]) -> Self {
        RayScale {
            origin: o[0].abs() + o[1].abs() + o[2].abs(),
            dir: d[0].abs() + d[1].abs() + d[2].abs(),
        }
    }
}

/// The triangles cut into runs: each run as long as the next triangle lies in the first one's
/// plane (within the margin's own scale) and is well shaped.
pub(crate) fn coplanar_runs(triangles: &[VertexEdges]) -> Vec<TriangleRun> {
    let mut runs = Vec::new();
    let mut start = 0;
    while start < triangles.len() {
        let mut end = start + 1;
        let plane = sin_at_v0(&triangles[start])
            .filter(|&sin| sin >= MIN_SIN)
            .map(|_| unit_plane(&triangles[start]));
        if let Some((normal, offset)) = plane {
            while end < triangles.len()
                && sin_at_v0(&triangles[end]).is_some_and(|sin| sin >= MIN_SIN)
                && thickness(&triangles[end], normal, offset)
                    <= ROUNDING * (1.0 + max_norm(&triangles[end]))
            {
                end += 1;
            }
        }
        let plane = plane
            .filter(|_| end - start > 1)
            .map(|(normal, offset)| run_plane(&triangles[start..end], normal, offset));
        runs.push(TriangleRun {
            triangles: start..end,
            plane,
        });
        start = end;
    }
    runs
}

fn vertices(tri: &VertexEdges) -> [DVec3; 3] {
    let v0 = DVec3::from(tri.0.map(f64::from));
    let (e1, e2) = (tri.1.map(f64::from), tri.2.map(f64::from));
    [v0, v0 + DVec3::from(e1), v0 + DVec3::from(e2)]
}

/// `sin α` between the edges from `v0`, `None` for a degenerate triangle.
fn sin_at_v0(tri: &VertexEdges) -> Option<f64> {
    let (e1, e2) = (
        DVec3::from(tri.1.map(f64::from)),
        DVec3::from(tri.2.map(f64::from)),
    );
    let sin = e1.cross(e2).length() / (e1.length() * e2.length());
    (sin > 0.0 && sin.is_finite()).then_some(sin)
}

/// The triangle's plane with its normal and offset rounded to `f32`, as the test uses them.
fn unit_plane(tri: &VertexEdges) -> ([f32; 3], f32) {
    let (e1, e2) = (
        DVec3::from(tri.1.map(f64::from)),
        DVec3::from(tri.2.map(f64::from)),
    );
    let normal = e1.cross(e2).normalize().as_vec3().to_array();
    let offset = DVec3::from(normal.map(f64::from)).dot(vertices(tri)[0]) as f32;
    (normal, offset)
}

/// The largest distance of the triangle's vertices from the plane, exactly as far as `f64`
/// goes (the normal's `f32` length is within `2^-23` of 1, ignored against the margin).
fn thickness(tri: &VertexEdges, normal: [f32; 3], offset: f32) -> f64 {
    let normal = DVec3::from(normal.map(f64::from));
    (vertices(tri).iter())
        .map(|v| (normal.dot(*v) - f64::from(offset)).abs())
        .fold(0.0, f64::max)
}

/// The largest `|v|_1` of the triangle's vertices.
fn max_norm(tri: &VertexEdges) -> f64 {
    (vertices(tri).iter())
        .map(|v| v.abs().element_sum())
        .fold(0.0, f64::max)
}

fn run_plane(triangles: &[VertexEdges], normal: [f32; 3], offset: f32) -> RunPlane {
    let growth = (triangles.iter())
        .map(|tri| ROUNDING / sin_at_v0(tri).unwrap_or(MIN_SIN))
        .fold(0.0, f64::max);
    let margin = (triangles.iter())
        .map(|tri| thickness(tri, normal, offset) + growth * (1.0 + max_norm(tri)))
        .fold(0.0, f64::max);
    // Rounded up to f32: a few ulps over.
    let up = |x: f64| (x * (1.0 + 1e-6)) as f32;
    RunPlane {
        normal,
        offset,
        margin: up(margin),
        growth: up(growth),
    }
}

#[cfg(target_arch = "x86_64")]
impl RunPlane {
    /// Bit `i` set where lane `i`'s ray stays clear of the plane for `t` in `(0, t_max)`: its
    /// signed distance minus the margin (see the module's documentation) has one sign at
    /// `t = 0` and at `t_max`. A NaN anywhere (an unusable lane, `∞ · 0`) leaves a lane unset.
    #[inline(always)]
    pub fn clear_lanes<S: Lanes>(
        &self,
        o: &[S; 3],
        d: &[S; 3],
        scale: &RayScale<S>,
        t_max: S,
    ) -> u32 {
        let n = self.normal.map(S::splat);
        let distance = n[0] * o[0] + n[1] * o[1] + n[2] * o[2] - S::splat(self.offset);
        let along = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
        let growth = S::splat(self.growth);
        let margin = S::splat(self.margin) + growth * scale.origin;
        let slope = growth * scale.dir;
        let zero = S::splat(0.0);
        let above = distance - margin;
        let above_far = above + t_max * (along - slope);
        let below = zero - distance - margin;
        let below_far = below - t_max * (along + slope);
        let clear_above = S::and(above.gt(zero), above_far.gt(zero));
        let clear_below = S::and(below.gt(zero), below_far.gt(zero));
        S::bits(S::or(clear_above, clear_below))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(v: [[f32; 3]; 3]) -> VertexEdges {
        let e = |k: usize| [0, 1, 2].map(|a| v[k][a] - v[0][a]);
        (v[0], e(1), e(2))
    }

    /// A rectangle's halves form a run, a triangle off its plane starts a new one, a sliver
    /// (`sin α` 0.01) stays alone, and a lone triangle has no plane.
    #[test]
    fn runs_follow_planes() {
        let triangles = [
            tri([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]),
            tri([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]),
            tri([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0]]),
            tri([[5.0, 0.0, 1.0], [5.0, 3.0, 1.0], [2.0, 1.0, 1.0]]),
            tri([[0.0, 0.0, 1.0], [100.0, 1.0, 1.0], [100.0, 0.0, 1.0]]),
            tri([[0.0, 0.0, 2.0], [1.0, 0.0, 2.0], [1.0, 1.0, 2.0]]),
        ];
        let runs = coplanar_runs(&triangles);
        let ranges: Vec<_> = runs.iter().map(|run| run.triangles.clone()).collect();
        assert_eq!(ranges, [0..2, 2..4, 4..5, 5..6]);
        let planes: Vec<_> = runs.iter().map(|run| run.plane.is_some()).collect();
        assert_eq!(planes, [true, true, false, false]);
    }
}
