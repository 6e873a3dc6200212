//! Export to files.

use super::*;

/// The tree, mesh options (with the host's progress callback), path and leaf options
/// (NULL: no leaves) every export takes, checked in that order.
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `path` is NULL or
/// NUL-terminated.
unsafe fn export_args<'a>(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    leaf_options: *const ArborLeafOptions,
    path: *const c_char,
) -> Result<ExportArgs<'a>, FfiError> {
    // SAFETY: the caller promises `tree` is NULL or live.
    let tree = unsafe { arg_ref(tree, "tree") }?;
    // SAFETY: the caller promises `mesh_options` is NULL or readable.
    let (mo, threads, progress, user) = unsafe { read_mesh_options_with_progress(mesh_options) }?;
    if path.is_null() {
        return Err(FfiError::null("path"));
    }
    // SAFETY: the caller promises a non-NULL `path` is NUL-terminated.
    let path = unsafe { CStr::from_ptr(path) }
        .to_str()
        .map_err(|_| crate::Error::invalid("path", "the path is not UTF-8"))?;
    let leaves = if leaf_options.is_null() {
        None
    } else {
        // SAFETY: the caller promises a non-NULL `leaf_options` is readable.
        Some(unsafe { read_leaf_options(leaf_options, true) }?)
    };
    Ok((tree, mo, (threads, progress, user), path, leaves))
}

/// What [`export_args`] reads: tree, mesh options, (threads, progress callback, user data), path,
/// leaf options.
type ExportArgs<'a> = (
    &'a ArborTree,
    MeshOptions,
    (u32, ArborProgressFn, *mut c_void),
    &'a str,
    Option<LeafOptions>,
);

/// Writes the bark mesh of `tree` (group `bark`) and, unless `leaf_options` is NULL, its
/// baked leaves (group `leaves`) as a Wavefront OBJ file at `path` (NUL-terminated UTF-8),
/// whole or not at all: written to a temporary file beside it and renamed over it only
/// when complete (a failure or a cancel leaves an existing file as it was; a device or
/// folder of that name is never written). The mesh options' progress callback sees
/// ARBOR_STAGE_MESH, then ARBOR_STAGE_WRITE. ARBOR_STATUS_IO_ERROR names the path on
/// failure.
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `path` is NULL or
/// NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_export_obj(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    leaf_options: *const ArborLeafOptions,
    path: *const c_char,
) -> ArborStatus {
    // SAFETY: as the caller promises (see the function's # Safety).
    unsafe {
        export_with(
            tree,
            mesh_options,
            leaf_options,
            path,
            |s, mo, leaves, path, run| crate::export::save_obj_tree_in(s, mo, leaves, path, run),
        )
    }
}

/// Writes bark (and leaves, when `leaf_options` is not NULL) as glTF 2.0: binary `.glb`,
/// or `.gltf` JSON with the buffer embedded, by the path's extension. Triangle lists,
/// counter-clockwise, Y up, whatever `mesh_options` asks (its sides, scale, tips and curve
/// rings stand; options that contradict themselves, such as an engine preset with another
/// up axis or winding, are refused with `arbor_mesh_size`'s error; the f32 range of
/// positions is checked in the space written); the settings in `asset.extras`.
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `path` is NULL or
/// NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_export_gltf(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    leaf_options: *const ArborLeafOptions,
    path: *const c_char,
) -> ArborStatus {
    // SAFETY: as the caller promises (see the function's # Safety).
    unsafe {
        export_with(
            tree,
            mesh_options,
            leaf_options,
            path,
            |s, mo, leaves, path, run| crate::export::save_gltf_in(s, mo, leaves, path, run),
        )
    }
}

/// What both exports do: read the arguments, then `save` the tree's skeleton with the
/// options and leaves to the path, on the host's threads and reporting to its callback.
///
/// # Safety
/// As [`export_args`].
unsafe fn export_with(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    leaf_options: *const ArborLeafOptions,
    path: *const c_char,
    save: impl FnOnce(
        &Skeleton,
        &MeshOptions,
        Option<&LeafOptions>,
        &str,
        &mut crate::progress::Run<'_>,
    ) -> crate::Result<()>,
) -> ArborStatus {
    guard(|| {
        // SAFETY: passed on from the caller.
        let (tree, mo, (threads, progress, user), path, leaves) =
            unsafe { export_args(tree, mesh_options, leaf_options, path) }?;
        let mut f = progress_closure(progress, user);
        let mut run = run_of(&mut f).threads(threads);
        save(tree.skeleton(), &mo, leaves.as_ref(), path, &mut run)?;
        Ok(())
    })
}
