//! Writing meshes to files other tools read.

mod obj;

pub use obj::{save_obj, save_obj_parts, write_obj, write_obj_parts};
