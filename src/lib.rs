//! arbor grows 3-D trees and turns them into meshes that go straight into GPU buffers.
//!
//! The pipeline runs one way, with plain data between the stages:
//!
//! ```text
//! cpfg grammar (lsystem) ──derive──▶ ModuleString ──interpret──┐
//! 1996 model (models::honda) ──build───────────────────────────┼──▶ Skeleton ──mesh──▶ Mesh, buffers
//! self-organizing world (models::growth) ──step, tree──────────┘        │            │
//!                                                         leaves, edits ┘   export: glTF, OBJ
//! ```
//!
//! **Sources of skeletons**
//! - [`lsystem`]: parametric L-systems in the language of cpfg (preprocessor, view files,
//!   conditions, stochastic and context-sensitive productions, statements, query modules,
//!   curve, function and surface files), derived and read by a 3-D turtle.
//! - [`models::honda`]: the 1996 branching model of Prusinkiewicz, Hammel, Hanan & Měch, with
//!   the paper's trees a–i as presets.
//! - [`models::growth`]: self-organizing trees (Pałubicki 2009) competing for light or
//!   space in a [`World`](models::growth::World) of obstacles.
//! - [`forest`]: many placed trees from any source, meshed into one buffer.
//!
//! **The skeleton and its meshes**
//! - [`skeleton`]: every internode as a [`Branch`]: start, end, radii, parent, birth, order,
//!   a curve an artist can bend; leaf sites, organs and polygons; collision pruning.
//! - [`mesh`]: each branch a truncated cone or a sweep along its curve; 32-byte interleaved
//!   [`Vertex`] and `u32` indices as a triangle list or triangle strips; leaves as
//!   instances or baked quads and prefabs; a [`PlanCache`](mesh::PlanCache) that re-meshes
//!   only the branches an edit touched. Size first, then write into any slice.
//! - [`export`]: glTF 2.0 (`.glb`, `.gltf`, instanced leaves, forests) and Wavefront OBJ,
//!   each written whole or not at all.
//!
//! **Running and limits**
//! - [`progress`]: one run context ([`Run`](progress::Run)): threads, progress and
//!   cancellation, taken the same way by every long operation's `_in` form.
//! - [`files`]: what a model may read (its folder, nothing, anything, or the host's
//!   reader) and how much.
//! - [`limits`]: the default bounds on modules, branches, vertices and leaves.
//! - [`error`]: one [`Error`] naming what, where and what was expected.
//! - [`enums`]: the numbered enums shared with C, with their names.
//! - [`geom`], [`rng`]: the turtle's frames, curves, grids and the seeded random stream.
//!
//! **Hosts**
//! - [`ffi`]: the C ABI of `include/arbor.h` (C, C++, C# and other hosts).
//!
//! Option structs (`MeshOptions`, `LeafOptions`, `LsystemOptions`, `WorldOptions`,
//! `FileOptions`, `Variation`) are `#[non_exhaustive]`: start from `Default` (or a preset)
//! and set fields, or chain their setters; each but `FileOptions` (whose every value is
//! valid) checks itself with `validate()`, as every call that takes it does.
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
//! let options = mesh::MeshOptions::default().radial_segments(6);
//! let size = mesh::mesh_size(&skeleton, &options)?;
//! let mut vertices = vec![mesh::Vertex::default(); size.vertices];
//! let mut indices = vec![0u32; size.indices];
//! mesh::write_mesh(&skeleton, &options, &mut vertices, &mut indices)?;
//! assert_eq!(indices.len(), 1023 * 6 * 6);
//! # Ok::<(), arbor::Error>(())
//! ```
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod collision;
pub mod enums;
pub mod error;
pub mod export;
#[allow(unsafe_code)]
pub mod ffi;
pub mod files;
pub mod forest;
pub mod geom;
pub mod impostor;
pub mod limits;
pub mod lod;
pub mod lsystem;
pub mod mesh;
pub mod models;
mod options;
pub mod progress;
pub mod raster;
pub mod rng;
pub mod scene;
pub mod skeleton;
pub mod source;
pub mod species;
pub mod texture;
pub mod wind;

pub use error::{Error, Result};
pub use mesh::{Mesh, MeshOptions, Topology, Vertex};
pub use models::honda::HondaParams;
pub use skeleton::{Branch, Skeleton};
