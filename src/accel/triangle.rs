//! Ray/triangle intersection by Möller & Trumbore 1997, "Fast, Minimum Storage Ray/Triangle
//! Intersection" (Journal of Graphics Tools 2(1)), four triangles at a time.
//!
//! The hit point is written in barycentric form `v0 + u e1 + v e2` with `e1 = v1 - v0`,
//! `e2 = v2 - v0`; equating it with `o + t d` gives a 3×3 linear system in `(t, u, v)` that
//! Cramer's rule solves with one cross product per side: `p = d × e2`, `q = (o - v0) × e1`,
//! `det = e1 · p`, `u = (o - v0) · p / det`, `v = d · q / det`, `t = e2 · q / det`.
//!
//! Leaves store their triangles as [`Triangle4`] packets: the same precomputed `v0, e1, e2`
//! laid out as structure of arrays, one SIMD lane (glam's `Vec4`: SSE2 on x86-64, NEON on
//! AArch64, scalar elsewhere) per triangle. The packet test performs exactly the scalar test's
//! operations in the same order, lane by lane, so both round alike; the unit tests check that
//! they agree bit for bit.

use glam::{Vec3, Vec3A, Vec4};

use super::aabb::Aabb;

/// The bounds of a triangle that can be hit: `None` for a degenerate (zero-area) or
/// non-finite one, which is left out of the tree.
pub(crate) fn triangle_bounds(v: &[Vec3; 3]) -> Option<Aabb> {
    let b = Aabb::from_points(v.iter().map(|&p| Vec3A::from(p)));
    let area2 = (v[1] - v[0]).cross(v[2] - v[0]).length_squared();
    (b.is_finite() && area2 > 0.0 && area2.is_finite()).then_some(b)
}

/// The four dot products of four pairs of vectors stored by coordinate (`a[axis]` holds the
/// four vectors' `axis` coordinates).
#[inline(always)]
pub(crate) fn dot4(a: &[Vec4; 3], b: &[Vec4; 3]) -> Vec4 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Up to four triangles, by coordinate: `v0[axis]` holds the four `v0.axis`, and so on; `ids`
/// are the triangles' primitive ids. An unused lane holds the zero triangle, whose `det` is 0
/// for every ray, so it is never hit. 160 bytes.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(crate) struct Triangle4 {
    v0: [Vec4; 3],
    e1: [Vec4; 3],
    e2: [Vec4; 3],
    pub ids: [u32; 4],
}

/// A packet test's result: the lane hit and its `(t, u, v)`.
pub(crate) struct LaneHit {
    pub lane: usize,
    pub t: f32,
    pub u: f32,
    pub v: f32,
}

impl LaneHit {
    /// Of the lanes set in `bits` (not all clear), the one of least `t`; with `ANY`, the
    /// first.
    #[inline(always)]
    pub fn pick<const ANY: bool>(mut bits: u32, t: Vec4) -> usize {
        let mut lane = bits.trailing_zeros() as usize;
        if !ANY {
            bits &= bits - 1;
            while bits != 0 {
                let other = bits.trailing_zeros() as usize;
                if t[other] < t[lane] {
                    lane = other;
                }
                bits &= bits - 1;
            }
        }
        lane
    }
}

impl Triangle4 {
    /// Packs up to four `(vertices, id)`.
    pub fn new<'a>(triangles: impl IntoIterator<Item = (&'a [Vec3; 3], u32)>) -> Triangle4 {
        let mut packet = Triangle4 {
            v0: [Vec4::ZERO; 3],
            e1: [Vec4::ZERO; 3],
            e2: [Vec4::ZERO; 3],
            ids: [0; 4],
        };
        for (lane, (v, id)) in triangles.into_iter().take(4).enumerate() {
            let (e1, e2) = (v[1] - v[0], v[2] - v[0]);
            for axis in 0..3 {
                packet.v0[axis][lane] = v[0][axis];
                packet.e1[axis][lane] = e1[axis];
                packet.e2[axis][lane] = e2[axis];
            }
            packet.ids[lane] = id;
        }
        packet
    }

    /// Triangle `lane`'s first vertex and its two edges, `v0`, `e1` and `e2`.
    #[inline(always)]
    pub fn vertex_and_edges(&self, lane: usize) -> ([f32; 3], [f32; 3], [f32; 3]) {
        let at = |v: &[Vec4; 3]| v.map(|axis| axis[lane]);
        (at(&self.v0), at(&self.e1), at(&self.e2))
    }

    /// The nearest of the four hits with `t` in `(t_min, t_max)`; with `ANY`, the first lane
    /// that hits. `o` and `d` are the ray's coordinates splatted across lanes. Every comparison
    /// is written so that a NaN (from `det ≈ 0`) rejects the lane.
    #[inline(always)]
    pub fn intersect<const ANY: bool>(
        &self,
        o: &[Vec4; 3],
        d: &[Vec4; 3],
        t_min: f32,
        t_max: f32,
    ) -> Option<LaneHit> {
        let [e1, e2] = [&self.e1, &self.e2];
        let cross = |a: &[Vec4; 3], b: &[Vec4; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let p = cross(d, e2);
        let det = dot4(e1, &p);
        let inv_det = Vec4::ONE / det;
        let s = [o[0] - self.v0[0], o[1] - self.v0[1], o[2] - self.v0[2]];
        let u = dot4(&s, &p) * inv_det;
        // Most packets a ray reaches lie beside it: when no lane passes the first barycentric
        // test, stop before the second cross product (the same operations on the lanes that
        // go on, so the results are unchanged).
        let u_mask = det.cmpne(Vec4::ZERO) & u.cmpge(Vec4::ZERO) & u.cmple(Vec4::ONE);
        if u_mask.bitmask() == 0 {
            return None;
        }
        let q = cross(&s, e1);
        let v = dot4(d, &q) * inv_det;
        let t = dot4(e2, &q) * inv_det;
        let mask = u_mask
            & v.cmpge(Vec4::ZERO)
            & (u + v).cmple(Vec4::ONE)
            & t.cmpgt(Vec4::splat(t_min))
            & t.cmplt(Vec4::splat(t_max));
        let bits = mask.bitmask();
        if bits == 0 {
            return None;
        }
        let lane = LaneHit::pick::<ANY>(bits, t);
        Some(LaneHit {
            lane,
            t: t[lane],
            u: u[lane],
            v: v[lane],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_xoshiro::Xoshiro256PlusPlus;
    use rand_xoshiro::rand_core::{Rng, SeedableRng};

    /// The one-triangle test, written with glam's vector operations: the reference the packet
    /// must match.
    fn scalar(v: &[Vec3; 3], o: Vec3A, d: Vec3A, t_min: f32, t_max: f32) -> Option<[f32; 3]> {
        let v0 = Vec3A::from(v[0]);
        let (e1, e2) = (Vec3A::from(v[1]) - v0, Vec3A::from(v[2]) - v0);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det == 0.0 {
            return None;
        }
        let inv_det = det.recip();
        let s = o - v0;
        let u = s.dot(p) * inv_det;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(e1);
        let v = d.dot(q) * inv_det;
        if !(v >= 0.0 && u + v <= 1.0) {
            return None;
        }
        let t = e2.dot(q) * inv_det;
        (t > t_min && t < t_max).then_some([t, u, v])
    }

    /// Random small-integer-grid triangles and rays aimed at their vertices, edges and
    /// interiors (exact edge hits on the grid, grazing rays in their planes), plus packets with
    /// empty lanes: each lane alone must give the scalar result bit for bit, and the packet
    /// the nearest of them.
    #[test]
    fn packet_matches_scalar_test_bit_for_bit() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let grid = |rng: &mut Xoshiro256PlusPlus| (rng.next_u32() % 9) as f32 * 0.5 - 2.0;
        let point = |rng: &mut Xoshiro256PlusPlus| Vec3::new(grid(rng), grid(rng), grid(rng));
        let (mut hits, mut edge_hits, mut grazing) = (0, 0, 0);
        for _ in 0..20_000 {
            let count = 1 + (rng.next_u32() % 4) as usize;
            let tris: Vec<[Vec3; 3]> = (0..count)
                .map(|_| [point(&mut rng), point(&mut rng), point(&mut rng)])
                .collect();
            let packet = Triangle4::new(tris.iter().zip(10..));
            let target = &tris[(rng.next_u32() % count as u32) as usize];
            let (a, b) = (rng.next_u32() % 3, rng.next_u32() % 5);
            // A vertex, an edge midpoint or a point inside: `b / 4` of the way along.
            let aim = target[a as usize].lerp(target[(a as usize + 1) % 3], b as f32 / 4.0);
            let origin = match rng.next_u32() % 4 {
                // In the target's plane: a grazing ray.
                0 => {
                    grazing += 1;
                    target[0] + (target[1] - target[0]) * 3.0 - (target[2] - target[0])
                }
                _ => point(&mut rng) * 3.0,
            };
            let (o, d) = (Vec3A::from(origin), Vec3A::from(aim - origin));
            let (t_min, t_max) = (
                0.0,
                if rng.next_u32().is_multiple_of(2) {
                    2.0
                } else {
                    0.7
                },
            );
            let splat = |v: Vec3A| [v.x, v.y, v.z].map(Vec4::splat);
            let got = packet.intersect::<false>(&splat(o), &splat(d), t_min, t_max);
            let expected = (tris.iter().enumerate())
                .filter_map(|(lane, v)| Some((lane, scalar(v, o, d, t_min, t_max)?)))
                .min_by(|a, b| a.1[0].total_cmp(&b.1[0]));
            match (got, expected) {
                (None, None) => {}
                (Some(hit), Some((lane, [t, u, v]))) => {
                    assert_eq!((hit.t, hit.u, hit.v), (t, u, v));
                    assert_eq!(packet.ids[hit.lane], 10 + lane as u32);
                    hits += 1;
                    edge_hits += (u == 0.0 || v == 0.0 || u + v == 1.0) as usize;
                }
                (g, e) => panic!("packet {:?} vs scalar {e:?}", g.map(|h| h.t)),
            }
            let any = packet.intersect::<true>(&splat(o), &splat(d), t_min, t_max);
            assert_eq!(any.is_some(), expected.is_some());
        }
        assert!(
            hits > 5000 && edge_hits > 500 && grazing > 2000,
            "{hits} {edge_hits}"
        );
    }
}
