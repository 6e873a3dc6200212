//! The C ABI: the only module with `unsafe` code, a thin shell over the Rust API that
//! nothing below it imports.
//!
//! `include/arbor.h` is generated from this module by cbindgen (see `cbindgen.toml`) and
//! committed; a test regenerates it and fails on any difference. Each export is a thin
//! shell: argument checks, a panic guard, conversion, then a call into the Rust API.
//!
//! Rust users do not need this module; it is public so that its documentation and the
//! layouts it fixes can be read here too.

mod collision;
mod curves;
mod export;
mod files;
mod forest;
mod formats;
mod ground;
mod growth;
mod guard;
mod handle;
mod layout;
mod leaves;
mod lod;
mod lsystem;
mod meshes;
#[cfg(test)]
mod mirror_gen;
mod wind;
#[rustfmt::skip]
mod mirrors;
mod options;
pub(crate) mod owned;
mod species;
mod status;
mod tree;

pub use collision::*;
pub use curves::*;
pub use export::*;
pub use files::*;
pub use forest::*;
pub use formats::*;
pub use ground::*;
pub use growth::*;
pub use layout::*;
pub use leaves::*;
pub use lod::*;
pub use lsystem::*;
pub use meshes::*;
pub use mirrors::*;
use options::*;
pub use species::*;
pub use status::*;
pub use tree::*;
pub use wind::*;

use crate::lsystem::{LSystem, LsystemOptions, MAX_SOURCE_BYTES};
use crate::mesh::{
    self, AnimationVertex, BranchRange, CurveGrowthRecord, CurveRecord, LeafInstance, LeafOptions,
    LeafPrefab, MeshOptions, Vertex, VertexCompact, VertexFormat,
};
use crate::models::honda::{self, HondaParams};
use crate::skeleton::{Branch, LeafSite, Organ, Skeleton};
use bytemuck::{Pod, Zeroable};
use guard::{
    FfiError, arg_ref, copy_out, guard, guard_value, in_slice, mesh_buffers, out_ref, out_slice,
    with_last_error, write_if_given,
};
use handle::Handle;
use std::ffi::{CStr, c_char, c_void};

#[cfg(test)]
mod tests;
