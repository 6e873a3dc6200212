//! arbor grows 3-D trees and turns them into meshes that go straight into GPU buffers.
//!
//! The pipeline runs one way, with plain data between the stages:
//!
//! ```text
//! tree-model parameters (honda) ──build──▶ Skeleton ──mesh::tubes / write_mesh──▶ Mesh
//!                                                                       │
//!                                                       export::write_obj, C ABI (ffi)
//! ```
//!
//! - [`models::honda`]: the 1996 branching model of Prusinkiewicz, Hammel, Hanan & Měch, with the
//!   paper's trees a–i as presets.
//! - [`skeleton`]: every internode as a [`Branch`]: start, end, radii, parent, depth, order.
//! - [`mesh`]: each branch a truncated cone; 32-byte interleaved [`Vertex`] and `u32`
//!   indices as a triangle list or triangle strips. Size first, then write into any slice.
//! - [`export`]: Wavefront OBJ.
//! - [`ffi`]: the C ABI of `include/arbor.h`.
//!
//! Conventions: right-handed, Y up, the model's own units (the presets have a trunk of 100),
//! counter-clockwise front faces, widths are diameters and radii are half of them.
//!
//! ```
//! use arbor::{mesh, models::honda};
//!
//! let params = honda::HondaParams::preset('g').unwrap();
//! let skeleton = honda::build(&params)?;
//! assert_eq!(skeleton.len(), 1023);
//!
//! // Size first, then write (into a Vec here; a mapped GPU buffer works the same way).
//! let options = mesh::MeshOptions { radial_segments: 6, ..Default::default() };
//! let size = mesh::mesh_size(&skeleton, &options)?;
//! let mut vertices = vec![mesh::Vertex::default(); size.vertices];
//! let mut indices = vec![0u32; size.indices];
//! mesh::write_mesh(&skeleton, &options, &mut vertices, &mut indices)?;
//! assert_eq!(indices.len(), 1023 * 6 * 6);
//! # Ok::<(), arbor::Error>(())
//! ```
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod enums;
pub mod error;
pub mod export;
#[allow(unsafe_code)]
pub mod ffi;
pub mod files;
pub mod forest;
pub mod geom;
pub mod limits;
pub mod lsystem;
pub mod mesh;
pub mod models;
pub mod progress;
pub mod rng;
pub mod skeleton;

pub use error::{Error, Result};
pub use mesh::{Mesh, MeshOptions, Topology, Vertex};
pub use models::honda::HondaParams;
pub use skeleton::{Branch, Skeleton};
