//! Area lights: emissive shapes, sampled by area (triangles) or by the cone they subtend
//! (spheres), one-sided on the side of the geometric normal.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::LightSample;
use crate::accel::PrimitiveRef;
use crate::film::luminance;
use crate::sampling::AliasTable;
use crate::sampling::warp::{uniform_cone, uniform_cone_pdf, uniform_sphere, uniform_triangle};
use crate::shape::geometry::{EmissiveShape, SceneGeometry};

#[derive(Clone, Debug)]
pub struct AreaLight {
    radiance: Vec3,
    shape: EmitterShape,
}

#[derive(Clone, Debug)]
enum EmitterShape {
    /// Two triangles that make a parallelogram (a rectangle light): sampled uniformly as one,
    /// without choosing a triangle or warping to it.
    Parallelogram(EmitterParallelogram),
    Triangles {
        triangles: Vec<EmitterTriangle>,
        by_area: AliasTable,
        area: f32,
    },
    Sphere {
        centre: Vec3,
        radius: f32,
    },
}

impl AreaLight {
    /// `None` for shapes that cannot emit (no area).
    pub fn new(shape: &EmissiveShape, geometry: &SceneGeometry) -> Option<Self> {
        let decode = |id: &u32| geometry.ids.decode(*id);
        let shape_kind = match decode(shape.primitives.first()?)? {
            PrimitiveRef::Triangle(_) | PrimitiveRef::InstanceTriangle { .. } => {
                let corners: Vec<[Vec3; 3]> = (shape.primitives.iter())
                    .filter_map(|id| geometry.world_triangle(decode(id)?))
                    .collect();
                let areas: Vec<f32> = corners.iter().map(triangle_area).collect();
                let triangles = corners.iter().map(EmitterTriangle::new).collect();
                let area: f32 = areas.iter().sum();
                if area.is_nan() || area <= 0.0 {
                    return None;
                }
                if let [first, second] = corners.as_slice()
                    && let Some(parallelogram) = EmitterParallelogram::new(first, second)
                {
                    return Some(Self {
                        radiance: shape.radiance,
                        shape: EmitterShape::Parallelogram(parallelogram),
                    });
                }
                EmitterShape::Triangles {
                    by_area: AliasTable::new(&areas),
                    triangles,
                    area,
                }
            }
            PrimitiveRef::Sphere(i) => {
                let sphere = geometry.spheres.get(i)?;
                // A sphere light is sampled as a round sphere: the mean of the axes' scales.
                let m = sphere.object_to_world.matrix3;
                let scale = (m.x_axis.length() + m.y_axis.length() + m.z_axis.length()) / 3.0;
                EmitterShape::Sphere {
                    centre: sphere.object_to_world.translation.into(),
                    radius: sphere.radius * scale,
                }
            }
            // An infinite plane cannot be sampled: the builder never makes it an emitter.
            PrimitiveRef::Plane(_) => return None,
        };
        Some(Self {
            radiance: shape.radiance,
            shape: shape_kind,
        })
    }

    pub fn radiance(&self) -> Vec3 {
        self.radiance
    }

    pub fn area(&self) -> f32 {
        match &self.shape {
            EmitterShape::Parallelogram(parallelogram) => parallelogram.area,
            EmitterShape::Triangles { area, .. } => *area,
            EmitterShape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
        }
    }

    pub fn power(&self) -> f32 {
        PI * self.area() * luminance(self.radiance)
    }

    pub fn sample(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        match &self.shape {
            EmitterShape::Parallelogram(parallelogram) => {
                let point =
                    parallelogram.corner + parallelogram.edge1 * u.x + parallelogram.edge2 * u.y;
                self.sample_towards(p, point, parallelogram.normal, parallelogram.area)
            }
            EmitterShape::Triangles {
                triangles,
                by_area,
                area,
            } => {
                let (index, _, remapped) = by_area.sample(u.x);
                let triangle = &triangles[index];
                let (b1, b2) = uniform_triangle(Vec2::new(remapped, u.y));
                let point = triangle.p0 + triangle.edge1 * b1 + triangle.edge2 * b2;
                self.sample_towards(p, point, triangle.normal, *area)
            }
            EmitterShape::Sphere { centre, radius } => {
                let to_centre = *centre - p;
                let d2 = to_centre.length_squared();
                let r2 = radius * radius;
                if d2 <= r2 * 1.0001 {
                    // From inside (or on) the sphere: sample its area uniformly.
                    let n = uniform_sphere(u);
                    let point = *centre + n * *radius;
                    let to_light = point - p;
                    let distance = to_light.length();
                    let wi = to_light / distance.max(1e-12);
                    let cos_light = -wi.dot(n);
                    if cos_light <= 0.0 {
                        return None;
                    }
                    return Some(LightSample {
                        wi,
                        distance,
                        radiance: self.radiance,
                        pdf: distance * distance / (cos_light * self.area()),
                        delta: false,
                    });
                }
                // Sample the cone the sphere subtends (pbrt-v3 §14.2.3).
                let cos_max = (1.0 - r2 / d2).max(0.0).sqrt();
                let axis = to_centre / d2.sqrt();
                let (t, b) = axis.any_orthonormal_pair();
                let local = uniform_cone(u, cos_max);
                let wi = (t * local.x + b * local.y + axis * local.z).normalize_or(axis);
                // Distance to the near intersection of the ray with the sphere.
                let along = to_centre.dot(wi);
                let distance = along - (r2 - (d2 - along * along)).max(0.0).sqrt();
                Some(LightSample {
                    wi,
                    distance,
                    radiance: self.radiance,
                    pdf: uniform_cone_pdf(cos_max),
                    delta: false,
                })
            }
        }
    }

    /// The sample of `point` on a flat emitter of unit `normal` and total `area`, chosen
    /// uniformly by area, seen from `p`: density distance^2 / (cos_light area) per solid angle.
    #[inline]
    fn sample_towards(&self, p: Vec3, point: Vec3, normal: Vec3, area: f32) -> Option<LightSample> {
        let to_light = point - p;
        let distance = to_light.length();
        if distance <= 0.0 {
            return None;
        }
        let wi = to_light / distance;
        let cos_light = -wi.dot(normal);
        if cos_light <= 0.0 {
            return None;
        }
        Some(LightSample {
            wi,
            distance,
            radiance: self.radiance,
            pdf: distance * distance / (cos_light * area),
            delta: false,
        })
    }

    /// Solid-angle density of `sample` from `p` choosing the emitter point `point` with
    /// geometric normal `normal` (the point a BSDF-sampled ray hit).
    pub fn pdf(&self, p: Vec3, point: Vec3, normal: Vec3) -> f32 {
        match &self.shape {
            EmitterShape::Parallelogram(EmitterParallelogram { area, .. })
            | EmitterShape::Triangles { area, .. } => {
                let to_light = point - p;
                let d2 = to_light.length_squared();
                let cos_light = (-to_light.normalize_or_zero()).dot(normal);
                if cos_light <= 0.0 {
                    0.0
                } else {
                    d2 / (cos_light * area)
                }
            }
            EmitterShape::Sphere { centre, radius } => {
                let d2 = (*centre - p).length_squared();
                let r2 = radius * radius;
                if d2 <= r2 * 1.0001 {
                    let to_light = point - p;
                    let cos_light = (-to_light.normalize_or_zero()).dot(normal).abs().max(1e-6);
                    to_light.length_squared() / (cos_light * self.area())
                } else {
                    uniform_cone_pdf((1.0 - r2 / d2).max(0.0).sqrt())
                }
            }
        }
    }
}

/// An emitting triangle as its samples use it: a corner, the edges from it and the unit
/// normal, computed once rather than at every light sample.
#[derive(Clone, Debug)]
struct EmitterTriangle {
    p0: Vec3,
    edge1: Vec3,
    edge2: Vec3,
    normal: Vec3,
}

impl EmitterTriangle {
    fn new(&[p0, p1, p2]: &[Vec3; 3]) -> Self {
        let (edge1, edge2) = (p1 - p0, p2 - p0);
        Self {
            p0,
            edge1,
            edge2,
            normal: edge1.cross(edge2).normalize_or_zero(),
        }
    }
}

/// A parallelogram emitter: `corner` + s `edge1` + t `edge2` for s, t in [0, 1], its unit
/// normal (the triangles' winding) and area. Mitsuba 3 samples its rectangles so
/// (`rectangle.cpp`, `sample_position`: a uniform point of the square, mapped affinely).
#[derive(Clone, Debug)]
struct EmitterParallelogram {
    corner: Vec3,
    edge1: Vec3,
    edge2: Vec3,
    normal: Vec3,
    area: f32,
}

impl EmitterParallelogram {
    /// The parallelogram two triangles make when they share an edge (their diagonal, by the
    /// same two vertices), lie in one plane facing one way, and the corners opposite the
    /// diagonal are its mirror images through the diagonal's midpoint (q + r = s + t, to 1e-5
    /// of the size); `None` otherwise.
    fn new(first: &[Vec3; 3], second: &[Vec3; 3]) -> Option<Self> {
        let shared: Vec<Vec3> = first
            .iter()
            .filter(|v| second.contains(v))
            .copied()
            .collect();
        let [s, t] = shared.as_slice() else {
            return None;
        };
        let opposite =
            |triangle: &[Vec3; 3]| triangle.iter().find(|v| !shared.contains(v)).copied();
        let (q, r) = (opposite(first)?, opposite(second)?);
        let (edge1, edge2) = (*s - q, *t - q);
        let size = edge1.length().max(edge2.length());
        let (n1, n2) = (
            EmitterTriangle::new(first).normal,
            EmitterTriangle::new(second).normal,
        );
        let area = edge1.cross(edge2).length();
        let is_parallelogram = (q + r - *s - *t).length() <= 1e-5 * size
            && n1.dot(n2) > 1.0 - 1e-5
            && area.is_finite()
            && area > 0.0;
        is_parallelogram.then_some(Self {
            corner: q,
            edge1,
            edge2,
            normal: n1,
            area,
        })
    }
}

fn triangle_area(t: &[Vec3; 3]) -> f32 {
    0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::PathRng;

    /// A rectangle as two triangles sharing the diagonal (1, 3), as a mesh loader writes it.
    fn rectangle() -> [[Vec3; 3]; 2] {
        let (p0, p1, p2, p3) = (
            Vec3::new(-0.5, -0.25, 2.0),
            Vec3::new(0.5, -0.25, 2.0),
            Vec3::new(0.5, 0.75, 2.0),
            Vec3::new(-0.5, 0.75, 2.0),
        );
        [[p0, p1, p3], [p1, p2, p3]]
    }

    fn as_triangles(corners: &[[Vec3; 3]]) -> AreaLight {
        let areas: Vec<f32> = corners.iter().map(triangle_area).collect();
        AreaLight {
            radiance: Vec3::ONE,
            shape: EmitterShape::Triangles {
                triangles: corners.iter().map(EmitterTriangle::new).collect(),
                by_area: AliasTable::new(&areas),
                area: areas.iter().sum(),
            },
        }
    }

    #[test]
    fn parallelograms_are_found_and_other_pairs_are_not() {
        let [first, second] = rectangle();
        let found = EmitterParallelogram::new(&first, &second).expect("a rectangle");
        assert!((found.area - 1.0).abs() < 1e-6);
        assert!((found.normal - first_normal(&first)).length() < 1e-6);
        // A kite: the corner opposite the diagonal is not the mirror image of the other.
        let mut kite = second;
        kite[1] += Vec3::new(0.3, 0.1, 0.0);
        assert!(EmitterParallelogram::new(&first, &kite).is_none());
        // Folded along the diagonal: not one plane.
        let mut folded = second;
        folded[1].z += 0.2;
        assert!(EmitterParallelogram::new(&first, &folded).is_none());
        // Wound the other way: its normal faces away.
        let flipped = [second[0], second[2], second[1]];
        assert!(EmitterParallelogram::new(&first, &flipped).is_none());
        // No shared edge.
        let apart = second.map(|v| v + Vec3::X * 3.0);
        assert!(EmitterParallelogram::new(&first, &apart).is_none());
    }

    fn first_normal(t: &[Vec3; 3]) -> Vec3 {
        (t[1] - t[0]).cross(t[2] - t[0]).normalize()
    }

    /// Sampled as one parallelogram or as its two triangles, the light's samples estimate the
    /// same solid angle (the mean of 1 / pdf) from a point that sees it obliquely, each density
    /// agrees with `pdf` at the sampled point, and every point lies on the rectangle. The bound
    /// is five standard errors of the difference of the two means.
    #[test]
    fn parallelogram_samples_match_the_triangles() {
        let corners = rectangle();
        let triangles = as_triangles(&corners);
        let parallelogram = AreaLight {
            radiance: Vec3::ONE,
            shape: EmitterShape::Parallelogram(
                EmitterParallelogram::new(&corners[0], &corners[1]).unwrap(),
            ),
        };
        let p = Vec3::new(0.9, -0.6, 2.7);
        let normal = first_normal(&corners[0]);
        let n = 200_000;
        let estimate = |light: &AreaLight, seed: u64| {
            let mut rng = PathRng::new(seed, 0, 0);
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let sample = light.sample(p, rng.next_2d()).expect("the light faces p");
                let point = p + sample.wi * sample.distance;
                assert!(
                    point.x.abs() <= 0.5 + 1e-5 && (-0.25 - 1e-5..=0.75 + 1e-5).contains(&point.y)
                );
                let pdf = light.pdf(p, point, normal);
                assert!((pdf - sample.pdf).abs() <= 1e-3 * pdf);
                let x = f64::from(1.0 / sample.pdf);
                sum += x;
                sum2 += x * x;
            }
            let mean = sum / n as f64;
            (mean, (sum2 / n as f64 - mean * mean) / n as f64)
        };
        let (a, var_a) = estimate(&parallelogram, 1);
        let (b, var_b) = estimate(&triangles, 2);
        assert!(
            (a - b).abs() <= 5.0 * (var_a + var_b).sqrt(),
            "{a} against {b}"
        );
    }
}
