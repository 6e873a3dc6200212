//! Curves: copy, smooth and edit branch curves, and write them as GPU records.

use super::*;
use crate::geom::Curve;
use crate::mesh::{CurveGrowthRecord, CurveRecord};

/// One branch as a cubic Bezier, 56 bytes: p0 is the branch's start, p3 its end.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ArborCurve {
    /// Start.
    pub p0: [f32; 3],
    /// First inner control point (tangent at p0 = 3 (p1 - p0)).
    pub p1: [f32; 3],
    /// Second inner control point (tangent at p3 = 3 (p3 - p2)).
    pub p2: [f32; 3],
    /// End.
    pub p3: [f32; 3],
    /// Radius at p0.
    pub r0: f32,
    /// Radius at p3.
    pub r1: f32,
}

const _: () = assert!(std::mem::size_of::<ArborCurve>() == 56);

/// Copies the curve of every branch of `tree` (branch order) into `out`: `capacity`
/// elements, at least arbor_tree_branch_count(), else ARBOR_STATUS_BUFFER_TOO_SMALL and
/// nothing written. Straight branches have their inner points at the thirds.
///
/// # Safety
/// `tree` is NULL or live; `out` is NULL or valid for writes of `capacity` curves.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_copy_curves(
    tree: *const ArborTree,
    out: *mut ArborCurve,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        let s = tree.skeleton();
        // SAFETY: the caller promises `out` holds `capacity` writable curves.
        let dst = unsafe { out_slice(out, capacity, s.len(), "out") }?;
        for (i, d) in dst.iter_mut().enumerate() {
            let c = s.curve(i);
            let b = &s.branches()[i];
            d.write(ArborCurve {
                p0: c.p0.to_array(),
                p1: c.p1.to_array(),
                p2: c.p2.to_array(),
                p3: c.p3.to_array(),
                r0: b.start_radius,
                r1: b.end_radius,
            });
        }
        Ok(())
    })
}

/// Replaces one branch's curve and radii. `curve->p0` must equal the branch's current
/// start, else ARBOR_STATUS_INVALID_ARGUMENT; every branch that grows from it, directly or
/// not (with its leaf sites and polygons), is translated by p3's displacement, so the
/// tree stays connected. A bad edit (index past the end, NaN, negative radius) changes
/// nothing. The tree's kept mesh plans are brought up to date (in time proportional to the
/// branch's subtree), so arbor_mesh_rewrite_branch() can rewrite only what changed.
///
/// # Safety
/// `tree` is NULL or live and not read by another thread meanwhile; `curve` is NULL or
/// readable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_set_curve(
    tree: *mut ArborTree,
    branch: usize,
    curve: *const ArborCurve,
) -> ArborStatus {
    guard(|| {
        if tree.is_null() {
            return Err(FfiError::null("tree"));
        }
        // SAFETY: non-null; the caller promises it is live and not shared for the call.
        let tree = unsafe { &mut *tree };
        // SAFETY: the caller promises `curve` is NULL or readable.
        let c = unsafe { arg_ref(curve, "curve") }?;
        let v = |p: [f32; 3]| glam::Vec3::from(p);
        let rust = Curve {
            p0: v(c.p0),
            p1: v(c.p1),
            p2: v(c.p2),
            p3: v(c.p3),
        };
        tree.edit_branch(branch, |s| s.set_curve(branch, &rust, c.r0, c.r1))?;
        Ok(())
    })
}

/// Bends every branch of `tree` into a C1 cubic Bezier along its axis (`tension` 0..=2:
/// 0 straight, 1 the usual); no joint moves. The tree's kept mesh plans are dropped.
///
/// # Safety
/// `tree` is NULL or live and not read by another thread meanwhile.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_smooth(tree: *mut ArborTree, tension: f32) -> ArborStatus {
    guard(|| {
        if tree.is_null() {
            return Err(FfiError::null("tree"));
        }
        // SAFETY: non-null; the caller promises it is live and not shared for the call.
        let tree = unsafe { &mut *tree };
        tree.edit(|s| s.smooth(tension))?;
        Ok(())
    })
}

/// Writes one ArborCurveRecord per branch (branch order) into `out` (`capacity` elements,
/// at least arbor_tree_branch_count()).
///
/// # Safety
/// `tree` is NULL or live; `out` is NULL or valid for writes of `capacity` records.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_curve_records_write(
    tree: *const ArborTree,
    out: *mut CurveRecord,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        let n = tree.skeleton().len();
        // SAFETY: the caller promises `out` holds `capacity` writable records (the two
        // record types share one layout, checked in layout.rs).
        let dst = unsafe { out_slice(out.cast::<CurveRecord>(), capacity, n, "out") }?;
        for (d, r) in dst
            .iter_mut()
            .zip(crate::mesh::curve_records(tree.skeleton()))
        {
            d.write(r);
        }
        Ok(())
    })
}

/// As arbor_tree_curve_records_write(), with each record's growth bounds.
///
/// # Safety
/// `tree` is NULL or live; `out` is NULL or valid for writes of `capacity` records.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_curve_growth_records_write(
    tree: *const ArborTree,
    out: *mut CurveGrowthRecord,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        let n = tree.skeleton().len();
        // SAFETY: as above (layouts checked in layout.rs).
        let dst = unsafe { out_slice(out.cast::<CurveGrowthRecord>(), capacity, n, "out") }?;
        for (d, r) in dst
            .iter_mut()
            .zip(crate::mesh::curve_growth_records(tree.skeleton()))
        {
            d.write(r);
        }
        Ok(())
    })
}
