//! Branches as GPU records, for hosts that ray-march curves instead of meshing them: one
//! record per branch with its cubic Bézier, radii, texture coordinates and order, in a
//! layout that std430 shader storage buffers read as they are.

use super::animation::{branch_phase, growth_times};
use crate::skeleton::{NO_PARENT, Skeleton};
use bytemuck::{Pod, Zeroable};

/// One branch for a shader, 80 bytes, every vec4 16-byte aligned (std430 `struct { vec4
/// p0_r0; vec4 p1_r1; vec4 p2_v0; vec4 p3_length; float u_offset; uint order; uint
/// parent; uint birth; }`). C: ArborCurveRecord.
///
/// A point at curve parameter t has texture v = `v0 + length * s(t)` (s the fraction of
/// the arc length, model units; divide by the mesh's texture scale) and u = `u_offset`
/// plus its angle around the curve / 2 pi.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct CurveRecord {
    /// Start (the branch's start).
    pub p0: [f32; 3],
    /// Radius at p0.
    pub r0: f32,
    /// First inner control point.
    pub p1: [f32; 3],
    /// Radius at p3.
    pub r1: f32,
    /// Second inner control point.
    pub p2: [f32; 3],
    /// Arc length from the root to p0, model units.
    pub v0: f32,
    /// End (the branch's end).
    pub p3: [f32; 3],
    /// Arc length of the curve, model units (from 32 chords).
    pub length: f32,
    /// Turn of the texture about the curve, 0..1: inherited along an axis, a per-branch
    /// phase where a lateral starts.
    pub u_offset: f32,
    /// Branching order.
    pub order: u32,
    /// Parent branch, or NO_PARENT (ARBOR_NO_PARENT).
    pub parent: u32,
    /// Birth (rewriting step or growth cycle).
    pub birth: u32,
}

/// A curve record with its growth bounds for animated growth, 96 bytes: the branch grows
/// from `grow_start` to `grow_end` (0..1, the animation stream's growth times). C:
/// ArborCurveGrowthRecord.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct CurveGrowthRecord {
    /// The branch.
    pub curve: CurveRecord,
    /// When it starts to grow, 0..1.
    pub grow_start: f32,
    /// When it is fully grown, 0..1.
    pub grow_end: f32,
    /// Zero (std430 padding to 16 bytes).
    pub reserved: [f32; 2],
}

const _: () = {
    assert!(std::mem::size_of::<CurveRecord>() == 80);
    assert!(std::mem::size_of::<CurveGrowthRecord>() == 96);
};

/// One record per branch of `skeleton`, in branch order.
pub fn curve_records(skeleton: &Skeleton) -> Vec<CurveRecord> {
    let b = skeleton.branches();
    let adjacency = skeleton.adjacency();
    let mut out: Vec<CurveRecord> = Vec::with_capacity(b.len());
    for (i, x) in b.iter().enumerate() {
        let c = skeleton.curve(i);
        let mut length = 0.0f64;
        let mut prev = c.p0;
        for k in 1..=32 {
            let p = c.point(k as f32 / 32.0);
            length += prev.distance(p) as f64;
            prev = p;
        }
        let (v0, u_offset) = match x.parent {
            NO_PARENT => (0.0, 0.0),
            p => {
                let parent = &out[p as usize];
                let continues = adjacency.continuation(p as usize) == Some(i as u32);
                (
                    parent.v0 + parent.length,
                    if continues {
                        parent.u_offset
                    } else {
                        branch_phase(i as u32)
                    },
                )
            }
        };
        out.push(CurveRecord {
            p0: c.p0.to_array(),
            r0: x.start_radius,
            p1: c.p1.to_array(),
            r1: x.end_radius,
            p2: c.p2.to_array(),
            v0,
            p3: c.p3.to_array(),
            length: length as f32,
            u_offset,
            order: x.order,
            parent: x.parent,
            birth: x.birth,
        });
    }
    out
}

/// [`curve_records`] with growth bounds: a branch starts at its birth but never before
/// its parent has finished, as in the animation stream.
pub fn curve_growth_records(skeleton: &Skeleton) -> Vec<CurveGrowthRecord> {
    let (start, total) = growth_times(skeleton);
    curve_records(skeleton)
        .into_iter()
        .zip(start)
        .map(|(curve, s)| CurveGrowthRecord {
            curve,
            grow_start: s / total,
            grow_end: (s + 1.0) / total,
            reserved: [0.0; 2],
        })
        .collect()
}
