//! Mitsuba's `disk` as an analytic primitive: read as one, hit where the placed unit disk is,
//! with Mitsuba's uv (u = r, v = φ / 2π, `disk.cpp`) and its normal `Mx × My`.

use std::f32::consts::TAU;

use crate::common;
use foton::integrator::Renderer;
use foton::scene::build::{RenderOptions, build_world};
use foton::scene::desc::Geometry;
use foton::shape::geometry::SceneGeometry;
use foton::shared::Shared;
use glam::{Affine3A, Quat, Vec3};

/// A scene of one textured disk (so that its uv is kept) placed by `transform`, with
/// `flip_normals` as given.
fn disk_scene(transform: &str, flip: bool) -> std::path::PathBuf {
    let text = format!(
        r#"<scene version="3.0.0">
        <texture type="checkerboard" id="checks"/>
        <shape type="disk">
            <boolean name="flip_normals" value="{flip}"/>
            <transform name="to_world">{transform}</transform>
            <bsdf type="diffuse"><ref name="reflectance" id="checks"/></bsdf>
        </shape></scene>"#
    );
    let path = common::temp_dir("disk").join(format!("disk-{flip}.xml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Rays along the normal at object-space points (r cos φ, r sin φ, 0) of a disk scaled by 2,
/// rotated and moved: inside the rim (r < 1) each hits at the placed point, with uv (r, φ / 2π)
/// and the normal the rotation turns +z to; just outside (r = 1.01) nothing is hit.
#[test]
fn hits_give_mitsubas_uv_and_normal() {
    let (axis, angle, centre) = (Vec3::new(1.0, 0.0, 0.0), 90.0f32, Vec3::new(1.0, 3.5, 1.0));
    let transform = format!(
        r#"<scale value="2"/><rotate x="1" angle="{angle}"/><translate x="{}" y="{}" z="{}"/>"#,
        centre.x, centre.y, centre.z
    );
    let desc = foton::scene::load(&disk_scene(&transform, false)).unwrap();
    assert_eq!(desc.shapes[0].geometry, Geometry::Disk);
    let (world, _) = build_world(desc, &RenderOptions::default());
    // The renderer's startup systems build the geometry.
    let renderer = Renderer::new(world);
    let geometry = renderer.world.resource::<Shared<SceneGeometry>>();
    let to_world = Affine3A::from_scale_rotation_translation(
        Vec3::splat(2.0),
        Quat::from_axis_angle(axis, angle.to_radians()),
        centre,
    );
    let normal = Quat::from_axis_angle(axis, angle.to_radians()) * Vec3::Z;
    let mut hits = 0;
    for i in 0..40 {
        for (j, r) in [0.05f32, 0.4, 0.7, 0.99, 1.01].into_iter().enumerate() {
            let phi = TAU * (i as f32 + 0.3 * j as f32 + 0.1) / 40.0;
            let target = to_world.transform_point3(Vec3::new(r * phi.cos(), r * phi.sin(), 0.0));
            let origin = target + normal * 3.0;
            let hit = geometry
                .accel
                .closest_hit(origin, -normal, 0.0, f32::INFINITY);
            let Some(hit) = hit else {
                assert!(r > 1.0, "r {r}, φ {phi}: missed");
                continue;
            };
            assert!(r < 1.0, "r {r}, φ {phi}: hit outside the rim");
            hits += 1;
            let surface = geometry.surface_point(&hit, &origin, &-normal);
            assert!((surface.position - target).length() < 1e-5);
            assert!((surface.geometric_normal - normal).length() < 1e-6);
            assert!((surface.shading_normal - normal).length() < 1e-6);
            assert!(
                (surface.uv.x - r).abs() < 1e-5,
                "u {} for r {r}",
                surface.uv.x
            );
            // v is in [0, 1): φ = 2π is v = 0.
            let v = phi / TAU;
            let off = (surface.uv.y - v).rem_euclid(1.0);
            assert!(
                off.min(1.0 - off) < 1e-5,
                "v {} for φ / 2π {v}",
                surface.uv.y
            );
            assert!((0.0..1.0).contains(&surface.uv.y));
        }
    }
    assert_eq!(hits, 160);
}

/// `flip_normals` keeps the tessellated disk (its triangles turned over).
#[test]
fn flipped_disks_stay_meshes() {
    let desc = foton::scene::load(&disk_scene("", true)).unwrap();
    assert!(matches!(
        desc.shapes[0].geometry,
        Geometry::TriangleMesh { .. }
    ));
}
