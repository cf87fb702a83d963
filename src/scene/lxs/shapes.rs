//! `Shape`: spheres, disks, cylinders, triangle meshes (inline or PLY), and the course's planes
//! and boxes.

use glam::{Vec2, Vec3};

use super::params::ParamList;
use super::parser::Parser;
use super::quadrics;
use crate::scene::desc::{Geometry, SceneError, ShapeDesc};
use crate::scene::io::ply;

impl Parser {
    /// Adds a shape with the current transform, material and area light.
    pub(super) fn shape(
        &mut self,
        kind: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<(), SceneError> {
        let geometry = match kind {
            "sphere" => {
                let radius = params.float("radius")?.unwrap_or(1.0);
                if radius <= 0.0 {
                    return Err(
                        self.error(line, format!("sphere: radius {radius} must be positive"))
                    );
                }
                Geometry::Sphere { radius }
            }
            "disk" => {
                let height = params.float("height")?.unwrap_or(0.0);
                let radius = params.float("radius")?.unwrap_or(1.0);
                let inner_radius = params.float("innerradius")?.unwrap_or(0.0);
                let phi_max = self.phi_max(line, params)?;
                if !(0.0 <= inner_radius && inner_radius < radius) {
                    return Err(self.error(
                        line,
                        format!("disk: need 0 <= innerradius ({inner_radius}) < radius ({radius})"),
                    ));
                }
                quadrics::disk(height, radius, inner_radius, phi_max)
            }
            "cylinder" => {
                let radius = params.float("radius")?.unwrap_or(1.0);
                let z0 = params.float("zmin")?.unwrap_or(-1.0);
                let z1 = params.float("zmax")?.unwrap_or(1.0);
                let phi_max = self.phi_max(line, params)?;
                if radius <= 0.0 || z0 == z1 {
                    return Err(self.error(
                        line,
                        format!("cylinder: radius {radius} must be positive and zmin {z0} differ from zmax {z1}"),
                    ));
                }
                quadrics::cylinder(radius, z0.min(z1), z0.max(z1), phi_max)
            }
            "trianglemesh" | "mesh" => match self.inline_mesh(kind, line, params)? {
                Some(mesh) => mesh,
                None => return Ok(()),
            },
            "plymesh" => {
                let filename = params
                    .string("filename")?
                    .ok_or_else(|| self.error(line, "plymesh: \"filename\" missing"))?;
                let what = format!("plymesh \"{filename}\"");
                let path = self.resolve(&filename, line, &what)?;
                ply::read(&path)
                    .map_err(|e| self.error(line, format!("{what}: {}: {e}", path.display())))?
            }
            "plane" => {
                let normal = params.vec3("N")?.unwrap_or(Vec3::Z);
                let normal = normal
                    .try_normalize()
                    .ok_or_else(|| self.error(line, "plane: the normal is zero"))?;
                Geometry::Plane { normal }
            }
            "box" => {
                let size = Vec3::new(
                    params.float("width")?.unwrap_or(1.0),
                    params.float("height")?.unwrap_or(1.0),
                    params.float("depth")?.unwrap_or(1.0),
                );
                if size.min_element() <= 0.0 {
                    return Err(self.error(line, format!("box: size {size} must be positive")));
                }
                box_mesh(size)
            }
            _ => {
                self.warn(line, format!("Shape \"{kind}\" unsupported: skipped"));
                params.ignore_all();
                return Ok(());
            }
        };
        let geometry = if self.state.reverse_orientation {
            self.reversed(geometry, line)
        } else {
            geometry
        };
        let mut shape = ShapeDesc {
            geometry,
            object_to_world: self.state.ctm,
            material: self.material_between_volumes(self.state.material),
            area_light: None,
            location: self.location(line),
        };
        shape.area_light = self.state.area_light.map(|light| light.radiance(&shape));
        self.scene.shapes.push(shape);
        Ok(())
    }

    /// `trianglemesh`/`mesh`: `indices` (or `triindices`) and/or `quadindices`, `P`, optional
    /// `N` and `uv` (or `st`). LuxRender 1.x's `shapes/mesh.cpp` reads quads (4 indices each)
    /// beside triangles; foton splits each quad a b c d into a b c and a c d (the same surface
    /// for the planar convex quads LuxRender intersects as quadrilaterals; uvs are then
    /// interpolated per triangle, not bilinearly). A mesh without `P` or indices (LuxBlend
    /// writes such) is skipped with a warning.
    fn inline_mesh(
        &mut self,
        kind: &str,
        line: usize,
        params: &mut ParamList,
    ) -> Result<Option<Geometry>, SceneError> {
        let triangles = match params.indices("indices")? {
            Some(indices) => Some(indices),
            None => params.indices("triindices")?,
        };
        let quads = params.indices("quadindices")?;
        let positions = params.floats("P", 3)?;
        let normals = params.floats("N", 3)?;
        let uvs = match params.floats("uv", 2)? {
            Some(uvs) => Some(uvs),
            None => params.floats("st", 2)?,
        };
        let (Some(positions), true) = (positions, triangles.is_some() || quads.is_some()) else {
            self.warn(
                line,
                format!("{kind} without \"P\" or \"indices\": skipped"),
            );
            return Ok(None);
        };
        let (triangles, quads) = (triangles.unwrap_or_default(), quads.unwrap_or_default());
        let positions: Vec<Vec3> = positions.chunks_exact(3).map(Vec3::from_slice).collect();
        let count = positions.len();
        if triangles.len() % 3 != 0 {
            return Err(self.error(
                line,
                format!("{kind}: {} indices, not a multiple of 3", triangles.len()),
            ));
        }
        if quads.len() % 4 != 0 {
            return Err(self.error(
                line,
                format!("{kind}: {} quadindices, not a multiple of 4", quads.len()),
            ));
        }
        let split_quads = quads
            .chunks_exact(4)
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
        let indices: Vec<[u32; 3]> = (triangles.chunks_exact(3))
            .map(|t| [t[0], t[1], t[2]])
            .chain(split_quads)
            .collect();
        if let Some(&bad) = indices.iter().flatten().find(|&&i| i as usize >= count) {
            return Err(self.error(
                line,
                format!("{kind}: index {bad} out of range ({count} vertices)"),
            ));
        }
        let normals: Option<Vec<Vec3>> =
            normals.map(|n| n.chunks_exact(3).map(Vec3::from_slice).collect());
        let uvs: Option<Vec<Vec2>> =
            uvs.map(|uv| uv.chunks_exact(2).map(Vec2::from_slice).collect());
        if let Some(n) = normals.as_ref().filter(|n| n.len() != count) {
            return Err(self.error(
                line,
                format!("{kind}: {} normals for {count} vertices", n.len()),
            ));
        }
        if let Some(uv) = uvs.as_ref().filter(|uv| uv.len() != count) {
            return Err(self.error(
                line,
                format!("{kind}: {} uvs for {count} vertices", uv.len()),
            ));
        }
        Ok(Some(Geometry::TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
        }))
    }

    /// A quadric's `phimax` in radians: degrees, 360 by default, clamped to [0, 360] as
    /// LuxRender does; zero (nothing to draw) is an error.
    fn phi_max(&self, line: usize, params: &mut ParamList) -> Result<f32, SceneError> {
        let degrees = params.float("phimax")?.unwrap_or(360.0).clamp(0.0, 360.0);
        if degrees > 0.0 {
            Ok(degrees.to_radians())
        } else {
            Err(self.error(line, "phimax must be positive"))
        }
    }

    /// `ReverseOrientation`: flips which side faces out.
    fn reversed(&mut self, geometry: Geometry, line: usize) -> Geometry {
        match geometry {
            Geometry::TriangleMesh {
                positions,
                normals,
                uvs,
                indices,
            } => Geometry::TriangleMesh {
                positions,
                normals: normals.map(|n| n.into_iter().map(|n| -n).collect()),
                uvs,
                indices: indices.into_iter().map(|[a, b, c]| [a, c, b]).collect(),
            },
            Geometry::Plane { normal } => Geometry::Plane { normal: -normal },
            sphere @ Geometry::Sphere { .. } => {
                self.warn(
                    line,
                    "ReverseOrientation on a sphere is not supported: ignored",
                );
                sphere
            }
            // `Shape` makes no instances (`ObjectInstance` does), and no analytic disks (its
            // disks are tessellated: `quadrics`).
            other @ (Geometry::Instance { .. } | Geometry::Disk) => other,
        }
    }
}

/// A closed box of `size`, centred on the origin: 12 triangles wound counter-clockwise seen
/// from outside, so (b - a) x (c - a) points out.
fn box_mesh(size: Vec3) -> Geometry {
    // Corner i has x, y, z = bits 0, 1, 2 of i (0: -half, 1: +half).
    let positions = (0..8u32)
        .map(|i| {
            let sign = Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32);
            (sign * 2.0 - 1.0) * size * 0.5
        })
        .collect();
    let quads: [[u32; 4]; 6] = [
        [0, 4, 6, 2], // -x
        [1, 3, 7, 5], // +x
        [0, 1, 5, 4], // -y
        [2, 6, 7, 3], // +y
        [0, 2, 3, 1], // -z
        [4, 5, 7, 6], // +z
    ];
    let indices = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    Geometry::TriangleMesh {
        positions,
        normals: None,
        uvs: None,
        indices,
    }
}
