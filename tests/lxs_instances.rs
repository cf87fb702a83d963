//! LuxRender's `ObjectBegin`/`ObjectInstance` as instances of shared meshes: the same image as
//! the shapes written out one by one, in less memory.

use std::fmt::Write;

use crate::common;
use foton::integrator::Renderer;
use foton::scene::build::{RenderOptions, build_world};
use foton::shape::geometry::SceneGeometry;
use foton::shared::Shared;
use glam::Vec3;

/// A UV sphere of radius 0.4 as an inline `trianglemesh` with smooth normals and uvs (u around,
/// v from pole to pole): shading it with face normals or barycentric uvs shows.
fn sphere_mesh(rings: usize, segments: usize) -> String {
    let mut points = String::new();
    let mut normals = String::new();
    let mut uvs = String::new();
    for i in 0..=rings {
        for j in 0..=segments {
            let (u, v) = (j as f32 / segments as f32, i as f32 / rings as f32);
            let (theta, phi) = (v * std::f32::consts::PI, u * std::f32::consts::TAU);
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            let p = n * 0.4;
            write!(points, "{} {} {} ", p.x, p.y, p.z).unwrap();
            write!(normals, "{} {} {} ", n.x, n.y, n.z).unwrap();
            write!(uvs, "{u} {v} ").unwrap();
        }
    }
    let mut indices = String::new();
    let at = |i: usize, j: usize| i * (segments + 1) + j;
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            write!(indices, "{a} {b} {c} {a} {c} {d} ").unwrap();
        }
    }
    format!(
        "Shape \"trianglemesh\" \"integer indices\" [{indices}] \"point P\" [{points}] \
         \"normal N\" [{normals}] \"float uv\" [{uvs}]\n"
    )
}

/// The object: a checkered smooth sphere and a small emitting quad above it.
fn object_shapes() -> String {
    format!(
        "AttributeBegin\nMaterial \"matte\" \"texture Kd\" \"checks\"\n{}AttributeEnd\n\
         AttributeBegin\nAreaLightSource \"area\" \"color L\" [4 4 4]\nMaterial \"matte\"\n\
         Shape \"trianglemesh\" \"integer indices\" [0 2 1 0 3 2] \
         \"point P\" [-0.1 -0.1 0.6 0.1 -0.1 0.6 0.1 0.1 0.6 -0.1 0.1 0.6]\nAttributeEnd\n",
        sphere_mesh(6, 8)
    )
}

/// Where the instances go: rotations, a non-uniform scale, translations.
const PLACEMENTS: [&str; 6] = [
    "Translate -1 0 0.5\nRotate 30 0 0 1",
    "Translate 0 0 0.5\nRotate 70 1 0 0",
    "Translate 1 0 0.5\nScale 1 1.3 0.8",
    "Translate -0.5 1 0.5\nRotate -40 0 1 0",
    "Translate 0.5 1 0.5\nScale 1.2 1.2 1.2",
    "Translate 0 -1 0.5\nRotate 120 0 0 1\nRotate 20 1 0 0",
];

fn scene_text(instanced: bool) -> String {
    let mut text = String::from(
        "LookAt 0 -4 3  0 0 0.3  0 0 1\nCamera \"perspective\" \"float fov\" [45]\n\
         SurfaceIntegrator \"directlighting\"\nWorldBegin\n\
         Texture \"checks\" \"color\" \"checkerboard\" \"float uscale\" [8] \"float vscale\" [4] \
         \"color tex1\" [0.9 0.2 0.1] \"color tex2\" [0.1 0.3 0.8]\n\
         LightSource \"point\" \"point from\" [2 -3 4] \"color L\" [20 20 20]\n\
         Material \"matte\"\nShape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \
         \"point P\" [-5 -5 0 5 -5 0 5 5 0 -5 5 0]\n",
    );
    if instanced {
        text += &format!("ObjectBegin \"thing\"\n{}ObjectEnd\n", object_shapes());
    }
    for placement in PLACEMENTS {
        let shapes = if instanced {
            "ObjectInstance \"thing\"\n".to_string()
        } else {
            object_shapes()
        };
        text += &format!("AttributeBegin\n{placement}\n{shapes}AttributeEnd\n");
    }
    text + "WorldEnd\n"
}

/// Renders the scene (instanced or written out) at `seed`; returns the image and the bytes its
/// geometry holds (the BVH and the per-triangle shading data).
fn render(instanced: bool, seed: u64) -> (Vec<Vec3>, usize, Vec<String>) {
    let dir = common::temp_dir("lxs-instances");
    let path = dir.join(format!("instanced-{instanced}.lxs"));
    std::fs::write(&path, scene_text(instanced)).unwrap();
    let desc = foton::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
    let notes = desc.notes.clone();
    let options = RenderOptions {
        resolution: Some((64, 48)),
        seed,
        ..common::options(16, 4)
    };
    let (world, _) = build_world(desc, &options);
    let mut renderer = Renderer::new(world);
    let g = renderer.world.resource::<Shared<SceneGeometry>>();
    let bytes = g.accel.stats().bytes
        + size(&g.triangles)
        + size(&g.triangle_normals)
        + size(&g.triangle_uvs)
        + g.meshes.iter().map(|m| size(m)).sum::<usize>()
        + g.mesh_normals.iter().map(|m| size(m)).sum::<usize>()
        + g.mesh_uvs.iter().map(|m| size(m)).sum::<usize>()
        + size(&g.instances)
        + size(&g.instance_normal_matrices)
        + size(&g.material)
        + size(&g.emitter);
    renderer.render(|_| true);
    (renderer.image(), bytes, notes)
}

fn size<T>(items: &[T]) -> usize {
    std::mem::size_of_val(items)
}

/// The instanced scene renders as the written-out one within noise. Each pixel's squared
/// difference to an independent render (another seed) of the written-out scene has the same
/// expectation whether the first image is instanced or written out (the variance of both
/// renders plus the squared bias, zero if they agree); so the mean over pixels of the paired
/// difference d = |I - F2|^2 - |F1 - F2|^2 must be within four of its standard errors of 0.
/// The geometry of six instances holds less than half the bytes of six copies.
#[test]
fn object_instances_render_as_their_copies_in_less_memory() {
    let (flat1, flat_bytes, _) = render(false, 1);
    let (flat2, _, _) = render(false, 2);
    let (instanced, instanced_bytes, notes) = render(true, 1);
    assert_eq!(
        notes,
        [
            "6 ObjectInstance of 1 objects: 6 shapes placed as instances of shared shapes, \
          6 emitting shapes copied (the instance level emits no light)"
        ]
    );
    let d: Vec<f64> = (instanced.iter().zip(&flat1).zip(&flat2))
        .map(|((i, f1), f2)| f64::from((*i - *f2).length_squared() - (*f1 - *f2).length_squared()))
        .collect();
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let variance = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let standard_error = (variance / n).sqrt();
    let noise = flat1
        .iter()
        .zip(&flat2)
        .map(|(a, b)| f64::from((*a - *b).length_squared()));
    let noise = noise.sum::<f64>() / n;
    eprintln!(
        "paired difference {mean:.3e} (standard error {standard_error:.3e}, noise {noise:.3e}); \
         geometry bytes instanced {instanced_bytes}, written out {flat_bytes}"
    );
    assert!(standard_error > 0.0);
    assert!(
        mean.abs() < 4.0 * standard_error,
        "instanced vs written out: {mean:.3e}, standard error {standard_error:.3e}"
    );
    assert!(
        2 * instanced_bytes < flat_bytes,
        "instanced {instanced_bytes} bytes, written out {flat_bytes}"
    );
}
