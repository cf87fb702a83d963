//! Tests of the format layer: one per feature, on scenes written here.

use std::path::Path;

use glam::{DMat4, DVec3};

use super::*;

fn parse(text: &str) -> Result<SceneTree, MitsubaError> {
    parse_str(text, Path::new("/nonexistent/t.xml"), &[])
}

fn scene(body: &str) -> SceneTree {
    parse(&format!("<scene version=\"3.0.0\">\n{body}\n</scene>")).unwrap()
}

fn first<'a>(tree: &'a SceneTree, tag: &str) -> &'a Object {
    tree.objects.iter().find(|o| o.tag == tag).unwrap()
}

#[test]
fn objects_properties_and_locations() {
    let tree = scene(
        "<shape type=\"sphere\" id=\"ball\">\n  <float name=\"radius\" value=\"2.5\"/>\n  \
         <integer name=\"n\" value=\"-3\"/>\n  <boolean name=\"flip_normals\" value=\"True\"/>\n  \
         <string name=\"s\" value=\"hi\"/>\n  <point name=\"center\" x=\"1\" z=\"3\"/>\n  \
         <vector name=\"d\" value=\"1, 2, 3\"/>\n  <rgb name=\"c\" value=\"0.5\"/>\n</shape>",
    );
    let shape = first(&tree, "shape");
    assert_eq!(
        (shape.plugin.as_str(), shape.id.as_deref()),
        ("sphere", Some("ball"))
    );
    assert_eq!((shape.loc.line, shape.loc.column), (2, 1));
    assert_eq!(shape.prop("radius").unwrap().value, Value::Float(2.5));
    assert_eq!(shape.prop("radius").unwrap().loc.line, 3);
    assert_eq!(shape.prop("n").unwrap().value, Value::Integer(-3));
    assert_eq!(
        shape.prop("flip_normals").unwrap().value,
        Value::Boolean(true)
    );
    assert_eq!(shape.prop("s").unwrap().value, Value::String("hi".into()));
    assert_eq!(
        shape.prop("center").unwrap().value,
        Value::Point(DVec3::new(1.0, 0.0, 3.0))
    );
    assert_eq!(
        shape.prop("d").unwrap().value,
        Value::Vector(DVec3::new(1.0, 2.0, 3.0))
    );
    assert_eq!(
        shape.prop("c").unwrap().value,
        Value::Rgb(DVec3::splat(0.5))
    );
    assert_eq!(
        tree.ids["ball"],
        tree.objects.iter().position(|o| o.tag == "shape").unwrap()
    );
}

#[test]
fn bad_values_are_errors_with_location_and_text() {
    let err = parse("<scene version=\"3.0.0\">\n  <integrator type=\"path\">\n    <integer name=\"max_depth\" value=\"six\"/>\n  </integrator>\n</scene>")
        .unwrap_err();
    assert_eq!((err.loc.line, err.loc.column), (3, 5), "{err}");
    assert!(err.message.contains("\"six\""), "{err}");
    for bad in [
        "<float name=\"a\" value=\"1.2.3\"/>",
        "<boolean name=\"a\" value=\"yes\"/>",
        "<rgb name=\"a\" value=\"1 2\"/>",
        "<float name=\"a\"/>",
    ] {
        assert!(
            parse(&format!(
                "<scene version=\"3.0.0\"><bsdf type=\"diffuse\">{bad}</bsdf></scene>"
            ))
            .is_err(),
            "{bad}"
        );
    }
    assert!(
        parse("<scene><shape type=\"sphere\"/></scene>")
            .unwrap_err()
            .message
            .contains("version")
    );
}

#[test]
fn defaults_parameters_and_overrides() {
    let text = "<scene version=\"3.0.0\">\n<default name=\"spp\" value=\"16\"/>\n<default name=\"sp\" value=\"7\"/>\n\
                <sampler type=\"independent\"><integer name=\"sample_count\" value=\"$spp\"/>\
                <integer name=\"other\" value=\"$sp\"/></sampler></scene>";
    let tree = parse(text).unwrap();
    let sampler = first(&tree, "sampler");
    assert_eq!(
        sampler.prop("sample_count").unwrap().value,
        Value::Integer(16)
    );
    assert_eq!(sampler.prop("other").unwrap().value, Value::Integer(7));
    let defines = [("spp".to_string(), "4".to_string())];
    let tree = parse_str(text, Path::new("t.xml"), &defines).unwrap();
    assert_eq!(
        first(&tree, "sampler").prop("sample_count").unwrap().value,
        Value::Integer(4)
    );
    // The type attribute is substituted too; an undefined parameter is an error.
    let tree =
        scene("<default name=\"integrator\" value=\"path\"/><integrator type=\"$integrator\"/>");
    assert_eq!(first(&tree, "integrator").plugin, "path");
    let err = parse("<scene version=\"3.0.0\"><integer name=\"a\" value=\"$nope\"/></scene>")
        .unwrap_err();
    assert!(err.message.contains("$nope"), "{err}");
}

#[test]
fn refs_and_aliases_share_one_object() {
    let tree = scene(
        "<bsdf type=\"diffuse\" id=\"white\"/>\n<alias id=\"white\" as=\"paper\"/>\n\
         <texture type=\"checkerboard\" id=\"tex\"/>\n\
         <shape type=\"sphere\"><ref id=\"paper\"/></shape>\n\
         <bsdf type=\"diffuse\" id=\"d\"><ref name=\"reflectance\" id=\"tex\"/></bsdf>",
    );
    let shape = first(&tree, "shape");
    let (_, bsdf) = shape.children_tagged(&tree, "bsdf").next().unwrap();
    assert_eq!(bsdf.id.as_deref(), Some("white"));
    let d = &tree.objects[tree.ids["d"]];
    assert_eq!(
        d.named_child(&tree, "reflectance").unwrap().plugin,
        "checkerboard"
    );
    let err = parse(
        "<scene version=\"3.0.0\">\n<shape type=\"sphere\"><ref id=\"nothing\"/></shape></scene>",
    )
    .unwrap_err();
    assert!(
        err.message.contains("\"nothing\"") && err.loc.line == 2,
        "{err}"
    );
    let err = parse("<scene version=\"3.0.0\">\n<bsdf type=\"diffuse\" id=\"a\"/>\n<bsdf type=\"diffuse\" id=\"a\"/></scene>").unwrap_err();
    assert!(
        err.message.contains("duplicate id") && err.loc.line == 3,
        "{err}"
    );
}

#[test]
fn transforms_compose_in_document_order() {
    let tree = scene(
        "<shape type=\"sphere\"><transform name=\"to_world\">\
         <scale value=\"2\"/><rotate z=\"1\" angle=\"90\"/><translate x=\"1\" y=\"2\" z=\"3\"/>\
         </transform></shape>",
    );
    let Value::Transform(m) = first(&tree, "shape").prop("to_world").unwrap().value else {
        panic!()
    };
    // (1, 0, 0) scaled to (2, 0, 0), rotated to (0, 2, 0), translated to (1, 4, 3).
    assert!((m.transform_point3(DVec3::X) - DVec3::new(1.0, 4.0, 3.0)).length() < 1e-12);
    let tree = scene(
        "<sensor type=\"perspective\"><transform name=\"to_world\">\
         <lookat origin=\"0, 0, 4\" target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform></sensor>\
         <shape type=\"rectangle\"><transform name=\"to_world\">\
         <matrix value=\"1 0 0 5  0 1 0 0  0 0 1 0  0 0 0 1\"/><scale x=\"3\"/></transform></shape>",
    );
    let Value::Transform(cam) = first(&tree, "sensor").prop("to_world").unwrap().value else {
        panic!()
    };
    assert_eq!(cam.transform_point3(DVec3::ZERO), DVec3::new(0.0, 0.0, 4.0));
    let Value::Transform(rect) = first(&tree, "shape").prop("to_world").unwrap().value else {
        panic!()
    };
    assert_eq!(
        rect,
        DMat4::from_scale(DVec3::new(3.0, 1.0, 1.0)) * DMat4::from_translation(DVec3::X * 5.0)
    );
    assert!(
        parse(
            "<scene version=\"3.0.0\"><shape type=\"sphere\"><translate x=\"1\"/></shape></scene>"
        )
        .is_err()
    );
}

#[test]
fn spectra_constant_sampled_and_by_context() {
    let tree = scene(
        "<bsdf type=\"diffuse\"><spectrum name=\"reflectance\" value=\"0.5\"/>\
         <spectrum name=\"flat\" value=\"360:0.5, 830:0.5\"/></bsdf>\
         <emitter type=\"constant\"><spectrum name=\"radiance\" value=\"360:2, 830:2\"/></emitter>",
    );
    let bsdf = first(&tree, "bsdf");
    assert_eq!(
        bsdf.prop("reflectance").unwrap().value,
        Value::Spectrum(DVec3::splat(0.5))
    );
    let Value::Spectrum(flat) = bsdf.prop("flat").unwrap().value else {
        panic!()
    };
    let Value::Spectrum(emitted) = first(&tree, "emitter").prop("radiance").unwrap().value else {
        panic!()
    };
    // A flat reflectance reflects D65 unchanged (grey); flat emission is reddish and not clamped.
    assert!(
        (flat - DVec3::splat(0.5)).abs().max_element() < 2e-3,
        "{flat}"
    );
    assert!(emitted.x > 2.0 && emitted.z < 2.0, "{emitted}");
    assert!(parse("<scene version=\"3.0.0\"><bsdf type=\"diffuse\"><spectrum name=\"a\" value=\"500:1, 400:1\"/></bsdf></scene>").is_err());
}

#[test]
fn old_versions_are_upgraded() {
    let tree = scene_v05(
        "<sensor type=\"perspective\"><string name=\"fovAxis\" value=\"x\"/>\
         <transform name=\"toWorld\"><lookAt origin=\"0 0 1\" target=\"0 0 0\" up=\"0 1 0\"/></transform></sensor>\
         <bsdf type=\"dielectric\"><float name=\"intIOR\" value=\"1.5\"/></bsdf>\
         <bsdf type=\"diffuse\"><rgb name=\"diffuseReflectance\" value=\"0.2\"/></bsdf>\
         <texture type=\"checkerboard\"><float name=\"uscale\" value=\"4\"/></texture>\
         <default name=\"fooBar\" value=\"1\"/>",
    );
    let sensor = first(&tree, "sensor");
    assert!(sensor.prop("fov_axis").is_some() && sensor.prop("to_world").is_some());
    assert!(first(&tree, "bsdf").prop("int_ior").is_some());
    assert!(
        tree.objects
            .iter()
            .any(|o| o.plugin == "diffuse" && o.prop("reflectance").is_some())
    );
    let Value::Transform(uv) = first(&tree, "texture").prop("to_uv").unwrap().value else {
        panic!()
    };
    assert_eq!(uv.transform_point3(DVec3::ONE), DVec3::new(4.0, 1.0, 1.0));
}

fn scene_v05(body: &str) -> SceneTree {
    parse(&format!("<scene version=\"0.5.0\">{body}</scene>")).unwrap()
}

#[test]
fn unknown_elements_and_capitalised_plugins_are_warnings() {
    let tree = scene(
        "<shape type=\"Sphere\"/>\n<foo bar=\"1\"/>\n<bsdf type=\"diffuse\" colour=\"red\"/>",
    );
    assert_eq!(first(&tree, "shape").plugin, "sphere");
    let messages: Vec<_> = tree.warnings.iter().map(ToString::to_string).collect();
    assert!(
        messages
            .iter()
            .any(|m| m.contains(":2:1: warning") && m.contains("Sphere")),
        "{messages:?}"
    );
    assert!(
        messages
            .iter()
            .any(|m| m.contains(":3:1:") && m.contains("<foo>")),
        "{messages:?}"
    );
    assert!(
        messages.iter().any(|m| m.contains("colour")),
        "{messages:?}"
    );
}

#[test]
fn unused_parameters_are_listed() {
    let tree = scene(
        "<bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"1\"/><float name=\"x\" value=\"1\"/></bsdf>",
    );
    let bsdf = first(&tree, "bsdf");
    bsdf.prop("reflectance");
    let unused: Vec<_> = bsdf.unused().map(|(name, _)| name).collect();
    assert_eq!(unused, vec!["x"]);
}

#[test]
fn includes_and_paths_resolve_like_mitsuba() {
    let dir = std::env::temp_dir().join(format!("foton-mitsuba-include-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("common/frag")).unwrap();
    std::fs::write(
        dir.join("common/frag/mat.xml"),
        "<scene version=\"2.0.0\">\n<bsdf type=\"diffuse\" id=\"m\"/>\n</scene>",
    )
    .unwrap();
    std::fs::write(
        dir.join("common/frag/broken.xml"),
        "<scene version=\"3.0.0\">\n<bsdf type=\"diffuse\">\n</scene>",
    )
    .unwrap();
    let main = dir.join("main.xml");
    let text = "<scene version=\"3.0.0\">\n<path value=\"common\"/>\n<include filename=\"frag/mat.xml\"/>\n<shape type=\"sphere\"><ref id=\"m\"/></shape>\n</scene>";
    let tree = parse_str(text, &main, &[]).unwrap();
    assert_eq!(
        tree.objects[tree.ids["m"]].loc.file.as_path(),
        dir.join("common/frag/mat.xml")
    );
    assert_eq!(
        tree.resolve("frag/mat.xml"),
        dir.join("common/frag/mat.xml")
    );
    // A missing include names the file and the including line.
    let err = parse_str(
        "<scene version=\"3.0.0\">\n\n<include filename=\"nope.xml\"/>\n</scene>",
        &main,
        &[],
    )
    .unwrap_err();
    assert!(
        err.message.contains("nope.xml") && err.loc.line == 3,
        "{err}"
    );
    // An error inside an included file is located there, and says where it was included from.
    let err = parse_str("<scene version=\"3.0.0\">\n<path value=\"common\"/>\n<include filename=\"frag/broken.xml\"/>\n</scene>", &main, &[])
        .unwrap_err();
    assert!(
        err.loc.file.ends_with("broken.xml") && err.message.contains("main.xml:3:1"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sampled_spectra_match_mitsuba() {
    // Mitsuba 3.9.1 (scalar_rgb), `mi.traverse` of the loaded scene: the Cornell box's red wall and
    // light of mitsuba-data's scenes/cbox/cbox.xml, and its flat 0.78 from 400 to 700 nm.
    let red = "400:0.04, 404:0.046, 408:0.048, 412:0.053, 416:0.049, 420:0.05, 424:0.053, 428:0.055, 432:0.057, 436:0.056, 440:0.059, 444:0.057, 448:0.061, 452:0.061, 456:0.06, 460:0.062, 464:0.062, 468:0.062, 472:0.061, 476:0.062, 480:0.06, 484:0.059, 488:0.057, 492:0.058, 496:0.058, 500:0.058, 504:0.056, 508:0.055, 512:0.056, 516:0.059, 520:0.057, 524:0.055, 528:0.059, 532:0.059, 536:0.058, 540:0.059, 544:0.061, 548:0.061, 552:0.063, 556:0.063, 560:0.067, 564:0.068, 568:0.072, 572:0.08, 576:0.09, 580:0.099, 584:0.124, 588:0.154, 592:0.192, 596:0.255, 600:0.287, 604:0.349, 608:0.402, 612:0.443, 616:0.487, 620:0.513, 624:0.558, 628:0.584, 632:0.62, 636:0.606, 640:0.609, 644:0.651, 648:0.612, 652:0.61, 656:0.65, 660:0.638, 664:0.627, 668:0.62, 672:0.63, 676:0.628, 680:0.642, 684:0.639, 688:0.657, 692:0.639, 696:0.635, 700:0.642";
    let tree = scene(&format!(
        "<bsdf type=\"diffuse\" id=\"red\"><spectrum name=\"reflectance\" value=\"{red}\"/></bsdf>\
         <bsdf type=\"diffuse\" id=\"light\"><spectrum name=\"reflectance\" value=\"400:0.78, 500:0.78, 600:0.78, 700:0.78\"/></bsdf>\
         <emitter type=\"area\"><spectrum name=\"radiance\" value=\"400:0, 500:8, 600:15.6, 700:18.4\"/></emitter>"
    ));
    let get = |object: &Object, name: &str| match object.prop(name).unwrap().value {
        Value::Spectrum(v) => v,
        ref other => panic!("{other:?}"),
    };
    let cases = [
        (
            get(&tree.objects[tree.ids["red"]], "reflectance"),
            DVec3::new(0.49132, 0.0492281, 0.0509219),
        ),
        (
            get(&tree.objects[tree.ids["light"]], "reflectance"),
            DVec3::new(0.776367, 0.77981, 0.776029),
        ),
        (
            get(first(&tree, "emitter"), "radiance"),
            DVec3::new(20.7108, 10.8546, 2.77115),
        ),
    ];
    for (ours, mitsuba) in cases {
        // Mitsuba prints 6 significant digits and works in single precision.
        assert!(
            ((ours - mitsuba) / mitsuba).abs().max_element() < 2e-4,
            "{ours} vs {mitsuba}"
        );
    }
}

#[test]
fn reconstruction_filters_are_mitsubas() {
    use crate::scene::desc::FilterKind;
    let filter = |rfilter: &str| {
        let tree = scene(&format!(
            "<sensor type=\"perspective\"><film type=\"hdrfilm\">{rfilter}</film></sensor>"
        ));
        let desc = convert::to_scene(&tree).unwrap();
        assert!(desc.warnings.is_empty(), "{rfilter}: {:?}", desc.warnings);
        (desc.filter.kind, desc.filter.radius.x)
    };
    assert_eq!(
        filter("<rfilter type=\"tent\"><float name=\"radius\" value=\"1.5\"/></rfilter>"),
        (FilterKind::Triangle, 1.5)
    );
    assert_eq!(
        filter("<rfilter type=\"tent\"/>"),
        (FilterKind::Triangle, 1.0)
    );
    assert_eq!(
        filter("<rfilter type=\"mitchell\"/>"),
        (
            FilterKind::Mitchell {
                b: 1.0 / 3.0,
                c: 1.0 / 3.0
            },
            2.0
        )
    );
    assert_eq!(
        filter(
            "<rfilter type=\"mitchell\"><float name=\"B\" value=\"0.5\"/><float name=\"C\" value=\"0.25\"/></rfilter>"
        ),
        (FilterKind::Mitchell { b: 0.5, c: 0.25 }, 2.0)
    );
}

#[test]
fn unread_command_line_parameters_are_warnings() {
    let text = "<scene version=\"3.0.0\"><default name=\"spp\" value=\"4\"/>\
                <sampler type=\"independent\"><integer name=\"sample_count\" value=\"$spp\"/></sampler></scene>";
    let defines = [
        ("spp".to_string(), "8".to_string()),
        ("sp".to_string(), "2".to_string()),
    ];
    let tree = parse_str(text, Path::new("t.xml"), &defines).unwrap();
    let messages: Vec<_> = tree.warnings.iter().map(|w| w.message.clone()).collect();
    assert_eq!(messages.len(), 1, "{messages:?}");
    assert!(messages[0].contains("sp=2"), "{messages:?}");
}

#[test]
fn a_byte_order_mark_before_stray_text_is_an_error_not_a_panic() {
    // Found by the `xml` fuzzer: quick-xml skips the BOM, so its byte positions can fall inside
    // the mark's three bytes, where the text cannot be sliced.
    let result = std::panic::catch_unwind(|| {
        parse("\u{feff}eQ<?xml version=\"1.0\"?>\n<scene version=\"0.5.0\">\n</scene>").map(|_| ())
    });
    assert!(result.is_ok(), "parsing panicked");
}

/// Conductors keep their complex index (named from Mitsuba's table, or `eta`/`k`, or the
/// default eta 0, k 1) and their roughness (Mitsuba's default Beckmann alpha 0.1, or GGX and
/// anisotropic alphas), without a warning; an unknown distribution is one.
#[test]
fn conductors_keep_their_complex_index_and_distribution() {
    use crate::scene::desc::{MaterialDesc, MicrofacetDistribution, Roughness};
    use glam::Vec3;
    let conductor = |bsdf: &str| {
        let tree = scene(&format!(
            "<sensor type=\"perspective\"/><shape type=\"sphere\">{bsdf}</shape>"
        ));
        let desc = convert::to_scene(&tree).unwrap();
        let found = desc.materials.iter().find_map(|m| match m {
            MaterialDesc::Conductor {
                eta, k, roughness, ..
            } => Some((*eta, *k, *roughness)),
            _ => None,
        });
        (found.expect("a conductor"), desc.warnings)
    };
    let cu = conductors::CONDUCTORS
        .iter()
        .find(|(n, _, _)| *n == "Cu")
        .unwrap();
    let ((eta, k, roughness), warnings) =
        conductor("<bsdf type=\"roughconductor\"><string name=\"material\" value=\"Cu\"/></bsdf>");
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!((eta.to_array(), k.to_array()), (cu.1, cu.2));
    assert_eq!(
        roughness,
        Some(Roughness {
            distribution: MicrofacetDistribution::Beckmann,
            alpha_u: 0.1,
            alpha_v: 0.1
        })
    );
    let ((eta, k, roughness), _) = conductor("<bsdf type=\"conductor\"/>");
    assert_eq!((eta, k, roughness), (Vec3::ZERO, Vec3::ONE, None));
    let ((eta, k, roughness), warnings) = conductor(
        "<bsdf type=\"roughconductor\"><rgb name=\"eta\" value=\"0.2, 0.9, 1.1\"/>\
         <rgb name=\"k\" value=\"3.9, 2.4, 2.1\"/><string name=\"distribution\" value=\"ggx\"/>\
         <float name=\"alpha_u\" value=\"0.05\"/><float name=\"alpha_v\" value=\"0.3\"/></bsdf>",
    );
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(
        (eta, k),
        (Vec3::new(0.2, 0.9, 1.1), Vec3::new(3.9, 2.4, 2.1))
    );
    assert_eq!(
        roughness,
        Some(Roughness {
            distribution: MicrofacetDistribution::Ggx,
            alpha_u: 0.05,
            alpha_v: 0.3
        })
    );
    let (_, warnings) = conductor(
        "<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"phong\"/></bsdf>",
    );
    assert_eq!(warnings.len(), 1, "{warnings:?}");
}
