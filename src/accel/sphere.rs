//! Ray/sphere intersection for spheres placed by an arbitrary affine map (ellipsoids included),
//! four at a time.
//!
//! The ray is carried into each sphere's object space by the inverse map. An affine map sends
//! `o + t d` to `M⁻¹o + t M⁻¹d`, so the ray parameter `t` is the same in both spaces: the object
//! space root is the world space `t`, with no rescaling.
//!
//! Leaves store their spheres as [`Sphere4`] packets: the inverse maps and radii laid out as
//! structure of arrays, one SIMD lane per sphere (as [`super::triangle::Triangle4`] does for
//! triangles), so that a leaf of two to four spheres costs one test, not one per sphere.

use glam::{Affine3A, Mat3A, Vec3A, Vec4};

use super::SphereInstance;
use super::aabb::Aabb;
use super::triangle::{LaneHit, dot4};

/// The world bounds of a sphere that can be hit: the 8 corners of the object-space box
/// `[-r, r]³`, mapped to world space. `None` for a sphere that cannot be hit or tested safely:
/// a radius that is not positive and finite, or a map that is not finite and invertible.
pub(crate) fn sphere_bounds(instance: &SphereInstance) -> Option<Aabb> {
    let m = &instance.object_to_world;
    let r = instance.radius;
    let det = m.matrix3.determinant();
    let valid = r > 0.0 && r.is_finite() && m.is_finite() && det != 0.0 && det.is_finite();
    if !valid || !m.inverse().is_finite() {
        return None;
    }
    let local = Aabb {
        min: Vec3A::splat(-r),
        max: Vec3A::splat(r),
    };
    Some(local.transformed(m)).filter(Aabb::is_finite)
}

/// The translation of a sphere's `world_to_object` map if that is all the map does (its linear
/// part the identity: a sphere given by centre and radius), for the tests and surface points
/// that then add it rather than multiply by the identity.
pub fn translation_only(world_to_object: &Affine3A) -> Option<Vec3A> {
    (world_to_object.matrix3 == Mat3A::IDENTITY).then_some(world_to_object.translation)
}

/// Up to four spheres of radius `radius` around the origin of the object space that
/// `world_to_object` maps to, by coefficient: `rows[i][j]` holds the four maps' entry (i, j) of
/// the 3×4 matrix (column 3 the translation); `ids` are the spheres' primitive ids. An unused
/// lane has the zero map and a NaN radius, which no comparison accepts, so it is never hit.
/// 224 bytes.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(crate) struct Sphere4 {
    rows: [[Vec4; 4]; 3],
    radius: Vec4,
    pub ids: [u32; 4],
}

impl Sphere4 {
    /// Packs up to four `(sphere, id)`, each accepted by [`sphere_bounds`].
    pub fn new<'a>(spheres: impl IntoIterator<Item = (&'a SphereInstance, u32)>) -> Sphere4 {
        let mut packet = Sphere4 {
            rows: [[Vec4::ZERO; 4]; 3],
            radius: Vec4::NAN,
            ids: [0; 4],
        };
        for (lane, (sphere, id)) in spheres.into_iter().take(4).enumerate() {
            let m: Affine3A = sphere.object_to_world.inverse();
            let columns = [
                m.matrix3.x_axis,
                m.matrix3.y_axis,
                m.matrix3.z_axis,
                m.translation,
            ];
            for (i, row) in packet.rows.iter_mut().enumerate() {
                for (j, column) in columns.iter().enumerate() {
                    row[j][lane] = column[i];
                }
            }
            packet.radius[lane] = sphere.radius;
            packet.ids[lane] = id;
        }
        packet
    }

    /// The nearest of the four hits with `t` in `(t_min, t_max)`; with `ANY`, the first lane
    /// that hits. `o` and `d` are the ray's coordinates splatted across lanes.
    ///
    /// Each lane finds the smallest root `t` in `(t_min, t_max)` of `|o + t d|² = r²` in its
    /// object space, solved as in pbrt-v4 §6.2.2 / Ray Tracing Gems ch. 7 (Haines et al.,
    /// "Precision Improvements for Ray/Sphere Intersection"): with `a = d·d`, `b = 2 o·d`,
    /// `c = o·o - r²`, the discriminant `b² - 4ac` cancels catastrophically for a small or
    /// distant sphere, so it is rewritten as `4a (r² - |o - (b / 2a) d|²) = 4a (r + l)(r - l)`,
    /// where `l` is the distance from the center to the ray's closest point; and the roots are
    /// taken as `q / a` and `c / q` with `q = -(b + sign(b) √Δ) / 2`, which never subtracts
    /// nearly equal numbers. A negative discriminant gives a NaN root, and every comparison is
    /// written so that a NaN rejects the lane.
    #[inline(always)]
    pub fn intersect<const ANY: bool>(
        &self,
        o: &[Vec4; 3],
        d: &[Vec4; 3],
        t_min: f32,
        t_max: f32,
    ) -> Option<LaneHit> {
        let map = |row: &[Vec4; 4], p: &[Vec4; 3]| row[0] * p[0] + row[1] * p[1] + row[2] * p[2];
        let o = self.rows.each_ref().map(|row| map(row, o) + row[3]);
        let d = self.rows.each_ref().map(|row| map(row, d));
        let r = self.radius;
        let a = dot4(&d, &d);
        let b = Vec4::splat(2.0) * dot4(&o, &d);
        let c = dot4(&o, &o) - r * r;
        let k = b / (Vec4::splat(2.0) * a);
        let closest = [0, 1, 2].map(|axis| o[axis] - k * d[axis]);
        let l = dot4(&closest, &closest).sqrt();
        let discriminant = Vec4::splat(4.0) * a * (r + l) * (r - l);
        let root = discriminant.sqrt();
        let q = Vec4::select(
            b.cmplt(Vec4::ZERO),
            Vec4::splat(-0.5) * (b - root),
            Vec4::splat(-0.5) * (b + root),
        );
        let (t0, t1) = (q / a, c / q);
        let ordered = t0.cmple(t1);
        let (near, far) = (Vec4::select(ordered, t0, t1), Vec4::select(ordered, t1, t0));
        let (lo, hi) = (Vec4::splat(t_min), Vec4::splat(t_max));
        let near_in = near.cmpgt(lo) & near.cmplt(hi);
        let far_in = far.cmpgt(lo) & far.cmplt(hi);
        // A lane whose discriminant is negative has NaN roots and fails both range tests.
        let bits = (near_in | far_in).bitmask();
        if bits == 0 {
            return None;
        }
        let t = Vec4::select(near_in, near, far);
        let lane = LaneHit::pick::<ANY>(bits, t);
        Some(LaneHit {
            lane,
            t: t[lane],
            u: 0.0,
            v: 0.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_random;
    use super::*;
    use glam::Vec3;
    use rand_xoshiro::Xoshiro256PlusPlus;
    use rand_xoshiro::rand_core::SeedableRng;

    /// The one-sphere test, written with glam's vector operations: the reference the packet
    /// must match.
    fn scalar(sphere: &SphereInstance, o: Vec3A, d: Vec3A, t_min: f32, t_max: f32) -> Option<f32> {
        let m = sphere.object_to_world.inverse();
        let (o, d) = (m.transform_point3a(o), m.transform_vector3a(d));
        let r = sphere.radius;
        let a = d.dot(d);
        let b = 2.0 * o.dot(d);
        let c = o.dot(o) - r * r;
        let l = (o - (b / (2.0 * a)) * d).length();
        let root = (4.0 * a * (r + l) * (r - l)).sqrt();
        let q = if b < 0.0 {
            -0.5 * (b - root)
        } else {
            -0.5 * (b + root)
        };
        let (t0, t1) = (q / a, c / q);
        let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        [near, far].into_iter().find(|&t| t > t_min && t < t_max)
    }

    /// Random ellipsoids and rays aimed near their centres (from inside and outside, grazing
    /// and missing), in packets of one to four: each lane alone must give the scalar result bit
    /// for bit, the packet the nearest of them, and an empty lane never a hit.
    #[test]
    fn packet_matches_scalar_test_bit_for_bit() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        let mut uniform = |lo: f32, hi: f32| test_random::uniform(&mut rng, lo, hi);
        let (mut hits, mut inside) = (0, 0);
        for _ in 0..20_000 {
            let count = 1 + (uniform(0.0, 4.0) as usize).min(3);
            let spheres: Vec<SphereInstance> = (0..count)
                .map(|_| {
                    let scale = Vec3::new(uniform(0.2, 2.0), uniform(0.2, 2.0), uniform(0.2, 2.0));
                    let axis = Vec3::new(uniform(-1.0, 1.0), uniform(-1.0, 1.0), 1.0).normalize();
                    let centre =
                        Vec3::new(uniform(-3.0, 3.0), uniform(-3.0, 3.0), uniform(-3.0, 3.0));
                    SphereInstance {
                        object_to_world: Affine3A::from_scale_rotation_translation(
                            scale,
                            glam::Quat::from_axis_angle(axis, uniform(0.0, 6.0)),
                            centre,
                        ),
                        radius: uniform(0.1, 1.5),
                    }
                })
                .collect();
            let packet = Sphere4::new(spheres.iter().zip(10..));
            let target = spheres[(uniform(0.0, count as f32) as usize).min(count - 1)]
                .object_to_world
                .translation;
            // Half the rays start near a centre (often inside), half anywhere.
            let spread = if uniform(0.0, 1.0) < 0.5 { 1.0 } else { 6.0 };
            let origin = target
                + Vec3A::new(
                    uniform(-spread, spread),
                    uniform(-spread, spread),
                    uniform(-spread, spread),
                );
            let aim =
                target + Vec3A::new(uniform(-2.0, 2.0), uniform(-2.0, 2.0), uniform(-2.0, 2.0));
            let (o, d) = (origin, aim - origin);
            let (t_min, t_max) = (uniform(-0.5, 0.5).max(0.0), uniform(0.5, 3.0));
            let splat = |v: Vec3A| [v.x, v.y, v.z].map(Vec4::splat);
            let got = packet.intersect::<false>(&splat(o), &splat(d), t_min, t_max);
            let expected = (spheres.iter().enumerate())
                .filter_map(|(lane, s)| Some((lane, scalar(s, o, d, t_min, t_max)?)))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            match (&got, expected) {
                (None, None) => {}
                (Some(hit), Some((lane, t))) => {
                    assert_eq!(hit.t, t);
                    assert_eq!(packet.ids[hit.lane], 10 + lane as u32);
                    hits += 1;
                    let m = spheres[lane].object_to_world.inverse();
                    inside += (m.transform_point3a(o).length() < spheres[lane].radius) as usize;
                }
                (g, e) => panic!("packet {:?} vs scalar {e:?}", g.as_ref().map(|h| h.t)),
            }
            let any = packet.intersect::<true>(&splat(o), &splat(d), t_min, t_max);
            assert_eq!(any.is_some(), expected.is_some());
        }
        assert!(
            hits > 4000 && inside > 1000,
            "{hits} hits, {inside} from inside"
        );
    }
}
