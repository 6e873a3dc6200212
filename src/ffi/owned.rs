//! Owned mesh buffers that the tube writer fills straight, without a zero fill first: the
//! one use of `unsafe` that serves the Rust API rather than a C entry point, kept here so
//! that every `unsafe` block of the crate lives in this module.

use crate::error::{Error, Result};
use crate::mesh::{MeshPlan, Vertex};
use crate::progress::Run;
use crate::skeleton::Skeleton;

/// The vertices and indices of `plan`'s mesh of `skeleton` in vectors of exactly the
/// plan's size, written in `run` by [`MeshPlan::write_uninit_in`] into their fresh
/// capacity. A zeroed allocation of reused memory is a `memset` of the whole mesh that the
/// write then overwrites (a tenth of building and meshing a small tree).
pub(crate) fn tube_buffers(
    plan: &MeshPlan,
    skeleton: &Skeleton,
    run: &mut Run<'_>,
) -> Result<(Vec<Vertex>, Vec<u32>)> {
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
    Ok((vertices, indices))
}
