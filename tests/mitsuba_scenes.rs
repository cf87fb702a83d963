//! Mitsuba scenes through `scene::load`: the seven shared public scenes load and render (skipped
//! where ../shared is absent), and the conversion's semantics on scenes written here.

use std::path::PathBuf;

use crate::common;
use foton::integrator::Renderer;
use foton::scene::build::{RenderOptions, build_world};
use foton::scene::desc::SceneDesc;
use glam::Vec3;

fn render(desc: SceneDesc, resolution: (u32, u32), spp: u32) -> Vec<Vec3> {
    render_seeded(desc, resolution, spp, 0)
}

fn render_seeded(desc: SceneDesc, resolution: (u32, u32), spp: u32, seed: u64) -> Vec<Vec3> {
    let options = RenderOptions {
        samples_per_pixel: Some(spp),
        resolution: Some(resolution),
        seed,
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

/// The mean and its standard error over the 8x8 pixels at the centre of a 40x20 image.
fn centre_mean(image: &[Vec3]) -> (f64, f64) {
    let values: Vec<f64> = (6..14)
        .flat_map(|y| (16..24).map(move |x| image[y * 40 + x].x as f64))
        .collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

#[test]
fn diffuse_is_black_from_the_back_unless_twosided() {
    // A diffuse quad (albedo 0.5) 5 units ahead filling the image's centre, its normal facing
    // away from the camera unless flipped, under a uniform sky of radiance 1: from its lit side it
    // is 0.5 (the albedo), from its back black in Mitsuba unless the BSDF is wrapped in twosided.
    let quad = |bsdf: &str, flip: bool| {
        format!(
            r#"<emitter type="constant"><rgb name="radiance" value="1"/></emitter>
            <shape type="rectangle"><boolean name="flip_normals" value="{flip}"/>
            <transform name="to_world"><translate z="5"/></transform>{bsdf}</shape>"#
        )
    };
    let diffuse = r#"<bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>"#;
    let twosided = format!(r#"<bsdf type="twosided">{diffuse}</bsdf>"#);
    let centre = |body: String| {
        let desc = foton::scene::load(&scene_with("x", &body)).unwrap();
        centre_mean(&render(desc, (40, 20), 16))
    };
    let (back, _) = centre(quad(diffuse, false));
    assert_eq!(back, 0.0, "one-sided diffuse seen from the back");
    for (what, body) in [
        ("twosided from the back", quad(&twosided, false)),
        ("one-sided from the front", quad(diffuse, true)),
    ] {
        let (mean, error) = centre(body);
        assert!(
            (mean - 0.5).abs() < 4.0 * error + 1e-4,
            "{what}: {mean} +- {error}, expected 0.5"
        );
    }
}

#[test]
fn hide_emitters_hides_what_the_camera_sees_directly() {
    // Under a sky of 0.25, behind an invisible (null) sheet: an emitting quad on the image's left
    // (x = +1.5), a diffuse one on its right. Mitsuba 3.9 with hide_emitters drops every camera
    // path whose first surface is an emitter (its reflection too) and those leaving unscattered;
    // light reflected by the diffuse quad stays.
    let scene = |hide: bool| {
        format!(
            r#"<integrator type="path"><boolean name="hide_emitters" value="{hide}"/></integrator>
            <emitter type="constant"><rgb name="radiance" value="0.25"/></emitter>
            <shape type="rectangle"><bsdf type="null"/>
            <transform name="to_world"><scale value="3"/><translate z="2"/></transform></shape>
            <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="4"/></emitter>
            <transform name="to_world"><scale value="0.5"/><rotate y="1" angle="180"/>
            <translate x="1.5" z="5"/></transform></shape>
            <shape type="rectangle"><bsdf type="twosided"><bsdf type="diffuse"/></bsdf>
            <transform name="to_world"><scale value="0.5"/><translate x="-1.5" z="5"/></transform>
            </shape>"#
        )
    };
    let render_with = |hide: bool| {
        let desc = foton::scene::load(&scene_with("x", &scene(hide))).unwrap();
        assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
        render(desc, (40, 20), 4)
    };
    let (sky, emitter, diffuse) = (0, 10 * 40 + 10, 10 * 40 + 30);
    let shown = render_with(false);
    assert!((shown[sky].x - 0.25).abs() < 1e-5, "sky {}", shown[sky]);
    assert!(shown[emitter].x >= 4.0, "emitter {}", shown[emitter]);
    let hidden = render_with(true);
    assert_eq!(hidden[sky], Vec3::ZERO, "sky through the null sheet");
    assert_eq!(
        hidden[emitter],
        Vec3::ZERO,
        "emitter through the null sheet"
    );
    assert!(hidden[diffuse].x > 0.01, "diffuse {}", hidden[diffuse]);
}

#[test]
fn instances_of_a_shapegroup_render_as_its_shapes_placed_one_by_one() {
    // A group of two meshes (a twosided red quad, a cube) and a sphere, placed three times, against
    // the same shapes written out with each member's transform followed by its instance's. The
    // two renders differ by noise only: their squared difference at different seeds is that of
    // two renders of the flattened scene (bounded at 1.25x: 800 pixels at 16 spp).
    let members = [
        (
            r#"type="rectangle""#,
            r#"<bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.2, 0.1"/></bsdf></bsdf>"#,
            r#"<scale value="0.5"/>"#,
        ),
        (
            r#"type="cube""#,
            "",
            r#"<scale value="0.3"/><translate x="0.6"/>"#,
        ),
        (
            r#"type="sphere""#,
            r#"<float name="radius" value="0.25"/>"#,
            r#"<translate y="0.6"/>"#,
        ),
    ];
    let placements = [
        r#"<rotate y="1" angle="30"/><translate x="-1.5" z="5"/>"#,
        r#"<scale value="1.2"/><translate x="1.2" z="6"/>"#,
        r#"<rotate x="1" angle="-40"/><translate y="0.3" z="4"/>"#,
    ];
    let sky = r#"<emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>"#;
    let shape = |(kind, inner, ops): &(&str, &str, &str), more: &str| {
        format!(
            r#"<shape {kind}>{inner}<transform name="to_world">{ops}{more}</transform></shape>"#
        )
    };
    let group: String = members.iter().map(|m| shape(m, "")).collect();
    let instanced: String = placements
        .iter()
        .map(|ops| {
            format!(
                r#"<shape type="instance"><ref id="group"/><transform name="to_world">{ops}</transform></shape>"#
            )
        })
        .collect();
    let instanced =
        format!(r#"{sky}<shape type="shapegroup" id="group">{group}</shape>{instanced}"#);
    let flattened: String = placements
        .iter()
        .flat_map(|ops| members.iter().map(move |m| shape(m, ops)))
        .collect();
    let flattened = format!("{sky}{flattened}");
    let render_seed = |body: &str, seed: u64| {
        let desc = foton::scene::load(&scene_with("x", body)).unwrap();
        assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
        render_seeded(desc, (40, 20), 16, seed)
    };
    let desc = foton::scene::load(&scene_with("x", &instanced)).unwrap();
    assert_eq!(desc.shape_groups.len(), 1);
    assert_eq!(desc.shape_groups[0].len(), 3);
    let squared_difference = |a: &[Vec3], b: &[Vec3]| -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (*x - *y).length_squared() as f64)
            .sum::<f64>()
            / a.len() as f64
    };
    let (flat1, flat2) = (render_seed(&flattened, 1), render_seed(&flattened, 2));
    let noise = squared_difference(&flat1, &flat2);
    let instances = render_seed(&instanced, 1);
    let difference = squared_difference(&instances, &flat2);
    assert!(noise > 0.0);
    assert!(
        difference < 1.25 * noise,
        "instanced vs flattened {difference}, flattened at two seeds {noise}"
    );
}
