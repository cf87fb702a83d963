//! The public LuxRender scenes of `../shared/scenes/luxrender` (SOURCES.md there): what foton
//! reads of them.

mod common;

use foton::scene::desc::MaterialDesc;
use foton::texture::TextureNode;

/// The six scenes' main files: each loads without error.
const SCENES: [&str; 6] = [
    "bidir-simple/default.lxs",
    "bumpmapping/default.lxs",
    "dispersion/dispersion-random.lxs",
    "old-allmaterials/allmaterials.lxs",
    "small-test-26path/26path.lxs",
    "texture-examples/texture-examples.lxs",
];

#[test]
fn shared_luxrender_scenes_load() {
    let Some(root) = common::shared_scene_folder("luxrender") else {
        return;
    };
    for scene in SCENES {
        let desc = foton::scene::load(&root.join(scene)).unwrap_or_else(|e| panic!("{e}"));
        println!("{scene}: loads, {} warnings", desc.warnings.len());
    }
}

/// texture-examples.lxs drives six spheres with LuxRender's procedural textures: each
/// material's Kd is a node of the graph of the class the file names, not a grey stand-in.
#[test]
fn texture_examples_reads_its_procedural_textures() {
    let Some(root) = common::shared_scene_folder("luxrender") else {
        return;
    };
    let path = root.join("texture-examples/texture-examples.lxs");
    let desc = foton::scene::load(&path).expect("texture-examples loads");
    let graph = &desc.texture_graph;
    let has = |f: fn(&TextureNode) -> bool| graph.nodes.iter().any(f);
    assert!(has(|n| matches!(n, TextureNode::Checkerboard2D { .. })));
    assert!(has(|n| matches!(n, TextureNode::Checkerboard3D { .. })));
    assert!(has(|n| matches!(n, TextureNode::Fbm { .. })));
    assert!(has(|n| matches!(n, TextureNode::Dots { .. })));
    assert!(has(|n| matches!(n, TextureNode::Marble { .. })));
    assert!(has(|n| matches!(n, TextureNode::Harlequin)));
    let textured = desc
        .materials
        .iter()
        .filter(|m| {
            matches!(
                m,
                MaterialDesc::Diffuse {
                    reflectance: foton::scene::desc::ColorParam::Texture(_)
                }
            )
        })
        .count();
    assert_eq!(textured, 6);
    assert!(
        desc.warnings
            .iter()
            .all(|w| !w.message.contains("unsupported: constant grey")),
        "{:?}",
        desc.warnings
    );
}
