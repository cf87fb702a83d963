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
            EmitterShape::Triangles { area, .. } => *area,
            EmitterShape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
        }
    }

    pub fn power(&self) -> f32 {
        PI * self.area() * luminance(self.radiance)
    }

    pub fn sample(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        match &self.shape {
            EmitterShape::Triangles {
                triangles,
                by_area,
                area,
            } => {
                let (index, _, remapped) = by_area.sample(u.x);
                let triangle = &triangles[index];
                let (b1, b2) = uniform_triangle(Vec2::new(remapped, u.y));
                let point = triangle.p0 + triangle.edge1 * b1 + triangle.edge2 * b2;
                let normal = triangle.normal;
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

    /// Solid-angle density of `sample` from `p` choosing the emitter point `point` with
    /// geometric normal `normal` (the point a BSDF-sampled ray hit).
    pub fn pdf(&self, p: Vec3, point: Vec3, normal: Vec3) -> f32 {
        match &self.shape {
            EmitterShape::Triangles { area, .. } => {
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

fn triangle_area(t: &[Vec3; 3]) -> f32 {
    0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length()
}
