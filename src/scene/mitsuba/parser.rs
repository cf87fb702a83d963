//! From the element tree of a Mitsuba XML file to the plugin tree, as Mitsuba 3's `parse_xml`
//! (src/core/xml.cpp) reads it: `$name` parameters (from `-D name=value`, then `<default>`),
//! `<include>`, `<path>`, `<alias>`, `<ref>`, typed properties and `<transform>` blocks.

use std::cell::Cell;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DMat4, DVec3};

use super::dom::{self, Element};
use super::error::{MitsubaError, MitsubaWarning, SourceLoc};
use super::spectrum::{self, SpectrumKind};
use super::transform;
use super::tree::{Child, Object, ObjectId, Property, SceneTree, Value, resolve_in};
use super::upgrade;

/// Mitsuba's `MI_XML_INCLUDE_MAX_RECURSION`.
const MAX_INCLUDE_DEPTH: usize = 15;

/// Elements that make an object (a plugin instance); `spectrum` too when it has a `type`.
const OBJECT_TAGS: [&str; 12] = [
    "shape",
    "bsdf",
    "emitter",
    "sensor",
    "film",
    "sampler",
    "rfilter",
    "integrator",
    "texture",
    "medium",
    "phase",
    "volume",
];

/// Parameters whose spectra may exceed 1 (Mitsuba's `is_unbounded_spectrum`).
const UNBOUNDED: [&str; 4] = ["eta", "k", "int_ior", "ext_ior"];

/// Reads the scene file at `path`. `defines` are `-D name=value` pairs: they take precedence over
/// the file's `<default>`s.
pub fn parse_file(path: &Path, defines: &[(String, String)]) -> Result<SceneTree, MitsubaError> {
    let file = Arc::new(path.to_path_buf());
    let text = std::fs::read_to_string(path).map_err(|err| {
        MitsubaError::new(&SourceLoc::new(&file, 1, 1), format!("cannot read: {err}"))
    })?;
    parse_str(&text, path, defines)
}

/// Reads scene `text` as if it were the file `path` (relative file names resolve next to it).
pub fn parse_str(
    text: &str,
    path: &Path,
    defines: &[(String, String)],
) -> Result<SceneTree, MitsubaError> {
    let file = Arc::new(path.to_path_buf());
    let mut warnings = Vec::new();
    let mut root = dom::parse_document(text, &file, &mut warnings)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut parser = Parser {
        objects: Vec::new(),
        ids: HashMap::new(),
        id_locs: HashMap::new(),
        params: defines.to_vec(),
        used_params: HashSet::new(),
        search_paths: vec![dir],
        warnings,
        refs: Vec::new(),
        include_depth: 0,
    };
    parser.substitute(&mut root)?;
    if root.name != "scene" {
        return Err(MitsubaError::new(
            &root.loc,
            format!("the root element is <{}>, not <scene>", root.name),
        ));
    }
    let version = root.attr("version").ok_or_else(|| {
        MitsubaError::new(
            &root.loc,
            "missing version attribute in root element <scene>",
        )
    })?;
    let version = upgrade::parse_version(&root, version)?;
    upgrade::upgrade(&mut root, version, &mut parser.warnings);
    let scene = parser.new_object("scene", "scene".into(), None, root.loc.clone());
    for child in &mut root.children {
        parser.element(child, scene, 1, path)?;
    }
    parser.resolve_refs()?;
    // Mitsuba 3.9 refuses a parameter the scene never reads ("Found unused parameters"); foton
    // warns and renders, as for any other unknown name.
    let scene_start = SourceLoc::new(&file, 1, 1);
    for (name, value) in defines {
        if !parser.used_params.contains(name) {
            parser.warn(
                &scene_start,
                format!("-D {name}={value}: the scene reads no parameter \"${name}\", ignored"),
            );
        }
    }
    Ok(SceneTree {
        objects: parser.objects,
        root: scene,
        ids: parser.ids,
        search_paths: parser.search_paths,
        warnings: parser.warnings,
    })
}

struct Parser {
    objects: Vec<Object>,
    ids: HashMap<String, ObjectId>,
    /// Where each id was given, for the duplicate-id error.
    id_locs: HashMap<String, SourceLoc>,
    params: Vec<(String, String)>,
    /// The parameters some `$name` read (the others given with -D are reported).
    used_params: HashSet<String>,
    search_paths: Vec<PathBuf>,
    warnings: Vec<MitsubaWarning>,
    /// `<ref>`s to resolve once every object is known: (parent, index in its children, id).
    refs: Vec<(ObjectId, usize, String)>,
    include_depth: usize,
}

impl Parser {
    fn warn(&mut self, loc: &SourceLoc, message: String) {
        self.warnings.push(MitsubaWarning {
            loc: loc.clone(),
            message,
        });
    }

    fn new_object(
        &mut self,
        tag: &str,
        plugin: String,
        id: Option<String>,
        loc: SourceLoc,
    ) -> ObjectId {
        self.objects.push(Object {
            tag: tag.to_string(),
            plugin,
            id,
            props: Vec::new(),
            children: Vec::new(),
            loc,
        });
        self.objects.len() - 1
    }

    /// Replaces `$name` in every attribute, longest names first (so that `$spp2` is not read as
    /// `$spp` followed by `2`). A `$` left over is an error.
    fn substitute(&mut self, el: &mut Element) -> Result<(), MitsubaError> {
        if !el.attrs.iter().any(|(_, v)| v.contains('$')) {
            return Ok(());
        }
        let mut params: Vec<_> = self.params.iter().collect();
        params.sort_by_key(|(name, _)| std::cmp::Reverse(name.len()));
        for (key, value) in &mut el.attrs {
            if !value.contains('$') {
                continue;
            }
            for (name, replacement) in &params {
                let reference = format!("${name}");
                if value.contains(&reference) {
                    *value = value.replace(&reference, replacement);
                    self.used_params.insert(name.to_string());
                }
            }
            if value.contains('$') {
                return Err(MitsubaError::new(
                    &el.loc,
                    format!(
                        "undefined parameter in {key}=\"{value}\" of <{}> (give it with -D name=value or <default>)",
                        el.name
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Reads `el`, a child of object `parent`, at `depth` (1: a child of the root scene), from file
    /// `file`.
    fn element(
        &mut self,
        el: &mut Element,
        parent: ObjectId,
        depth: usize,
        file: &Path,
    ) -> Result<(), MitsubaError> {
        self.substitute(el)?;
        let tag = el.name.as_str();
        if OBJECT_TAGS.contains(&tag) || (tag == "spectrum" && el.attr("type").is_some()) {
            return self.object(el, parent, file);
        }
        match tag {
            "ref" => {
                self.check_attrs(el, &["id", "name"]);
                let id = required(el, "id")?.to_string();
                let name = el.attr("name").map(str::to_string);
                let children = &mut self.objects[parent].children;
                children.push(Child {
                    name,
                    object: ObjectId::MAX,
                    loc: el.loc.clone(),
                    used: Cell::new(false),
                });
                self.refs.push((parent, children.len() - 1, id));
            }
            "default" => {
                self.check_attrs(el, &["name", "value"]);
                let name = required(el, "name")?;
                if name.is_empty() {
                    return Err(MitsubaError::new(&el.loc, "<default> with an empty name"));
                }
                let value = required(el, "value")?;
                if !self.params.iter().any(|(n, _)| n == name) {
                    self.params.push((name.to_string(), value.to_string()));
                }
            }
            "alias" => {
                self.check_attrs(el, &["id", "as"]);
                let (id, alias) = (required(el, "id")?, required(el, "as")?);
                let target = *self.ids.get(id).ok_or_else(|| {
                    MitsubaError::new(&el.loc, format!("<alias> of unknown id \"{id}\""))
                })?;
                self.register_id(alias, target, &el.loc)?;
            }
            "path" => {
                self.check_attrs(el, &["value"]);
                let value = required(el, "value")?;
                if depth != 1 {
                    return Err(MitsubaError::new(
                        &el.loc,
                        "<path> can only be a child of the root <scene>",
                    ));
                }
                self.add_path(value, file, &el.loc)?;
            }
            "include" => self.include(el, parent, depth)?,
            "transform" => {
                self.check_attrs(el, &["name"]);
                let name = required(el, "name")?.to_string();
                let mut matrix = DMat4::IDENTITY;
                for op in &mut el.children {
                    self.substitute(op)?;
                    matrix = self.transform_op(op)? * matrix;
                }
                self.set(parent, name, Value::Transform(matrix), &el.loc);
            }
            "translate" | "rotate" | "scale" | "lookat" | "matrix" => {
                return Err(MitsubaError::new(
                    &el.loc,
                    format!("<{tag}> outside a <transform>"),
                ));
            }
            "string" | "float" | "integer" | "boolean" | "point" | "vector" | "rgb"
            | "spectrum" => {
                let within_emitter = self.objects[parent].tag == "emitter";
                let (name, value) = self.property(el, within_emitter)?;
                self.set(parent, name, value, &el.loc);
            }
            _ => {
                let message = format!(
                    "unknown element <{tag}> in {} skipped",
                    self.objects[parent].describe()
                );
                self.warn(&el.loc, message);
            }
        }
        Ok(())
    }

    fn set(&mut self, object: ObjectId, name: String, value: Value, loc: &SourceLoc) {
        self.objects[object].props.push(Property {
            name,
            value,
            loc: loc.clone(),
            used: Cell::new(false),
        });
    }

    /// Attributes other than `allowed` are reported and ignored.
    fn check_attrs(&mut self, el: &Element, allowed: &[&str]) {
        let unknown: Vec<_> = el
            .attrs
            .iter()
            .filter(|(k, _)| !allowed.contains(&k.as_str()))
            .map(|(k, v)| format!("{k}=\"{v}\""))
            .collect();
        if !unknown.is_empty() {
            let message = format!(
                "unknown attribute {} of <{}> ignored",
                unknown.join(" "),
                el.name
            );
            self.warn(&el.loc, message);
        }
    }

    fn register_id(
        &mut self,
        id: &str,
        object: ObjectId,
        loc: &SourceLoc,
    ) -> Result<(), MitsubaError> {
        if id.starts_with('_') {
            return Err(MitsubaError::new(
                loc,
                format!("invalid id \"{id}\": a leading underscore is reserved"),
            ));
        }
        if let Some(previous) = self.id_locs.get(id) {
            return Err(MitsubaError::new(
                loc,
                format!("duplicate id \"{id}\" (first given at {previous})"),
            ));
        }
        self.ids.insert(id.to_string(), object);
        self.id_locs.insert(id.to_string(), loc.clone());
        Ok(())
    }

    fn object(
        &mut self,
        el: &mut Element,
        parent: ObjectId,
        file: &Path,
    ) -> Result<(), MitsubaError> {
        self.check_attrs(el, &["type", "id", "name"]);
        let written = required(el, "type")?;
        let plugin = written.to_lowercase();
        if plugin != written {
            let message = format!("plugin name \"{written}\" read as \"{plugin}\"");
            self.warn(&el.loc, message);
        }
        let id = el.attr("id").map(str::to_string);
        let object = self.new_object(&el.name, plugin, id.clone(), el.loc.clone());
        if let Some(id) = &id {
            self.register_id(id, object, &el.loc)?;
        }
        self.objects[parent].children.push(Child {
            name: el.attr("name").map(str::to_string),
            object,
            loc: el.loc.clone(),
            used: Cell::new(false),
        });
        for child in &mut el.children {
            // Depth 2: `<path>` is not allowed inside objects.
            self.element(child, object, 2, file)?;
        }
        Ok(())
    }

    fn add_path(&mut self, value: &str, file: &Path, loc: &SourceLoc) -> Result<(), MitsubaError> {
        let path = Path::new(value);
        let mut resolved = path.to_path_buf();
        if path.is_relative() {
            // Next to the file that says it first, then through the search folders.
            resolved = file.parent().unwrap_or(Path::new("")).join(path);
            if !resolved.exists()
                && let Some(found) = self
                    .search_paths
                    .iter()
                    .map(|d| d.join(path))
                    .find(|p| p.exists())
            {
                resolved = found;
            }
        }
        if !resolved.is_dir() {
            return Err(MitsubaError::new(
                loc,
                format!(
                    "<path> folder \"{value}\" not found ({})",
                    resolved.display()
                ),
            ));
        }
        self.search_paths.insert(0, resolved);
        Ok(())
    }

    fn include(
        &mut self,
        el: &Element,
        parent: ObjectId,
        depth: usize,
    ) -> Result<(), MitsubaError> {
        self.check_attrs(el, &["filename"]);
        let name = required(el, "filename")?;
        let found = self
            .search_paths
            .iter()
            .map(|d| d.join(name))
            .find(|p| p.is_file())
            .or_else(|| {
                Path::new(name)
                    .is_absolute()
                    .then(|| PathBuf::from(name))
                    .filter(|p| p.is_file())
            });
        let Some(path) = found else {
            let looked: Vec<_> = self
                .search_paths
                .iter()
                .map(|d| d.display().to_string())
                .collect();
            return Err(MitsubaError::new(
                &el.loc,
                format!(
                    "included file \"{name}\" not found (looked in {})",
                    looked.join(", ")
                ),
            ));
        };
        if self.include_depth >= MAX_INCLUDE_DEPTH {
            return Err(MitsubaError::new(
                &el.loc,
                format!("more than {MAX_INCLUDE_DEPTH} nested <include>s (a cycle?)"),
            ));
        }
        let from = |mut err: MitsubaError| {
            if !err.message.contains("(included from") {
                err.message = format!("{} (included from {})", err.message, el.loc);
            }
            err
        };
        let file = Arc::new(path.clone());
        let text = std::fs::read_to_string(&path).map_err(|err| {
            MitsubaError::new(
                &el.loc,
                format!("cannot read included file \"{}\": {err}", path.display()),
            )
        })?;
        let mut root = dom::parse_document(&text, &file, &mut self.warnings).map_err(from)?;
        self.include_depth += 1;
        let result = (|| {
            if root.name == "scene" {
                self.substitute(&mut root)?;
                if let Some(version) = root.attr("version") {
                    let version = upgrade::parse_version(&root, version)?;
                    upgrade::upgrade(&mut root, version, &mut self.warnings);
                }
                for child in &mut root.children {
                    self.element(child, parent, depth, &path)?;
                }
                Ok(())
            } else {
                self.element(&mut root, parent, depth, &path)
            }
        })();
        self.include_depth -= 1;
        result.map_err(from)
    }

    fn resolve_refs(&mut self) -> Result<(), MitsubaError> {
        for (parent, index, id) in std::mem::take(&mut self.refs) {
            let child = &mut self.objects[parent].children[index];
            child.object = *self.ids.get(&id).ok_or_else(|| {
                MitsubaError::new(&child.loc, format!("reference to unknown id \"{id}\""))
            })?;
        }
        Ok(())
    }

    /// A property element: its name and typed value.
    fn property(
        &mut self,
        el: &Element,
        within_emitter: bool,
    ) -> Result<(String, Value), MitsubaError> {
        let name = required(el, "name")?.to_string();
        let bad = |what: &str, text: &str| {
            MitsubaError::new(
                &el.loc,
                format!("could not parse {what} \"{text}\" in <{}>", el.name),
            )
        };
        let value = match el.name.as_str() {
            "string" => {
                self.check_attrs(el, &["name", "value"]);
                Value::String(required(el, "value")?.to_string())
            }
            "float" => {
                self.check_attrs(el, &["name", "value"]);
                let text = required(el, "value")?;
                Value::Float(parse_f64(text).ok_or_else(|| bad("floating point value", text))?)
            }
            "integer" => {
                self.check_attrs(el, &["name", "value"]);
                let text = required(el, "value")?;
                Value::Integer(
                    text.trim()
                        .parse()
                        .map_err(|_| bad("integer value", text))?,
                )
            }
            "boolean" => {
                self.check_attrs(el, &["name", "value"]);
                let text = required(el, "value")?;
                match text.trim().to_lowercase().as_str() {
                    "true" => Value::Boolean(true),
                    "false" => Value::Boolean(false),
                    _ => return Err(bad("boolean value (true or false)", text)),
                }
            }
            "point" | "vector" => {
                self.check_attrs(el, &["name", "value", "x", "y", "z"]);
                let v = xyz(el, 0.0)?;
                if el.name == "point" {
                    Value::Point(v)
                } else {
                    Value::Vector(v)
                }
            }
            "rgb" => {
                self.check_attrs(el, &["name", "value"]);
                let text = required(el, "value")?;
                let numbers = parse_list(text).ok_or_else(|| bad("RGB value", text))?;
                match numbers.as_slice() {
                    [v] => Value::Rgb(DVec3::splat(*v)),
                    [r, g, b] => Value::Rgb(DVec3::new(*r, *g, *b)),
                    _ => return Err(bad("RGB value (one or three numbers)", text)),
                }
            }
            "spectrum" => {
                self.check_attrs(el, &["name", "value", "filename"]);
                let kind = if within_emitter {
                    SpectrumKind::Emission
                } else if UNBOUNDED.contains(&name.as_str()) {
                    SpectrumKind::Unbounded
                } else {
                    SpectrumKind::Reflectance
                };
                Value::Spectrum(self.spectrum(el, kind)?)
            }
            _ => unreachable!("property tags are matched by the caller"),
        };
        Ok((name, value))
    }

    /// `<spectrum value="0.5"/>`, `value="400:0.1, 500:0.2, ..."` or `filename="x.spd"`, as RGB.
    fn spectrum(&mut self, el: &Element, kind: SpectrumKind) -> Result<DVec3, MitsubaError> {
        let (wavelengths, values, text) = match (el.attr("value"), el.attr("filename")) {
            (Some(text), None) => {
                let tokens: Vec<_> = tokens(text).collect();
                if let [single] = tokens.as_slice()
                    && !single.contains(':')
                {
                    let v = parse_f64(single).ok_or_else(|| {
                        MitsubaError::new(
                            &el.loc,
                            format!("could not parse constant spectrum \"{text}\""),
                        )
                    })?;
                    return Ok(DVec3::splat(v));
                }
                let mut pairs = (Vec::new(), Vec::new());
                for token in tokens {
                    let pair = token
                        .split_once(':')
                        .and_then(|(w, v)| Some((parse_f64(w)?, parse_f64(v)?)));
                    let (w, v) = pair.ok_or_else(|| {
                        MitsubaError::new(
                            &el.loc,
                            format!(
                                "could not parse wavelength:value pair \"{token}\" in <spectrum>"
                            ),
                        )
                    })?;
                    pairs.0.push(w);
                    pairs.1.push(v);
                }
                (pairs.0, pairs.1, text.to_string())
            }
            (None, Some(name)) => {
                let path = resolve_in(&self.search_paths, name);
                let (w, v) =
                    read_spd(&path).map_err(|message| MitsubaError::new(&el.loc, message))?;
                (w, v, name.to_string())
            }
            _ => {
                return Err(MitsubaError::new(
                    &el.loc,
                    "<spectrum> needs one of the attributes value or filename",
                ));
            }
        };
        if wavelengths.len() < 2 || wavelengths.windows(2).any(|w| w[1] <= w[0]) {
            return Err(MitsubaError::new(
                &el.loc,
                format!("spectrum \"{text}\" needs at least two wavelengths in increasing order"),
            ));
        }
        let (rgb, clamped) = spectrum::sampled_to_rgb(&wavelengths, &values, kind);
        if clamped {
            let message = format!("spectrum clamped into the sRGB gamut: {rgb:.4}");
            self.warn(&el.loc, message);
        }
        Ok(rgb)
    }

    /// One operation inside a `<transform>`, as a matrix.
    fn transform_op(&mut self, el: &Element) -> Result<DMat4, MitsubaError> {
        let invalid =
            |what: &str| MitsubaError::new(&el.loc, format!("invalid <{}>: {what}", el.name));
        Ok(match el.name.as_str() {
            "translate" => {
                self.check_attrs(el, &["value", "x", "y", "z"]);
                transform::translate(xyz(el, 0.0)?)
            }
            "scale" => {
                self.check_attrs(el, &["value", "x", "y", "z"]);
                transform::scale(xyz(el, 1.0)?)
            }
            "rotate" => {
                self.check_attrs(el, &["value", "x", "y", "z", "angle"]);
                let text = required(el, "angle")?;
                let angle = parse_f64(text).ok_or_else(|| invalid(&format!("angle \"{text}\"")))?;
                transform::rotate(xyz(el, 0.0)?, angle).ok_or_else(|| invalid("zero axis"))?
            }
            "lookat" => {
                self.check_attrs(el, &["origin", "target", "up"]);
                let origin = vector3(el, "origin")?;
                let target = vector3(el, "target")?;
                let up = if el.attr("up").is_some() {
                    vector3(el, "up")?
                } else {
                    DVec3::ZERO
                };
                transform::look_at(origin, target, up)
                    .ok_or_else(|| invalid("origin equals target, or up is parallel to the view"))?
            }
            "matrix" => {
                self.check_attrs(el, &["value"]);
                let text = required(el, "value")?;
                let values =
                    parse_list(text).ok_or_else(|| invalid(&format!("value \"{text}\"")))?;
                transform::matrix(&values)
                    .ok_or_else(|| invalid(&format!("{} values, expected 16 or 9", values.len())))?
            }
            other => {
                return Err(MitsubaError::new(
                    &el.loc,
                    format!(
                        "<{other}> inside a <transform> (expected translate, rotate, scale, lookat or matrix)"
                    ),
                ));
            }
        })
    }
}

fn required<'a>(el: &'a Element, key: &str) -> Result<&'a str, MitsubaError> {
    el.attr(key).ok_or_else(|| {
        MitsubaError::new(
            &el.loc,
            format!("missing attribute \"{key}\" in <{}>", el.name),
        )
    })
}

/// Tokens separated by commas and white space, as Mitsuba's `string::tokenize`.
fn tokens(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
}

fn parse_f64(text: &str) -> Option<f64> {
    text.trim().parse().ok()
}

fn parse_list(text: &str) -> Option<Vec<f64>> {
    tokens(text).map(parse_f64).collect()
}

/// `value="v"` or `value="x y z"`, or the attributes `x`, `y`, `z` (each `default` if absent).
fn xyz(el: &Element, default: f64) -> Result<DVec3, MitsubaError> {
    let bad = |text: &str| {
        MitsubaError::new(
            &el.loc,
            format!("could not parse \"{text}\" in <{}>", el.name),
        )
    };
    if let Some(text) = el.attr("value") {
        if ["x", "y", "z"].iter().any(|k| el.attr(k).is_some()) {
            return Err(MitsubaError::new(
                &el.loc,
                format!("<{}> mixes value with x, y, z", el.name),
            ));
        }
        let v = parse_list(text).ok_or_else(|| bad(text))?;
        return match v.as_slice() {
            [s] => Ok(DVec3::splat(*s)),
            [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
            _ => Err(bad(text)),
        };
    }
    let mut v = DVec3::splat(default);
    for (i, key) in ["x", "y", "z"].into_iter().enumerate() {
        if let Some(text) = el.attr(key) {
            v[i] = parse_f64(text).ok_or_else(|| bad(text))?;
        }
    }
    Ok(v)
}

/// An attribute holding exactly three numbers (`origin="0, 0, 4"`).
fn vector3(el: &Element, key: &str) -> Result<DVec3, MitsubaError> {
    let text = required(el, key)?;
    match parse_list(text).as_deref() {
        Some([x, y, z]) => Ok(DVec3::new(*x, *y, *z)),
        _ => Err(MitsubaError::new(
            &el.loc,
            format!("{key}=\"{text}\" in <{}> must be three numbers", el.name),
        )),
    }
}

/// A `.spd` file: a wavelength and a value per line, `#` comments.
fn read_spd(path: &Path) -> Result<(Vec<f64>, Vec<f64>), String> {
    let text = std::fs::read_to_string(path)
        .map_err(|err| format!("cannot read spectrum file \"{}\": {err}", path.display()))?;
    let mut out = (Vec::new(), Vec::new());
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        match parse_list(line).as_deref() {
            Some([w, v]) => {
                out.0.push(*w);
                out.1.push(*v);
            }
            _ => {
                return Err(format!(
                    "{}:{}: expected \"wavelength value\", got \"{line}\"",
                    path.display(),
                    n + 1
                ));
            }
        }
    }
    Ok(out)
}
