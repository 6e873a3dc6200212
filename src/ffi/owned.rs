//! Owned meshes for the C ABI (`arbor_mesh_create`, the OBJ export): the tube writer fills
//! the buffers' fresh capacity straight, without the zero fill of the Rust API's
//! [`MeshPlan::mesh_in`], which a host that creates and frees meshes would pay on every
//! call (the allocator hands reused memory back, which `calloc` must clear).

use crate::error::{Error, Result};
use crate::mesh::{Mesh, MeshPlan, Vertex};
use crate::progress::Run;
use crate::skeleton::Skeleton;

/// `plan`'s owned mesh of `skeleton`, its buffers of exactly the plan's size, written in
/// `run` by [`MeshPlan::write_uninit_in`] into their fresh capacity. A zeroed allocation of
/// reused memory is a `memset` of the whole mesh that the write then overwrites (a third
/// of creating the mesh of a small tree).
pub(crate) fn owned_mesh(plan: &MeshPlan, skeleton: &Skeleton, run: &mut Run<'_>) -> Result<Mesh> {
    let size = plan.size();
    let mut vertices =
        crate::limits::try_with_capacity::<Vertex>(size.vertices, "the mesh's vertices")?;
    let mut indices = crate::limits::try_with_capacity::<u32>(size.indices, "the mesh's indices")?;
    let written = plan.write_uninit_in(
        skeleton,
        &mut vertices.spare_capacity_mut()[..size.vertices],
        &mut indices.spare_capacity_mut()[..size.indices],
        run,
    )?;
    if written != size {
        return Err(Error::invalid(
            "plan",
            format!("wrote {written:?} of a mesh sized {size:?}"),
        ));
    }
    // SAFETY: `write_uninit_in` returned Ok with the counts `size`, and on success it has
    // initialised every slot of those counts' prefixes of the slices it was given (its
    // documented contract; each writer checks that it filled its range exactly). Those
    // prefixes are the first `size.vertices` and `size.indices` slots of the vectors'
    // capacity, which `try_with_capacity` reserved, so the lengths stay within capacity.
    unsafe {
        vertices.set_len(size.vertices);
        indices.set_len(size.indices);
    }
    Ok(plan.owned_mesh(vertices, indices))
}
