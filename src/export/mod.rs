//! Writing meshes and [scenes](crate::scene) to files other tools read.
//!
//! Every `save_*` function writes its file whole or not at all (a temporary file beside
//! it, flushed and renamed over it): a failure or a cancel leaves an existing file as it
//! was and no partial file.

mod atomic;
mod gltf;
mod obj;

pub use gltf::{
    gltf_bytes, gltf_bytes_instanced, gltf_mesh_options, gltf_scene_bytes, save_gltf, save_gltf_in,
    save_gltf_instanced, save_gltf_instanced_in, save_gltf_scene, save_gltf_world,
};
pub use obj::{
    save_obj, save_obj_parts, save_obj_parts_in, save_obj_scene, save_obj_tree, save_obj_tree_in,
    write_obj, write_obj_parts,
};
