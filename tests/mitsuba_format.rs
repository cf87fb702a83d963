//! The Mitsuba format layer on the shared public scenes: every XML file parses, with no error, and
//! every mesh it names reads. Skipped where ../shared (or $FOTON_SHARED) is absent.

use crate::common;
use foton::scene::io::{obj, serialized};
use foton::scene::mitsuba::{self, Value};

/// The main file of each shared scene (SOURCES.md).
const SCENES: [&str; 9] = [
    "mdata-cbox/cbox.xml",
    "mdata-cbox/cbox-rgb.xml",
    "mdata-cbox/cbox-spectral.xml",
    "mdata-matpreview/matpreview.xml",
    "mdata-hello/scenes/hello.xml",
    "mdata-roughconductor-copper/docs/scenes/bsdf_roughconductor_copper.xml",
    "tut-cbox/scenes/cbox.xml",
    "bitterli-cornell-box/scene_v0.6.xml",
    "ppg-torus/scene.xml",
];

#[test]
fn shared_scenes_parse_and_their_meshes_read() {
    let Some(root) = common::shared_scene_folder("mitsuba") else {
        return;
    };
    for scene in SCENES {
        let tree = mitsuba::parse_file(&root.join(scene), &[])
            .unwrap_or_else(|err| panic!("{scene}: {err}"));
        let shapes: Vec<_> = tree.objects.iter().filter(|o| o.tag == "shape").collect();
        assert!(!shapes.is_empty(), "{scene}: no shapes");
        assert!(
            tree.objects.iter().any(|o| o.tag == "sensor"),
            "{scene}: no sensor"
        );
        for shape in shapes {
            let filename = match shape.prop("filename").map(|p| &p.value) {
                Some(Value::String(name)) => tree.resolve(name),
                _ => continue,
            };
            let mesh = match shape.plugin.as_str() {
                "obj" => obj::read_obj(&filename),
                "serialized" => {
                    let index = match shape.prop("shape_index").map(|p| &p.value) {
                        Some(Value::Integer(i)) => *i as usize,
                        _ => 0,
                    };
                    serialized::read_serialized(&filename, index)
                }
                _ => continue,
            }
            .unwrap_or_else(|err| panic!("{scene}: {err}"));
            let n = mesh.positions.len() as u32;
            assert!(!mesh.indices.is_empty(), "{scene}: {}", filename.display());
            assert!(mesh.indices.iter().flatten().all(|&i| i < n));
            for attr in [
                mesh.normals.as_ref().map(Vec::len),
                mesh.uvs.as_ref().map(Vec::len),
            ] {
                assert!(attr.is_none_or(|len| len == n as usize));
            }
        }
    }
}

#[test]
fn shared_scene_features_read_as_mitsuba_reads_them() {
    let Some(root) = common::shared_scene_folder("mitsuba") else {
        return;
    };
    // Version 0.5: `toWorld` and `sampleCount` upgraded.
    let tree = mitsuba::parse_file(&root.join("bitterli-cornell-box/scene_v0.6.xml"), &[]).unwrap();
    let sensor = tree.objects.iter().find(|o| o.tag == "sensor").unwrap();
    assert!(sensor.prop("to_world").is_some());
    let sampler = tree.objects.iter().find(|o| o.tag == "sampler").unwrap();
    assert_eq!(
        sampler.prop("sample_count").unwrap().value,
        Value::Integer(64)
    );
    // `<path>` then `<include>` resolved against the scene's folder; `$spp` from the include's
    // default, overridden on the command line.
    let copper =
        root.join("mdata-roughconductor-copper/docs/scenes/bsdf_roughconductor_copper.xml");
    let tree = mitsuba::parse_file(&copper, &[("spp".into(), "8".into())]).unwrap();
    let sampler = tree.objects.iter().find(|o| o.tag == "sampler").unwrap();
    assert_eq!(
        sampler.prop("sample_count").unwrap().value,
        Value::Integer(8)
    );
    assert!(tree.resolve("textures/museum.exr").is_file());
    // `type="$integrator"` from a default.
    let torus = mitsuba::parse_file(&root.join("ppg-torus/scene.xml"), &[]).unwrap();
    let integrator = torus
        .objects
        .iter()
        .find(|o| o.tag == "integrator")
        .unwrap();
    assert_eq!(integrator.plugin, "path_guiding_integrator");
}
