//! Mitsuba 3 XML scenes (format versions 0.4 to 3.x), read with quick-xml into a plugin tree
//! ([`tree::SceneTree`]): objects with a type, a plugin name, an id, typed properties and child
//! objects, each with the file, line and column it came from. Older scenes are upgraded as Mitsuba
//! upgrades them (`upgrade`).

pub mod conductors;
pub mod convert;
pub mod dom;
pub mod emitters;
pub mod error;
pub mod materials;
pub mod parser;
pub mod shapes;
pub mod spectrum;
pub mod transform;
pub mod tree;
pub mod upgrade;

pub use convert::load_with;
pub use error::{MitsubaError, MitsubaWarning, SourceLoc};
pub use parser::{parse_file, parse_str};
pub use tree::{Object, ObjectId, SceneTree, Value};

#[cfg(test)]
mod tests;
