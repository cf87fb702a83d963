//! `ObjectBegin "name"` … `ObjectEnd` and `ObjectInstance "name"`: LuxRender's (and pbrt's)
//! object instancing. The shapes between `ObjectBegin` and `ObjectEnd` are kept, not drawn,
//! with the transformation current at their definition; each `ObjectInstance` draws them under
//! the transformation current at the instance, so a shape's object-to-world map is
//! CTM(instance) x CTM(definition) (LuxRender 1.x `api.cpp`, pbrt-v1 `api.cpp`).
//! `ObjectBegin` opens an attribute block as `AttributeBegin` does.
//!
//! An object becomes a shape group (`SceneDesc::shape_groups`) and each instance a
//! [`Geometry::Instance`] of it: its meshes are built once and placed by the second level of
//! the BVH (`accel::instances`), with their normals, uvs and materials. The instance level
//! emits no light, so an object's emitting shapes are copied into each instance instead
//! (`--verbose` says how many of each).

use super::parser::Parser;
use crate::scene::desc::{Geometry, SceneError, ShapeDesc};

/// The object being defined: its name and its first shape in `SceneDesc::shapes`.
pub(super) struct OpenObject {
    pub name: String,
    pub first_shape: usize,
}

/// A defined object: its shape group (`None` when all its shapes emit) and the emitting
/// shapes each instance copies.
pub(super) struct Object {
    group: Option<usize>,
    emitters: Vec<ShapeDesc>,
}

/// What the instances drew, for `--verbose`.
#[derive(Default)]
pub(super) struct InstanceCounts {
    pub instances: usize,
    pub shared_shapes: usize,
    pub copied_emitters: usize,
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
        let (emitters, members): (Vec<ShapeDesc>, Vec<ShapeDesc>) = (self.scene.shapes)
            .drain(open.first_shape..)
            .partition(|shape| shape.area_light.is_some());
        let group = (!members.is_empty()).then(|| {
            self.scene.shape_groups.push(members);
            self.scene.shape_groups.len() - 1
        });
        if (self.objects)
            .insert(open.name.clone(), Object { group, emitters })
            .is_some()
        {
            self.warn(line, format!("ObjectBegin \"{}\" redefined", open.name));
        }
        Ok(())
    }

    /// Places the named object under the current transformation.
    pub(super) fn object_instance(&mut self, name: &str, line: usize) -> Result<(), SceneError> {
        let object = self.objects.get(name).ok_or_else(|| {
            self.error(line, format!("ObjectInstance \"{name}\": no such object"))
        })?;
        let instance_to_world = self.state.ctm;
        let copies = (object.emitters.iter()).map(|shape| ShapeDesc {
            object_to_world: instance_to_world * shape.object_to_world,
            ..shape.clone()
        });
        let instance = object.group.map(|group| ShapeDesc {
            geometry: Geometry::Instance { group },
            object_to_world: instance_to_world,
            material: None,
            area_light: None,
            location: self.location(line),
        });
        let shared = object
            .group
            .map_or(0, |group| self.scene.shape_groups[group].len());
        let placed: Vec<ShapeDesc> = instance.into_iter().chain(copies).collect();
        self.instance_counts.instances += 1;
        self.instance_counts.shared_shapes += shared;
        self.instance_counts.copied_emitters += object.emitters.len();
        self.scene.shapes.extend(placed);
        Ok(())
    }

    /// The note `--verbose` prints about instancing, if the scene has instances.
    pub(super) fn instance_note(&self) -> Option<String> {
        let counts = &self.instance_counts;
        (counts.instances > 0).then(|| {
            format!(
                "{} ObjectInstance of {} objects: {} shapes placed as instances of shared \
                 shapes, {} emitting shapes copied (the instance level emits no light)",
                counts.instances,
                self.objects.len(),
                counts.shared_shapes,
                counts.copied_emitters
            )
        })
    }
}
