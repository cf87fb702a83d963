//! Scenes written for Mitsuba 0.4 to 1.x read as Mitsuba 3 reads them: its `upgrade_tree`
//! (src/core/xml.cpp) renames parameters from camelCase to snake_case (`intIOR` -> `int_ior`,
//! `fovAxis` -> `fov_axis`, `toWorld` -> `to_world`), `<lookAt>` to `<lookat>`, reserved ids
//! (a leading `_`), diffuse's `diffuse_reflectance` to `reflectance`, and texture `uoffset`,
//! `voffset`, `uscale`, `vscale` to a `to_uv` transform.

use super::dom::Element;
use super::error::{MitsubaError, MitsubaWarning};

/// A `major.minor.patch` version.
pub type Version = (u32, u32, u32);

/// Reads a `version` attribute: three numbers separated by periods.
pub fn parse_version(el: &Element, text: &str) -> Result<Version, MitsubaError> {
    let parts: Vec<_> = text
        .split(['.', ' '])
        .filter(|p| !p.is_empty())
        .map(|p| p.parse::<u32>())
        .collect();
    match parts.as_slice() {
        [Ok(a), Ok(b), Ok(c)] => Ok((*a, *b, *c)),
        _ => Err(MitsubaError::new(
            &el.loc,
            format!(
                "could not parse version number \"{text}\" (expected three numbers such as 3.0.0)"
            ),
        )),
    }
}

/// Upgrades the tree under `root`, written for `version`, in place.
pub fn upgrade(root: &mut Element, version: Version, warnings: &mut Vec<MitsubaWarning>) {
    if version >= (2, 0, 0) {
        return;
    }
    upgrade_element(root, warnings);
}

fn upgrade_element(el: &mut Element, warnings: &mut Vec<MitsubaWarning>) {
    if el.name != "default"
        && let Some(name) = el.attr("name")
    {
        let snake = snake_case(name);
        el.set_attr("name", snake);
    }
    if el.name == "lookAt" {
        el.name = "lookat".to_string();
    }
    if let Some(id) = el.attr("id").filter(|id| id.starts_with('_')) {
        let renamed = format!("ID{id}__UPGR");
        warnings.push(MitsubaWarning {
            loc: el.loc.clone(),
            message: format!("reserved identifier \"{id}\" renamed to \"{renamed}\""),
        });
        el.set_attr("id", renamed);
    }
    let diffuse = el.name == "bsdf" && el.attr("type") == Some("diffuse");
    for child in &mut el.children {
        upgrade_element(child, warnings);
        if diffuse && child.attr("name") == Some("diffuse_reflectance") {
            child.set_attr("name", "reflectance".to_string());
        }
    }
    uv_transform(el);
}

/// Mitsuba's rule: before every lower-case letter followed by an upper-case one, an underscore,
/// and the run of upper-case letters after it in lower case (`intIOR` -> `int_ior`).
fn snake_case(name: &str) -> String {
    let mut chars: Vec<char> = name.chars().collect();
    let mut i = 0;
    while i + 1 < chars.len() {
        if chars[i].is_ascii_lowercase() && chars[i + 1].is_ascii_uppercase() {
            chars.insert(i + 1, '_');
            i += 2;
            while i < chars.len() && chars[i].is_ascii_uppercase() {
                chars[i] = chars[i].to_ascii_lowercase();
                i += 1;
            }
        }
        i += 1;
    }
    chars.into_iter().collect()
}

/// `<float name="uoffset">` and friends become `<transform name="to_uv">` with a translate, then a
/// scale, as Mitsuba's upgrade writes them.
fn uv_transform(el: &mut Element) {
    const NAMES: [&str; 4] = ["uoffset", "voffset", "uscale", "vscale"];
    let is_uv =
        |c: &Element| c.name == "float" && c.attr("name").is_some_and(|n| NAMES.contains(&n));
    if !el.children.iter().any(is_uv) {
        return;
    }
    let mut values = [0.0, 0.0, 1.0, 1.0];
    let mut loc = el.loc.clone();
    el.children.retain(|c| {
        if !is_uv(c) {
            return true;
        }
        let k = NAMES
            .iter()
            .position(|n| Some(*n) == c.attr("name"))
            .unwrap();
        // An unparsable value keeps the default; the conversion would not have read it either.
        values[k] = c
            .attr("value")
            .and_then(|v| v.trim().parse().ok())
            .unwrap_or(values[k]);
        loc = c.loc.clone();
        false
    });
    let op = |name: &str, x: f64, y: f64| Element {
        name: name.to_string(),
        attrs: vec![("x".into(), x.to_string()), ("y".into(), y.to_string())],
        children: Vec::new(),
        loc: loc.clone(),
    };
    let mut ops = Vec::new();
    if values[0] != 0.0 || values[1] != 0.0 {
        ops.push(op("translate", values[0], values[1]));
    }
    if values[2] != 1.0 || values[3] != 1.0 {
        ops.push(op("scale", values[2], values[3]));
    }
    el.children.push(Element {
        name: "transform".to_string(),
        attrs: vec![("name".into(), "to_uv".into())],
        children: ops,
        loc,
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camel_case_becomes_snake_case_as_mitsuba_does() {
        assert_eq!(snake_case("intIOR"), "int_ior");
        assert_eq!(snake_case("fovAxis"), "fov_axis");
        assert_eq!(snake_case("toWorld"), "to_world");
        assert_eq!(snake_case("sampleCount"), "sample_count");
        assert_eq!(snake_case("max_depth"), "max_depth");
        assert_eq!(snake_case("uvScale"), "uv_scale");
    }
}
