//! The layout: ring frames and texture v flowing from parents to children, and the
//! compact format's v scale.

use super::*;

/// Per-branch values the writer reads, computed in one pass from parents to children (ring
/// frames and arc length flow down the tree); the writing itself can then run on chunks of
/// branches independently. Each branch's direction and end ring are recomputed where they
/// are needed, which is cheaper than storing them.
#[derive(Clone)]
pub(crate) struct Layout {
    pub(crate) first_vertex: Vec<u32>,
    pub(crate) first_index: Vec<u32>,
    /// Ring frame vector p of each branch.
    pub(crate) frame_p: Vec<Vec3>,
    /// v at each branch's end.
    pub(crate) v_end: Vec<f32>,
    /// With inner rings: the frame vector at each branch's end (carried along its curve by
    /// rotation-minimising frames); empty otherwise.
    pub(crate) frame_end: Vec<Vec3>,
}

/// The plan's v_scale: 1 for f32 vertices; for compact ones the power of two at or above
/// the largest v a vertex can get (a branch's end, plus the radius a point tip reaches
/// beyond it).
pub(super) fn v_scale(skeleton: &Skeleton, o: &MeshOptions, l: &Layout) -> f32 {
    if o.vertex_format == VertexFormat::F32 {
        return 1.0;
    }
    let v_end = l.v_end.iter().fold(0.0f32, |m, &v| m.max(v));
    let r = skeleton
        .branches()
        .iter()
        .fold(0.0f32, |m, b| m.max(b.start_radius).max(b.end_radius));
    crate::mesh::compact::v_scale_for(to_f32(v_end as f64 + r as f64 / o.texture_scale as f64))
}

/// Branch `i`'s ring frame at its start, from its parent's (with a sweep, also the frame
/// and v at its end; straight branches get v from [`set_v_end`]): the part of the layout an
/// edit of a branch changes for it and its subtree.
/// `d` is the branch's direction at its start (its curve's tangent in a sweep) and `from`
/// the parent's at the joint when the caller has it.
#[inline(always)]
pub(super) fn frames(
    skeleton: &Skeleton,
    plan: &Plan,
    l: &mut Layout,
    i: usize,
    (d, from): (Vec3, Option<Vec3>),
    own_ring: bool,
    inv_ts: f64,
) {
    let b = &skeleton.branches()[i];
    let sweep = plan.inner > 0;
    let frame = start_frame(skeleton, i, d, own_ring, |parent| {
        if sweep {
            transport(l.frame_end[parent], plan.t1[parent], d)
        } else {
            let from = from.unwrap_or_else(|| direction(&skeleton.branches()[parent]));
            transport(l.frame_p[parent], from, d)
        }
    });
    l.frame_p[i] = frame;
    if sweep {
        // The arc through the ring centres, and the frame at the end.
        let mut arc = 0.0f32;
        l.frame_end[i] = skeleton.curve(i).rotation_minimising_frames(
            d,
            l.frame_p[i],
            plan.inner + 1,
            |_, _, _, _, a| arc = a,
        );
        set_v_end(&mut l.v_end, b, i, arc as f64, inv_ts);
    }
}

/// Branch `i`'s ring frame vector at its start, `d` its direction there. A ring of its own
/// starts its seam at the turtle's up vector where the generator had a turtle (so a
/// grammar's rolls reach the bark); a root's comes from [`ring_basis`]; any other is
/// `carried(parent)`, the parent's frame carried along the joint, so an axis's tube never
/// twists at a joint.
#[inline(always)]
pub(super) fn start_frame(
    skeleton: &Skeleton,
    i: usize,
    d: Vec3,
    own_ring: bool,
    carried: impl FnOnce(usize) -> Vec3,
) -> Vec3 {
    let turtle = skeleton
        .up(i)
        .filter(|_| own_ring)
        .and_then(|u| (u - d * u.dot(d)).try_normalize());
    match (turtle, skeleton.branches()[i].parent) {
        (Some(p), _) => p,
        (None, NO_PARENT) => ring_basis(d.as_dvec3()).0.as_vec3(),
        (None, parent) => carried(parent as usize),
    }
}

/// v at the end of branch `b` (number `i`), `len` along from its parent's end (its
/// own start for a root); clamped so that absurd lengths cannot push uv past the f32 range.
#[inline(always)]
pub(super) fn set_v_end(v_end: &mut [f32], b: &Branch, i: usize, len: f64, inv_ts: f64) {
    let v0 = if b.parent == NO_PARENT {
        0.0
    } else {
        v_end[b.parent as usize]
    };
    v_end[i] = v_after(v0, len, inv_ts);
}

/// v at a branch's end, `len` along from `v0` at its start (clamped so that absurd
/// lengths cannot push uv past the f32 range).
#[inline(always)]
pub(super) fn v_after(v0: f32, len: f64, inv_ts: f64) -> f32 {
    to_f32(v0 as f64 + len * inv_ts)
}
