//! From the plugin tree to the scene description, with Mitsuba's semantics: its sensor and film
//! conventions, how it counts path depth, its emitters' units, its shapes' parametrisations.
//! Plugins are read by the files beside this one (`materials`, `shapes`, `emitters`); what foton
//! cannot render exactly is approximated with a warning naming what changes; unknown plugins and
//! parameters are warnings with file:line:col, and loading goes on.

use std::collections::HashMap;
use std::path::Path;

use glam::{DMat4, DVec3, Vec2, Vec3};

use super::error::SourceLoc;
use super::tree::{Object, ObjectId, SceneTree, Value};
use super::{emitters, materials, shapes};
use crate::camera::pinhole;
use crate::scene::desc::{
    ColorParam, FilterDesc, FilterKind, Location, MaterialId, SceneDesc, SceneError, SceneWarning,
    TextureId, ToneMap,
};

/// Reads the Mitsuba scene at `path` with `-D name=value` parameters `defines` (the loader
/// registered for `.xml` in `scene::LOADERS`).
pub fn load_with(path: &Path, defines: &[(String, String)]) -> Result<SceneDesc, SceneError> {
    let tree = super::parse_file(path, defines).map_err(|e| SceneError {
        location: location(&e.loc),
        message: e.message,
    })?;
    to_scene(&tree)
}

/// A [`SourceLoc`] as the description's [`Location`].
pub fn location(loc: &SourceLoc) -> Location {
    Location {
        file: loc.file.to_path_buf(),
        line: loc.line,
        column: Some(loc.column),
    }
}

/// Converts a parsed tree.
pub fn to_scene(tree: &SceneTree) -> Result<SceneDesc, SceneError> {
    let root = tree.root();
    let mut cx = Converter {
        tree,
        desc: SceneDesc::empty(location(&root.loc)),
        materials: HashMap::new(),
        textures: HashMap::new(),
        shape_groups: HashMap::new(),
    };
    cx.desc
        .warnings
        .extend(tree.warnings.iter().map(|w| SceneWarning {
            location: location(&w.loc),
            message: w.message.clone(),
        }));
    // Mitsuba's defaults: a film of 768x576 (hdrfilm), linear output, a Gaussian filter.
    cx.desc.film.x_resolution = 768;
    cx.desc.film.y_resolution = 576;
    cx.desc.film.tonemap = ToneMap::Linear { scale: 1.0 };
    cx.desc.filter = gaussian_filter(0.5);
    cx.integrator(root);
    let mut sensors = root.children_tagged(tree, "sensor");
    if let Some((_, sensor)) = sensors.next() {
        cx.sensor(sensor);
    } else {
        cx.warn(
            &root.loc,
            "no <sensor>: Mitsuba's default camera (perspective, 45 degrees at the origin)".into(),
        );
        cx.desc.camera.kind = &pinhole::CAMERA;
        cx.desc.camera.fov_degrees = 45.0 * 576.0 / 768.0;
    }
    for (_, extra) in sensors {
        cx.warn(
            &extra.loc,
            format!(
                "{} ignored: only the first sensor renders",
                extra.describe()
            ),
        );
    }
    for child in &root.children {
        let object = &tree.objects[child.object];
        match object.tag.as_str() {
            "shape" => {
                child_used(child);
                shapes::shape(&mut cx, object)?;
            }
            "emitter" => {
                child_used(child);
                emitters::emitter(&mut cx, object)?;
            }
            // Declared for later reference; converted where used.
            "bsdf" | "texture" | "spectrum" | "sensor" | "integrator" => child_used(child),
            _ => {}
        }
    }
    cx.report_unused(root);
    Ok(cx.desc)
}

fn child_used(child: &super::tree::Child) {
    child.used.set(true);
}

pub struct Converter<'a> {
    pub tree: &'a SceneTree,
    pub desc: SceneDesc,
    /// BSDF objects already converted (a `ref` shares one material).
    pub materials: HashMap<ObjectId, MaterialId>,
    pub textures: HashMap<ObjectId, TextureId>,
    /// `shapegroup`s already converted: their index in `SceneDesc::shape_groups`.
    pub shape_groups: HashMap<ObjectId, usize>,
}

impl Converter<'_> {
    pub fn warn(&mut self, loc: &SourceLoc, message: String) {
        self.desc.warnings.push(SceneWarning {
            location: location(loc),
            message,
        });
    }

    pub fn error(&self, loc: &SourceLoc, message: String) -> SceneError {
        SceneError {
            location: location(loc),
            message,
        }
    }

    /// Warns about every parameter of `object` nobody read.
    pub fn report_unused(&mut self, object: &Object) {
        let unused: Vec<_> = object
            .unused()
            .map(|(n, l)| (n.to_string(), l.clone()))
            .collect();
        for (name, loc) in unused {
            self.warn(
                &loc,
                format!(
                    "parameter \"{name}\" of {} not supported, ignored",
                    object.describe()
                ),
            );
        }
    }

    fn wrong_type(&mut self, object: &Object, name: &str, value: &Value, expected: &str) {
        let loc = object
            .prop(name)
            .map_or(object.loc.clone(), |p| p.loc.clone());
        self.warn(
            &loc,
            format!(
                "\"{name}\" of {} is a {}, expected {expected}: default used",
                object.describe(),
                value.type_name()
            ),
        );
    }

    pub fn float(&mut self, object: &Object, name: &str, default: f32) -> f32 {
        match object.prop(name).map(|p| p.value.clone()) {
            None => default,
            Some(Value::Float(v)) => v as f32,
            Some(Value::Integer(v)) => v as f32,
            Some(other) => {
                self.wrong_type(object, name, &other, "a float");
                default
            }
        }
    }

    pub fn int(&mut self, object: &Object, name: &str, default: i64) -> i64 {
        match object.prop(name).map(|p| p.value.clone()) {
            None => default,
            Some(Value::Integer(v)) => v,
            Some(other) => {
                self.wrong_type(object, name, &other, "an integer");
                default
            }
        }
    }

    pub fn bool(&mut self, object: &Object, name: &str, default: bool) -> bool {
        match object.prop(name).map(|p| p.value.clone()) {
            None => default,
            Some(Value::Boolean(v)) => v,
            Some(other) => {
                self.wrong_type(object, name, &other, "a boolean");
                default
            }
        }
    }

    pub fn string(&mut self, object: &Object, name: &str) -> Option<String> {
        match object.prop(name).map(|p| p.value.clone()) {
            None => None,
            Some(Value::String(v)) => Some(v),
            Some(other) => {
                self.wrong_type(object, name, &other, "a string");
                None
            }
        }
    }

    /// A `point` or `vector` (or a float for all three).
    pub fn vec3(&mut self, object: &Object, name: &str, default: Vec3) -> Vec3 {
        match object.prop(name).map(|p| p.value.clone()) {
            None => default,
            Some(Value::Point(v) | Value::Vector(v)) => v.as_vec3(),
            Some(other) => {
                self.wrong_type(object, name, &other, "a point or vector");
                default
            }
        }
    }

    /// A colour given as `rgb`, `spectrum` or `float`, without textures.
    pub fn rgb(&mut self, object: &Object, name: &str, default: Vec3) -> Vec3 {
        match object.prop(name).map(|p| p.value.clone()) {
            None => default,
            Some(Value::Rgb(v) | Value::Spectrum(v)) => v.as_vec3(),
            Some(Value::Float(v)) => Vec3::splat(v as f32),
            Some(other) => {
                self.wrong_type(object, name, &other, "a colour");
                default
            }
        }
    }

    /// A colour parameter: a constant, or a texture given by `<texture name=...>` or `<ref name=...>`.
    pub fn color(&mut self, object: &Object, name: &str, default: Vec3) -> ColorParam {
        if let Some(texture) = object.named_child(self.tree, name) {
            return match materials::texture(self, texture) {
                Some(id) => ColorParam::Texture(id),
                None => ColorParam::Constant(default),
            };
        }
        ColorParam::Constant(self.rgb(object, name, default))
    }

    /// A transform (identity if absent), in f64 as composed.
    pub fn transform(&mut self, object: &Object, name: &str) -> DMat4 {
        match object.prop(name).map(|p| p.value.clone()) {
            None => DMat4::IDENTITY,
            Some(Value::Transform(m)) => m,
            Some(other) => {
                self.wrong_type(object, name, &other, "a transform");
                DMat4::IDENTITY
            }
        }
    }

    fn integrator(&mut self, root: &Object) {
        let tree = self.tree;
        let Some((_, integrator)) = root.children_tagged(tree, "integrator").next() else {
            // Mitsuba's default: path, max_depth -1.
            self.desc.max_depth = Some(UNLIMITED_DEPTH);
            return;
        };
        let depth = match integrator.plugin.as_str() {
            "path" => self.int(integrator, "max_depth", -1),
            "direct" => {
                integrator.prop("emitter_samples");
                integrator.prop("bsdf_samples");
                self.warn(
                    &integrator.loc,
                    "integrator \"direct\" rendered as path tracing to depth 2 (direct light with \
                     MIS; its emitter_samples and bsdf_samples change the noise, not the mean)"
                        .into(),
                );
                2
            }
            other => {
                let other = other.to_string();
                self.warn(
                    &integrator.loc,
                    format!("integrator \"{other}\" not supported: rendered with \"path\" and its max_depth"),
                );
                self.int(integrator, "max_depth", -1)
            }
        };
        // Mitsuba counts surface interactions including the emitter seen: max_depth 1 is emitted
        // light only, 2 adds direct lighting. foton's max depth counts scattering events: one less.
        self.desc.max_depth = Some(match depth {
            d if d < 0 => UNLIMITED_DEPTH,
            0 => {
                self.warn(
                    &integrator.loc,
                    "max_depth 0 renders black in Mitsuba; emitted light is shown".into(),
                );
                0
            }
            d => (d - 1).min(UNLIMITED_DEPTH as i64) as u32,
        });
        if let Some(p) = integrator.prop("rr_depth") {
            let loc = p.loc.clone();
            self.warn(
                &loc,
                "rr_depth: foton's Russian roulette starts after its own depth (this changes the noise, \
                 not the mean)"
                    .into(),
            );
        }
        self.desc.hide_emitters = self.bool(integrator, "hide_emitters", false);
        self.report_unused(integrator);
    }

    fn sensor(&mut self, sensor: &Object) {
        let tree = self.tree;
        let (mut width, mut height) = (768u32, 576u32);
        if let Some((_, film)) = sensor.children_tagged(tree, "film").next() {
            if film.plugin != "hdrfilm" {
                self.warn(
                    &film.loc,
                    format!("film \"{}\" read as \"hdrfilm\"", film.plugin),
                );
            }
            width = self.int(film, "width", 768).clamp(1, 1 << 16) as u32;
            height = self.int(film, "height", 576).clamp(1, 1 << 16) as u32;
            for ignored in [
                "pixel_format",
                "component_format",
                "file_format",
                "high_quality_edges",
            ] {
                film.prop(ignored);
            }
            for crop in [
                "crop_offset_x",
                "crop_offset_y",
                "crop_width",
                "crop_height",
            ] {
                if let Some(p) = film.prop(crop) {
                    let loc = p.loc.clone();
                    self.warn(
                        &loc,
                        format!("{crop} not supported: the whole film renders"),
                    );
                }
            }
            if let Some((_, rfilter)) = film.children_tagged(tree, "rfilter").next() {
                self.desc.filter = self.rfilter(rfilter);
            }
            self.report_unused(film);
        }
        self.desc.film.x_resolution = width;
        self.desc.film.y_resolution = height;
        if let Some((_, sampler)) = sensor.children_tagged(tree, "sampler").next() {
            let spp = self.int(sampler, "sample_count", 4).max(1);
            self.desc.pixel_samples = Some(spp as u32);
            if ![
                "independent",
                "stratified",
                "multijitter",
                "ldsampler",
                "orthogonal",
            ]
            .contains(&sampler.plugin.as_str())
            {
                self.warn(
                    &sampler.loc,
                    format!(
                        "sampler \"{}\" rendered with foton's sampler",
                        sampler.plugin
                    ),
                );
            }
            sampler.prop("seed");
            self.report_unused(sampler);
        }
        // Mitsuba's camera space has x to the image's left; foton's to its right.
        let to_world =
            self.transform(sensor, "to_world") * DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0));
        let camera = &mut self.desc.camera;
        camera.camera_to_world = to_world.as_mat4();
        camera.location = location(&sensor.loc);
        match sensor.plugin.as_str() {
            "perspective" | "thinlens" => {}
            other => {
                let other = other.to_string();
                self.warn(
                    &sensor.loc,
                    format!("sensor \"{other}\" rendered as \"perspective\""),
                );
            }
        }
        // `fov` along `fov_axis`, or else a `focal_length` (default 50 mm) on a 36 x 24 mm film, a
        // field of view along the film's diagonal, as Mitsuba's `parse_fov`.
        let (fov, axis) = if sensor.prop("fov").is_some() {
            let fov = self.float(sensor, "fov", 45.0);
            (
                fov,
                self.string(sensor, "fov_axis")
                    .unwrap_or_else(|| "x".into()),
            )
        } else {
            let mm = match sensor.prop("focal_length").map(|p| p.value.clone()) {
                Some(Value::String(s)) => s.trim_end_matches("mm").trim().parse().unwrap_or(50.0),
                Some(Value::Float(v)) => v as f32,
                _ => 50.0,
            };
            sensor.prop("fov_axis");
            let diagonal = 36f32.hypot(24.0);
            (
                2.0 * (diagonal / (2.0 * mm)).atan().to_degrees(),
                "diagonal".to_string(),
            )
        };
        let (w, h) = (width as f32, height as f32);
        let axis_len = match axis.as_str() {
            "x" => w,
            "y" => h,
            "diagonal" => w.hypot(h),
            "smaller" => w.min(h),
            "larger" => w.max(h),
            other => {
                let other = other.to_string();
                self.warn(&sensor.loc, format!("fov_axis \"{other}\" unknown: x used"));
                w
            }
        };
        // The field of view along the shorter image side, which foton's perspective spans:
        // tan(fov_short / 2) = tan(fov / 2) * short / axis_len.
        let half = (fov.to_radians() / 2.0).tan() * w.min(h) / axis_len;
        self.desc.camera.kind = &pinhole::CAMERA;
        self.desc.camera.fov_degrees = 2.0 * half.atan().to_degrees();
        if sensor.plugin == "thinlens" {
            self.desc.camera.lens_radius = self.float(sensor, "aperture_radius", 0.0);
            self.desc.camera.focal_distance = self.float(sensor, "focus_distance", 0.0).max(1e-4);
        } else {
            sensor.prop("focus_distance");
        }
        for clip in ["near_clip", "far_clip"] {
            sensor.prop(clip);
        }
        // The sensor's own children were read above.
        for child in &sensor.children {
            child.used.set(true);
        }
        self.report_unused(sensor);
    }

    fn rfilter(&mut self, rfilter: &Object) -> FilterDesc {
        match rfilter.plugin.as_str() {
            "box" => FilterDesc {
                kind: FilterKind::Box,
                radius: Vec2::splat(0.5),
            },
            "gaussian" => {
                let stddev = self.float(rfilter, "stddev", 0.5);
                self.report_unused(rfilter);
                gaussian_filter(stddev)
            }
            // Mitsuba's `tent`: max(0, 1 - |x| / radius), foton's triangle.
            "tent" => {
                let radius = self.float(rfilter, "radius", 1.0);
                self.report_unused(rfilter);
                FilterDesc {
                    kind: FilterKind::Triangle,
                    radius: Vec2::splat(radius.max(1e-3)),
                }
            }
            // Mitsuba's `mitchell` (B, C default 1/3) and `catmullrom` (B 0, C 1/2): the cubic
            // k(|x|) over radius 2 (`rfilters/mitchell.cpp`), which is foton's Mitchell at
            // radius 2 (it evaluates k(2 |x| / radius)).
            "mitchell" | "catmullrom" => {
                let (b, c) = if rfilter.plugin == "mitchell" {
                    (
                        self.float(rfilter, "B", 1.0 / 3.0),
                        self.float(rfilter, "C", 1.0 / 3.0),
                    )
                } else {
                    (0.0, 0.5)
                };
                self.report_unused(rfilter);
                FilterDesc {
                    kind: FilterKind::Mitchell { b, c },
                    radius: Vec2::splat(2.0),
                }
            }
            other => {
                let other = other.to_string();
                self.warn(
                    &rfilter.loc,
                    format!("rfilter \"{other}\" not supported: Mitsuba's default Gaussian used"),
                );
                gaussian_filter(0.5)
            }
        }
    }
}

/// Mitsuba's depth -1 (unlimited): a depth no path reaches before Russian roulette ends it.
const UNLIMITED_DEPTH: u32 = 1024;

/// Mitsuba's `gaussian`: exp(-x^2 / (2 stddev^2)) minus its value at the radius 4 stddev, which is
/// foton's (pbrt's) Gaussian with alpha = 1 / (2 stddev^2).
fn gaussian_filter(stddev: f32) -> FilterDesc {
    FilterDesc {
        kind: FilterKind::Gaussian {
            alpha: 1.0 / (2.0 * stddev * stddev),
        },
        radius: Vec2::splat(4.0 * stddev),
    }
}
