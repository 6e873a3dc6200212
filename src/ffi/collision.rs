//! Collision capsules for the trunk and the main limbs, into the host's memory.

use super::*;
use crate::collision::Capsule;

/// Writes at most `max_capsules` (1..=ARBOR_MAX_CAPSULES) collision capsules of `tree`
/// (the trunk first, then its limbs, thickest first; each ArborCapsule a segment `a` to
/// `b` and a radius, in the conventions of `mesh_options`, NULL: the defaults) for the
/// branches thicker than `min_radius` (model units; 0: a tenth of the trunk's radius).
/// `*count` (when not NULL) gets how many there are; `out` (NULL: count only) holds
/// `capacity` capsules: at least that many, else ARBOR_STATUS_BUFFER_TOO_SMALL and
/// nothing written.
///
/// # Safety
/// `tree` is NULL or live; `mesh_options` is NULL or readable; `out` is NULL or writable
/// for `capacity` capsules; `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_capsules_write(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    max_capsules: u32,
    min_radius: f32,
    out: *mut Capsule,
    capacity: usize,
    count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: passed on from the caller.
        let (tree, mo) = unsafe { tree_in(tree, mesh_options) }?;
        let caps =
            crate::collision::capsules(tree.skeleton(), max_capsules as usize, min_radius, &mo)?;
        if !out.is_null() {
            // SAFETY: the caller promises `out` holds `capacity` writable capsules.
            let dst = unsafe { out_slice(out, capacity, caps.len(), "out") }?;
            for (d, c) in dst.iter_mut().zip(&caps) {
                d.write(*c);
            }
        }
        if !count.is_null() {
            // SAFETY: the caller promises a non-NULL `count` is writable.
            *unsafe { out_ref(count, "count") }? = caps.len();
        }
        Ok(())
    })
}
