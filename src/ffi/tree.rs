//! Trees: the 1996 model, copies of branches and leaf sites, variation and pruning.

use super::*;

/// A generated tree (its branch skeleton). Opaque; create with arbor_tree_from_honda(),
/// arbor_tree_from_lsystem() or arbor_tree_from_branches(), free with arbor_tree_free().
/// A `const ArborTree *` may be read from several threads at once.
///
/// The tree keeps the mesh plans (layout of every branch) of the last few mesh options it
/// was sized or written with, so arbor_mesh_size() followed by arbor_mesh_write(), or a
/// re-upload, computes the layout once and allocates nothing in proportion to the tree.
pub struct ArborTree(pub(crate) crate::mesh::PlanCache);

impl ArborTree {
    pub(crate) fn new(skeleton: Skeleton) -> Self {
        ArborTree(crate::mesh::PlanCache::new(skeleton))
    }
}

impl std::ops::Deref for ArborTree {
    type Target = crate::mesh::PlanCache;
    fn deref(&self) -> &Self::Target {
        &self.0
    }
}

impl std::ops::DerefMut for ArborTree {
    fn deref_mut(&mut self) -> &mut Self::Target {
        &mut self.0
    }
}

/// Writes the parameters of the paper's tree `name` ('a'..'i', upper case accepted) to
/// `*out`. Unknown name: ARBOR_STATUS_INVALID_ARGUMENT; `out` NULL:
/// ARBOR_STATUS_NULL_ARGUMENT.
///
/// # Safety
/// `out` is NULL or valid for writes of one ArborHondaParams.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_honda_preset(name: u32, out: *mut HondaParams) -> ArborStatus {
    guard(|| {
        let params = char::from_u32(name)
            .and_then(HondaParams::preset)
            .ok_or_else(|| {
                FfiError::invalid(format!(
                    "invalid argument `name`: unknown preset {name:#x}; expected 'a'..'i'"
                ))
            })?;
        // SAFETY: the caller promises `out` is NULL or writable.
        *unsafe { out_ref(out, "out") }? = params;
        Ok(())
    })
}

/// Grows the 1996 model with `params` and writes a new tree to `*out` (free it with
/// arbor_tree_free). Every field is validated (ARBOR_STATUS_INVALID_ARGUMENT names the
/// field); a model that would make more than 16,777,216 branches returns
/// ARBOR_STATUS_LIMIT_EXCEEDED at once. `*out` is written only on success.
///
/// # Safety
/// `params` is NULL or points to an ArborHondaParams; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_from_honda(
    params: *const HondaParams,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `params` is NULL or readable.
        let params: HondaParams = *unsafe { arg_ref(params, "params") }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let skeleton = crate::source::Source::Honda(params).grow(0)?;
        *out = ArborTree::new(skeleton).into_handle();
        Ok(())
    })
}

/// Makes a tree from a host's own skeleton: `count` branches, parents before children
/// (each `parent` is ARBOR_NO_PARENT or the index of an earlier branch), finite positions,
/// finite radii >= 0; `depth` is kept as the branch's birth step, `order` as its branching
/// order. The branches are copied; every function that takes a tree takes it (ring frames
/// come from parallel transport, since a host's skeleton has no turtle). Writes the new
/// tree to `*out` on success (free it with arbor_tree_free()).
///
/// ARBOR_STATUS_INVALID_ARGUMENT names the first branch that breaks a rule and the rule;
/// `branches` may be NULL only when `count` is 0.
///
/// # Safety
/// `branches` is NULL or readable for `count` elements; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_from_branches(
    branches: *const Branch,
    count: usize,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        if count > crate::limits::DEFAULT_MAX_BRANCHES {
            return Err(crate::Error::LimitExceeded {
                limit_name: "max_branches",
                what: "branches",
                limit: crate::limits::DEFAULT_MAX_BRANCHES as u64,
                requested: count as u64,
                step: None,
            }
            .into());
        }
        // SAFETY: the caller promises `count` readable branches (ArborBranch and Branch
        // share one layout, checked field by field in layout.rs).
        let src = unsafe { in_slice(branches.cast::<Branch>(), count, "branches") }?;
        let skeleton = Skeleton::new(src.to_vec())?;
        *out = ArborTree::new(skeleton).into_handle();
        Ok(())
    })
}

/// Frees a tree. NULL does nothing. The tree must not be used afterwards.
///
/// # Safety
/// `tree` is NULL or a tree from this library not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_free(tree: *mut ArborTree) {
    // SAFETY: the caller promises `tree` is NULL or a live tree of this library.
    unsafe { ArborTree::free_handle(tree) }
}

/// Number of branches of `tree`; 0 for NULL.
///
/// # Safety
/// `tree` is NULL or a live tree.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_branch_count(tree: *const ArborTree) -> usize {
    guard_value(0, || {
        // SAFETY: the caller promises `tree` is NULL or live.
        unsafe { arg_ref(tree, "tree") }.map_or(0, |t| t.skeleton().len())
    })
}

/// Copies all branches of `tree` into `out`, parents before children. `capacity` is the
/// number of ArborBranch elements `out` holds; less than arbor_tree_branch_count() gives
/// ARBOR_STATUS_BUFFER_TOO_SMALL and writes nothing.
///
/// # Safety
/// `tree` is NULL or live; `out` is NULL or valid for writes of `capacity` branches.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_copy_branches(
    tree: *const ArborTree,
    out: *mut Branch,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        let src = tree.skeleton().branches();
        // SAFETY: the caller promises `out` holds `capacity` writable branches
        // (ArborBranch and Branch share one layout, asserted in layout.rs).
        unsafe { copy_out(src, out.cast::<Branch>(), capacity, "out") }
    })
}

/// Number of `~` leaf sites of `tree`; 0 for NULL.
///
/// # Safety
/// `tree` is NULL or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_leaf_site_count(tree: *const ArborTree) -> usize {
    guard_value(0, || {
        // SAFETY: the caller promises `tree` is NULL or live.
        unsafe { arg_ref(tree, "tree") }.map_or(0, |t| t.skeleton().leaves().len())
    })
}

/// Copies the leaf sites of `tree` into `out` (`capacity` elements, at least
/// arbor_tree_leaf_site_count(), else ARBOR_STATUS_BUFFER_TOO_SMALL).
///
/// # Safety
/// `tree` is NULL or live; `out` is NULL or valid for writes of `capacity` sites.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_copy_leaf_sites(
    tree: *const ArborTree,
    out: *mut LeafSite,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        let src = tree.skeleton().leaves();
        // SAFETY: the caller promises `out` holds `capacity` writable sites (one layout,
        // asserted in layout.rs).
        unsafe {
            copy_out(
                src,
                out.cast::<crate::skeleton::LeafSite>(),
                capacity,
                "out",
            )
        }
    })
}

/// Number of spheres and discs of `tree`; 0 for NULL.
///
/// # Safety
/// `tree` is NULL or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_organ_count(tree: *const ArborTree) -> usize {
    guard_value(0, || {
        // SAFETY: the caller promises `tree` is NULL or live.
        unsafe { arg_ref(tree, "tree") }.map_or(0, |t| t.skeleton().organs().len())
    })
}

/// Copies the spheres and discs of `tree` into `out` (`capacity` elements, at least
/// arbor_tree_organ_count(), else ARBOR_STATUS_BUFFER_TOO_SMALL).
///
/// # Safety
/// `tree` is NULL or live; `out` is NULL or valid for writes of `capacity` organs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_copy_organs(
    tree: *const ArborTree,
    out: *mut Organ,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        let src = tree.skeleton().organs();
        // SAFETY: the caller promises `out` holds `capacity` writable organs (one layout,
        // asserted in layout.rs).
        unsafe { copy_out(src, out.cast::<crate::skeleton::Organ>(), capacity, "out") }
    })
}

/// Copies the colour index (`;` `,`) of every branch into `out` (`capacity` values, at
/// least arbor_tree_branch_count(), else ARBOR_STATUS_BUFFER_TOO_SMALL). A tree whose
/// generator set no colours writes 0 for every branch.
///
/// # Safety
/// `tree` is NULL or live; `out` is NULL or valid for writes of `capacity` values.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_copy_branch_colors(
    tree: *const ArborTree,
    out: *mut u32,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        let n = tree.skeleton().len();
        // SAFETY: the caller promises `out` holds `capacity` writable values.
        let dst = unsafe { out_slice(out, capacity, n, "out") }?;
        let colors = tree.skeleton().colors();
        for (k, d) in dst.iter_mut().enumerate() {
            d.write(colors.get(k).copied().unwrap_or(0));
        }
        Ok(())
    })
}

/// Grows the 1996 model with seeded variation of every branch's angles (up to +-4 degrees
/// branching, +-10 divergence), length and width (up to +-6%), so trees from the same
/// parameters differ; `seed` 0 gives exactly arbor_tree_from_honda(). Same seed, same tree.
///
/// # Safety
/// `params` is NULL or readable; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_from_honda_varied(
    params: *const HondaParams,
    seed: u64,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `params` is NULL or readable.
        let params: HondaParams = *unsafe { arg_ref(params, "params") }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let variation = honda::Variation {
            seed,
            ..Default::default()
        };
        let skeleton = honda::build_varied(&params, &variation)?;
        *out = ArborTree::new(skeleton).into_handle();
        Ok(())
    })
}

/// Makes a new tree from `tree` without its colliding branches: where two branches'
/// volumes intersect and they do not meet at a joint, the deeper one goes with its
/// subtree (a parent left with no children gets a closed tip). Writes the new tree to
/// `*out` and, if `removed` is not NULL, how many branches went.
///
/// # Safety
/// `tree` is NULL or live; `out` is NULL or writable; `removed` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_prune_collisions(
    tree: *const ArborTree,
    out: *mut *mut ArborTree,
    removed: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let pruned = crate::skeleton::prune::prune_collisions(tree.skeleton());
        if !removed.is_null() {
            // SAFETY: the caller promises a non-NULL `removed` is writable.
            *unsafe { out_ref(removed, "removed") }? = pruned.removed;
        }
        *out = ArborTree::new(pruned.skeleton).into_handle();
        Ok(())
    })
}
