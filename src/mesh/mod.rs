//! Meshes: every branch of a [`Skeleton`](crate::skeleton::Skeleton) as a truncated cone, in GPU-ready buffers.
//!
//! Size first ([`mesh_size`], exact counts), then write into caller slices
//! ([`write_mesh`]), so a host can fill a mapped GPU buffer directly; or [`tubes`] for owned
//! `Vec`s allocated once at their exact size.
//!
//! Each branch is a truncated cone between two rings of `segments + 1` vertices (the seam
//! vertex is duplicated so `u` runs 0..=1 around the circumference). With mitred joints
//! (the default) a branch that continues its parent's axis shares the parent's end ring,
//! placed in the plane that bisects the bend, so an axis is one watertight tube; a lateral
//! branch starts with its own ring sunk into its parent. Rings are oriented by parallel
//! transport along the tree, so seams do not twist. `v` is the arc length from the root
//! divided by [`MeshOptions::texture_scale`]. Normals are those of the cone, outward.
//! Front faces are counter-clockwise seen from outside unless [`Winding::Clockwise`].
//!
//! Per branch, vertices are written in this order: its own start ring (if it does not
//! share its parent's), its end ring, a base cap (roots, if asked), then its tip (a cap or
//! a point, for the last branch of an axis, if asked); indices follow the same order.

mod animation;
mod cache;
mod compact;
mod leaves;
mod lod;
mod options;
mod plan;
mod quantize;
mod records;
mod rings;
mod strips;
mod sweep;
mod topology;
mod tube;
mod tubes;

pub use animation::{AnimationVertex, AnimationVertexCompact, animation};
pub use cache::PlanCache;
pub use compact::{VertexCompact, VertexSlot};
pub use leaves::{
    LeafInstance, LeafOptions, LeafPrefab, Placed, keep_for, leaf_animation, leaf_branches,
    leaf_cell, leaf_cells, leaf_instances, leaf_mesh, leaf_mesh_placed, leaf_mesh_size, place_all,
    write_leaf_mesh,
};
pub use lod::{LodLevel, mesh_lods};
pub use options::{Axes, Joints, MeshOptions, Tip, Topology, UpAxis, VertexFormat, Winding};
pub(crate) use options::{check_fields, check_options};
pub(crate) use plan::branch_sides;
pub use plan::{BranchRange, MeshPlan};
pub use records::{CurveGrowthRecord, CurveRecord, curve_growth_records, curve_records};
pub(crate) use rings::Out;
pub(crate) use rings::Slot;
pub use topology::Triangles;
pub use tubes::{branch_ranges, mesh_size, tubes, write_mesh, write_mesh_uninit};

use bytemuck::{Pod, Zeroable};

/// Index that separates strips in triangle-strip-restart output (ARBOR_RESTART_INDEX in
/// C): OpenGL's GL_PRIMITIVE_RESTART_FIXED_INDEX for 32-bit indices.
pub const RESTART_INDEX: u32 = u32::MAX;

/// Fewest sides a branch may have (`radial_segments`, `min_radial_segments`).
pub const MIN_RADIAL_SEGMENTS: u32 = 3;
/// Most sides a branch may have (`radial_segments`).
pub const MAX_RADIAL_SEGMENTS: u32 = 64;

/// One mesh vertex (C: ArborVertex), 32 bytes, interleaved: position at offset 0, normal
/// at 12, uv at 24; stride 32.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    /// Position in the skeleton's units.
    pub position: [f32; 3],
    /// Unit outward normal.
    pub normal: [f32; 3],
    /// u around the branch (0..1, the seam vertex duplicated); v along it: the arc length
    /// from the root divided by the mesh options' `texture_scale` (so v grows past 1 on
    /// any branch longer than `texture_scale`: tree a reaches about 400 at scale 1).
    pub uv: [f32; 2],
}

const _: () = {
    assert!(std::mem::size_of::<Vertex>() == 32);
    assert!(std::mem::offset_of!(Vertex, position) == 0);
    assert!(std::mem::offset_of!(Vertex, normal) == 12);
    assert!(std::mem::offset_of!(Vertex, uv) == 24);
};

/// Exact element counts of a mesh's two buffers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshSize {
    /// Number of [`Vertex`] elements.
    pub vertices: usize,
    /// Number of `u32` indices (restart indices included).
    pub indices: usize,
}

impl MeshSize {
    /// [`Error::BufferTooSmall`](crate::error::Error::BufferTooSmall) naming the first buffer
    /// whose capacity is below this size.
    pub fn check_capacity(&self, vertices: usize, indices: usize) -> crate::error::Result<()> {
        for (buffer, required, capacity) in [
            ("vertices", self.vertices, vertices),
            ("indices", self.indices, indices),
        ] {
            if capacity < required {
                return Err(crate::error::Error::BufferTooSmall {
                    buffer,
                    required,
                    capacity,
                });
            }
        }
        Ok(())
    }
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
    /// For each branch of the skeleton (or leaf, for a leaf mesh), the vertices and indices
    /// it owns; they tile both buffers in order. Empty where not recorded.
    pub ranges: Vec<BranchRange>,
}

impl Mesh {
    /// The mesh's triangles as index triples in front-face (counter-clockwise) order,
    /// whatever the topology; degenerate strip triangles are skipped.
    pub fn triangles(&self) -> Triangles<'_> {
        Triangles::new(&self.indices, self.topology)
    }
}
