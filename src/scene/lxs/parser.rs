//! The directive interpreter: graphics state, transforms, blocks and includes. What each
//! directive produces is built in `camera.rs`, `materials.rs`, `shapes.rs` and `lights.rs`.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};

use super::lights::AreaLight;
use super::objects::{InstanceCounts, Object, OpenObject};
use super::params::ParamList;
use super::paths::{Resolved, resolve};
use super::tokenizer::{Token, TokenKind, tokenize};
use super::version::{self, LuxVersion};
use super::volumes::Volumes;
use crate::scene::desc::{
    ColorParam, Location, MaterialDesc, MaterialId, SceneDesc, SceneError, SceneWarning,
};
use crate::settings::IntegratorKind;

/// What `AttributeBegin`/`AttributeEnd` save and restore.
#[derive(Clone, Debug)]
pub(super) struct GraphicsState {
    /// The current transformation matrix: object (or light) space to world.
    pub ctm: Mat4,
    pub material: Option<MaterialId>,
    pub area_light: Option<AreaLight>,
    pub reverse_orientation: bool,
    /// `Interior` and `Exterior`: the named volumes inside and outside the shapes that follow.
    pub interior: Option<String>,
    pub exterior: Option<String>,
}

impl Default for GraphicsState {
    fn default() -> Self {
        Self {
            ctm: Mat4::IDENTITY,
            material: None,
            area_light: None,
            reverse_orientation: false,
            interior: None,
            exterior: None,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Block {
    Attribute,
    Transform,
    Object,
}

impl Block {
    fn begin(self) -> &'static str {
        match self {
            Block::Attribute => "AttributeBegin",
            Block::Transform => "TransformBegin",
            Block::Object => "ObjectBegin",
        }
    }
}

/// Directives LuxBlend writes that say nothing foton uses.
const IGNORED_DIRECTIVES: &[&str] = &["Renderer", "Accelerator", "VolumeIntegrator", "LightGroup"];

/// The type names LuxRender 1.x registers for the directives whose type foton does not act on
/// (lux core/dynload registrations, and `multiimage` of older exporters); any other name is a
/// typo or another renderer's and gets a warning.
const KNOWN_TYPES: &[(&str, &[&str])] = &[
    ("Film", &["fleximage", "multiimage"]),
    (
        "Sampler",
        &["metropolis", "lowdiscrepancy", "random", "erpt", "sobol"],
    ),
    (
        "SurfaceIntegrator",
        &[
            "bidirectional",
            "path",
            "directlighting",
            "distributedpath",
            "exphotonmap",
            "igi",
            "sppm",
        ],
    ),
    ("Renderer", &["sampler", "hybrid", "sppm", "luxcore", "slg"]),
    (
        "Accelerator",
        &[
            "qbvh",
            "sqbvh",
            "bvh",
            "kdtree",
            "tabreckdtree",
            "unsafekdtree",
            "grid",
            "none",
        ],
    ),
    ("VolumeIntegrator", &["single", "emission", "multi", "none"]),
];

pub(super) struct Parser {
    pub state: GraphicsState,
    stack: Vec<(Block, GraphicsState, Location)>,
    /// Where `WorldBegin` was, and whether `WorldEnd` has been read.
    world: Option<Location>,
    world_ended: bool,
    /// The file being read and its folder (paths in it resolve against that folder).
    pub file: PathBuf,
    pub dir: PathBuf,
    /// The main scene file's folder (LuxRender resolves names in included files against it).
    pub main_dir: PathBuf,
    /// Absolute paths of the files being read, outermost first (to catch Include cycles).
    include_chain: Vec<PathBuf>,
    pub named_materials: HashMap<String, MaterialId>,
    pub named_textures: HashMap<String, ColorParam>,
    /// `ObjectBegin` … `ObjectEnd`: the object being defined, and those defined.
    pub open_object: Option<OpenObject>,
    pub objects: HashMap<String, Object>,
    /// What the `ObjectInstance`s read drew.
    pub instance_counts: InstanceCounts,
    /// Named volumes and the `glass2` materials that read them.
    pub volumes: Volumes,
    /// The LuxRender release the scene is read as: `-D lux_version`, else the main file's
    /// version comment, else 1.x final (`version.rs`).
    version_override: Option<LuxVersion>,
    pub version: LuxVersion,
    /// What a light given by `gain` alone is multiplied by: 1, or for releases before 1.0
    /// LuxRender's film units ([`version::photometric_scale`]).
    pub film_units: f32,
    /// What has been read so far.
    pub scene: SceneDesc,
}

impl Parser {
    fn new(path: &Path, version_override: Option<LuxVersion>) -> Self {
        Self {
            state: GraphicsState::default(),
            stack: Vec::new(),
            world: None,
            world_ended: false,
            file: path.to_path_buf(),
            dir: PathBuf::new(),
            main_dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
            include_chain: Vec::new(),
            named_materials: HashMap::new(),
            named_textures: HashMap::new(),
            open_object: None,
            objects: HashMap::new(),
            instance_counts: InstanceCounts::default(),
            volumes: Volumes::default(),
            version_override,
            version: version::FINAL,
            film_units: 1.0,
            scene: SceneDesc::empty(Location::line(path, 0)),
        }
    }

    /// Sets the release the scene is read as, from the main file's `text`, with one note when
    /// it is read as LuxRender 0.x.
    fn read_version(&mut self, text: &str) {
        let (version, source) = match (self.version_override, LuxVersion::from_header(text)) {
            (Some(version), _) => (version, format!("-D {}", version::OVERRIDE_PARAMETER)),
            (None, Some(version)) => (version, "its version comment".to_string()),
            (None, None) => return,
        };
        self.version = version;
        if version.has_absolute_reinhard() {
            self.film_units = version::photometric_scale();
            self.scene.notes.push(format!(
                "read as LuxRender {version} ({source}): LuxRender 0.x's Reinhard tone map on \
                 absolute luminance, and lights given by gain alone in its film units (x {:.0}); \
                 -D {}=1.6 for LuxRender 1.x's",
                self.film_units,
                version::OVERRIDE_PARAMETER
            ));
        }
    }

    pub fn location(&self, line: usize) -> Location {
        Location::line(&self.file, line)
    }

    pub fn error(&self, line: usize, message: impl Into<String>) -> SceneError {
        SceneError {
            location: self.location(line),
            message: message.into(),
        }
    }

    pub fn warn(&mut self, line: usize, message: impl Into<String>) {
        let warning = SceneWarning {
            location: self.location(line),
            message: message.into(),
        };
        self.scene.warnings.push(warning);
    }

    /// Finds a file named in the current file (see `paths::resolve`), warning when it was found
    /// in a parent folder. `what` is the naming text, e.g. `Include "x.lxo"`.
    pub fn resolve(&mut self, name: &str, line: usize, what: &str) -> Result<PathBuf, SceneError> {
        match resolve(name, &self.dir, &self.main_dir) {
            Ok(Resolved {
                path,
                found_in_parent,
            }) => {
                if found_in_parent {
                    self.warn(
                        line,
                        format!(
                            "files found in a parent folder of the file naming them{FIRST_EXAMPLE}{what} as {}",
                            path.display()
                        ),
                    );
                }
                Ok(path)
            }
            Err(message) => Err(self.error(line, format!("{what}: {message}"))),
        }
    }

    fn read_file(&mut self, path: &Path) -> Result<(), SceneError> {
        let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
        let text = std::fs::read_to_string(path).map_err(|e| SceneError {
            location: Location::line(path, 0),
            message: format!("cannot read: {e}"),
        })?;
        if self.include_chain.is_empty() {
            self.read_version(&text);
        }
        let outer_file = std::mem::replace(&mut self.file, path.to_path_buf());
        let outer_dir = std::mem::replace(
            &mut self.dir,
            path.parent().map(Path::to_path_buf).unwrap_or_default(),
        );
        self.include_chain.push(absolute);
        let result = self.interpret(&text);
        self.include_chain.pop();
        self.file = outer_file;
        self.dir = outer_dir;
        result
    }

    fn interpret(&mut self, text: &str) -> Result<(), SceneError> {
        let tokens = tokenize(&self.file, text)?;
        let mut rest = &tokens[..];
        while let Some((first, after)) = rest.split_first() {
            let TokenKind::Identifier(name) = &first.kind else {
                return Err(self.error(
                    first.line,
                    format!("expected a directive, found {}", first.text()),
                ));
            };
            // A directive's arguments run up to the next bare word outside brackets.
            let mut depth = 0usize;
            let end = after
                .iter()
                .position(|t| match t.kind {
                    TokenKind::OpenBracket => {
                        depth += 1;
                        false
                    }
                    TokenKind::CloseBracket => {
                        depth = depth.saturating_sub(1);
                        false
                    }
                    TokenKind::Identifier(_) => depth == 0,
                    _ => false,
                })
                .unwrap_or(after.len());
            self.directive(name, first.line, &after[..end])?;
            rest = &after[end..];
        }
        Ok(())
    }

    fn directive(&mut self, name: &str, line: usize, args: &[Token]) -> Result<(), SceneError> {
        match name {
            "LookAt" => {
                let v = self.numbers(name, line, args, 9)?;
                let look_at = self.look_at(line, &v)?;
                self.state.ctm *= look_at;
            }
            "Transform" => {
                let v = self.numbers(name, line, args, 16)?;
                self.state.ctm = Mat4::from_cols_slice(&v);
            }
            "ConcatTransform" => {
                let v = self.numbers(name, line, args, 16)?;
                self.state.ctm *= Mat4::from_cols_slice(&v);
            }
            "Translate" => {
                let v = self.numbers(name, line, args, 3)?;
                self.state.ctm *= Mat4::from_translation(Vec3::from_slice(&v));
            }
            "Scale" => {
                let v = self.numbers(name, line, args, 3)?;
                self.state.ctm *= Mat4::from_scale(Vec3::from_slice(&v));
            }
            "Rotate" => {
                let v = self.numbers(name, line, args, 4)?;
                let axis = Vec3::from_slice(&v[1..])
                    .try_normalize()
                    .ok_or_else(|| self.error(line, "Rotate: the axis is zero"))?;
                self.state.ctm *= Mat4::from_axis_angle(axis, v[0].to_radians());
            }
            "Identity" => {
                self.numbers(name, line, args, 0)?;
                self.state.ctm = Mat4::IDENTITY;
            }
            "ReverseOrientation" => {
                self.numbers(name, line, args, 0)?;
                self.state.reverse_orientation = !self.state.reverse_orientation;
            }
            "AttributeBegin" | "TransformBegin" => {
                self.numbers(name, line, args, 0)?;
                let block = if name == "AttributeBegin" {
                    Block::Attribute
                } else {
                    Block::Transform
                };
                self.stack
                    .push((block, self.state.clone(), self.location(line)));
            }
            "AttributeEnd" | "TransformEnd" => {
                self.numbers(name, line, args, 0)?;
                let block = if name == "AttributeEnd" {
                    Block::Attribute
                } else {
                    Block::Transform
                };
                self.end_block(block, name, line)?;
            }
            "WorldBegin" => {
                self.numbers(name, line, args, 0)?;
                if let Some(first) = &self.world {
                    return Err(self.error(line, format!("WorldBegin again (first at {first})")));
                }
                self.world = Some(self.location(line));
                self.state.ctm = Mat4::IDENTITY;
            }
            "WorldEnd" => {
                self.numbers(name, line, args, 0)?;
                if self.world.is_none() || self.world_ended {
                    return Err(self.error(line, "WorldEnd without WorldBegin"));
                }
                if let Some((block, _, at)) = self.stack.last() {
                    return Err(self.error(
                        line,
                        format!("WorldEnd while the {} at {at} is still open", block.begin()),
                    ));
                }
                self.world_ended = true;
            }
            "Include" => {
                let (mut strings, params) = self.strings(name, line, args, 1)?;
                let params = ParamList::parse(&self.file, params, &mut self.scene.warnings)?;
                params.warn_unused(name, &mut self.scene.warnings);
                let target = strings.remove(0);
                self.include(&target, line)?;
            }
            "ObjectBegin" => {
                let name = self.one_name(name, line, args)?;
                self.object_begin(&name, line)?;
                self.stack
                    .push((Block::Object, self.state.clone(), self.location(line)));
            }
            "ObjectEnd" => {
                self.numbers(name, line, args, 0)?;
                self.end_block(Block::Object, name, line)?;
                self.object_end(line)?;
            }
            "ObjectInstance" => {
                let name = self.one_name(name, line, args)?;
                self.object_instance(&name, line)?;
            }
            "Interior" | "Exterior" => {
                let volume = self.one_name(name, line, args)?;
                self.set_volume(name, &volume, line);
            }
            _ => {
                let Some(kind) = self.known_with_params(name) else {
                    self.warn(line, format!("unknown directive {name} ignored"));
                    return Ok(());
                };
                let (strings, params) = self.strings(name, line, args, kind)?;
                let mut params = ParamList::parse(&self.file, params, &mut self.scene.warnings)?;
                let context = format!("{name} \"{}\"", strings.first().map_or("", String::as_str));
                self.with_params(name, line, &strings, &mut params)?;
                params.warn_unused(&context, &mut self.scene.warnings);
            }
        }
        Ok(())
    }

    /// The number of leading quoted strings a directive with a parameter list takes.
    fn known_with_params(&self, name: &str) -> Option<usize> {
        match name {
            "Camera" | "Film" | "Sampler" | "SurfaceIntegrator" | "PixelFilter" | "Material"
            | "MakeNamedMaterial" | "NamedMaterial" | "Shape" | "LightSource"
            | "AreaLightSource" | "Texture" => Some(1),
            "MakeNamedVolume" => Some(2),
            name if IGNORED_DIRECTIVES.contains(&name) => Some(1),
            _ => None,
        }
    }

    fn with_params(
        &mut self,
        name: &str,
        line: usize,
        strings: &[String],
        params: &mut ParamList,
    ) -> Result<(), SceneError> {
        let first = strings.first().map_or("", String::as_str);
        if let Some((_, known)) = KNOWN_TYPES.iter().find(|(directive, _)| *directive == name)
            && !known.contains(&first)
        {
            self.warn(
                line,
                format!(
                    "unknown {name} type \"{first}\" (LuxRender has {})",
                    known.join(", ")
                ),
            );
        }
        match name {
            "Camera" => self.camera(first, line, params)?,
            "Film" => self.film_directive(first, line, params)?,
            "Sampler" => {
                self.scene.pixel_samples = self.positive_int(params, "pixelsamples", line)?;
            }
            "SurfaceIntegrator" => {
                self.surface_integrator(first, line);
                let depth = match self.count(params, "maxdepth", line)? {
                    Some(depth) => Some(depth),
                    None => self.count(params, "eyedepth", line)?,
                };
                self.scene.max_depth = depth.or(self.scene.max_depth);
            }
            "PixelFilter" => self.pixel_filter(first, line, params)?,
            "Material" => {
                let material = self.material(first, line, params)?;
                let id = self.push_material(first, material);
                self.state.material = Some(id);
            }
            "MakeNamedMaterial" => {
                let kind = params.string("type")?.unwrap_or_default();
                let material = self.material(&kind, line, params)?;
                let id = self.push_material(&kind, material);
                if self.named_materials.insert(first.to_string(), id).is_some() {
                    self.warn(line, format!("MakeNamedMaterial \"{first}\" redefined"));
                }
            }
            "NamedMaterial" => {
                let id = *self.named_materials.get(first).ok_or_else(|| {
                    self.error(line, format!("NamedMaterial \"{first}\": no such material"))
                })?;
                self.state.material = Some(id);
            }
            "Texture" => self.texture(strings, line, params)?,
            "MakeNamedVolume" => self.make_named_volume(strings, line, params)?,
            "Shape" => self.shape(first, line, params)?,
            "LightSource" => self.light(first, line, params)?,
            "AreaLightSource" => self.area_light(first, line, params)?,
            // Renderer, Accelerator, …: nothing foton uses; their parameters are not reported.
            _ => params.ignore_all(),
        }
        Ok(())
    }

    /// Adds a material of LuxRender type `kind`, noting a `glass2` (bumped or not), whose
    /// index the shapes' volumes set.
    fn push_material(&mut self, kind: &str, material: MaterialDesc) -> MaterialId {
        let interface = match &material {
            MaterialDesc::Bump { material, .. } => &self.scene.materials[*material],
            other => other,
        };
        let glass2 = kind == "glass2"
            && matches!(
                interface,
                MaterialDesc::Dielectric { .. } | MaterialDesc::ThinDielectric { .. }
            );
        self.scene.materials.push(material);
        let id = self.scene.materials.len() - 1;
        if glass2 {
            self.note_glass2(id);
        }
        id
    }

    fn include(&mut self, target: &str, line: usize) -> Result<(), SceneError> {
        let what = format!("Include \"{target}\"");
        let path = self.resolve(target, line, &what)?;
        let absolute = std::path::absolute(&path).unwrap_or_else(|_| path.clone());
        if self.include_chain.contains(&absolute) {
            return Err(self.error(line, format!("{what}: includes itself")));
        }
        self.read_file(&path).map_err(|error| {
            if error.location.line == 0 {
                self.error(line, format!("{what}: {}", error.message))
            } else {
                error
            }
        })
    }

    fn end_block(&mut self, block: Block, name: &str, line: usize) -> Result<(), SceneError> {
        match self.stack.pop() {
            Some((open, saved, _)) if open == block => {
                match block {
                    Block::Attribute | Block::Object => self.state = saved,
                    Block::Transform => self.state.ctm = saved.ctm,
                }
                Ok(())
            }
            Some((open, _, at)) => Err(self.error(
                line,
                format!("{name} does not match the {} at {at}", open.begin()),
            )),
            None => Err(self.error(line, format!("{name} without {}", block.begin()))),
        }
    }

    /// The numbers after a directive, bare or in brackets: exactly `count` of them.
    fn numbers(
        &self,
        name: &str,
        line: usize,
        args: &[Token],
        count: usize,
    ) -> Result<Vec<f32>, SceneError> {
        let mut numbers = Vec::new();
        for token in args {
            match token.kind {
                TokenKind::Number(value) => numbers.push(value as f32),
                TokenKind::OpenBracket | TokenKind::CloseBracket if count > 0 => {}
                _ => {
                    return Err(
                        self.error(token.line, format!("{name}: unexpected {}", token.text()))
                    );
                }
            }
        }
        if numbers.len() != count {
            return Err(self.error(
                line,
                format!("{name}: {} values, expected {count}", numbers.len()),
            ));
        }
        Ok(numbers)
    }

    /// The leading quoted strings of a directive (`count` of them; `Texture` may take two more:
    /// its type and class) and the parameter-list tokens after them.
    /// The one quoted name after a directive (`ObjectBegin "name"`), and nothing else.
    fn one_name(&self, name: &str, line: usize, args: &[Token]) -> Result<String, SceneError> {
        let (mut strings, rest) = self.strings(name, line, args, 1)?;
        if !rest.is_empty() {
            return Err(self.error(line, format!("{name} takes one quoted name only")));
        }
        Ok(strings.remove(0))
    }

    fn strings<'t>(
        &self,
        name: &str,
        line: usize,
        args: &'t [Token],
        count: usize,
    ) -> Result<(Vec<String>, &'t [Token]), SceneError> {
        let limit = if name == "Texture" { 3 } else { count };
        let mut strings = Vec::new();
        for token in args.iter().take(limit) {
            match &token.kind {
                TokenKind::Quoted(text) if strings.len() < count || !text.contains(' ') => {
                    strings.push(text.clone());
                }
                _ => break,
            }
        }
        if strings.len() < count {
            return Err(self.error(line, format!("{name}: expected a quoted name or type")));
        }
        let used = strings.len();
        Ok((strings, &args[used..]))
    }

    /// The world-to-camera matrix of `LookAt eye look up`, right-handed: camera x is
    /// normalize(dir x up), y = x' x dir, z = dir.
    fn look_at(&self, line: usize, v: &[f32]) -> Result<Mat4, SceneError> {
        let eye = Vec3::from_slice(&v[0..3]);
        let look = Vec3::from_slice(&v[3..6]);
        let up = Vec3::from_slice(&v[6..9]);
        let degenerate = || self.error(line, "LookAt: eye, look and up do not define a view");
        let dir = (look - eye).try_normalize().ok_or_else(degenerate)?;
        let right = dir.cross(up).try_normalize().ok_or_else(degenerate)?;
        let camera_up = right.cross(dir);
        let camera_to_world = Mat4::from_cols(
            right.extend(0.0),
            camera_up.extend(0.0),
            dir.extend(0.0),
            eye.extend(1.0),
        );
        Ok(camera_to_world.inverse())
    }

    /// An integer parameter that must be > 0.
    pub fn positive_int(
        &self,
        params: &mut ParamList,
        name: &str,
        line: usize,
    ) -> Result<Option<u32>, SceneError> {
        match params.int(name)? {
            Some(value) if value > 0 => u32::try_from(value)
                .map(Some)
                .map_err(|_| self.error(line, format!("\"{name}\" {value} is too large"))),
            Some(value) => Err(self.error(line, format!("\"{name}\" {value} must be positive"))),
            None => Ok(None),
        }
    }

    /// An integer parameter that must be >= 0.
    fn count(
        &self,
        params: &mut ParamList,
        name: &str,
        line: usize,
    ) -> Result<Option<u32>, SceneError> {
        match params.int(name)? {
            Some(value) => u32::try_from(value)
                .map(Some)
                .map_err(|_| self.error(line, format!("\"{name}\" {value} is out of range"))),
            None => Ok(None),
        }
    }

    /// `SurfaceIntegrator`: `directlighting` (direct light plus specular bounces) is foton's
    /// ray caster; the integrators foton lacks are path traced, which converges to the same
    /// image (`bidirectional`, `sppm`, …) or a less biased one (`igi`, `exphotonmap`).
    fn surface_integrator(&mut self, kind: &str, line: usize) {
        self.scene.integrator = match kind {
            "directlighting" => Some(IntegratorKind::RayCaster),
            "path" => Some(IntegratorKind::PathTracer),
            "bidirectional" | "distributedpath" | "exphotonmap" | "igi" | "sppm" => {
                self.warn(
                    line,
                    format!(
                        "SurfaceIntegrator \"{kind}\" is not in foton: rendered with its path tracer \
                         (unidirectional, next-event estimation with MIS)"
                    ),
                );
                None
            }
            // Not LuxRender's: `with_params` has warned of the unknown type.
            _ => None,
        };
    }

    /// Checks that nothing was left open at the end of the scene, and hands over the result.
    fn finish(mut self) -> Result<SceneDesc, SceneError> {
        if let Some((block, _, at)) = self.stack.last() {
            return Err(SceneError {
                location: at.clone(),
                message: format!("{} is never closed", block.begin()),
            });
        }
        if let Some(at) = &self.world
            && !self.world_ended
        {
            return Err(SceneError {
                location: at.clone(),
                message: "WorldBegin is never closed by WorldEnd".into(),
            });
        }
        if let Some(note) = self.instance_note() {
            self.scene.notes.push(note);
        }
        self.scene.warnings = once_per_kind(std::mem::take(&mut self.scene.warnings));
        Ok(self.scene)
    }
}

/// Reads the scene file at `path` and the files it includes, as LuxRender `version_override`
/// if given.
pub(super) fn parse(
    path: &Path,
    version_override: Option<LuxVersion>,
) -> Result<SceneDesc, SceneError> {
    let mut parser = Parser::new(path, version_override);
    parser.read_file(path)?;
    parser.finish()
}

/// Separates a warning's kind from its first example, where occurrences differ in their text.
const FIRST_EXAMPLE: &str = "; the first: ";

/// Warnings once per kind: where several say the same (or the same kind, for files found in a
/// parent folder), the first stays, at its location, with the count of all of them.
fn once_per_kind(warnings: Vec<SceneWarning>) -> Vec<SceneWarning> {
    let kind = |w: &SceneWarning| match w.message.split_once(FIRST_EXAMPLE) {
        Some((kind, _)) => kind.to_string(),
        None => w.message.clone(),
    };
    let mut first_of_kind: HashMap<String, usize> = HashMap::new();
    let mut kept: Vec<(SceneWarning, usize)> = Vec::new();
    for warning in warnings {
        match first_of_kind.entry(kind(&warning)) {
            std::collections::hash_map::Entry::Occupied(index) => kept[*index.get()].1 += 1,
            std::collections::hash_map::Entry::Vacant(slot) => {
                slot.insert(kept.len());
                kept.push((warning, 1));
            }
        }
    }
    kept.into_iter()
        .map(|(mut warning, count)| {
            if count > 1 {
                warning.message = format!("{} ({count} times)", warning.message);
            }
            warning
        })
        .collect()
}
