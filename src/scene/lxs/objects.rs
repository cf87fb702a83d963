//! `ObjectBegin "name"` … `ObjectEnd` and `ObjectInstance "name"`: LuxRender's (and pbrt's)
//! object instancing. The shapes between `ObjectBegin` and `ObjectEnd` are kept, not drawn,
//! with the transformation current at their definition; each `ObjectInstance` draws them under
//! the transformation current at the instance, so a shape's object-to-world map is
//! CTM(instance) x CTM(definition) (LuxRender 1.x `api.cpp`, pbrt-v1 `api.cpp`).
//! `ObjectBegin` opens an attribute block as `AttributeBegin` does.
//!
//! foton flattens instances into copies of the shapes (the two-level BVH of `accel::instances`
//! is not yet fed by the loader); `--verbose` says how many.

use super::parser::Parser;
use crate::scene::desc::{SceneError, ShapeDesc};

/// The object being defined: its name and its first shape in `SceneDesc::shapes`.
pub(super) struct OpenObject {
    pub name: String,
    pub first_shape: usize,
}

impl Parser {
    pub(super) fn object_begin(&mut self, name: &str, line: usize) -> Result<(), SceneError> {
        if let Some(open) = &self.open_object {
            return Err(self.error(
                line,
                format!(
                    "ObjectBegin \"{name}\" inside ObjectBegin \"{}\"",
                    open.name
                ),
            ));
        }
        self.open_object = Some(OpenObject {
            name: name.to_string(),
            first_shape: self.scene.shapes.len(),
        });
        Ok(())
    }

    /// Moves the shapes defined since `ObjectBegin` into the named object.
    pub(super) fn object_end(&mut self, line: usize) -> Result<(), SceneError> {
        let open = self
            .open_object
            .take()
            .ok_or_else(|| self.error(line, "ObjectEnd without ObjectBegin"))?;
        let shapes: Vec<ShapeDesc> = self.scene.shapes.drain(open.first_shape..).collect();
        if self.objects.insert(open.name.clone(), shapes).is_some() {
            self.warn(line, format!("ObjectBegin \"{}\" redefined", open.name));
        }
        Ok(())
    }

    /// Draws the named object's shapes under the current transformation.
    pub(super) fn object_instance(&mut self, name: &str, line: usize) -> Result<(), SceneError> {
        let shapes = self.objects.get(name).ok_or_else(|| {
            self.error(line, format!("ObjectInstance \"{name}\": no such object"))
        })?;
        let instance_to_world = self.state.ctm;
        let copies: Vec<ShapeDesc> = shapes
            .iter()
            .map(|shape| ShapeDesc {
                object_to_world: instance_to_world * shape.object_to_world,
                ..shape.clone()
            })
            .collect();
        self.instanced_shapes += copies.len();
        self.instance_count += 1;
        self.scene.shapes.extend(copies);
        Ok(())
    }
}
