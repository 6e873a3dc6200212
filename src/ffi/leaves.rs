//! Leaves: instances and baked leaf meshes.

use super::*;

/// A leaf shape loaded once (see arbor_leaf_prefab_load()). Opaque; free with
/// arbor_leaf_prefab_free(). A `const ArborLeafPrefab *` may be used from several threads
/// at once.
pub struct ArborLeafPrefab(std::sync::Arc<LeafPrefab>);

/// Loads the OBJ file at `obj_path` (NUL-terminated UTF-8) as a leaf shape, read under the
/// file policy of `options` (its `file_access`, `read_file` and `max_file_bytes`; NULL: the
/// defaults; its `prefab_obj_path` and `prefab` are not read), and writes the handle to
/// `*out`. Set it as ArborLeafOptions.prefab so that sizing and writing leaf meshes do not
/// read the file again. ARBOR_STATUS_IO_ERROR if it cannot be read, PARSE_ERROR if it is
/// not an OBJ with triangles.
///
/// # Safety
/// `obj_path` is NULL or NUL-terminated; `options` is NULL or readable; `out` is NULL or
/// writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_prefab_load(
    obj_path: *const c_char,
    options: *const ArborLeafOptions,
    out: *mut *mut ArborLeafPrefab,
) -> ArborStatus {
    guard(|| {
        if obj_path.is_null() {
            return Err(FfiError::null("obj_path"));
        }
        // SAFETY: the caller promises a NUL-terminated path.
        let path = unsafe { CStr::from_ptr(obj_path) }
            .to_str()
            .map_err(|_| crate::Error::invalid("obj_path", "the path is not UTF-8"))?;
        let o = if options.is_null() {
            ArborLeafOptions::default()
        } else {
            // SAFETY: the caller promises `options` is readable for its struct_size bytes.
            unsafe { read_growing(options, "options") }?
        };
        let files = file_options(
            o.file_access,
            o.read_file,
            o.read_file_user_data,
            o.max_file_bytes,
        )?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let prefab = LeafPrefab::from_obj_with(path, &files)?;
        *out = ArborLeafPrefab(std::sync::Arc::new(prefab)).into_handle();
        Ok(())
    })
}

/// The number of triangles of a loaded leaf shape; 0 for NULL.
///
/// # Safety
/// `prefab` is NULL or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_prefab_triangle_count(prefab: *const ArborLeafPrefab) -> usize {
    // SAFETY: the caller promises `prefab` is NULL or live.
    guard_value(0, || {
        unsafe { prefab.as_ref() }.map_or(0, |p| p.0.triangles.len())
    })
}

/// Frees a leaf shape; NULL does nothing. Options that point to it must not be used after.
///
/// # Safety
/// `prefab` is NULL or a live handle from arbor_leaf_prefab_load(), freed once.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_prefab_free(prefab: *mut ArborLeafPrefab) {
    // SAFETY: the caller promises `prefab` is NULL or a live prefab of this library.
    unsafe { ArborLeafPrefab::free_handle(prefab) }
}

/// sizeof(ArborLeafOptions) of its first layout (up to `prefab_obj_path`): the smallest
/// `struct_size` accepted.
pub const ARBOR_LEAF_OPTIONS_MIN_SIZE: usize = 56;

growing!(ArborLeafOptions as "ArborLeafOptions", ARBOR_LEAF_OPTIONS_MIN_SIZE,
    first_added: max_leaves, defaults: Self::from_rust(&LeafOptions::default()));

impl Default for ArborLeafOptions {
    /// What arbor_leaf_options_init() writes for this library's size.
    fn default() -> Self {
        Self::defaults()
    }
}

const _: () = assert!(std::mem::size_of::<LeafInstance>() == 32);

/// Writes the default leaf options into the first `struct_size` bytes at `options`
/// (pass `sizeof(ArborLeafOptions)`), with `options->struct_size = struct_size`, and
/// nothing beyond. The header's static inline arbor_leaf_options_default() does this for
/// you. NULL does nothing.
///
/// # Safety
/// `options` is NULL or writable for `struct_size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_options_init(
    options: *mut ArborLeafOptions,
    struct_size: usize,
) {
    // SAFETY: the caller promises `struct_size` writable bytes at `options`.
    unsafe { init_for_host(options, struct_size) }
}

/// The leaf options behind `options` (NULL: the defaults); `load_prefab` reads the OBJ.
///
/// # Safety
/// `options` is NULL or readable, its `prefab_obj_path` NULL or NUL-terminated and its
/// `prefab` NULL or live.
pub(crate) unsafe fn read_leaf_options(
    options: *const ArborLeafOptions,
    load_prefab: bool,
) -> Result<LeafOptions, FfiError> {
    if options.is_null() {
        return Ok(LeafOptions::default());
    }
    // SAFETY: the caller promises `options` is readable for its struct_size bytes; NULL
    // was handled above.
    let o = &unsafe { read_growing(options, "leaf_options") }?;
    let files = file_options(
        o.file_access,
        o.read_file,
        o.read_file_user_data,
        o.max_file_bytes,
    )?;
    if !o.prefab.is_null() && !o.prefab_obj_path.is_null() {
        return Err(crate::Error::invalid(
            "prefab",
            "set together with prefab_obj_path; expected one of them",
        )
        .into());
    }
    // SAFETY: the caller promises a non-NULL `prefab` is a live handle.
    let prefab = if let Some(handle) = unsafe { o.prefab.as_ref() } {
        Some(handle.0.clone())
    } else if load_prefab && !o.prefab_obj_path.is_null() {
        // SAFETY: the caller promises a non-NULL path is NUL-terminated.
        let path = unsafe { CStr::from_ptr(o.prefab_obj_path) };
        let path = path
            .to_str()
            .map_err(|_| crate::Error::invalid("prefab_obj_path", "the path is not UTF-8"))?;
        Some(std::sync::Arc::new(LeafPrefab::from_obj_with(
            path, &files,
        )?))
    } else {
        None
    };
    Ok(LeafOptions {
        prefab,
        ..o.to_rust()?
    })
}

/// What the leaf calls read first: the tree, the leaf options (`load_prefab`: reading the
/// prefab's OBJ) and the mesh options, NULL options meaning the defaults.
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable, as [`read_leaf_options`].
unsafe fn leaf_args<'t>(
    tree: *const ArborTree,
    leaf_options: *const ArborLeafOptions,
    mesh_options: *const ArborMeshOptions,
    load_prefab: bool,
) -> Result<(&'t ArborTree, LeafOptions, MeshOptions), FfiError> {
    // SAFETY: the caller promises `tree` is NULL or live.
    let tree = unsafe { arg_ref(tree, "tree") }?;
    // SAFETY: the caller promises `leaf_options` is NULL or readable.
    let lo = unsafe { read_leaf_options(leaf_options, load_prefab) }?;
    // SAFETY: the caller promises `mesh_options` is NULL or readable.
    let (mo, _) = unsafe { read_mesh_options(mesh_options) }?;
    Ok((tree, lo, mo))
}

/// Writes the number of leaf instances of `tree` with `leaf_options` (NULL: defaults) to
/// `*count`; `mesh_options` (NULL: defaults) supplies the up axis and scale.
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_instance_count(
    tree: *const ArborTree,
    leaf_options: *const ArborLeafOptions,
    mesh_options: *const ArborMeshOptions,
    count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises each is NULL or live (readable).
        let (tree, lo, mo) = unsafe { leaf_args(tree, leaf_options, mesh_options, false) }?;
        // SAFETY: the caller promises `count` is NULL or writable.
        let count = unsafe { out_ref(count, "count") }?;
        *count = mesh::leaf_instances(tree.skeleton(), &lo, &mo)?.len();
        Ok(())
    })
}

/// Writes the leaf instances of `tree` into `out` (`capacity` elements, at least
/// arbor_leaf_instance_count()'s, else ARBOR_STATUS_BUFFER_TOO_SMALL and nothing written).
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `out` is NULL or valid for
/// writes of `capacity` instances.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_instances_write(
    tree: *const ArborTree,
    leaf_options: *const ArborLeafOptions,
    mesh_options: *const ArborMeshOptions,
    out: *mut LeafInstance,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises each is NULL or live (readable).
        let (tree, lo, mo) = unsafe { leaf_args(tree, leaf_options, mesh_options, false) }?;
        let leaves = mesh::leaf_instances(tree.skeleton(), &lo, &mo)?;
        // SAFETY: the caller promises `out` holds `capacity` writable instances.
        let dst = unsafe { out_slice(out.cast::<LeafInstance>(), capacity, leaves.len(), "out") }?;
        for (d, l) in dst.iter_mut().zip(leaves) {
            d.write(l);
        }
        Ok(())
    })
}

/// Exact vertex and index counts of the baked leaf mesh (every leaf a copy of the leaf
/// shape, then the grammar's polygons), in the topology and conventions of
/// `mesh_options` (NULL: defaults).
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; the counts NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_mesh_size(
    tree: *const ArborTree,
    leaf_options: *const ArborLeafOptions,
    mesh_options: *const ArborMeshOptions,
    vertex_count: *mut usize,
    index_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises each is NULL or live (readable).
        let (tree, lo, mo) = unsafe { leaf_args(tree, leaf_options, mesh_options, true) }?;
        // SAFETY: the caller promises both are NULL or writable.
        let vc = unsafe { out_ref(vertex_count, "vertex_count") }?;
        // SAFETY: as above.
        let ic = unsafe { out_ref(index_count, "index_count") }?;
        let size = mesh::leaf_mesh_size(tree.skeleton(), &lo, &mo)?;
        *vc = size.vertices;
        *ic = size.indices;
        Ok(())
    })
}

/// Writes the baked leaf mesh into caller memory; the same buffer rules as
/// arbor_mesh_write().
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `vertices` and `indices` are
/// NULL or valid for writes of their capacities and do not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_mesh_write(
    tree: *const ArborTree,
    leaf_options: *const ArborLeafOptions,
    mesh_options: *const ArborMeshOptions,
    vertices: *mut Vertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises each is NULL or live (readable).
        let (tree, lo, mo) = unsafe { leaf_args(tree, leaf_options, mesh_options, true) }?;
        let size = mesh::leaf_mesh_size(tree.skeleton(), &lo, &mo)?;
        // SAFETY: the caller promises both hold their capacities, writable, apart.
        let (v, i) =
            unsafe { mesh_buffers(vertices, vertex_capacity, indices, index_capacity, size) }?;
        mesh::write_leaf_mesh(tree.skeleton(), &lo, &mo, v, i)?;
        Ok(())
    })
}

/// Like arbor_mesh_create() for the baked leaf mesh (see arbor_leaf_mesh_write()).
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_mesh_create(
    tree: *const ArborTree,
    leaf_options: *const ArborLeafOptions,
    mesh_options: *const ArborMeshOptions,
    out: *mut *mut ArborMesh,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises each is NULL or live (readable).
        let (tree, lo, mo) = unsafe { leaf_args(tree, leaf_options, mesh_options, true) }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let mesh = mesh::leaf_mesh(tree.skeleton(), &lo, &mo)?;
        *out = ArborMesh { mesh }.into_handle();
        Ok(())
    })
}
