//! Writing meshes to files other tools read.

mod gltf;
mod obj;

pub(crate) use gltf::save_gltf_reporting;
pub use gltf::{
    gltf_bytes, gltf_bytes_instanced, gltf_forest_bytes, gltf_forest_nodes_bytes, save_gltf,
    save_gltf_forest, save_gltf_forest_nodes, save_gltf_with_progress,
};
pub use obj::{save_obj, save_obj_parts, write_obj, write_obj_parts};
