//! Mitsuba scenes through `scene::load`: the seven shared public scenes load and render (skipped
//! where ../shared is absent), and the conversion's semantics on scenes written here.

mod common;

use std::path::PathBuf;

use foton::integrator::Renderer;
use foton::scene::build::{RenderOptions, build_world};
use foton::scene::desc::SceneDesc;
use glam::Vec3;

fn render(desc: SceneDesc, resolution: (u32, u32), spp: u32) -> Vec<Vec3> {
    let options = RenderOptions {
        samples_per_pixel: Some(spp),
        resolution: Some(resolution),
        ..RenderOptions::default()
    };
    let (world, _) = build_world(desc, &options);
    let mut renderer = Renderer::new(world);
    renderer.render(|_| true);
    renderer.image()
}

#[test]
fn the_seven_shared_scenes_load_and_render() {
    let Some(root) = common::shared_scene_folder("mitsuba") else {
        return;
    };
    for scene in [
        "mdata-cbox/cbox.xml",
        "mdata-matpreview/matpreview.xml",
        "mdata-hello/scenes/hello.xml",
        "mdata-roughconductor-copper/docs/scenes/bsdf_roughconductor_copper.xml",
        "tut-cbox/scenes/cbox.xml",
        "bitterli-cornell-box/scene_v0.6.xml",
        "ppg-torus/scene.xml",
    ] {
        let desc = foton::scene::load(&root.join(scene)).unwrap_or_else(|e| panic!("{e}"));
        for w in &desc.warnings {
            eprintln!("{w}");
        }
        assert!(!desc.shapes.is_empty(), "{scene}");
        let image = render(desc, (32, 24), 4);
        assert!(
            image.iter().all(|p| p.is_finite()),
            "{scene}: non-finite pixels"
        );
        let mean = image.iter().sum::<Vec3>() / image.len() as f32;
        assert!(mean.max_element() > 1e-3, "{scene}: black image ({mean})");
    }
}

fn write(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("foton-mitsuba-scenes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

const SENSOR: &str = r#"<sensor type="perspective">
        <float name="fov" value="60"/><string name="fov_axis" value="$axis"/>
        <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="20"/>
        <rfilter type="box"/></film></sensor>"#;

fn scene_with(axis: &str, body: &str) -> PathBuf {
    let text = format!(
        "<scene version=\"3.0.0\"><default name=\"axis\" value=\"{axis}\"/>{SENSOR}{body}</scene>"
    );
    write(&format!("{axis}-{}.xml", body.len()), &text)
}

#[test]
fn fov_axis_gives_the_field_of_view_of_the_shorter_side() {
    // 40x20 film, 60 degrees along the named axis: the shorter (y) side's field of view follows
    // tan(fy / 2) = tan(30 deg) * 20 / axis length.
    for (axis, len) in [
        ("x", 40.0f32),
        ("y", 20.0),
        ("smaller", 20.0),
        ("larger", 40.0),
        ("diagonal", 40f32.hypot(20.0)),
    ] {
        let desc = foton::scene::load(&scene_with(axis, "")).unwrap();
        assert!(desc.camera.kind.names.contains(&"perspective"));
        let fov_degrees = desc.camera.fov_degrees;
        let expected = 2.0 * (30f32.to_radians().tan() * 20.0 / len).atan().to_degrees();
        assert!(
            (fov_degrees - expected).abs() < 1e-3,
            "{axis}: {fov_degrees} vs {expected}"
        );
    }
}

#[test]
fn the_image_is_not_mirrored() {
    // Looking down +z with y up, world +x is to the viewer's left (Mitsuba's camera x = up x
    // forward = +x points to the image's left): a glowing sphere at x = 1.5 shows on the left half.
    let body = r#"<shape type="sphere"><point name="center" x="1.5" y="0" z="5"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>"#;
    let image = render(
        foton::scene::load(&scene_with("x", body)).unwrap(),
        (40, 20),
        4,
    );
    let half = |left: bool| -> f32 {
        (0..20)
            .flat_map(|y| (0..20).map(move |x| (x + if left { 0 } else { 20 }, y)))
            .map(|(x, y)| image[y * 40 + x].x)
            .sum()
    };
    assert!(
        half(true) > 10.0 * half(false).max(1e-6),
        "left {} right {}",
        half(true),
        half(false)
    );
}

#[test]
fn max_depth_counts_as_mitsuba_counts() {
    for (mitsuba, foton) in [("1", 0u32), ("2", 1), ("6", 5)] {
        let path = scene_with(
            "x",
            &format!(
                r#"<integrator type="path"><integer name="max_depth" value="{mitsuba}"/></integrator>"#
            ),
        );
        assert_eq!(foton::scene::load(&path).unwrap().max_depth, Some(foton));
    }
    let unlimited = foton::scene::load(&scene_with("x", r#"<integrator type="path"/>"#)).unwrap();
    assert!(unlimited.max_depth.unwrap() >= 1000);
}

#[test]
fn unknown_plugins_warn_and_missing_meshes_are_errors_naming_file_and_line() {
    // SENSOR spans lines 1 to 5; the body's elements follow on lines 6 and 7.
    let body = "\n<shape type=\"teapot\"/>\n<shape type=\"sphere\"><bsdf type=\"diffuse\"><float name=\"wobble\" value=\"1\"/></bsdf></shape>";
    let desc = foton::scene::load(&scene_with("x", body)).unwrap();
    let warnings: Vec<_> = desc.warnings.iter().map(ToString::to_string).collect();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("\"teapot\"") && w.contains(":6:1:")),
        "{warnings:?}"
    );
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("\"wobble\"") && w.contains(":7:")),
        "{warnings:?}"
    );
    let path = scene_with(
        "x",
        "\n\n<shape type=\"obj\"><string name=\"filename\" value=\"missing.obj\"/></shape>",
    );
    let err = foton::scene::load(&path).unwrap_err().to_string();
    assert!(
        err.contains("missing.obj") && err.contains(&format!("{}:7:1", path.display())),
        "{err}"
    );
    let broken = write(
        "broken.xml",
        "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n</scene>",
    );
    let err = foton::scene::load(&broken).unwrap_err().to_string();
    assert!(
        err.contains("broken.xml:3:") && err.contains("</scene>"),
        "{err}"
    );
}

#[test]
fn textured_reflectance_reaches_the_material() {
    // A twosided diffuse wall filling the view under a uniform sky of radiance 1, direct light
    // only (Mitsuba max_depth 2): each pixel is the reflectance, here a checkerboard whose two
    // colours are equal. Noise: MIS between cosine sampling (exact here) and uniform sky
    // sampling; the image mean of 800 pixels at 16 spp is well within 1%.
    let albedo = Vec3::new(0.25, 0.5, 0.75);
    let body = format!(
        r#"<integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
        <texture type="checkerboard" id="checks">
            <rgb name="color0" value="{0}, {1}, {2}"/><rgb name="color1" value="{0}, {1}, {2}"/>
        </texture>
        <shape type="rectangle">
            <transform name="to_world"><scale value="10"/><translate z="3"/></transform>
            <bsdf type="twosided"><bsdf type="diffuse"><ref name="reflectance" id="checks"/></bsdf></bsdf>
        </shape>"#,
        albedo.x, albedo.y, albedo.z
    );
    let image = render(
        foton::scene::load(&scene_with("x", &body)).unwrap(),
        (40, 20),
        16,
    );
    let mean = image.iter().copied().sum::<Vec3>() / image.len() as f32;
    assert!(
        ((mean - albedo) / albedo).abs().max_element() < 0.01,
        "mean {mean} against the reflectance {albedo}"
    );
}
