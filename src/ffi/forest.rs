//! Forests: many placed trees in one mesh.

use super::*;

/// One tree of a forest: the 1996 model's parameters, a variation seed (0: none) and its
/// placement (position of its root, turn about the up axis in degrees, uniform scale).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArborForestTree {
    /// The model's parameters.
    pub params: HondaParams,
    /// Variation seed, as arbor_tree_from_honda_varied(); 0 for none.
    pub seed: u64,
    /// Where the root stands, in the output space of the mesh options.
    pub position: [f32; 3],
    /// Turn about the up axis, degrees.
    pub rotation: f32,
    /// Uniform scale, > 0.
    pub scale: f32,
}

/// Grows `count` trees (on all cores when arbor is built with its `parallel` feature),
/// places them and merges them into one new mesh object written to `*out` (read it with
/// arbor_mesh_vertices() / arbor_mesh_indices(), free it with arbor_mesh_free()).
///
/// # Safety
/// `trees` is NULL (only with `count` 0) or readable for `count` elements; `options` is
/// NULL or readable; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_mesh_create(
    trees: *const ArborForestTree,
    count: usize,
    options: *const ArborMeshOptions,
    out: *mut *mut ArborMesh,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `trees` is readable for `count` elements.
        let trees = unsafe { read_forest(trees, count) }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let (options, threads) = unsafe { read_mesh_options(options) }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let mesh = crate::forest::merged_in(&trees, &options, &on_threads(threads))?;
        *out = ArborMesh { mesh }.into_handle();
        Ok(())
    })
}

/// The placed forest of `trees` as Rust values.
///
/// # Safety
/// `trees` is NULL (only with `count` 0) or readable for `count` elements.
pub(crate) unsafe fn read_forest<'a>(
    trees: *const ArborForestTree,
    count: usize,
) -> Result<Vec<crate::forest::Placed<'a>>, FfiError> {
    // SAFETY: the caller promises `trees` is readable for `count` elements.
    let trees = unsafe { in_slice(trees, count, "trees") }?;
    Ok(trees
        .iter()
        .map(|t| crate::forest::Placed {
            item: crate::forest::Item {
                source: crate::forest::Source::Honda(t.params),
                seed: t.seed,
            },
            position: t.position,
            rotation: t.rotation,
            scale: t.scale,
        })
        .collect())
}

/// Exact vertex and index counts of the merged forest mesh arbor_forest_mesh_write()
/// writes (the trees are grown to count them; arbor_forest_mesh_create() grows them once).
///
/// # Safety
/// `trees` is NULL (only with `count` 0) or readable for `count` elements; `options` is
/// NULL or readable; the counts are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_mesh_size(
    trees: *const ArborForestTree,
    count: usize,
    options: *const ArborMeshOptions,
    vertex_count: *mut usize,
    index_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `trees` is readable for `count` elements.
        let placed = unsafe { read_forest(trees, count) }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let (options, threads) = unsafe { read_mesh_options(options) }?;
        // SAFETY: the caller promises both counts are NULL or writable.
        let vc = unsafe { out_ref(vertex_count, "vertex_count") }?;
        // SAFETY: as above.
        let ic = unsafe { out_ref(index_count, "index_count") }?;
        let size = crate::forest::merged_size_in(&placed, &options, &on_threads(threads))?;
        *vc = size.vertices;
        *ic = size.indices;
        Ok(())
    })
}

/// Writes the merged forest mesh into caller memory; the buffer rules of
/// arbor_mesh_write().
///
/// # Safety
/// As arbor_forest_mesh_size(), and `vertices` / `indices` are NULL or valid for writes
/// of their capacities and do not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_mesh_write(
    trees: *const ArborForestTree,
    count: usize,
    options: *const ArborMeshOptions,
    vertices: *mut Vertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `trees` is readable for `count` elements.
        let placed = unsafe { read_forest(trees, count) }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let (options, threads, progress, user) =
            unsafe { read_mesh_options_with_progress(options) }?;
        let whole = mesh::MeshSize {
            vertices: vertex_capacity,
            indices: index_capacity,
        };
        // SAFETY: the caller promises both hold their capacities, writable, apart.
        let (v, i) =
            unsafe { mesh_buffers(vertices, vertex_capacity, indices, index_capacity, whole) }?;
        // Grows and meshes every tree once; checks the capacities before writing.
        let mut f = progress_closure(progress, user);
        let mut run = run_of(&mut f).threads(threads);
        crate::forest::write_merged_uninit_in(&placed, &options, v, i, &mut run)?;
        Ok(())
    })
}
