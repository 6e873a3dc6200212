//! Writing meshes to files other tools read.

mod gltf;
mod obj;

pub use gltf::{gltf_bytes, gltf_bytes_instanced, gltf_forest_bytes, save_gltf, save_gltf_forest};
pub use obj::{save_obj, save_obj_parts, write_obj, write_obj_parts};
