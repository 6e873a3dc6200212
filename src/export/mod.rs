//! Writing meshes to files other tools read.
//!
//! Every `save_*` function writes its file whole or not at all (a temporary file beside
//! it, flushed and renamed over it): a failure or a cancel leaves an existing file as it
//! was and no partial file.

mod atomic;
mod gltf;
mod obj;

pub(crate) use gltf::save_gltf_reporting;
pub use gltf::{
    gltf_bytes, gltf_bytes_instanced, gltf_forest_bytes, gltf_forest_nodes_bytes, save_gltf,
    save_gltf_forest, save_gltf_forest_nodes, save_gltf_instanced,
    save_gltf_instanced_with_progress, save_gltf_with_progress,
};
pub(crate) use obj::save_obj_parts_reporting;
pub use obj::{save_obj, save_obj_parts, save_obj_parts_with_progress, write_obj, write_obj_parts};
