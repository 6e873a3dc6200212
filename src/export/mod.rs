//! Writing meshes to files other tools read.

mod obj;

pub use obj::{save_obj, write_obj};
