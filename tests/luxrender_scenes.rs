//! The public LuxRender scenes of `../shared/scenes/luxrender` (SOURCES.md there): what foton
//! reads of them.

use crate::common::{self, correlation, downsample};
use foton::film::{apply_display_tone_map, exposure_scale, read_png_linear};
use foton::integrator::Renderer;
use foton::scene::build::{RenderOptions, build_world, tone_map};
use foton::scene::desc::MaterialDesc;
use foton::texture::TextureNode;
use glam::Vec3;

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

/// How foton's image of a scene compares with LuxRender's own render of it.
struct Agreement {
    /// Pearson correlation of block luminances (structure: what is where, how bright).
    correlation: f32,
    /// The same for foton's image mirrored left to right: what the test makes of an image with
    /// the same content in the wrong places.
    mirrored_correlation: f32,
    /// foton's mean luminance over LuxRender's.
    brightness: f32,
}

/// Renders `scene` at `width` x `height` (a divisor of LuxRender's resolution) and `spp`, tone
/// maps it as the scene's `Film` asks and clamps it to display range as LuxRender's 8-bit PNG
/// is, then compares `blocks_across` x (as many down) blocks of luminance with `reference`.
fn compare_with_luxrender(
    scene: &str,
    reference: &str,
    (width, height): (usize, usize),
    spp: u32,
    blocks_across: usize,
) -> Option<Agreement> {
    let root = common::shared_scene_folder("luxrender")?;
    let desc = foton::scene::load(&root.join(scene)).unwrap_or_else(|e| panic!("{e}"));
    let (gamma, tonemap) = (desc.film.gamma, tone_map(desc.film.tonemap));
    let options = RenderOptions {
        samples_per_pixel: Some(spp),
        resolution: Some((width as u32, height as u32)),
        ..RenderOptions::default()
    };
    let mut renderer = Renderer::new(build_world(desc, &options).0);
    renderer.render(|_| true);
    let mut ours = renderer.image();
    let scale = exposure_scale(tonemap, &ours, gamma);
    ours.iter_mut().for_each(|p| *p *= scale);
    apply_display_tone_map(tonemap, &mut ours, gamma);
    let ours: Vec<Vec3> = ours
        .iter()
        .map(|p| p.clamp(Vec3::ZERO, Vec3::ONE))
        .collect();
    let mirrored: Vec<Vec3> = (0..width * height)
        .map(|i| ours[(i / width) * width + width - 1 - i % width])
        .collect();

    let (rw, rh, theirs) = read_png_linear(&root.join(reference)).expect("LuxRender's render");
    let (rw, rh) = (rw as usize, rh as usize);
    assert_eq!(rw * height, rh * width, "{reference}: another aspect ratio");
    let factor = width / blocks_across;
    let reference_factor = rw / blocks_across;
    let ours_blocks = downsample(&ours, width, height, factor);
    let mirrored_blocks = downsample(&mirrored, width, height, factor);
    let reference_blocks = downsample(&theirs, rw, rh, reference_factor);
    assert_eq!(ours_blocks.len(), reference_blocks.len());
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let agreement = Agreement {
        correlation: correlation(&ours_blocks, &reference_blocks),
        mirrored_correlation: correlation(&mirrored_blocks, &reference_blocks),
        brightness: mean(&ours_blocks) / mean(&reference_blocks),
    };
    println!(
        "{scene}: correlation {:.3} (mirrored {:.3}), brightness ratio {:.3}",
        agreement.correlation, agreement.mirrored_correlation, agreement.brightness
    );
    Some(agreement)
}

/// The bar: block correlation at least 0.95, brightness within 10%; and the comparison
/// must tell the mirror image apart.
fn assert_matches(agreement: &Agreement) {
    assert!(
        agreement.correlation >= 0.95,
        "correlation {}",
        agreement.correlation
    );
    assert!(
        agreement.mirrored_correlation < agreement.correlation - 0.05,
        "the comparison cannot tell the mirror image apart: {}",
        agreement.mirrored_correlation
    );
    assert!(
        (0.9..=1.1).contains(&agreement.brightness),
        "brightness ratio {}",
        agreement.brightness
    );
}

/// bidir-simple: LuxRender's bidirectional render (Metropolis, 1024 spp) of a matte room lit by
/// a blackbody area light normalised by `power` and `efficacy`; foton path traces it. The file
/// was exported for LuxRender 0.6, so its Reinhard is LuxRender 0.x's, on absolute luminance
/// (`lxs::version`); LuxRender 1.x's gives correlation 0.88 and 3.3x the brightness.
#[test]
fn bidir_simple_looks_like_luxrenders_render() {
    if let Some(agreement) = compare_with_luxrender(
        "bidir-simple/default.lxs",
        "bidir-simple/reference-1024.png",
        (128, 96),
        64,
        16,
    ) {
        assert_matches(&agreement);
    }
}

/// bumpmapping: direct lighting (foton's ray caster) of bump-mapped matte surfaces under a
/// blackbody point light given by `gain` alone. Exported for LuxRender 0.6: LuxRender 0.x's
/// Reinhard on the film's photometric luminance (`lxs::version`); LuxRender 1.x's reading gives
/// 0.25x the brightness.
#[test]
fn bumpmapping_looks_like_luxrenders_render() {
    if let Some(agreement) = compare_with_luxrender(
        "bumpmapping/default.lxs",
        "bumpmapping/reference.png",
        (160, 120),
        16,
        16,
    ) {
        assert_matches(&agreement);
    }
}

/// texture-examples: six spheres with LuxRender's procedural textures on a matte disk, an
/// orthographic camera, a sphere light and a dim environment. It rests on the sphere light's
/// default 100 W x 17 lm/W (without it the sky drowns the light's shadows) and on `dots`'
/// swapped `inside`/`outside`.
/// Measured (200x300, 16 spp): correlation 0.999 (mirrored 0.109), brightness 1.015x.
#[test]
fn texture_examples_looks_like_luxrenders_render() {
    if let Some(agreement) = compare_with_luxrender(
        "texture-examples/texture-examples.lxs",
        "texture-examples/texture-examples.png",
        (200, 300),
        16,
        10,
    ) {
        assert_matches(&agreement);
    }
}
