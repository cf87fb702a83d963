//! Two triangles that make a parallelogram (a rectangle's halves, a quad's), tested by the
//! flat tracer's closest hits as one: half the triangle tests on a scene of rectangles.
//!
//! Triangles `T0 = (w0, x, y)` and `T1 = (w1, x, y)` (in any vertex order) that share the edge
//! `x y` make the parallelogram `w0 + s (x - w0) + r (y - w0)`, `s, r` in `[0, 1]`, when
//! `w1 = x + y - w0`; `T0` is its half `s + r <= 1`, `T1` the other. Möller–Trumbore against the
//! parallelogram is the triangle's test with the bound `s + r <= 1` replaced by `r <= 1` (Lagae
//! and Dutré, "An efficient ray-quadrilateral intersection test", 2005, for the general
//! quadrilateral); a hit is reported on the half it falls in, with that triangle's barycentrics,
//! an affine map of `(s, r)` with integer coefficients (below). This file pairs the triangles;
//! the flat tracer's `parallelogram_lanes` tests the pairs, through the triangles' one
//! Möller–Trumbore in lanes.
//!
//! The values are not the tree's to the bit: `t` comes from other edges' cross products, and
//! `(u, v)` from `(s, r)` rather than the triangle's own test, each within a few units of
//! rounding of it; a ray within rounding of the shared edge may be reported on either half,
//! never on neither (the two triangles' tests can miss both there). Only exact parallelograms
//! are paired (to rounding: see [`pair`]), so that the surface tested is the triangles'.

use glam::Vec3;

/// A parallelogram `v0 + s e1 + r e2`, `s, r` in `[0, 1]`, made of two triangles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Parallelogram {
    pub v0: [f32; 3],
    pub e1: [f32; 3],
    pub e2: [f32; 3],
    /// The triangles' ids: the half `s + r <= 1` (the corner `v0`'s), then the other.
    pub ids: [u32; 2],
    /// Per half, its triangle's barycentrics of vertices 1 and 2 from `(s, r)`:
    /// `u = m[0] s + m[1] r + m[2]`, `v = m[3] s + m[4] r + m[5]`.
    pub barycentrics: [[f32; 6]; 2],
}

/// How far `w1` may be from `x + y - w0`, relative to the largest coordinate of the four
/// vertices, for two triangles to be paired: a few units of f32 rounding, as a rectangle's
/// corners placed by a transform carry.
const PARALLELOGRAM_TOLERANCE: f64 = 4.0 * f32::EPSILON as f64;

/// Two triangles' shared edge: its two vertices, in `first`'s order, and the vertex of each
/// triangle off it; `None` unless each has three distinct vertices and they share exactly two
/// (the same `f32` values, as a mesh's shared vertex has). The one test of "two halves" for
/// the flat tracer's parallelograms and the rectangle lamps (`light::area`).
pub(crate) fn shared_edge(first: &[Vec3; 3], second: &[Vec3; 3]) -> Option<([Vec3; 2], [Vec3; 2])> {
    let distinct = |t: &[Vec3; 3]| t[0] != t[1] && t[1] != t[2] && t[2] != t[0];
    if !distinct(first) || !distinct(second) {
        return None;
    }
    let shared: Vec<Vec3> = first
        .iter()
        .filter(|v| second.contains(v))
        .copied()
        .collect();
    let &[x, y] = shared.as_slice() else {
        return None;
    };
    let off = |t: &[Vec3; 3]| t.iter().find(|&&v| v != x && v != y).copied();
    Some(([x, y], [off(first)?, off(second)?]))
}

/// The parallelogram of triangles `a` and `b` (ids `ids`), if they make one: they share an
/// edge ([`shared_edge`]) and the two others are opposite corners, `a`'s at `v0`.
pub(super) fn pair(a: &[Vec3; 3], b: &[Vec3; 3], ids: [u32; 2]) -> Option<Parallelogram> {
    let ([x, y], [w0, w1]) = shared_edge(a, b)?;
    // In f64, where the four f32 values sum without rounding at any sensible scale.
    let [w0d, w1d, xd, yd] = [w0, w1, x, y].map(|p| p.as_dvec3());
    let off = (w1d - (xd + yd - w0d)).abs().max_element();
    let scale = [w0d, w1d, xd, yd].map(|p| p.abs().max_element());
    let scale = scale.into_iter().fold(0.0, f64::max);
    let opposite_corners = off <= PARALLELOGRAM_TOLERANCE * scale;
    if !opposite_corners {
        return None;
    }
    // Each vertex's corner (s, r): v0 = w0 (0, 0), x (1, 0), y (0, 1), w1 (1, 1).
    let corner = |p: Vec3| match p {
        p if p == w0 || p == w1 => [f64::from(p == w1); 2],
        p if p == x => [1.0, 0.0],
        _ => [0.0, 1.0],
    };
    let barycentrics = [a, b].map(|t| barycentric_map(t.map(corner)));
    let (e1, e2) = ((xd - w0d).as_vec3(), (yd - w0d).as_vec3());
    let spans_area = e1.cross(e2).length_squared() > 0.0;
    if !spans_area {
        return None;
    }
    Some(Parallelogram {
        v0: w0.to_array(),
        e1: e1.to_array(),
        e2: e2.to_array(),
        ids,
        barycentrics,
    })
}

/// The affine map from a point's `(s, r)` to the barycentrics `(u, v)` of vertices 1 and 2 of
/// a triangle whose vertices sit at the corners `c`: `(s, r) = c0 + u (c1 - c0) + v (c2 - c0)`,
/// a 2 x 2 system of determinant ±1 (the corners are three of the unit square's), so that the
/// inverse has integer entries and the map is exact but for the final products and sums.
fn barycentric_map([c0, c1, c2]: [[f64; 2]; 3]) -> [f32; 6] {
    let (a, b) = (c1[0] - c0[0], c2[0] - c0[0]);
    let (c, d) = (c1[1] - c0[1], c2[1] - c0[1]);
    let det = a * d - b * c;
    // (u, v) = M^-1 ((s, r) - c0), M = [[a, b], [c, d]].
    let (i00, i01, i10, i11) = (d / det, -b / det, -c / det, a / det);
    let u0 = -(i00 * c0[0] + i01 * c0[1]);
    let v0 = -(i10 * c0[0] + i11 * c0[1]);
    [i00, i01, u0, i10, i11, v0].map(|x| x as f32)
}

/// Pairs consecutive triangles of `triangles` (ids `ids`) into parallelograms where they make
/// one: the parallelograms, and the indices of the triangles left alone, in order.
pub(super) fn pair_consecutive(
    triangles: &[[Vec3; 3]],
    ids: &[u32],
) -> (Vec<Parallelogram>, Vec<usize>) {
    let (mut parallelograms, mut alone) = (Vec::new(), Vec::new());
    let mut i = 0;
    while i < triangles.len() {
        let paired = (i + 1 < triangles.len())
            .then(|| pair(&triangles[i], &triangles[i + 1], [ids[i], ids[i + 1]]))
            .flatten();
        match paired {
            Some(parallelogram) => {
                parallelograms.push(parallelogram);
                i += 2;
            }
            None => {
                alone.push(i);
                i += 1;
            }
        }
    }
    (parallelograms, alone)
}

#[cfg(test)]
mod tests {
    use super::super::test_random;
    use glam::{Affine3A, Quat};
    use rand_xoshiro::Xoshiro256PlusPlus;
    use rand_xoshiro::rand_core::SeedableRng;

    use super::super::{Accel, Primitives};
    use super::*;

    /// A rectangle's corners `a b c d` (in order round it) under a rotation, scale and move.
    fn rectangle(rng: &mut Xoshiro256PlusPlus) -> [Vec3; 4] {
        let mut uniform = |lo: f32, hi: f32| test_random::uniform(rng, lo, hi);
        let axis = Vec3::new(uniform(-1.0, 1.0), uniform(-1.0, 1.0), uniform(-1.0, 1.0));
        let to_world = Affine3A::from_scale_rotation_translation(
            Vec3::new(uniform(0.2, 2.0), uniform(0.2, 2.0), 1.0),
            Quat::from_axis_angle(axis.normalize_or(Vec3::X), uniform(0.0, 6.0)),
            Vec3::new(uniform(-3.0, 3.0), uniform(-3.0, 3.0), uniform(-3.0, 3.0)),
        );
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(x, y)| to_world.transform_point3(Vec3::new(x, y, 0.0)))
    }

    /// The rectangle `abcd`'s two triangles, split along `a c` or `b d`, each triangle's
    /// vertices rotated by `turns`, the triangles in either order.
    fn halves(
        [a, b, c, d]: [Vec3; 4],
        split: usize,
        turns: [usize; 2],
        swap: bool,
    ) -> [[Vec3; 3]; 2] {
        let halves = match split {
            0 => [[a, b, c], [a, c, d]],
            _ => [[a, b, d], [b, c, d]],
        };
        let [mut first, mut second] = [0, 1].map(|k| {
            let t = halves[k];
            [0, 1, 2].map(|i| t[(i + turns[k]) % 3])
        });
        if swap {
            std::mem::swap(&mut first, &mut second);
        }
        [first, second]
    }

    /// A triangle's point at barycentrics `(u, v)` of vertices 1 and 2.
    fn at(t: &[Vec3; 3], u: f32, v: f32) -> Vec3 {
        t[0] + u * (t[1] - t[0]) + v * (t[2] - t[0])
    }

    /// Every split, vertex order and order of a rectangle's two triangles makes a parallelogram
    /// whose halves are the triangles: a point `(s, r)` of it is, by the half's barycentric
    /// map, the same point of that half's triangle. Triangles that share one vertex, or two
    /// whose other corners are not opposite (a trapezoid's, a kite's), are not paired.
    #[test]
    fn rectangles_pair_in_any_vertex_order() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        let mut paired = 0;
        for _ in 0..20 {
            let corners = rectangle(&mut rng);
            for split in 0..2 {
                for turns in (0..9).map(|k| [k % 3, k / 3]) {
                    for swap in [false, true] {
                        let [t0, t1] = halves(corners, split, turns, swap);
                        let quad = pair(&t0, &t1, [7, 9]).expect("a rectangle's halves pair");
                        paired += 1;
                        let [v0, e1, e2] = [quad.v0, quad.e1, quad.e2].map(Vec3::from);
                        for (s, r) in [(0.1, 0.2), (0.7, 0.1), (0.45, 0.5), (0.9, 0.8), (0.2, 0.95)]
                        {
                            let half = usize::from(s + r > 1.0);
                            let m = quad.barycentrics[half];
                            let (u, v) = (m[0] * s + m[1] * r + m[2], m[3] * s + m[4] * r + m[5]);
                            assert!(
                                (0.0..=1.0).contains(&u)
                                    && (0.0..=1.0).contains(&v)
                                    && u + v <= 1.0
                            );
                            let triangle = [t0, t1][half];
                            let expected: Vec3 = v0 + s * e1 + r * e2;
                            assert!((at(&triangle, u, v) - expected).length() < 1e-5);
                        }
                    }
                }
            }
            let [a, b, c, d] = corners;
            let trapezoid = [[a, b, c], [a, c, d + (c - d) * 0.01]];
            let kite = [[a, b, c], [a, c, d + (d - b) * 0.01]];
            let one_shared = [[a, b, c], [a, d, d + (d - c)]];
            for [t0, t1] in [trapezoid, kite, one_shared] {
                assert_eq!(pair(&t0, &t1, [0, 1]), None);
            }
        }
        assert_eq!(paired, 20 * 2 * 9 * 2);
    }

    /// Rectangles traced flat, their halves paired, against the tree (which tests each
    /// triangle): rays aimed at points inside them (at least 1e-3 from an edge, from random
    /// origins) hit the same triangle at the same `t`, `u` and `v` within 1e-4 (rounding,
    /// conditioned by the ray's angle to the plane); rays at points of the shared edge hit one
    /// half or the other, never neither; rays at points 1e-3 outside a rectangle miss it.
    #[test]
    fn paired_rectangles_hit_as_their_triangles() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(6);
        let mut uniform = move |lo: f32, hi: f32| test_random::uniform(&mut rng, lo, hi);
        let mut scene_rng = Xoshiro256PlusPlus::seed_from_u64(7);
        let (mut inside, mut on_diagonal) = (0, 0);
        for scene in 0..30 {
            let rectangles: Vec<[Vec3; 4]> = (0..4).map(|_| rectangle(&mut scene_rng)).collect();
            let triangles: Vec<[Vec3; 3]> = (rectangles.iter().enumerate())
                .flat_map(|(k, &corners)| {
                    halves(corners, (k + scene) % 2, [k % 3, scene % 3], false)
                })
                .collect();
            let ids: Vec<u32> = (0..triangles.len() as u32).collect();
            let (pairs, alone) = pair_consecutive(&triangles, &ids);
            assert_eq!((pairs.len(), alone.len()), (4, 0), "every rectangle paired");
            let primitives = Primitives {
                triangles,
                ..Default::default()
            };
            let accel = Accel::build(&primitives);
            let (mut origins, mut dirs, mut kinds) = (Vec::new(), Vec::new(), Vec::new());
            for (k, &[a, b, c, d]) in rectangles.iter().enumerate() {
                for i in 0..40 {
                    let (s, r) = match i % 4 {
                        // Inside, away from the edges.
                        0 | 1 => (uniform(1e-3, 1.0 - 1e-3), uniform(1e-3, 1.0 - 1e-3)),
                        // On the shared edge (a c or b d, the split of rectangle k).
                        2 => {
                            let x = uniform(0.0, 1.0);
                            if (k + scene) % 2 == 0 {
                                (x, x)
                            } else {
                                (x, 1.0 - x)
                            }
                        }
                        // Just outside, past each side in turn.
                        _ => {
                            let (along, off) = (uniform(0.0, 1.0), [-1e-3, 1.0 + 1e-3][i / 4 % 2]);
                            if i / 8 % 2 == 0 {
                                (off, along)
                            } else {
                                (along, off)
                            }
                        }
                    };
                    let target = a + s * (b - a) + r * (d - a);
                    let _ = c;
                    let origin =
                        Vec3::new(uniform(-6.0, 6.0), uniform(-6.0, 6.0), uniform(-6.0, 6.0));
                    origins.push(origin);
                    dirs.push(target - origin);
                    kinds.push((k, i % 4, s.min(r).min(1.0 - s).min(1.0 - r)));
                }
            }
            let n = origins.len();
            let mut hits = vec![None; n];
            accel.closest_hits(&origins, &dirs, 0.0, &vec![1.5; n], &mut hits);
            for i in 0..n {
                let (k, kind, _) = kinds[i];
                let ids = [2 * k as u32, 2 * k as u32 + 1];
                let tree = accel.closest_hit(origins[i], dirs[i], 0.0, 1.5);
                let cosine = dirs[i]
                    .normalize()
                    .dot(
                        (rectangles[k][1] - rectangles[k][0])
                            .cross(rectangles[k][3] - rectangles[k][0])
                            .normalize(),
                    )
                    .abs();
                // Another rectangle in front of the target: nothing to compare on this one.
                if tree.is_some_and(|h| !ids.contains(&h.prim) && h.t < 1.0 - 1e-3) {
                    continue;
                }
                let tolerance = 1e-5 / cosine.max(1e-2);
                match kind {
                    0 | 1 => {
                        let (got, tree) = (hits[i].expect("inside"), tree.expect("inside"));
                        assert_eq!(got.prim, tree.prim, "ray {i}");
                        assert!(
                            (got.t - tree.t).abs() <= tolerance,
                            "ray {i}: t {} against {}",
                            got.t,
                            tree.t
                        );
                        assert!(
                            (got.u - tree.u).abs() <= 10.0 * tolerance,
                            "ray {i}: u {} against {}",
                            got.u,
                            tree.u
                        );
                        assert!(
                            (got.v - tree.v).abs() <= 10.0 * tolerance,
                            "ray {i}: v {} against {}",
                            got.v,
                            tree.v
                        );
                        inside += 1;
                    }
                    2 => {
                        let got = hits[i].expect("on the shared edge");
                        assert!(
                            ids.contains(&got.prim) && (got.t - 1.0).abs() <= tolerance,
                            "ray {i}: {got:?}"
                        );
                        on_diagonal += 1;
                    }
                    // Not at a grazing angle, where 1e-3 outside is within rounding.
                    _ if cosine > 0.05 => assert!(
                        hits[i].is_none_or(|h| !ids.contains(&h.prim)),
                        "ray {i}: {:?}",
                        hits[i]
                    ),
                    _ => {}
                }
            }
        }
        assert!(
            inside > 1500 && on_diagonal > 700,
            "{inside} inside, {on_diagonal} on the diagonal"
        );
    }
}
