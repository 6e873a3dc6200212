//! Meshes: every branch of a [`Skeleton`](crate::Skeleton) as a truncated cone, in GPU-ready buffers.
//!
//! Size first ([`mesh_size`], exact counts), then write into caller slices
//! ([`write_mesh`]), so a host can fill a mapped GPU buffer directly; or [`tubes`] for owned
//! `Vec`s allocated once at their exact size.
//!
//! Each branch gets two rings of `radial_segments + 1` vertices (the seam vertex is
//! duplicated so `u` runs 0..=1 around the circumference), first the ring at `start`, then
//! the ring at `end`. `v` runs from 0 at `start` to 1 at `end`. Normals are those of the
//! cone: outward, tilted toward the narrow end when the branch tapers. Front faces are
//! counter-clockwise seen from outside.

mod topology;
mod tubes;

pub use topology::Triangles;
pub use tubes::{mesh_size, tubes, write_mesh, write_mesh_uninit};

use bytemuck::{Pod, Zeroable};

/// Index that separates strips in [`Topology::TriangleStripRestart`] output: OpenGL's
/// `GL_PRIMITIVE_RESTART_FIXED_INDEX` for 32-bit indices.
pub const RESTART_INDEX: u32 = u32::MAX;

/// Fewest sides a branch may have.
pub const MIN_RADIAL_SEGMENTS: u32 = 3;
/// Most sides a branch may have.
pub const MAX_RADIAL_SEGMENTS: u32 = 64;

/// One vertex: 32 bytes, interleaved, the layout of the C type `ArborVertex`.
///
/// Attribute offsets: position 0, normal 12, uv 24; stride 32.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    /// Position in the skeleton's units.
    pub position: [f32; 3],
    /// Unit outward normal.
    pub normal: [f32; 3],
    /// `u` around the circumference (0..=1, seam duplicated), `v` along the branch (0..=1).
    pub uv: [f32; 2],
}

const _: () = {
    assert!(std::mem::size_of::<Vertex>() == 32);
    assert!(std::mem::offset_of!(Vertex, position) == 0);
    assert!(std::mem::offset_of!(Vertex, normal) == 12);
    assert!(std::mem::offset_of!(Vertex, uv) == 24);
};

/// How the index buffer strings triangles together. The numbers are those of the C enum
/// `ArborTopology`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Topology {
    /// Three indices per triangle (what Unity and Unreal take).
    #[default]
    TriangleList = 0,
    /// One strip per branch, strips separated by [`RESTART_INDEX`] (OpenGL
    /// `GL_PRIMITIVE_RESTART_FIXED_INDEX`).
    TriangleStripRestart = 1,
    /// One strip for the whole mesh, branches joined by degenerate triangles.
    TriangleStripDegenerate = 2,
}

impl Topology {
    /// All topologies, in their numeric order.
    pub const ALL: [Topology; 3] = [
        Topology::TriangleList,
        Topology::TriangleStripRestart,
        Topology::TriangleStripDegenerate,
    ];

    /// The topology with C number `value`, `None` for an unknown number.
    pub fn from_u32(value: u32) -> Option<Self> {
        Self::ALL.get(value as usize).copied()
    }
}

/// Options of the tube mesher. Plain data; `Default` gives the documented defaults.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshOptions {
    /// Sides of each truncated cone, 3..=64. Default 8.
    pub radial_segments: u32,
    /// Index buffer layout. Default [`Topology::TriangleList`].
    pub topology: Topology,
}

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            radial_segments: 8,
            topology: Topology::TriangleList,
        }
    }
}

/// Exact element counts of a mesh's two buffers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshSize {
    /// Number of [`Vertex`] elements.
    pub vertices: usize,
    /// Number of `u32` indices (restart indices included).
    pub indices: usize,
}

/// An owned mesh: vertex and index buffers and the topology of the indices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Interleaved vertices.
    pub vertices: Vec<Vertex>,
    /// Indices into `vertices`, laid out as `topology` says.
    pub indices: Vec<u32>,
    /// How `indices` strings triangles together.
    pub topology: Topology,
}

impl Mesh {
    /// The mesh's triangles as index triples in front-face (counter-clockwise) order,
    /// whatever the topology; degenerate strip triangles are skipped.
    pub fn triangles(&self) -> Triangles<'_> {
        Triangles::new(&self.indices, self.topology)
    }
}
