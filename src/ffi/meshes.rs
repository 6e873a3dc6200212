//! Bark meshes: options, size then write, branch ranges, levels of detail, owned meshes, the animation stream.

use super::*;
use crate::progress::Run;

/// sizeof(ArborMeshOptions) of its first layout (up to `scale`): the smallest
/// `struct_size` accepted.
pub const ARBOR_MESH_OPTIONS_MIN_SIZE: usize = 52;

growing!(ArborMeshOptions as "ArborMeshOptions", ARBOR_MESH_OPTIONS_MIN_SIZE,
    first_added: threads, defaults: Self::from_rust(&MeshOptions::default()));

impl Default for ArborMeshOptions {
    /// What arbor_mesh_options_init() writes for this library's size.
    fn default() -> Self {
        Self::defaults()
    }
}

/// Writes the default mesh options (see ArborMeshOptions for each default) into the first
/// `struct_size` bytes at `options`, with `options->struct_size = struct_size`, and
/// nothing beyond; pass `sizeof(ArborMeshOptions)`. The header's static inline
/// arbor_mesh_options_default() does this for you. NULL does nothing.
///
/// # Safety
/// `options` is NULL or writable for `struct_size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_options_init(
    options: *mut ArborMeshOptions,
    struct_size: usize,
) {
    // SAFETY: the caller promises `struct_size` writable bytes at `options`.
    unsafe { init_for_host(options, struct_size) }
}

/// The options behind `options`, or the defaults for NULL, with the host's thread count
/// (`threads`, which the Rust API keeps in a [`Run`]).
///
/// # Safety
/// `options` is NULL or points to a readable ArborMeshOptions.
pub(crate) unsafe fn read_mesh_options(
    options: *const ArborMeshOptions,
) -> Result<(MeshOptions, u32), FfiError> {
    // SAFETY: passed on from the caller.
    let (o, threads, _, _) = unsafe { read_mesh_options_with_progress(options) }?;
    Ok((o, threads))
}

/// `tree` and the conventions of `mesh_options` (NULL: the defaults) it is drawn in.
///
/// # Safety
/// `tree` is NULL or live; `mesh_options` is NULL or readable.
pub(crate) unsafe fn tree_in<'a>(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
) -> Result<(&'a ArborTree, MeshOptions), FfiError> {
    // SAFETY: the caller promises `tree` is NULL or live.
    let tree = unsafe { arg_ref(tree, "tree") }?;
    // SAFETY: the caller promises `mesh_options` is NULL or readable.
    let (mo, _) = unsafe { read_mesh_options(mesh_options) }?;
    Ok((tree, mo))
}

/// The mesh options at `options` with the host's thread count and progress callback
/// (NULL: none).
///
/// # Safety
/// As [`read_mesh_options`].
pub(crate) unsafe fn read_mesh_options_with_progress(
    options: *const ArborMeshOptions,
) -> Result<(MeshOptions, u32, ArborProgressFn, *mut c_void), FfiError> {
    if options.is_null() {
        return Ok((MeshOptions::default(), 0, None, std::ptr::null_mut()));
    }
    // SAFETY: the caller promises `options` is readable for its struct_size bytes; NULL
    // was handled above.
    let o = unsafe { read_growing(options, "options") }?;
    Ok((o.to_rust()?, o.threads, o.progress, o.progress_user_data))
}

/// A run on the host's `threads` (no callback).
pub(crate) fn on_threads(threads: u32) -> Run<'static> {
    Run::default().threads(threads)
}

/// The `count` mesh options of a host's array: its elements are the host's
/// ArborMeshOptions, all of the first one's `struct_size`, so element k starts at byte
/// k x `levels[0].struct_size`.
///
/// # Safety
/// `levels` is NULL (only with `count` 0) or readable for `count` elements of the host's
/// ArborMeshOptions.
pub(crate) unsafe fn read_mesh_options_array(
    levels: *const ArborMeshOptions,
    count: usize,
) -> Result<Vec<(MeshOptions, u32)>, FfiError> {
    // SAFETY: passed on from the caller.
    let levels = unsafe { read_growing_array(levels, count, "levels") }?;
    levels
        .into_iter()
        .enumerate()
        .map(|(k, o)| {
            let rust = o.to_rust().map_err(|e| FfiError::from(e).at_level(k))?;
            Ok((rust, o.threads))
        })
        .collect()
}

/// Writes the exact number of vertices and indices arbor_mesh_write() needs for `tree`
/// with `options` (NULL: the defaults). Both out-pointers are required and written only
/// on success. More than 2^32 - 1 vertices: ARBOR_STATUS_LIMIT_EXCEEDED.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; the counts are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_size(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    vertex_count: *mut usize,
    index_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let (options, threads) = unsafe { read_mesh_options(options) }?;
        // SAFETY: the caller promises both are NULL or writable.
        let vc = unsafe { out_ref(vertex_count, "vertex_count") }?;
        // SAFETY: as above.
        let ic = unsafe { out_ref(index_count, "index_count") }?;
        let size = tree.plan_in(&options, &on_threads(threads))?.size();
        *vc = size.vertices;
        *ic = size.indices;
        Ok(())
    })
}

/// Writes the mesh of `tree` into caller memory (a malloc'd array or a mapped GPU buffer):
/// `vertex_capacity` ArborVertex elements and `index_capacity` uint32_t indices. Capacities
/// below arbor_mesh_size()'s counts give ARBOR_STATUS_BUFFER_TOO_SMALL and nothing is
/// written; larger buffers are fine and only their first elements are written. A buffer
/// may be NULL only when its count is 0.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `vertices` and `indices` are
/// NULL or valid for writes of their capacities and do not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_write(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    vertices: *mut Vertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live and `options` NULL or readable.
        let w = unsafe { MeshWrite::read(tree, options) }?;
        // SAFETY: the caller promises both hold their capacities, writable, apart.
        let (v, i) =
            unsafe { mesh_buffers(vertices, vertex_capacity, indices, index_capacity, w.size()) }?;
        w.write(v, i)
    })
}

/// What every mesh write reads first: the tree, its options with the host's progress
/// callback, and the plan the tree keeps for them.
pub(super) struct MeshWrite<'a> {
    tree: &'a ArborTree,
    pub(super) options: MeshOptions,
    threads: u32,
    progress: ArborProgressFn,
    user: *mut c_void,
    plan: std::sync::Arc<mesh::MeshPlan>,
}

impl MeshWrite<'_> {
    /// # Safety
    /// `tree` is NULL or live; `options` is NULL or readable.
    pub(super) unsafe fn read(
        tree: *const ArborTree,
        options: *const ArborMeshOptions,
    ) -> Result<Self, FfiError> {
        // SAFETY: passed on from the caller.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: passed on from the caller.
        let (options, threads, progress, user) =
            unsafe { read_mesh_options_with_progress(options) }?;
        let plan = tree.plan_in(&options, &on_threads(threads))?;
        Ok(MeshWrite {
            tree,
            options,
            threads,
            progress,
            user,
            plan,
        })
    }

    pub(super) fn size(&self) -> mesh::MeshSize {
        self.plan.size()
    }

    /// Writes the mesh into the host's slots on the options' threads, reporting to the
    /// host's callback.
    pub(super) fn write<V: mesh::VertexSlot>(
        &self,
        vertices: &mut [V],
        indices: &mut [std::mem::MaybeUninit<u32>],
    ) -> Result<(), FfiError> {
        let mut f = progress_closure(self.progress, self.user);
        let mut run = run_of(&mut f).threads(self.threads);
        self.plan
            .write_uninit_in(self.tree.skeleton(), vertices, indices, &mut run)?;
        Ok(())
    }
}

/// Rewrites, inside buffers that hold the complete mesh of `tree` written with `options`
/// (`vertex_count` / `index_count`: their full sizes, those of arbor_mesh_size()), only
/// what the edits (arbor_tree_set_curve() of `branch`, or others) changed: the result
/// equals a full arbor_mesh_write() byte for byte, for every buffer that holds a full
/// write made at any time since the tree's plan for `options` was made (each rewrite
/// covers every branch edited since then, so two buffers, or two threads each with their
/// own, are all brought up to date; the work grows with the edits, never past a full
/// write). Branch ranges stay as they were
/// (an edit that would change them drops the plan; then, and when no plan for `options`
/// is kept, this writes the whole mesh, still correctly). For a twig of a large tree this
/// is thousands of times faster than a full write; rewrite the vertex range from
/// arbor_mesh_branch_ranges() with glBufferSubData. Sizes other than the mesh's:
/// ARBOR_STATUS_BUFFER_TOO_SMALL or INVALID_ARGUMENT; a branch past the end:
/// INVALID_ARGUMENT.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `vertices` and `indices` are
/// NULL or valid for reads and writes of their counts and hold the mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_rewrite_branch(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    branch: usize,
    vertices: *mut Vertex,
    vertex_count: usize,
    indices: *mut u32,
    index_count: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live and `options` NULL or
        // readable, and the buffers' counts.
        unsafe {
            rewrite_branch(
                tree,
                options,
                branch,
                vertices,
                vertex_count,
                indices,
                index_count,
            )
        }
    })
}

/// Both rewrites' one path, for vertices of type `T`.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `vertices` is NULL or valid for
/// reads and writes of `vertex_count` elements of `T`, `indices` of `index_count`.
pub(super) unsafe fn rewrite_branch<T>(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    branch: usize,
    vertices: *mut T,
    vertex_count: usize,
    indices: *mut u32,
    index_count: usize,
) -> Result<(), FfiError>
where
    std::mem::MaybeUninit<T>: mesh::VertexSlot,
{
    // SAFETY: the caller promises `tree` is NULL or live.
    let tree = unsafe { arg_ref(tree, "tree") }?;
    // SAFETY: the caller promises `options` is NULL or readable.
    let (options, threads) = unsafe { read_mesh_options(options) }?;
    let n = tree.skeleton().len();
    if branch >= n {
        return Err(crate::Error::invalid(
            "branch",
            format!("{branch}; the tree has {n} branches"),
        )
        .into());
    }
    let kept = tree.pending(&options);
    let (plan, pending) = match &kept {
        Some((plan, pending)) => (plan.clone(), pending.clone()),
        None => (tree.plan_in(&options, &on_threads(threads))?, Vec::new()),
    };
    let size = plan.size();
    if vertex_count != size.vertices || index_count != size.indices {
        return Err(crate::Error::invalid(
            "vertex_count",
            format!(
                "buffers of {vertex_count} vertices and {index_count} indices; the mesh \
                 has {} and {}: size and write it again",
                size.vertices, size.indices
            ),
        )
        .into());
    }
    // SAFETY: the caller promises `vertices` holds `vertex_count` elements.
    let v = unsafe { out_slice(vertices, vertex_count, size.vertices, "vertices") }?;
    if kept.is_none() {
        // No plan was kept through the edits: write everything (the indices too).
        // SAFETY: the caller promises `indices` holds `index_count` indices.
        let i = unsafe { out_slice(indices, index_count, size.indices, "indices") }?;
        plan.write_uninit_in(tree.skeleton(), v, i, &mut on_threads(threads))?;
        return Ok(());
    }
    plan.rewrite_uninit(tree.skeleton(), &pending, v)?;
    Ok(())
}

/// Copies, for each branch of `tree`, the vertices and indices it owns in the mesh that
/// arbor_mesh_write() writes with `options` (NULL: the defaults): `capacity` elements,
/// at least arbor_tree_branch_count(), else ARBOR_STATUS_BUFFER_TOO_SMALL. The ranges are
/// consecutive and tile both buffers; a culled branch has empty ranges.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `out` is NULL or valid for
/// writes of `capacity` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_branch_ranges(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    out: *mut BranchRange,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let (options, threads) = unsafe { read_mesh_options(options) }?;
        let n = tree.skeleton().len();
        // SAFETY: the caller promises `out` holds `capacity` writable elements.
        let dst = unsafe { out_slice(out.cast::<BranchRange>(), capacity, n, "out") }?;
        let ranges = tree.plan_in(&options, &on_threads(threads))?.ranges();
        for (d, r) in dst.iter_mut().zip(ranges) {
            d.write(r);
        }
        Ok(())
    })
}

/// Sizes of several levels of detail in one call: `levels` holds `level_count` mesh
/// options (for example growing cull_radius, fewer radial_segments), all initialised with
/// the same struct_size (element k is read at byte k x `levels[0].struct_size`); the counts
/// of level k go to `vertex_counts[k]` and `index_counts[k]`.
///
/// # Safety
/// `tree` is NULL or live; `levels` is NULL (only with `level_count` 0) or readable for
/// `level_count` options; the count arrays are NULL or writable for `level_count` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_lod_size(
    tree: *const ArborTree,
    levels: *const ArborMeshOptions,
    level_count: usize,
    vertex_counts: *mut usize,
    index_counts: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `levels` is readable for `level_count` options.
        let levels = unsafe { read_mesh_options_array(levels, level_count) }?;
        let sizes = levels
            .iter()
            .map(|(o, threads)| Ok(tree.plan_in(o, &on_threads(*threads))?.size()))
            .collect::<Result<Vec<_>, FfiError>>()?;
        // SAFETY: the caller promises both arrays hold `level_count` writable elements.
        let vc = unsafe { out_slice(vertex_counts, level_count, level_count, "vertex_counts") }?;
        // SAFETY: as above.
        let ic = unsafe { out_slice(index_counts, level_count, level_count, "index_counts") }?;
        for ((v, i), s) in vc.iter_mut().zip(ic.iter_mut()).zip(sizes) {
            v.write(s.vertices);
            i.write(s.indices);
        }
        Ok(())
    })
}

/// Writes several levels of detail in one call: level k into `vertices[k]` (capacity
/// `vertex_capacities[k]`) and `indices[k]` (capacity `index_capacities[k]`). Every
/// capacity is checked before anything is written.
///
/// # Safety
/// `tree` is NULL or live; `levels`, `vertices`, `vertex_capacities`, `indices` and
/// `index_capacities` are NULL (only with `level_count` 0) or readable for `level_count`
/// elements; each buffer pointer is NULL or valid for writes of its capacity, and no two
/// buffers overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_lod_write(
    tree: *const ArborTree,
    levels: *const ArborMeshOptions,
    level_count: usize,
    vertices: *const *mut Vertex,
    vertex_capacities: *const usize,
    indices: *const *mut u32,
    index_capacities: *const usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises each array is readable for `level_count` elements.
        let (levels, vs, vcaps, is, icaps) = unsafe {
            (
                read_mesh_options_array(levels, level_count)?,
                in_slice(vertices, level_count, "vertices")?,
                in_slice(vertex_capacities, level_count, "vertex_capacities")?,
                in_slice(indices, level_count, "indices")?,
                in_slice(index_capacities, level_count, "index_capacities")?,
            )
        };
        let mut plans = Vec::with_capacity(level_count);
        for (k, (o, threads)) in levels.iter().enumerate() {
            let plan = tree.plan_in(o, &on_threads(*threads))?;
            let size = plan.size();
            size.check_capacity(vcaps[k], icaps[k])
                .map_err(|e| FfiError::from(e).at_level(k))?;
            plans.push((plan, size));
        }
        for (k, (plan, size)) in plans.into_iter().enumerate() {
            // SAFETY: the caller promises the level's buffers hold their capacities.
            let v =
                unsafe { out_slice(vs[k].cast::<Vertex>(), vcaps[k], size.vertices, "vertices") }
                    .map_err(|e| e.at_level(k))?;
            // SAFETY: as above.
            let i = unsafe { out_slice(is[k], icaps[k], size.indices, "indices") }
                .map_err(|e| e.at_level(k))?;
            let mut run = on_threads(levels[k].1);
            plan.write_uninit_in(tree.skeleton(), v, i, &mut run)?;
        }
        Ok(())
    })
}

/// A mesh arbor owns (made by arbor_mesh_create(), arbor_leaf_mesh_create() or
/// arbor_forest_mesh_create()): for hosts that prefer to read buffers in place and copy
/// them where they like. Opaque; free with arbor_mesh_free(). A
/// `const ArborMesh *` may be read from several threads at once.
pub struct ArborMesh {
    pub(crate) mesh: crate::Mesh,
}

/// Builds the bark mesh of `tree` with `options` (NULL: the defaults) into a new mesh
/// object written to `*out` (free it with arbor_mesh_free()); read it with
/// arbor_mesh_vertices() and arbor_mesh_indices(). `*out` is written only on success.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_create(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    out: *mut *mut ArborMesh,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let (options, threads, progress, user) =
            unsafe { read_mesh_options_with_progress(options) }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let plan = tree.plan_in(&options, &on_threads(threads))?;
        let mut f = progress_closure(progress, user);
        let mesh =
            super::owned::owned_mesh(&plan, tree.skeleton(), &mut run_of(&mut f).threads(threads))?;
        *out = ArborMesh { mesh }.into_handle();
        Ok(())
    })
}

/// The vertices of `mesh`, valid until arbor_mesh_free(); their number goes to `*count`
/// (if `count` is not NULL). NULL mesh: returns NULL and a count of 0.
///
/// # Safety
/// `mesh` is NULL or live; `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_vertices(
    mesh: *const ArborMesh,
    count: *mut usize,
) -> *const Vertex {
    guard_value(std::ptr::null(), || {
        // SAFETY: the caller promises `mesh` is NULL or live.
        let m = unsafe { arg_ref(mesh, "mesh") }.ok();
        let v = m.map_or(&[][..], |m| &m.mesh.vertices[..]);
        // SAFETY: the caller promises `count` is NULL or writable.
        if let Ok(c) = unsafe { out_ref(count, "count") } {
            *c = v.len();
        }
        if m.is_some() {
            v.as_ptr().cast()
        } else {
            std::ptr::null()
        }
    })
}

/// The indices of `mesh` (laid out as arbor_mesh_topology() says), valid until
/// arbor_mesh_free(); their number goes to `*count` (if `count` is not NULL). NULL mesh:
/// returns NULL and a count of 0.
///
/// # Safety
/// `mesh` is NULL or live; `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_indices(
    mesh: *const ArborMesh,
    count: *mut usize,
) -> *const u32 {
    guard_value(std::ptr::null(), || {
        // SAFETY: the caller promises `mesh` is NULL or live.
        let m = unsafe { arg_ref(mesh, "mesh") }.ok();
        let i = m.map_or(&[][..], |m| &m.mesh.indices[..]);
        // SAFETY: the caller promises `count` is NULL or writable.
        if let Ok(c) = unsafe { out_ref(count, "count") } {
            *c = i.len();
        }
        if m.is_some() {
            i.as_ptr()
        } else {
            std::ptr::null()
        }
    })
}

/// The ArborTopology of `mesh`'s indices (ARBOR_TOPOLOGY_TRIANGLE_LIST for NULL).
///
/// # Safety
/// `mesh` is NULL or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_topology(mesh: *const ArborMesh) -> u32 {
    guard_value(0, || {
        // SAFETY: the caller promises `mesh` is NULL or live.
        unsafe { arg_ref(mesh, "mesh") }.map_or(0, |m| m.mesh.topology as u32)
    })
}

/// Frees a mesh. NULL does nothing. Pointers from arbor_mesh_vertices() and
/// arbor_mesh_indices() become invalid.
///
/// # Safety
/// `mesh` is NULL or a mesh from this library not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_free(mesh: *mut ArborMesh) {
    // SAFETY: the caller promises `mesh` is NULL or a live mesh of this library.
    unsafe { ArborMesh::free_handle(mesh) }
}

/// Writes the animation stream of the mesh arbor_mesh_write() makes with `options` (NULL:
/// defaults): `capacity` elements, at least the vertex count of arbor_mesh_size().
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `out` is NULL or valid for
/// writes of `capacity` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_animation_write(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    out: *mut AnimationVertex,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let (options, threads) = unsafe { read_mesh_options(options) }?;
        let data = tree
            .plan_in(&options, &on_threads(threads))?
            .animation(tree.skeleton())?;
        // SAFETY: the caller promises `out` holds `capacity` writable elements.
        let dst = unsafe {
            out_slice(
                out.cast::<mesh::AnimationVertex>(),
                capacity,
                data.len(),
                "out",
            )
        }?;
        for (d, v) in dst.iter_mut().zip(data) {
            d.write(v);
        }
        Ok(())
    })
}
