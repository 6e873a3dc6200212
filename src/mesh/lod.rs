//! Levels of detail: several meshes of one tree in one call.

use super::{Mesh, MeshOptions, tubes};
use crate::error::Result;
use crate::skeleton::Skeleton;

/// One level of detail made by [`mesh_lods`].
#[derive(Clone, Debug, PartialEq)]
pub struct LodLevel {
    /// The mesh of this level.
    pub mesh: Mesh,
    /// Its number of vertices.
    pub vertex_count: usize,
    /// Its number of triangles (degenerate strip joins not counted).
    pub triangle_count: usize,
}

/// Several levels of detail of one tree in one call (for example the same options with
/// growing `cull_radius` and shrinking `radial_segments`), each with its counts.
pub fn mesh_lods(skeleton: &Skeleton, levels: &[MeshOptions]) -> Result<Vec<LodLevel>> {
    levels
        .iter()
        .map(|o| {
            let mesh = tubes(skeleton, o)?;
            Ok(LodLevel {
                vertex_count: mesh.vertices.len(),
                triangle_count: mesh.triangles().count(),
                mesh,
            })
        })
        .collect()
}
