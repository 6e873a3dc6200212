//! The animation stream: per-vertex growth time, order, position along the branch and a
//! phase, for a host's growth and wind shaders.

use super::MeshOptions;
use super::plan::{BASE_CAP, MeshPlan, SHARES_START, TIP};
use crate::error::Result;
use crate::skeleton::Skeleton;

/// Per-vertex animation data for a host's growth and wind shaders: an optional second
/// vertex stream, one element per vertex of the mesh of the same tree and options (16
/// bytes; C: ArborAnimationVertex).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct AnimationVertex {
    /// When the vertex appears as the tree grows, 0..=1: (start + along) / total, where a
    /// branch starts at its birth (counted from the earliest) but not before its parent
    /// has finished, and each branch takes one unit. Never smaller on a child than on its
    /// parent. Draw vertices with `growth <= t` and move t from 0 to 1.
    pub growth: f32,
    /// Branching order of the branch (0 on the trunk axis), for wind stiffness.
    pub order: f32,
    /// Position along the branch, 0 at its base and 1 at its tip.
    pub along: f32,
    /// A per-branch phase in [0, 1), so branches sway out of step.
    pub phase: f32,
}

/// The animation stream packed to match [`VertexCompact`](super::VertexCompact): 8 bytes
/// (C: ArborAnimationVertexCompact), four uint16. `growth`, `along` and `phase` are unorm16
/// (value / 65535, rounded to nearest); `order` is the branching order as an integer
/// (saturating at 65,535). Bound as four normalised unsigned shorts, a shader reads order
/// as `y * 65535.0`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct AnimationVertexCompact {
    /// [`AnimationVertex::growth`], unorm16.
    pub growth: u16,
    /// [`AnimationVertex::order`], an integer.
    pub order: u16,
    /// [`AnimationVertex::along`], unorm16.
    pub along: u16,
    /// [`AnimationVertex::phase`], unorm16.
    pub phase: u16,
}

const _: () = assert!(std::mem::size_of::<AnimationVertexCompact>() == 8);

impl AnimationVertexCompact {
    /// `a` packed.
    pub fn encode(a: &AnimationVertex) -> Self {
        let unorm = |c: f32| (c.clamp(0.0, 1.0) * 65535.0).round() as u16;
        AnimationVertexCompact {
            growth: unorm(a.growth),
            order: a.order.clamp(0.0, 65535.0) as u16,
            along: unorm(a.along),
            phase: unorm(a.phase),
        }
    }

    /// The stream element this one stands for.
    pub fn decode(&self) -> AnimationVertex {
        let f = |c: u16| c as f32 / 65535.0;
        AnimationVertex {
            growth: f(self.growth),
            order: self.order as f32,
            along: f(self.along),
            phase: f(self.phase),
        }
    }
}

/// A per-branch phase in [0, 1) from the branch index (the same on every run).
pub(crate) fn branch_phase(i: u32) -> f32 {
    // The first SplitMix64 output seeded with the index.
    (crate::rng::Rng::new(i as u64).next_u64() >> 40) as f32 / (1u64 << 24) as f32
}

/// When each branch starts to grow, and the length of the whole growth, in units of one
/// internode's growth: a branch starts at its birth (counted from the earliest birth) but
/// never before its parent has finished, and takes one unit. For the 1996 model (births
/// one step apart from parent to child) this is the birth step; for a grammar whose
/// internodes are all born at the last step it is a wave from the root to the tips.
pub(crate) fn growth_times(skeleton: &Skeleton) -> (Vec<f32>, f32) {
    let b = skeleton.branches();
    let lo = b.iter().map(|x| x.birth).min().unwrap_or(0);
    let mut start = vec![0.0f32; b.len()];
    let mut total = 1.0f32;
    for (i, x) in b.iter().enumerate() {
        let born = (x.birth - lo) as f32;
        start[i] = if x.parent == crate::skeleton::NO_PARENT {
            born
        } else {
            born.max(start[x.parent as usize] + 1.0)
        };
        total = total.max(start[i] + 1.0);
    }
    (start, total)
}

/// The animation stream of the mesh [`tubes`](super::tubes()) makes with `options` (see
/// [`AnimationVertex`]); its length is the mesh's vertex count.
pub fn animation(skeleton: &Skeleton, options: &MeshOptions) -> Result<Vec<AnimationVertex>> {
    MeshPlan::new(skeleton, options)?.animation(skeleton)
}

impl MeshPlan {
    /// The animation stream of this plan's mesh (see [`animation`]).
    pub fn animation(&self, skeleton: &Skeleton) -> Result<Vec<AnimationVertex>> {
        self.check_skeleton(skeleton)?;
        let plan = &self.plan;
        let (start, total) = growth_times(skeleton);
        let mut out = Vec::with_capacity(plan.size.vertices);
        for (i, b) in skeleton.branches().iter().enumerate() {
            let s = plan.segs[i] as usize;
            if s == 0 {
                continue;
            }
            let f = plan.flags[i];
            let at = |along: f32| AnimationVertex {
                growth: (start[i] + along) / total,
                order: b.order as f32,
                along,
                phase: branch_phase(i as u32),
            };
            if f & SHARES_START == 0 {
                out.extend(std::iter::repeat_n(at(0.0), s + 1));
            }
            // The inner rings of a sweep, at equal curve parameters.
            for j in 1..=plan.inner {
                out.extend(std::iter::repeat_n(
                    at(j as f32 / (plan.inner + 1) as f32),
                    s + 1,
                ));
            }
            out.extend(std::iter::repeat_n(at(1.0), s + 1));
            if f & BASE_CAP != 0 {
                out.extend(std::iter::repeat_n(at(0.0), s));
            }
            if f & TIP != 0 {
                out.extend(std::iter::repeat_n(at(1.0), s));
            }
        }
        debug_assert_eq!(out.len(), plan.size.vertices);
        Ok(out)
    }

    /// [`animation`](Self::animation) packed to match compact vertices (see
    /// [`AnimationVertexCompact`]).
    pub fn animation_compact(&self, skeleton: &Skeleton) -> Result<Vec<AnimationVertexCompact>> {
        Ok(self
            .animation(skeleton)?
            .iter()
            .map(AnimationVertexCompact::encode)
            .collect())
    }
}
