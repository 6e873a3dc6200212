//! The mesh plan: what every branch gets (sides, joints, caps, exact counts) and where it
//! goes (offsets, ring frames, texture v), decided once per tree and options. The size
//! query, the writer, the branch ranges and the animation stream all read one plan, and a
//! host that keeps it (the C ABI keeps it with the tree) writes again without redoing it
//! or allocating in proportion to the tree.

use super::rings::{Circle, circle, to_f32};
use super::strips::StripRules;
use super::{
    Joints, MAX_RADIAL_SEGMENTS, MeshOptions, MeshSize, RESTART_INDEX, Tip, VertexFormat,
    check_options,
};
use crate::error::{Error, Result};
use crate::geom::transport::{ring_basis, transport};
use crate::progress::Run;
use crate::skeleton::{Branch, NO_PARENT, Skeleton};
use glam::Vec3;
use rustc_hash::FxHashMap;

mod counts;
mod edit;
mod layout;

use counts::{check_size, sides_and_continuations};
pub(crate) use layout::Layout;

/// The sides each branch of `skeleton` gets with `o` (0: culled), as its tube is meshed.
pub(crate) fn branch_sides(skeleton: &Skeleton, o: &MeshOptions) -> Result<Vec<u8>> {
    sides_and_continuations(skeleton.branches(), o).map(|(sides, _)| sides)
}
use layout::{frames, set_v_end, start_frame, v_after, v_scale};

/// The vertices and indices one branch owns: `first_vertex..first_vertex + vertex_count`
/// and `first_index..first_index + index_count`. Ranges of consecutive branches are
/// consecutive; a dropped branch has empty ranges. A branch that shares its parent's ring
/// indexes vertices of its parent. C: ArborBranchRange (see arbor_mesh_branch_ranges()).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BranchRange {
    /// First vertex the branch owns.
    pub first_vertex: u32,
    /// Number of vertices it owns (0 for a culled branch).
    pub vertex_count: u32,
    /// First index it owns (joins and restarts before its strips included).
    pub first_index: u32,
    /// Number of indices it owns.
    pub index_count: u32,
}

pub(crate) const SHARES_START: u8 = 1;
pub(crate) const MITRE_END: u8 = 2;
pub(crate) const BASE_CAP: u8 = 4;
pub(crate) const TIP: u8 = 8;

/// A joint is mitred only while the bend is below 90 degrees (cos > 0): the shared ring stretches
/// by 1 / cos(bend / 2) (at most √2) and its normals smooth a crease of at most 90 degrees.
/// Sharper bends get separate rings, the continuing branch's sunk into its parent.
const MITRE_MIN_COS: f32 = 0.0;

/// What each branch gets, decided once and shared by the size query and the writer.
#[derive(Clone)]
pub(crate) struct Plan {
    /// Sides per branch; 0 for a dropped branch.
    pub(crate) segs: Vec<u8>,
    pub(crate) flags: Vec<u8>,
    /// The kept branch that continues each branch's axis, or NO_PARENT.
    pub(crate) cont: Vec<u32>,
    /// Rings inside every branch (`curve_rings`).
    pub(crate) inner: usize,
    /// With inner rings: the unit tangents of each branch's curve at its start and end
    /// (the joints' directions); empty otherwise.
    pub(crate) t0: Vec<Vec3>,
    pub(crate) t1: Vec<Vec3>,
    pub(crate) size: MeshSize,
    pub(crate) rules: StripRules,
    /// With `even_texels`, per branch what u is multiplied by around it: a whole number
    /// of repeats (> 0), or for a branch thinner than the tile the fraction of it taken
    /// twice, mirrored (< 0, its magnitude); empty otherwise (once).
    pub(crate) wraps: Vec<f32>,
}

/// Unit direction of a branch (+Y for a zero-length branch); in f64 only when the f32
/// difference of its ends overflows or underflows.
#[inline]
pub(crate) fn direction(b: &Branch) -> Vec3 {
    let d = Vec3::from(b.end) - Vec3::from(b.start);
    let l2 = d.length_squared();
    if l2.is_finite() && l2 > 1e-30 {
        return d * l2.sqrt().recip();
    }
    (b.end().as_dvec3() - b.start().as_dvec3())
        .try_normalize()
        .map_or(Vec3::Y, |d| d.as_vec3())
}

/// [`direction`] and [`length`] of a branch with one square root (the same values).
#[inline]
pub(crate) fn axis(b: &Branch) -> (Vec3, f64) {
    let d = Vec3::from(b.end) - Vec3::from(b.start);
    let l2 = d.length_squared();
    if l2.is_finite() && l2 > 1e-30 {
        let l = l2.sqrt();
        return (d * l.recip(), l as f64);
    }
    (direction(b), length(b))
}

/// Length of a branch, in f64 when its f32 difference overflows.
#[inline]
pub(crate) fn length(b: &Branch) -> f64 {
    let l = (Vec3::from(b.end) - Vec3::from(b.start)).length();
    if l.is_finite() {
        l as f64
    } else {
        (b.end().as_dvec3() - b.start().as_dvec3()).length()
    }
}

/// Which branches a mesh with `cull_radius` keeps: a branch whose larger radius is below
/// it is dropped with its whole subtree.
pub(crate) fn kept_branches(skeleton: &Skeleton, cull_radius: f32) -> Vec<bool> {
    let branches = skeleton.branches();
    let mut kept = vec![false; branches.len()];
    for (i, b) in branches.iter().enumerate() {
        let parent_kept = b.parent == NO_PARENT || kept[b.parent as usize];
        kept[i] = parent_kept && b.start_radius.max(b.end_radius) >= cull_radius;
    }
    kept
}

/// The plan and its layout, in two passes in branch order (parents before children): the
/// first finds each branch's sides and continuation, the second (which needs every
/// branch's continuation) its joints, counts, offsets, ring frame and texture v. Each pass
/// reads every branch once and the plan keeps only what the writer cannot recompute
/// cheaply: a fresh plan's memory is page faults, which cost more than the arithmetic. On
/// two threads a straight tree's second pass is cut in two parts of branches, one a thread
/// (see [`joints_part`](Plan::joints_part)); a sweep's runs its frames on one thread and
/// its counts on the other.
fn plan(skeleton: &Skeleton, o: &MeshOptions, threads: u32) -> Result<(Plan, Layout)> {
    check_options(o)?;
    let branches = skeleton.branches();
    let n = branches.len();
    let inner = o.curve_rings as usize;
    // With two threads, the second faults in the second pass's arrays (fresh memory costs
    // a page fault per 4 KiB, about as much as the arithmetic) while this one makes the
    // first pass.
    let both = n >= PLAN_BRANCHES_PER_THREAD && plan_threads(threads) > 1;
    let fresh = both.then(|| std::thread::spawn(move || SecondPass::faulted_in(n)));
    let sides = sides_and_continuations(branches, o);
    // Joined before any error is returned: no thread outlives the call.
    let SecondPass {
        frame_p,
        v_end,
        mut flags,
        mut first_vertex,
        mut first_index,
    } = match fresh {
        Some(h) => h.join().expect("faulting in memory does not panic"),
        None => SecondPass::zeroed(n),
    };
    let (segs, cont) = sides?;
    // With a sweep, the joints' directions are the curves' tangents.
    let (t0, t1): (Vec<Vec3>, Vec<Vec3>) = if inner > 0 {
        (0..n)
            .map(|i| {
                let c = skeleton.curve(i);
                let d = direction(&branches[i]);
                (
                    c.tangent(0.0).try_normalize().unwrap_or(d),
                    c.tangent(1.0).try_normalize().unwrap_or(d),
                )
            })
            .unzip()
    } else {
        (Vec::new(), Vec::new())
    };
    let wraps = if o.even_texels {
        wraps(branches, o.texture_scale)
    } else {
        Vec::new()
    };
    let mut plan = Plan {
        wraps,
        flags: Vec::new(),
        segs,
        cont,
        inner,
        t0,
        t1,
        size: MeshSize::default(),
        rules: StripRules {
            topology: o.topology,
            clockwise: o.reversed(),
        },
    };
    let mut l = Layout {
        first_vertex: Vec::new(),
        first_index: Vec::new(),
        frame_p,
        v_end,
        frame_end: if inner > 0 {
            vec![Vec3::ZERO; n]
        } else {
            Vec::new()
        },
    };
    let (nv, ni) = if inner == 0 {
        plan.straight_pass(
            skeleton,
            o,
            both,
            &mut flags,
            (&mut l.frame_p, &mut l.v_end),
            (&mut first_vertex, &mut first_index),
        )
    } else if both {
        // A sweep's joints and ring frames (a chain from parents to children, with v
        // along the curves) on this thread; the counts and offsets beside it on another,
        // which decides the joints for itself, the same way.
        let plan = &plan;
        let (fv, fi) = (&mut first_vertex, &mut first_index);
        std::thread::scope(|scope| {
            let offsets = scope.spawn(move || plan.offsets(branches, o, 0, None, (fv, fi), true));
            plan.joints_and_frames(skeleton, o, &mut flags, &mut l);
            offsets.join().expect("the offsets' thread does not panic")
        })
    } else {
        plan.joints_and_frames(skeleton, o, &mut flags, &mut l);
        let counts = (&mut first_vertex[..], &mut first_index[..]);
        plan.offsets(branches, o, 0, Some(&flags), counts, true)
    };
    (l.first_vertex, l.first_index) = (first_vertex, first_index);
    plan.flags = flags;
    plan.size = check_size(nv, ni, o)?;
    Ok((plan, l))
}

/// The most times u wraps around a branch with `even_texels`.
const MAX_WRAPS: f64 = 4096.0;

/// Steps of the mirrored fraction per doubling: a branch's texels are within 2^(1/8)
/// (9 %) of the tile's, and a continuation whose step is its parent's shares its ring.
const MIRROR_STEPS: f64 = 4.0;

/// What u is multiplied by around each branch for texels of one size (see
/// [`Plan::wraps`]): its mean circumference over the texture's scale, rounded to a whole
/// number of repeats when it is at least one; below, half of it (taken twice, mirrored),
/// rounded to a step of [`MIRROR_STEPS`] per doubling.
fn wraps(branches: &[Branch], texture_scale: f32) -> Vec<f32> {
    branches
        .iter()
        .map(|b| {
            let r = 0.5 * (b.start_radius as f64 + b.end_radius as f64);
            let turns = std::f64::consts::TAU * r / texture_scale as f64;
            if turns >= 1.0 || !turns.is_finite() {
                turns.round().clamp(1.0, MAX_WRAPS) as f32
            } else {
                let half = (0.5 * turns).max(1e-6);
                let stepped = ((half.log2() * MIRROR_STEPS).round() / MIRROR_STEPS).exp2();
                -(stepped.min(0.5) as f32)
            }
        })
        .collect()
}

/// The arrays the plan's second pass fills, one element a branch, zero.
struct SecondPass {
    frame_p: Vec<Vec3>,
    v_end: Vec<f32>,
    flags: Vec<u8>,
    first_vertex: Vec<u32>,
    first_index: Vec<u32>,
}

impl SecondPass {
    fn zeroed(n: usize) -> Self {
        SecondPass {
            frame_p: vec![Vec3::ZERO; n],
            v_end: vec![0.0; n],
            flags: vec![0; n],
            first_vertex: vec![0; n],
            first_index: vec![0; n],
        }
    }

    /// [`zeroed`](Self::zeroed), every page touched (for a thread that has the time).
    fn faulted_in(n: usize) -> Self {
        let mut s = Self::zeroed(n);
        fault_in(&mut s.frame_p, Vec3::ZERO);
        fault_in(&mut s.v_end, 0.0);
        fault_in(&mut s.flags, 0);
        fault_in(&mut s.first_vertex, 0);
        fault_in(&mut s.first_index, 0);
        s
    }
}

/// Writes `value` into one element of every 4 KiB of `v`: a fresh allocation's pages are
/// faulted in (a zeroed allocation may not have touched them), for another thread to fill.
fn fault_in<T: Copy>(v: &mut [T], value: T) {
    let step = (4096 / std::mem::size_of::<T>().max(1)).max(1);
    for k in (0..v.len()).step_by(step) {
        // Opaque to the optimiser: a zero stored into zeroed memory is still a write.
        v[k] = std::hint::black_box(value);
    }
}

/// Fewest branches for which a plan's second pass is split across two threads.
const PLAN_BRANCHES_PER_THREAD: usize = 32_768;

/// The threads a run's thread count asks for ([`Run::threads`](crate::progress::Run::threads)).
fn plan_threads(threads: u32) -> usize {
    match threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        t => t as usize,
    }
}

impl Plan {
    /// What u is multiplied by around branch `i` (1 without `even_texels`; see
    /// [`wraps`](Self::wraps) for its sign).
    #[inline(always)]
    pub(crate) fn wrap(&self, i: usize) -> f32 {
        self.wraps.get(i).map_or(1.0, |&w| w)
    }

    /// The flags of kept branch `i` that it decides itself: base cap, a start ring shared
    /// with its parent (a mitred joint: the parent then has [`MITRE_END`]), tip.
    #[inline]
    fn own_flags(&self, branches: &[Branch], o: &MeshOptions, i: usize) -> u8 {
        let at_start = || self.direction_at(branches, i, false);
        let at_end = |p| self.direction_at(branches, p, true);
        self.decide_flags(branches, o, i, at_start, at_end).0
    }

    /// [`own_flags`](Self::own_flags) with the directions at the joint given: `d` gives
    /// branch `i`'s at its start, `parent_d` its parent's at its end, each asked only when
    /// a mitre is possible. Also returns the parent's direction when it was asked.
    #[inline(always)]
    fn decide_flags(
        &self,
        branches: &[Branch],
        o: &MeshOptions,
        i: usize,
        d: impl FnOnce() -> Vec3,
        parent_d: impl FnOnce(usize) -> Vec3,
    ) -> (u8, Option<Vec3>) {
        let b = &branches[i];
        let (mut f, mut from) = (0, None);
        if b.parent == NO_PARENT {
            if o.base_cap {
                f |= BASE_CAP;
            }
        } else {
            let p = b.parent as usize;
            if o.joints == Joints::Mitred
                && self.cont[p] == i as u32
                && self.segs[p] == self.segs[i]
                && self.wrap(p) == self.wrap(i)
            {
                let dp = parent_d(p);
                from = Some(dp);
                if dp.dot(d()) > MITRE_MIN_COS {
                    f |= SHARES_START;
                }
            }
        }
        if self.cont[i] == NO_PARENT && o.tip != Tip::Open {
            f |= TIP;
        }
        (f, from)
    }

    /// Branch `i`'s direction at its start, or at its end with `end` (its curve's tangent
    /// in a sweep).
    #[inline(always)]
    fn direction_at(&self, branches: &[Branch], i: usize, end: bool) -> Vec3 {
        match (self.inner > 0, end) {
            (false, _) => direction(&branches[i]),
            (true, false) => self.t0[i],
            (true, true) => self.t1[i],
        }
    }

    /// A swept tree's flags, ring frames and texture v, in branch order: the joints
    /// decided as [`own_flags`](Self::own_flags) decides them, from the curves' tangents.
    fn joints_and_frames(
        &self,
        skeleton: &Skeleton,
        o: &MeshOptions,
        flags: &mut [u8],
        l: &mut Layout,
    ) {
        debug_assert!(self.inner > 0);
        let branches = skeleton.branches();
        let inv_ts = 1.0 / o.texture_scale as f64;
        for i in 0..branches.len() {
            if self.segs[i] == 0 {
                continue;
            }
            let d = self.direction_at(branches, i, false);
            let parent_d = |p| self.direction_at(branches, p, true);
            let (f, from) = self.decide_flags(branches, o, i, || d, parent_d);
            flags[i] |= f;
            if f & SHARES_START != 0 {
                flags[branches[i].parent as usize] |= MITRE_END;
            }
            frames(
                skeleton,
                self,
                l,
                i,
                (d, from),
                f & SHARES_START == 0,
                inv_ts,
            );
        }
    }

    /// A straight tree's second pass: each kept branch's flags, ring frame, v at its end
    /// and counts, into `flags`, `(frame_p, v_end)` and `(first_vertex, first_index)`;
    /// returns the totals. With `both`, the branches are cut in two parts at the middle
    /// and each thread makes one ([`joints_part`](Self::joints_part)): the same plan
    /// either way.
    fn straight_pass(
        &self,
        skeleton: &Skeleton,
        o: &MeshOptions,
        both: bool,
        flags: &mut [u8],
        (frame_p, v_end): (&mut [Vec3], &mut [f32]),
        (first_vertex, first_index): (&mut [u32], &mut [u32]),
    ) -> (u64, u64) {
        let branches = skeleton.branches();
        let make = |lo: usize,
                    flags: &mut [u8],
                    frame_p: &mut [Vec3],
                    v_end: &mut [f32],
                    counts: (&mut [u32], &mut [u32]),
                    first: bool| {
            let mut earlier = Earlier::default();
            self.joints_part(skeleton, o, lo, (flags, frame_p, v_end), &mut earlier);
            self.offsets(branches, o, lo, Some(flags), counts, first)
        };
        if !both {
            return make(0, flags, frame_p, v_end, (first_vertex, first_index), true);
        }
        let m = flags.len() / 2;
        let (flags_a, flags_b) = flags.split_at_mut(m);
        let (frame_a, frame_b) = frame_p.split_at_mut(m);
        let (v_a, v_b) = v_end.split_at_mut(m);
        let (fv_a, fv_b) = first_vertex.split_at_mut(m);
        let (fi_a, fi_b) = first_index.split_at_mut(m);
        // The second part's first strip follows one of the first part unless that part
        // keeps no branch.
        let first_b = self.segs[..m].iter().all(|&s| s == 0);
        let make = &make;
        let ((nv_a, ni_a), (nv_b, ni_b)) = std::thread::scope(|scope| {
            let (fv, fi) = (&mut fv_b[..], &mut fi_b[..]);
            let second = scope.spawn(move || make(m, flags_b, frame_b, v_b, (fv, fi), first_b));
            let first = make(0, flags_a, frame_a, v_a, (fv_a, fi_a), true);
            (
                first,
                second
                    .join()
                    .expect("the plan's second part does not panic"),
            )
        });
        // The second part counted from zero: its branches start after the first part's.
        for (v, i) in fv_b.iter_mut().zip(fi_b.iter_mut()) {
            *v = v.wrapping_add(nv_a as u32);
            *i = i.wrapping_add(ni_a as u32);
        }
        (nv_a + nv_b, ni_a + ni_b)
    }

    /// The joints, ring frames and v at the ends of a straight tree's branches
    /// `lo..lo + flags.len()` (a part of them, which one thread makes), in branch order,
    /// into the part's own slices of the plan's arrays. A part after the first works out
    /// what it needs of earlier branches (a parent's ring frame and v, along its chain of
    /// parents: [`Earlier`]) itself, with the arithmetic their own part uses, so the plan
    /// does not depend on how the tree is cut. In branch order from the generators (a
    /// parent's subtree follows it) those are the few ancestors of the part's first branch.
    fn joints_part(
        &self,
        skeleton: &Skeleton,
        o: &MeshOptions,
        lo: usize,
        (flags, frame_p, v_end): (&mut [u8], &mut [Vec3], &mut [f32]),
        before_part: &mut Earlier,
    ) {
        let branches = skeleton.branches();
        let hi = lo + flags.len();
        // One length for the three: one bounds check a branch.
        let (frame_p, v_end) = (&mut frame_p[..flags.len()], &mut v_end[..flags.len()]);
        // The last branch's direction: along an axis written in one run, the next
        // branch's parent.
        let mut last = (usize::MAX, Vec3::ZERO);
        for i in lo..hi {
            if self.segs[i] == 0 {
                continue;
            }
            let b = &branches[i];
            let (d, len) = axis(b);
            let before = std::mem::replace(&mut last, (i, d));
            let parent_d = |p| {
                if before.0 == p {
                    before.1
                } else {
                    direction(&branches[p])
                }
            };
            let p = b.parent as usize;
            let parent = if b.parent == NO_PARENT {
                (Vec3::ZERO, 0.0)
            } else if p >= lo {
                (frame_p[p - lo], v_end[p - lo])
            } else {
                before_part.get(self, skeleton, o, p)
            };
            let k = i - lo;
            let f;
            (f, frame_p[k], v_end[k]) =
                self.straight_branch(skeleton, o, i, (d, len), parent_d, parent);
            flags[k] |= f;
            if f & SHARES_START != 0 && p >= lo {
                flags[p - lo] |= MITRE_END;
            }
            // A continuation in a later part decides its joint there; the end it shares
            // is marked here, decided the same way.
            let c = self.cont[i];
            if c != NO_PARENT
                && c as usize >= hi
                && self.own_flags(branches, o, c as usize) & SHARES_START != 0
            {
                flags[k] |= MITRE_END;
            }
        }
    }

    /// Straight branch `i`'s joint flags, ring frame and v at its end, from its direction
    /// and length, its parent's direction (`parent_d`, asked only where a mitre is
    /// possible) and its parent's ring frame and v at its end (zero for a root): what
    /// [`joints_part`](Self::joints_part) makes of each branch, and [`Earlier`] of the
    /// branches before a part.
    #[inline(always)]
    fn straight_branch(
        &self,
        skeleton: &Skeleton,
        o: &MeshOptions,
        i: usize,
        (d, len): (Vec3, f64),
        parent_d: impl FnOnce(usize) -> Vec3,
        (frame, v): (Vec3, f32),
    ) -> (u8, Vec3, f32) {
        let branches = skeleton.branches();
        let (f, from) = self.decide_flags(branches, o, i, || d, parent_d);
        let own = start_frame(skeleton, i, d, f & SHARES_START == 0, |p| {
            transport(frame, from.unwrap_or_else(|| direction(&branches[p])), d)
        });
        let inv_ts = 1.0 / o.texture_scale as f64;
        (f, own, v_after(v, len, inv_ts))
    }

    /// The first vertex and first index of branches `lo..lo + first_vertex.len()`,
    /// counted from zero (`first`: no strip comes before the first of them), and their
    /// totals (past the u32 range only on the way to the size's error). The flags are
    /// read from `flags` (from branch `lo` on) when they are known, else decided here.
    fn offsets(
        &self,
        branches: &[Branch],
        o: &MeshOptions,
        lo: usize,
        flags: Option<&[u8]>,
        (first_vertex, first_index): (&mut [u32], &mut [u32]),
        mut first: bool,
    ) -> (u64, u64) {
        let (mut nv, mut ni): (u64, u64) = (0, 0);
        for (k, (fv, fi)) in first_vertex
            .iter_mut()
            .zip(first_index.iter_mut())
            .enumerate()
        {
            let i = lo + k;
            (*fv, *fi) = (nv as u32, ni as u32);
            if self.segs[i] == 0 {
                continue;
            }
            let f = match flags {
                Some(flags) => flags[k],
                None => self.own_flags(branches, o, i),
            };
            let (v, idx) = self.counts(i, f, o.tip, &mut first);
            nv += v as u64;
            ni += idx as u64;
        }
        (nv, ni)
    }
}

/// Ring frames and v at the ends of branches before a part of a straight tree (see
/// [`joints_part`](Plan::joints_part)), worked out so far.
#[derive(Default)]
struct Earlier(FxHashMap<u32, (Vec3, f32)>);

impl Earlier {
    /// The ring frame and v at the end of branch `p`, before the part. Rare (a part's
    /// first branches), so kept out of the part's loop.
    #[cold]
    #[inline(never)]
    fn get(&mut self, plan: &Plan, skeleton: &Skeleton, o: &MeshOptions, p: usize) -> (Vec3, f32) {
        let branches = skeleton.branches();
        // Up the chain of parents to a root or to a branch worked out already.
        let mut chain = Vec::new();
        let mut x = p;
        while !self.0.contains_key(&(x as u32)) {
            chain.push(x);
            match branches[x].parent {
                NO_PARENT => break,
                q => x = q as usize,
            }
        }
        // Then down it, as `joints_part` goes.
        for &x in chain.iter().rev() {
            let parent = match branches[x].parent {
                NO_PARENT => (Vec3::ZERO, 0.0),
                q => self.0[&q],
            };
            let parent_d = |q| direction(&branches[q]);
            let (_, own, v) =
                plan.straight_branch(skeleton, o, x, axis(&branches[x]), parent_d, parent);
            self.0.insert(x as u32, (own, v));
        }
        self.0[&(p as u32)]
    }
}

/// Everything the writer needs for one tree and one set of options, computed once: a host
/// that writes the same tree again (re-uploads, several buffers) keeps it and pays only
/// for the writing. 30 bytes per branch (66 with `curve_rings`).
///
/// ```
/// use arbor::{mesh, models::honda};
/// let tree = honda::build(&honda::HondaParams::preset('a').unwrap())?;
/// let plan = mesh::MeshPlan::new(&tree, &mesh::MeshOptions::default())?;
/// let size = plan.size();
/// let mut vertices = vec![mesh::Vertex::default(); size.vertices];
/// let mut indices = vec![0u32; size.indices];
/// plan.write(&tree, &mut vertices, &mut indices)?;
/// # Ok::<(), arbor::Error>(())
/// ```
#[derive(Clone)]
pub struct MeshPlan {
    pub(crate) options: MeshOptions,
    pub(crate) branch_count: usize,
    pub(crate) plan: Plan,
    pub(crate) layout: Layout,
    /// Unit circle per side count in use (empty for the others).
    pub(crate) tables: Vec<Circle>,
    /// With `even_texels`, the same circles with u mirrored ([`circle_mirrored`](super::rings::circle_mirrored)); empty otherwise.
    pub(crate) mirrored_tables: Vec<Circle>,
    /// What the writers divide v by: 1, or for compact vertices the power of two at or
    /// above the mesh's largest v.
    pub(crate) v_scale: f32,
}

impl std::fmt::Debug for MeshPlan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshPlan")
            .field("options", &self.options)
            .field("branch_count", &self.branch_count)
            .field("size", &self.plan.size)
            .finish_non_exhaustive()
    }
}

impl MeshPlan {
    /// The plan of `skeleton`'s mesh with `options`.
    ///
    /// Fails with [`Error::InvalidArgument`] for bad options and [`Error::LimitExceeded`]
    /// when the vertices or indices could not all be addressed with 32 bits
    /// ([`RESTART_INDEX`] is reserved).
    pub fn new(skeleton: &Skeleton, options: &MeshOptions) -> Result<Self> {
        Self::new_in(skeleton, options, &Run::default())
    }

    /// [`new`](Self::new) on `run`'s threads: a tree of 32,768 branches or more is planned
    /// on two when the run allows more than one (by default it does).
    pub fn new_in(skeleton: &Skeleton, options: &MeshOptions, run: &Run<'_>) -> Result<Self> {
        // Per branch: the plan's sides, flags and continuation (6 bytes), the layout's
        // offsets, frame and texture end (24), with inner rings two tangents and an end
        // frame (36).
        let per_branch = 6 + 24 + if options.curve_rings > 0 { 36 } else { 0 };
        crate::limits::check_available(skeleton.len().saturating_mul(per_branch), "the mesh plan")?;
        let (plan, layout) = plan(skeleton, options, run.threads_or(0))?;
        let mut tables = vec![Circle::default(); MAX_RADIAL_SEGMENTS as usize + 1];
        let mut mirrored = if options.even_texels {
            tables.clone()
        } else {
            Vec::new()
        };
        for &s in &plan.segs {
            if s > 0 && tables[s as usize].is_empty() {
                tables[s as usize] = circle(s as usize);
                if let Some(m) = mirrored.get_mut(s as usize) {
                    *m = super::rings::circle_mirrored(s as usize);
                }
            }
        }
        let v_scale = v_scale(skeleton, options, &layout);
        Ok(MeshPlan {
            options: *options,
            branch_count: skeleton.len(),
            plan,
            layout,
            tables,
            mirrored_tables: mirrored,
            v_scale,
        })
    }

    /// What the compact format's v is stored over (see [`VertexCompact`](super::VertexCompact)): the power of
    /// two at or above the largest v of the mesh (at least 1); 1 for
    /// [`VertexFormat::F32`], whose v is written as it is. It can change when an edit
    /// lengthens the tree ([`update_after_edit`](Self::update_after_edit) then returns
    /// every branch).
    pub fn v_scale(&self) -> f32 {
        self.v_scale
    }

    /// First vertex of kept branch `i`'s end ring: after its own start ring (unless it
    /// shares its parent's) and its inner rings.
    #[inline]
    pub(crate) fn end_ring(&self, i: usize) -> u32 {
        let ring = self.plan.segs[i] as usize + 1;
        let own_start = if self.plan.flags[i] & SHARES_START != 0 {
            0
        } else {
            ring
        };
        self.layout.first_vertex[i] + (own_start + self.plan.inner * ring) as u32
    }

    /// The exact vertex and index counts of the mesh.
    pub fn size(&self) -> MeshSize {
        self.plan.size
    }

    /// The options the plan was made with.
    pub fn options(&self) -> &MeshOptions {
        &self.options
    }

    /// Whether this plan serves `options` (they are the options it was made with).
    pub fn serves(&self, options: &MeshOptions) -> bool {
        *options == self.options
    }

    /// For each branch, the vertices and indices it owns.
    pub fn ranges(&self) -> Vec<BranchRange> {
        // From the layout's offsets: each range ends where the next branch's starts.
        let (lay, size) = (&self.layout, self.plan.size);
        let n = lay.first_vertex.len();
        (0..n)
            .map(|i| {
                let (v, idx) = (lay.first_vertex[i], lay.first_index[i]);
                let (v_end, idx_end) = if i + 1 < n {
                    (lay.first_vertex[i + 1], lay.first_index[i + 1])
                } else {
                    (size.vertices as u32, size.indices as u32)
                };
                BranchRange {
                    first_vertex: v,
                    vertex_count: v_end - v,
                    first_index: idx,
                    index_count: idx_end - idx,
                }
            })
            .collect()
    }

    /// [`Error::InvalidArgument`] naming `vertex_format` unless the options ask for
    /// vertices of `format`.
    pub(crate) fn check_format(&self, format: VertexFormat) -> Result<()> {
        use crate::enums::Numbered;
        let asked = self.options.vertex_format;
        if asked != format {
            return Err(Error::invalid(
                "vertex_format",
                format!(
                    "the options ask for {} vertices ({}), the buffer holds {} ones ({})",
                    asked.name(),
                    asked.c_enumerator(),
                    format.name(),
                    format.c_enumerator()
                ),
            ));
        }
        Ok(())
    }

    /// [`Error::InvalidArgument`] unless `skeleton` has the branch count the plan was made
    /// for.
    pub(crate) fn check_skeleton(&self, skeleton: &Skeleton) -> Result<()> {
        if skeleton.len() != self.branch_count {
            return Err(Error::invalid(
                "plan",
                format!(
                    "made for {} branches, used with a skeleton of {}",
                    self.branch_count,
                    skeleton.len()
                ),
            ));
        }
        Ok(())
    }
}
