//! Wind as a skin, into the host's memory: the bones along the trunk and limbs with their
//! inverse bind matrices, every vertex's four joints and weights, and the looping clip's
//! keys, so an engine plug-in builds its own skeleton and animation from them.

use super::*;
use crate::wind::Bone;

/// Elements `per` a unit times `units`, or a clear error when that overflows.
fn times(units: usize, per: usize, name: &'static str) -> Result<usize, FfiError> {
    units
        .checked_mul(per)
        .ok_or_else(|| FfiError::invalid(format!("{name}: {units} x {per} overflows size_t")))
}

/// The rig of `tree` drawn with `mesh_options`, at most `max_bones` bones.
///
/// # Safety
/// `tree` is NULL or live; `mesh_options` is NULL or readable.
unsafe fn rig_of<'a>(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    max_bones: u32,
) -> Result<(&'a ArborTree, MeshOptions, crate::wind::Rig), FfiError> {
    // SAFETY: passed on from the caller.
    let (tree, mo) = unsafe { tree_in(tree, mesh_options) }?;
    let rig = crate::wind::rig(tree.skeleton(), max_bones as usize, &mo)?;
    Ok((tree, mo, rig))
}

/// Writes the bones of `tree`'s wind skin: at most `max_bones` (1..=ARBOR_MAX_BONES;
/// four along the trunk, then two a limb, thickest limbs first) in the conventions of
/// `mesh_options` (NULL: the defaults), parents before children, the first the trunk's
/// base (each ArborBone its head, tail, parent, ARBOR_NO_PARENT for the root, and the
/// wood's radius at its head). `inverse_bind` (NULL: not asked) gets 16 floats a bone:
/// its inverse bind matrix, column-major as glTF's (the translation moving its head to
/// the origin). `*count` (when not NULL) gets how many bones there are; `out` and
/// `inverse_bind` hold `capacity` bones: at least that many, else
/// ARBOR_STATUS_BUFFER_TOO_SMALL and nothing written.
///
/// # Safety
/// `tree` is NULL or live; `mesh_options` is NULL or readable; `out` is NULL or writable
/// for `capacity` bones, `inverse_bind` NULL or writable for `16 * capacity` floats;
/// `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_bones_write(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    max_bones: u32,
    out: *mut Bone,
    inverse_bind: *mut f32,
    capacity: usize,
    count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: passed on from the caller.
        let (_, _, rig) = unsafe { rig_of(tree, mesh_options, max_bones) }?;
        let n = rig.bones.len();
        let bones = if out.is_null() {
            None
        } else {
            // SAFETY: the caller promises `out` holds `capacity` writable bones.
            Some(unsafe { out_slice(out, capacity, n, "out") }?)
        };
        let matrices = if inverse_bind.is_null() {
            None
        } else {
            let cap = times(capacity, 16, "inverse_bind")?;
            // SAFETY: the caller promises `inverse_bind` holds 16 * `capacity` floats.
            Some(unsafe { out_slice(inverse_bind, cap, 16 * n, "inverse_bind") }?)
        };
        if let Some(dst) = bones {
            for (d, b) in dst.iter_mut().zip(&rig.bones) {
                d.write(*b);
            }
        }
        if let Some(dst) = matrices {
            for (d, b) in dst.chunks_exact_mut(16).zip(&rig.bones) {
                for (x, v) in d.iter_mut().zip(b.inverse_bind()) {
                    x.write(v);
                }
            }
        }
        if !count.is_null() {
            // SAFETY: the caller promises a non-NULL `count` is writable.
            *unsafe { out_ref(count, "count") }? = n;
        }
        Ok(())
    })
}

/// Writes each branch's pivot for a Pivot-Painter-style wind shader (the glTF file's
/// `arbor_pivots`), 8 floats a branch in branch order, in the conventions of
/// `mesh_options` (NULL: the defaults): where it turns (its start: x, y, z), its length,
/// its axis (unit, start to end: x, y, z) and its parent's index (-1 for a root). A
/// vertex's branch is the one whose range of arbor_mesh_branch_ranges() holds it.
/// `*count` (when not NULL) gets the branches; `out` (NULL: count only) holds `capacity`
/// branches (8 floats each): at least that many, else ARBOR_STATUS_BUFFER_TOO_SMALL and
/// nothing written.
///
/// # Safety
/// `tree` is NULL or live; `mesh_options` is NULL or readable; `out` is NULL or writable
/// for `8 * capacity` floats; `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_pivots_write(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    out: *mut f32,
    capacity: usize,
    count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: passed on from the caller.
        let (tree, mo) = unsafe { tree_in(tree, mesh_options) }?;
        let n = tree.skeleton().branches().len();
        if !out.is_null() {
            let cap = times(capacity, 8, "capacity")?;
            // SAFETY: the caller promises `out` holds 8 * `capacity` floats.
            let dst = unsafe { out_slice(out, cap, 8 * n, "out") }?;
            let pivots = crate::wind::pivots(tree.skeleton(), &mo);
            for (d, p) in dst.chunks_exact_mut(8).zip(&pivots) {
                for (x, v) in d.iter_mut().zip(p) {
                    x.write(*v);
                }
            }
        }
        if !count.is_null() {
            // SAFETY: the caller promises a non-NULL `count` is writable.
            *unsafe { out_ref(count, "count") }? = n;
        }
        Ok(())
    })
}

/// Writes the skin of the mesh arbor_mesh_write() writes for `tree` with `options`
/// (NULL: the defaults), on the bones arbor_tree_bones_write() writes with the same
/// options and `max_bones`: four joints (`joints`, unsigned shorts) and four weights
/// (`weights`, floats summing to one) a vertex, in the mesh's vertex order. `*vertex_count`
/// (when not NULL) gets the mesh's vertices; `joints` and `weights` (NULL: count only)
/// hold `vertex_capacity` vertices (4 elements each): at least that many, else
/// ARBOR_STATUS_BUFFER_TOO_SMALL and nothing written.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `joints` and `weights` are NULL
/// or writable for `4 * vertex_capacity` elements; `vertex_count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_skin_write(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    max_bones: u32,
    joints: *mut u16,
    weights: *mut f32,
    vertex_capacity: usize,
    vertex_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: passed on from the caller.
        let (tree, mo, rig) = unsafe { rig_of(tree, options, max_bones) }?;
        let size = tree.plan_in(&mo, &on_threads(0))?.size();
        let n = size.vertices;
        // SAFETY: passed on from the caller.
        unsafe {
            write_skin(joints, weights, vertex_capacity, n, || {
                let bark = crate::mesh::tubes(tree.skeleton(), &mo)?;
                Ok(crate::wind::weights(&rig, &bark)?)
            })
        }?;
        if !vertex_count.is_null() {
            // SAFETY: the caller promises a non-NULL `vertex_count` is writable.
            *unsafe { out_ref(vertex_count, "vertex_count") }? = n;
        }
        Ok(())
    })
}

/// Writes `influences()` (four joints and four weights a vertex, `n` of them) into
/// `joints` and `weights` where either is not NULL: each holds `4 * vertex_capacity`
/// elements, at least `4 * n`, else ARBOR_STATUS_BUFFER_TOO_SMALL and nothing written
/// (the influences are not worked out).
///
/// # Safety
/// `joints` and `weights` are NULL or writable for `4 * vertex_capacity` elements.
unsafe fn write_skin(
    joints: *mut u16,
    weights: *mut f32,
    vertex_capacity: usize,
    n: usize,
    influences: impl FnOnce() -> Result<Vec<crate::wind::Influence>, FfiError>,
) -> Result<(), FfiError> {
    if joints.is_null() && weights.is_null() {
        return Ok(());
    }
    let cap = times(vertex_capacity, 4, "vertex_capacity")?;
    let j = if joints.is_null() {
        None
    } else {
        // SAFETY: the caller promises `joints` holds 4 * `vertex_capacity` shorts.
        Some(unsafe { out_slice(joints, cap, 4 * n, "joints") }?)
    };
    let w = if weights.is_null() {
        None
    } else {
        // SAFETY: the caller promises `weights` holds 4 * `vertex_capacity` floats.
        Some(unsafe { out_slice(weights, cap, 4 * n, "weights") }?)
    };
    let influences = influences()?;
    if influences.len() != n {
        return Err(FfiError::invalid(format!(
            "the skin has {} vertices; the mesh {n}",
            influences.len()
        )));
    }
    if let Some(j) = j {
        for (d, x) in j.chunks_exact_mut(4).zip(&influences) {
            for (s, v) in d.iter_mut().zip(x.0) {
                s.write(v);
            }
        }
    }
    if let Some(w) = w {
        for (d, x) in w.chunks_exact_mut(4).zip(&influences) {
            for (s, v) in d.iter_mut().zip(x.1) {
                s.write(v);
            }
        }
    }
    Ok(())
}

/// Writes the skin of part `part` (0: the bark, 1: the baked leaves) of level `level` of
/// `lods`, on the bones arbor_tree_bones_write() writes for the tree and mesh options the
/// chain was made from with `max_bones`: four joints (`joints`, unsigned shorts) and four
/// weights (`weights`, floats summing to one) a vertex, in the order
/// arbor_lods_mesh_write() writes the part's vertices. A level's bark rides the bones of
/// the branches it was merged from (so every level bends as the full tree does), each
/// leaf its branch's bone. `*vertex_count` (when not NULL) gets the part's vertices;
/// `joints` and `weights` (NULL: count only) hold `vertex_capacity` vertices (4 elements
/// each): at least that many, else ARBOR_STATUS_BUFFER_TOO_SMALL and nothing written.
///
/// # Safety
/// `lods` is NULL or live; `joints` and `weights` are NULL or writable for
/// `4 * vertex_capacity` elements; `vertex_count` is NULL or writable.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn arbor_lods_skin_write(
    lods: *const ArborLods,
    level: usize,
    part: u32,
    max_bones: u32,
    joints: *mut u16,
    weights: *mut f32,
    vertex_capacity: usize,
    vertex_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `lods` is NULL or live.
        let lods = unsafe { arg_ref(lods, "lods") }?;
        let l = lods.level(level)?;
        let n = super::lod::part_of(l, part)?.map_or(0, |m| m.vertices.len());
        let (skeleton, mo) = (&lods.skeleton, &lods.mesh_options);
        let rig = crate::wind::rig(skeleton, max_bones as usize, mo)?;
        // SAFETY: passed on from the caller.
        unsafe {
            write_skin(joints, weights, vertex_capacity, n, || {
                Ok(crate::wind::level_part_weights(
                    &rig,
                    skeleton,
                    mo,
                    l,
                    part == 1,
                )?)
            })
        }?;
        if !vertex_count.is_null() {
            // SAFETY: the caller promises a non-NULL `vertex_count` is writable.
            *unsafe { out_ref(vertex_count, "vertex_count") }? = n;
        }
        Ok(())
    })
}

/// Writes the looping wind clip of the bones arbor_tree_bones_write() writes for `tree`
/// with `mesh_options` and `max_bones`: `duration` seconds (0.5..=60) at
/// `keys_per_second` (1..=60), the wind blowing along `wind` (3 floats, level, in the
/// mesh's axes; NULL: +X) at `strength` (0..=4), varied by `seed`. `times` gets each key's
/// time (from 0 to `duration`, the last key the first again); `rotations` each bone's
/// rotation relative to its rest at each key, a unit quaternion x, y, z, w: bone `b`'s
/// key `k` at `4 * (b * key_count + k)`. `*key_count` and `*bone_count` (when not NULL)
/// get the counts; `times` holds `key_capacity` floats and `rotations`
/// `4 * bone_capacity * key_capacity` (NULL: counts only): at least the counts, else
/// ARBOR_STATUS_BUFFER_TOO_SMALL and nothing written.
///
/// # Safety
/// `tree` is NULL or live; `mesh_options` NULL or readable; `wind` NULL or readable for 3
/// floats; `times` NULL or writable for `key_capacity` floats, `rotations` for
/// `4 * bone_capacity * key_capacity`; `key_count` and `bone_count` NULL or writable.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn arbor_tree_wind_clip_write(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    max_bones: u32,
    wind: *const f32,
    strength: f32,
    duration: f32,
    keys_per_second: u32,
    seed: u64,
    times_out: *mut f32,
    key_capacity: usize,
    rotations: *mut f32,
    bone_capacity: usize,
    key_count: *mut usize,
    bone_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: passed on from the caller.
        let (_, mo, rig) = unsafe { rig_of(tree, mesh_options, max_bones) }?;
        let wind = if wind.is_null() {
            glam::Vec3::X
        } else {
            // SAFETY: the caller promises a non-NULL `wind` holds 3 readable floats.
            let w = unsafe { in_slice(wind, 3, "wind") }?;
            glam::Vec3::new(w[0], w[1], w[2])
        };
        if !wind.is_finite() {
            return Err(FfiError::invalid(format!(
                "wind: {wind}; expected a finite direction"
            )));
        }
        let clip = crate::wind::clip(
            &rig,
            mo.up(),
            wind,
            strength,
            duration,
            keys_per_second,
            seed,
        )?;
        let (keys, bones) = (clip.times.len(), clip.rotations.len());
        // Both buffers checked before either is written.
        let times_dst = if times_out.is_null() {
            None
        } else {
            // SAFETY: the caller promises `times` holds `key_capacity` writable floats.
            Some(unsafe { out_slice(times_out, key_capacity, keys, "times") }?)
        };
        let rotations_dst = if rotations.is_null() {
            None
        } else {
            if bone_capacity < bones || key_capacity < keys {
                return Err(crate::Error::BufferTooSmall {
                    buffer: "rotations",
                    required: 4 * bones * keys,
                    capacity: 4usize
                        .saturating_mul(bone_capacity)
                        .saturating_mul(key_capacity),
                }
                .into());
            }
            let cap = times(
                times(bone_capacity, key_capacity, "rotations")?,
                4,
                "rotations",
            )?;
            // SAFETY: the caller promises `rotations` holds 4 * `bone_capacity` *
            // `key_capacity` writable floats.
            Some(unsafe { out_slice(rotations, cap, 4 * bones * keys, "rotations") }?)
        };
        if let Some(dst) = times_dst {
            for (d, &t) in dst.iter_mut().zip(&clip.times) {
                d.write(t);
            }
        }
        if let Some(dst) = rotations_dst {
            for (d, q) in dst.chunks_exact_mut(4).zip(clip.rotations.iter().flatten()) {
                for (s, &v) in d.iter_mut().zip(q) {
                    s.write(v);
                }
            }
        }
        if !key_count.is_null() {
            // SAFETY: the caller promises a non-NULL `key_count` is writable.
            *unsafe { out_ref(key_count, "key_count") }? = keys;
        }
        if !bone_count.is_null() {
            // SAFETY: the caller promises a non-NULL `bone_count` is writable.
            *unsafe { out_ref(bone_count, "bone_count") }? = bones;
        }
        Ok(())
    })
}
