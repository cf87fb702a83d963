//! The LuxRender release a scene is read as (`src/scene/lxs/version.rs`): the exporter's
//! version comment, `-D lux_version`, and what changes for releases before 1.0.

use std::path::PathBuf;

use foton::scene::desc::{LightDesc, SceneDesc, ToneMap};
use foton::scene::lxs::load_with;
use glam::Vec3;

/// LuxRender's film units over foton's, from outside foton's code: 683 lm/W times the CIE 1931
/// y function's integral, 106.857 nm (360-830 nm; LuxRender's 380-720 nm holds all but 0.1%,
/// and foton's analytic fit of the function is within about 1%).
const PHOTOMETRIC: f32 = 683.0 * 106.857;

const BODY: &str = "
Film \"fleximage\" \"string tonemapkernel\" [\"reinhard\"] \"float reinhard_prescale\" [1]
    \"float reinhard_postscale\" [1.2] \"float reinhard_burn\" [6]
WorldBegin
LightSource \"point\" \"color L\" [1 0.5 0.25] \"float gain\" [2]
LightSource \"point\" \"color L\" [1 1 1] \"float power\" [60] \"float efficacy\" [15]
LightSource \"infinite\" \"color L\" [0.2 0.2 0.2] \"float gain\" [3]
AttributeBegin
AreaLightSource \"area\" \"color L\" [1 1 1] \"float power\" [100] \"float efficacy\" [17]
Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [0 0 0 1 0 0 0 1 0]
AttributeEnd
WorldEnd
";

fn load(name: &str, header: &str, defines: &[(&str, &str)]) -> SceneDesc {
    let dir = std::env::temp_dir().join(format!("foton-lxs-versions-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path: PathBuf = dir.join(format!("{name}.lxs"));
    std::fs::write(&path, format!("{header}{BODY}")).unwrap();
    let defines: Vec<(String, String)> = defines
        .iter()
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    load_with(&path, &defines).unwrap_or_else(|e| panic!("{e}"))
}

/// The first point light's intensity (gain alone), the second's (normalised by power), the
/// environment's radiance (gain alone) and the area light's radiance (normalised by power).
fn emissions(desc: &SceneDesc) -> [Vec3; 4] {
    let points: Vec<Vec3> = desc
        .lights
        .iter()
        .filter_map(|l| match l {
            LightDesc::Point { intensity, .. } => Some(*intensity),
            _ => None,
        })
        .collect();
    let environment = desc
        .lights
        .iter()
        .find_map(|l| match l {
            LightDesc::Infinite { radiance, .. } => Some(*radiance),
            _ => None,
        })
        .expect("the infinite light");
    let area = desc
        .shapes
        .iter()
        .find_map(|s| s.area_light.as_ref().map(|a| a.radiance))
        .expect("the area light");
    [points[0], points[1], environment, area]
}

fn is_absolute_reinhard(desc: &SceneDesc) -> bool {
    match desc.film.tonemap {
        ToneMap::ReinhardAbsolute {
            prescale,
            postscale,
            burn,
        } => {
            assert_eq!((prescale, postscale, burn), (1.0, 1.2, 6.0));
            true
        }
        ToneMap::Reinhard { .. } => false,
        other => panic!("{other:?}"),
    }
}

/// Each emission of `old` over `new`'s.
fn ratios(old: &SceneDesc, new: &SceneDesc) -> [f32; 4] {
    let (old, new) = (emissions(old), emissions(new));
    std::array::from_fn(|i| old[i].x / new[i].x)
}

#[test]
fn a_scene_exported_for_luxrender_0_6_is_read_as_0_x() {
    let new = load("final", "", &[]);
    assert!(!is_absolute_reinhard(&new));
    assert!(new.notes.is_empty(), "{:?}", new.notes);
    for header in [
        "# Lux Render v0.6RC6 Scene File\n# Exported by LuxBlend Blender Exporter\n",
        "# LuxRender v0.8 Scene File\n",
    ] {
        let old = load("old", header, &[]);
        assert!(is_absolute_reinhard(&old), "{header}");
        let [point, normalised_point, environment, normalised_area] = ratios(&old, &new);
        // Lights given by gain alone are in LuxRender's photometric film units; those
        // normalised by power keep their luminance power x efficacy / (pi area) (or / 4 pi).
        for ratio in [point, environment] {
            assert!((ratio / PHOTOMETRIC - 1.0).abs() < 0.01, "{ratio}");
        }
        assert_eq!([normalised_point, normalised_area], [1.0, 1.0]);
        assert_eq!(old.notes.len(), 1, "{:?}", old.notes);
        assert!(old.notes[0].contains("LuxRender 0."), "{}", old.notes[0]);
    }
    let final_header = load("one", "# LuxRender v1.6 Scene File\n", &[]);
    assert!(!is_absolute_reinhard(&final_header));
    assert_eq!(ratios(&final_header, &new), [1.0; 4]);
}

#[test]
fn lux_version_overrides_the_comment() {
    let new = load("override-final", "", &[]);
    let forced_new = load(
        "forced-new",
        "# Lux Render v0.6RC6 Scene File\n",
        &[("lux_version", "1.6")],
    );
    assert!(!is_absolute_reinhard(&forced_new));
    assert_eq!(ratios(&forced_new, &new), [1.0; 4]);
    assert!(forced_new.notes.is_empty(), "{:?}", forced_new.notes);
    assert!(forced_new.warnings.is_empty(), "{:?}", forced_new.warnings);

    let forced_old = load("forced-old", "", &[("lux_version", "0.6")]);
    assert!(is_absolute_reinhard(&forced_old));
    assert!((ratios(&forced_old, &new)[0] / PHOTOMETRIC - 1.0).abs() < 0.01);
    assert!(forced_old.notes[0].contains("-D lux_version"));

    // A value that is no version, and any other name, are warnings; the comment then rules.
    let bad = load(
        "bad",
        "# Lux Render v0.6RC6 Scene File\n",
        &[("lux_version", "new"), ("spp", "4")],
    );
    assert!(is_absolute_reinhard(&bad));
    let messages: Vec<&str> = bad.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(messages.len(), 2, "{messages:?}");
    assert!(messages[0].contains("lux_version=new") && messages[0].contains("not a version"));
    assert!(messages[1].contains("spp=4") && messages[1].contains("lux_version"));
}
