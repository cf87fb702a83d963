//! The plugin tree of a Mitsuba scene: objects (a tag such as `shape` or `bsdf`, a plugin name such
//! as `obj` or `diffuse`, an optional id), each with typed properties and child objects, nested or
//! referenced. Nothing here knows what a plugin means; the conversion to a scene reads it.

use std::cell::Cell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3};

use super::error::{MitsubaWarning, SourceLoc};

/// Index of an object in [`SceneTree::objects`].
pub type ObjectId = usize;

/// A property's value, as typed in the file.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Float(f64),
    Integer(i64),
    Boolean(bool),
    String(String),
    Point(DVec3),
    Vector(DVec3),
    /// `<rgb>`: linear RGB.
    Rgb(DVec3),
    /// `<spectrum>`: a constant, or wavelength:value pairs already converted to linear RGB.
    Spectrum(DVec3),
    /// `<transform>`: the composed operations.
    Transform(DMat4),
}

impl Value {
    /// The element name that writes this type, for messages.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::Float(_) => "float",
            Value::Integer(_) => "integer",
            Value::Boolean(_) => "boolean",
            Value::String(_) => "string",
            Value::Point(_) => "point",
            Value::Vector(_) => "vector",
            Value::Rgb(_) => "rgb",
            Value::Spectrum(_) => "spectrum",
            Value::Transform(_) => "transform",
        }
    }
}

#[derive(Clone, Debug)]
pub struct Property {
    pub name: String,
    pub value: Value,
    pub loc: SourceLoc,
    /// Set once the conversion reads it, so that unread parameters can be reported.
    pub(crate) used: Cell<bool>,
}

/// A child object: nested in the element, or a `<ref>` to an object with an id.
#[derive(Clone, Debug)]
pub struct Child {
    /// The `name` attribute (`<ref name="reflectance" id="tex"/>`), if any.
    pub name: Option<String>,
    pub object: ObjectId,
    /// Where the nested element or the `<ref>` is.
    pub loc: SourceLoc,
    pub(crate) used: Cell<bool>,
}

#[derive(Clone, Debug)]
pub struct Object {
    /// The element: `scene`, `shape`, `bsdf`, `emitter`, `sensor`, `film`, `sampler`, `rfilter`,
    /// `integrator`, `texture`, `spectrum`, `medium`, ...
    pub tag: String,
    /// The `type` attribute, lower case: the plugin.
    pub plugin: String,
    pub id: Option<String>,
    pub props: Vec<Property>,
    pub children: Vec<Child>,
    pub loc: SourceLoc,
}

impl Object {
    /// The property `name`, marked as read.
    pub fn prop(&self, name: &str) -> Option<&Property> {
        let p = self.props.iter().rev().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    /// Children with element `tag`, in file order, marked as read.
    pub fn children_tagged<'a>(
        &'a self,
        tree: &'a SceneTree,
        tag: &'a str,
    ) -> impl Iterator<Item = (&'a Child, &'a Object)> + 'a {
        self.children.iter().filter_map(move |c| {
            let object = &tree.objects[c.object];
            (object.tag == tag).then(|| {
                c.used.set(true);
                (c, object)
            })
        })
    }

    /// The child given for parameter `name` (`<texture name="reflectance" .../>` or
    /// `<ref name="reflectance" id=.../>`), marked as read.
    pub fn named_child<'a>(&'a self, tree: &'a SceneTree, name: &str) -> Option<&'a Object> {
        let c = self
            .children
            .iter()
            .rev()
            .find(|c| c.name.as_deref() == Some(name))?;
        c.used.set(true);
        Some(&tree.objects[c.object])
    }

    /// Properties and children nobody has read: what the conversion skipped.
    pub fn unused(&self) -> impl Iterator<Item = (&str, &SourceLoc)> {
        let props = self
            .props
            .iter()
            .filter(|p| !p.used.get())
            .map(|p| (p.name.as_str(), &p.loc));
        let children = self
            .children
            .iter()
            .filter(|c| !c.used.get())
            .map(|c| (c.name.as_deref().unwrap_or("(nested object)"), &c.loc));
        props.chain(children)
    }

    /// `tag "plugin"` (and the id), for messages.
    pub fn describe(&self) -> String {
        match &self.id {
            Some(id) => format!("{} \"{}\" (id \"{id}\")", self.tag, self.plugin),
            None => format!("{} \"{}\"", self.tag, self.plugin),
        }
    }
}

/// A parsed scene: every object (the root is a `scene`), the folders that relative file names
/// are resolved against, and the warnings met while reading.
#[derive(Clone, Debug)]
pub struct SceneTree {
    pub objects: Vec<Object>,
    pub root: ObjectId,
    /// Objects by `id` (aliases included).
    pub ids: HashMap<String, ObjectId>,
    /// Tried in order for a relative file name: folders added by `<path>` (last added first), then
    /// the folder of the main scene file.
    pub search_paths: Vec<PathBuf>,
    pub warnings: Vec<MitsubaWarning>,
}

impl SceneTree {
    pub fn root(&self) -> &Object {
        &self.objects[self.root]
    }

    /// The file a scene names, as Mitsuba's file resolver finds it: absolute names as they are,
    /// relative ones in the first search folder that has them (or in the main scene's folder if
    /// none does, so that an error names a plausible path).
    pub fn resolve(&self, name: &str) -> PathBuf {
        resolve_in(&self.search_paths, name)
    }
}

/// [`SceneTree::resolve`] with the folders given.
pub fn resolve_in(search_paths: &[PathBuf], name: &str) -> PathBuf {
    let path = Path::new(name);
    if path.is_absolute() {
        return path.to_path_buf();
    }
    search_paths
        .iter()
        .map(|dir| dir.join(path))
        .find(|p| p.exists())
        .unwrap_or_else(|| {
            search_paths
                .last()
                .map_or_else(|| path.to_path_buf(), |dir| dir.join(path))
        })
}
