//! Export to files.

use super::*;

/// The tree, mesh options and path every export takes, checked in that order.
///
/// # Safety
/// `tree` is NULL or live; `mesh_options` is NULL or readable; `path` is NULL or
/// NUL-terminated.
unsafe fn export_args<'a>(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    path: *const c_char,
) -> Result<(&'a ArborTree, MeshOptions, &'a str), FfiError> {
    // SAFETY: the caller promises `tree` is NULL or live.
    let tree = unsafe { arg_ref(tree, "tree") }?;
    // SAFETY: the caller promises `mesh_options` is NULL or readable.
    let mo = unsafe { read_mesh_options(mesh_options) }?;
    if path.is_null() {
        return Err(FfiError::null("path"));
    }
    // SAFETY: the caller promises a non-NULL `path` is NUL-terminated.
    let path = unsafe { CStr::from_ptr(path) }
        .to_str()
        .map_err(|_| crate::Error::invalid("path", "the path is not UTF-8"))?;
    Ok((tree, mo, path))
}

/// Writes the bark mesh of `tree` (group `bark`) and, unless `leaf_options` is NULL, its
/// baked leaves (group `leaves`) as a Wavefront OBJ file at `path` (NUL-terminated UTF-8),
/// creating or truncating it. ARBOR_STATUS_IO_ERROR names the path on failure.
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
    guard(|| {
        // SAFETY: as the caller promises (see the function's # Safety).
        let (tree, mo, path) = unsafe { export_args(tree, mesh_options, path) }?;
        // SAFETY: export_args read the same options, so they are readable.
        let (_, progress, user) = unsafe { read_mesh_options_with_progress(mesh_options) }?;
        let plan = mesh::MeshPlan::new(&tree.skeleton, &mo)?;
        let bark = match progress_closure(progress, user) {
            Some(mut f) => plan.mesh_with_progress(&tree.skeleton, &mut f)?,
            None => plan.mesh(&tree.skeleton)?,
        };
        let result = if leaf_options.is_null() {
            crate::export::save_obj_parts(&[("bark", &bark)], path)
        } else {
            // SAFETY: the caller promises `leaf_options` is readable.
            let lo = unsafe { read_leaf_options(leaf_options, true) }?;
            let leaves = mesh::leaf_mesh(&tree.skeleton, &lo, &mo)?;
            crate::export::save_obj_parts(&[("bark", &bark), ("leaves", &leaves)], path)
        };
        result.map_err(|e| match e {
            crate::Error::Io(io) => crate::Error::Io(std::io::Error::new(
                io.kind(),
                format!("cannot write {path}: {io}"),
            )),
            other => other,
        })?;
        Ok(())
    })
}

/// Writes bark (and leaves, when `leaf_options` is not NULL) as glTF 2.0: binary `.glb`,
/// or `.gltf` JSON with the buffer embedded, by the path's extension. Triangle lists,
/// counter-clockwise, Y up, whatever `mesh_options` asks (its sides, scale, tips and curve
/// rings stand); the settings in `asset.extras`.
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
    guard(|| {
        // SAFETY: as the caller promises (see the function's # Safety).
        let (tree, mo, path) = unsafe { export_args(tree, mesh_options, path) }?;
        let leaves = if leaf_options.is_null() {
            None
        } else {
            // SAFETY: the caller promises `leaf_options` is readable.
            Some(unsafe { read_leaf_options(leaf_options, true) }?)
        };
        // SAFETY: export_args read the same options, so they are readable.
        let (_, progress, user) = unsafe { read_mesh_options_with_progress(mesh_options) }?;
        let (skeleton, leaves) = (&tree.skeleton, leaves.as_ref());
        match progress_closure(progress, user) {
            Some(mut f) => {
                crate::export::save_gltf_with_progress(skeleton, &mo, leaves, path, &mut f)?
            }
            None => crate::export::save_gltf(skeleton, &mo, leaves, path)?,
        }
        Ok(())
    })
}
