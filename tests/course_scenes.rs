//! foton's images of the course's scenes against the one LuxRender render the course kept.

use crate::common::{self, correlation, downsample};
use foton::film::{exposure_scale, read_png_linear};
use foton::integrator::Renderer;
use foton::scene::build::{RenderOptions, build_world, tone_map};
use glam::Vec3;

/// `metal2_scene` as foton renders it (tone-mapped as the scene asks, clamped to display
/// range) has the structure of LuxRender's render: the floor, the two rough metal spheres with
/// their highlights, their soft shadows, in the same places. Compared as luminance on a
/// 24 x 13.5-pixel grid of blocks, where LuxRender's and foton's noise average out.
#[test]
fn metal2_scene_looks_like_luxrenders_render() {
    let Some(itba) = common::shared_scenes() else {
        return;
    };
    let desc = foton::scene::load(&itba.join("metal2_scene/untitled.lxs")).expect("metal2 loads");
    let (film_gamma, tonemap) = (desc.film.gamma, desc.film.tonemap);
    let (w, h) = (240usize, 135usize);
    let options = RenderOptions {
        samples_per_pixel: Some(32),
        max_depth: Some(4),
        resolution: Some((w as u32, h as u32)),
        ..RenderOptions::default()
    };
    let mut renderer = Renderer::new(build_world(desc, &options).0);
    renderer.render(|_| true);
    let ours = renderer.image();
    let scale = exposure_scale(tone_map(tonemap), &ours, film_gamma);
    let display: Vec<Vec3> = ours
        .iter()
        .map(|p| (*p * scale).clamp(Vec3::ZERO, Vec3::ONE))
        .collect();

    let reference_path = itba.join("metal2_scene/untitled.Scene.00001.png");
    let (rw, rh, reference) = read_png_linear(&reference_path).expect("LuxRender's render");
    assert_eq!((rw, rh), (960, 540));
    let ours_blocks = downsample(&display, w, h, 10);
    let reference_blocks = downsample(&reference, 960, 540, 40);
    let mirrored: Vec<Vec3> = (0..w * h)
        .map(|i| display[(i / w) * w + w - 1 - i % w])
        .collect();
    let mirrored_blocks = downsample(&mirrored, w, h, 10);

    let r = correlation(&ours_blocks, &reference_blocks);
    let r_mirrored = correlation(&mirrored_blocks, &reference_blocks);
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let brightness = mean(&ours_blocks) / mean(&reference_blocks);
    println!("correlation {r:.3} (mirrored {r_mirrored:.3}), brightness ratio {brightness:.3}");
    // Measured: 0.972 (its mirror image: 0.430), brightness 0.92 of LuxRender's at 32 spp.
    assert!(r > 0.93, "correlation with LuxRender's render {r}");
    assert!(
        r_mirrored < 0.8,
        "the test must tell a mirrored image apart: {r_mirrored}"
    );
    assert!(
        (0.8..1.2).contains(&brightness),
        "brightness ratio {brightness}"
    );
}
