//! LuxRender's `disk` and `cylinder` (its `shapes/disk.cpp`, `shapes/cylinder.cpp`, after pbrt
//! v1), tessellated into triangle meshes with the quadrics' own uv and orientation.
//!
//! - Disk: in the plane z = `height`, radii `innerradius` to `radius`, angles 0 to `phimax`
//!   degrees; u = phi / phimax, v = 1 - (r - innerradius) / (radius - innerradius). Its normal
//!   dp/du x dp/dv is +z (dp/du is along +phi, dp/dv points to the centre).
//! - Cylinder: radius `radius` about the z axis from `zmin` to `zmax`, angles 0 to `phimax`;
//!   u = phi / phimax, v = (z - zmin) / (zmax - zmin); its normal dp/du x dp/dv points out.
//!
//! Triangles are wound so that (b - a) x (c - a) is that normal (foton's emitting side). The
//! polygons keep the quadrics' areas exactly, so an emitting disk or cylinder keeps its power:
//! a wedge of angle t between chords has area r² sin(t) / 2 against the sector's r² t / 2, so
//! the disk's rings are pushed out by sqrt(t / sin t); a cylinder's facet has width
//! 2 r sin(t / 2) against the arc's r t, so its radius grows by (t / 2) / sin(t / 2).

use glam::{Vec2, Vec3};

use crate::scene::desc::Geometry;

/// Segments of a full turn; fewer for a partial one (at least 3 for any).
const SEGMENTS_PER_TURN: f32 = 128.0;

/// The number of angular segments and the angle each spans, for `phimax` in radians.
fn segments(phi_max: f32) -> (u32, f32) {
    let count = (SEGMENTS_PER_TURN * phi_max / std::f32::consts::TAU)
        .ceil()
        .max(3.0) as u32;
    (count, phi_max / count as f32)
}

/// The `count + 1` edges of `count` segments of angle `step`: u (0 to 1), cos phi, sin phi.
fn segment_edges(count: u32, step: f32) -> impl Iterator<Item = (f32, f32, f32)> {
    (0..=count).map(move |i| {
        let (sin, cos) = (i as f32 * step).sin_cos();
        (i as f32 / count as f32, cos, sin)
    })
}

/// `sqrt(t / sin t)`, the factor that gives chord wedges of angle `t` the area of their sectors.
fn wedge_area_scale(t: f32) -> f32 {
    (t / t.sin()).sqrt()
}

/// A disk or annulus (LuxRender's `disk`); `phi_max` in radians, in (0, 2 pi].
pub fn disk(height: f32, radius: f32, inner_radius: f32, phi_max: f32) -> Geometry {
    let (count, step) = segments(phi_max);
    let scale = wedge_area_scale(step);
    let (outer, inner) = (radius * scale, inner_radius * scale);
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    let mut indices = Vec::new();
    // For each segment edge i: the outer vertex 2i and the inner vertex 2i + 1. A full disk's
    // centre is one point but gets a vertex per edge, so that u interpolates per segment.
    for (u, cos, sin) in segment_edges(count, step) {
        positions.push(Vec3::new(outer * cos, outer * sin, height));
        positions.push(Vec3::new(inner * cos, inner * sin, height));
        uvs.push(Vec2::new(u, 0.0));
        uvs.push(Vec2::new(u, 1.0));
    }
    for i in 0..count {
        let (outer_a, inner_a, outer_b, inner_b) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
        // (outer_b - outer_a) runs along +phi, (inner_b - outer_a) towards the centre: their
        // cross product is +z.
        indices.push([outer_a, outer_b, inner_b]);
        if inner_radius > 0.0 {
            indices.push([outer_a, inner_b, inner_a]);
        }
    }
    Geometry::TriangleMesh {
        positions,
        normals: None,
        uvs: Some(uvs),
        indices,
    }
}

/// An open cylinder about z (LuxRender's `cylinder`); `phi_max` in radians, in (0, 2 pi].
/// Shading normals are the true cylinder's, so it looks round at any tessellation.
pub fn cylinder(radius: f32, z_min: f32, z_max: f32, phi_max: f32) -> Geometry {
    let (count, step) = segments(phi_max);
    let half = 0.5 * step;
    let facet_radius = radius * half / half.sin();
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    let mut indices = Vec::new();
    // For each segment edge i: the bottom vertex 2i and the top vertex 2i + 1.
    for (u, cos, sin) in segment_edges(count, step) {
        for (z, v) in [(z_min, 0.0), (z_max, 1.0)] {
            positions.push(Vec3::new(facet_radius * cos, facet_radius * sin, z));
            normals.push(Vec3::new(cos, sin, 0.0));
            uvs.push(Vec2::new(u, v));
        }
    }
    for i in 0..count {
        let (bottom_a, top_a, bottom_b, top_b) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
        // (bottom_b - bottom_a) runs along +phi, (top_b - bottom_a) has +z: their cross
        // product points out.
        indices.push([bottom_a, bottom_b, top_b]);
        indices.push([bottom_a, top_b, top_a]);
    }
    Geometry::TriangleMesh {
        positions,
        normals: Some(normals),
        uvs: Some(uvs),
        indices,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::{PI, TAU};

    /// Each triangle's area and its geometric normal (b - a) x (c - a), normalised.
    fn triangles(geometry: &Geometry) -> Vec<(f32, Vec3, [u32; 3])> {
        let Geometry::TriangleMesh {
            positions, indices, ..
        } = geometry
        else {
            panic!("a mesh");
        };
        indices
            .iter()
            .map(|&[a, b, c]| {
                let [pa, pb, pc] = [a, b, c].map(|i| positions[i as usize]);
                let cross = (pb - pa).cross(pc - pa);
                (0.5 * cross.length(), cross.normalize(), [a, b, c])
            })
            .collect()
    }

    #[test]
    fn disk_faces_up_with_the_area_and_uv_of_luxrenders() {
        for (inner, phi_max) in [(0.0, TAU), (0.5, TAU), (0.0, PI / 2.0), (1.0, 1.0)] {
            let (radius, height) = (2.0, 0.3);
            let disk = disk(height, radius, inner, phi_max);
            let area: f32 = triangles(&disk).iter().map(|t| t.0).sum();
            let expected = 0.5 * phi_max * (radius * radius - inner * inner);
            assert!(
                (area / expected - 1.0).abs() < 1e-4,
                "area {area} {expected}"
            );
            for (_, normal, _) in triangles(&disk) {
                assert!((normal - Vec3::Z).length() < 1e-4, "normal {normal}");
            }
            let Geometry::TriangleMesh { positions, uvs, .. } = &disk else {
                unreachable!()
            };
            for (p, uv) in positions.iter().zip(uvs.as_ref().unwrap()) {
                assert_eq!(p.z, height);
                let phi = p.y.atan2(p.x).rem_euclid(TAU);
                let r = p.truncate().length();
                if r > 1e-3 && uv.x > 1e-6 && uv.x < 1.0 - 1e-6 {
                    assert!((phi / phi_max - uv.x).abs() < 1e-4, "u {uv} at phi {phi}");
                }
                // v = 1 - (r - ri) / (radius - ri), on the polygon's pushed-out rings.
                let scale = r / if uv.y == 0.0 { radius } else { inner.max(1e-9) };
                if uv.y == 0.0 || inner > 0.0 {
                    assert!((scale - 1.0).abs() < 0.01, "ring radius {r} at v {}", uv.y);
                }
            }
        }
    }

    #[test]
    fn cylinder_faces_out_with_the_area_and_uv_of_luxrenders() {
        for phi_max in [TAU, PI] {
            let (radius, z_min, z_max) = (1.5, -0.5, 2.0);
            let cylinder = cylinder(radius, z_min, z_max, phi_max);
            let area: f32 = triangles(&cylinder).iter().map(|t| t.0).sum();
            let expected = (z_max - z_min) * phi_max * radius;
            assert!(
                (area / expected - 1.0).abs() < 1e-4,
                "area {area} {expected}"
            );
            let Geometry::TriangleMesh { positions, uvs, .. } = &cylinder else {
                unreachable!()
            };
            for (_, normal, [a, b, c]) in triangles(&cylinder) {
                let centre =
                    (positions[a as usize] + positions[b as usize] + positions[c as usize]) / 3.0;
                let outward = centre.truncate().extend(0.0).normalize();
                assert!(normal.dot(outward) > 0.99, "normal {normal} at {centre}");
            }
            for (p, uv) in positions.iter().zip(uvs.as_ref().unwrap()) {
                assert!((uv.y - (p.z - z_min) / (z_max - z_min)).abs() < 1e-6);
                let phi = p.y.atan2(p.x).rem_euclid(TAU);
                if uv.x > 1e-6 && uv.x < 1.0 - 1e-6 {
                    assert!((phi / phi_max - uv.x).abs() < 1e-4, "u {uv} at phi {phi}");
                }
            }
        }
    }
}
