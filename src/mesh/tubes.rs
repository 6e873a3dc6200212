//! The tube mesher: every branch a truncated cone, axes joined into watertight tubes.

use super::plan::{BranchRange, MeshPlan, SHARES_START};
use super::rings::Slot;
use super::strips::StripWriter;
use super::tube::PerWrite;
use super::{MAX_RADIAL_SEGMENTS, Mesh, MeshOptions, MeshSize, Vertex, VertexSlot};
use crate::error::Result;
use crate::progress::{self, Run, Stage};
use crate::skeleton::{NO_PARENT, Skeleton};
use std::mem::MaybeUninit;

/// The exact vertex and index counts [`write_mesh`] needs for `skeleton`.
///
/// Fails with [`Error::InvalidArgument`](crate::error::Error::InvalidArgument) for bad options and
/// [`Error::LimitExceeded`](crate::error::Error::LimitExceeded) when the vertices or indices could
/// not all be addressed with 32 bits ([`RESTART_INDEX`](super::RESTART_INDEX) is reserved).
/// To size and write the same tree more than once, make a [`MeshPlan`] and keep it.
pub fn mesh_size(skeleton: &Skeleton, options: &MeshOptions) -> Result<MeshSize> {
    Ok(MeshPlan::new(skeleton, options)?.size())
}

/// For each branch, the vertices and indices it owns in the mesh of `options`.
pub fn branch_ranges(skeleton: &Skeleton, options: &MeshOptions) -> Result<Vec<BranchRange>> {
    Ok(MeshPlan::new(skeleton, options)?.ranges())
}

/// An owned mesh of `skeleton`, its buffers allocated once at their exact size, with the
/// branch ranges.
pub fn tubes(skeleton: &Skeleton, options: &MeshOptions) -> Result<Mesh> {
    MeshPlan::new(skeleton, options)?.mesh(skeleton)
}

/// Writes the mesh of `skeleton` into `vertices` and `indices` and returns the counts
/// written (those of [`mesh_size`]). Longer slices are fine; only the prefix is written.
///
/// A slice shorter than needed gives [`Error::BufferTooSmall`](crate::error::Error::BufferTooSmall)
/// and nothing is written.
pub fn write_mesh<V: VertexSlot>(
    skeleton: &Skeleton,
    options: &MeshOptions,
    vertices: &mut [V],
    indices: &mut [u32],
) -> Result<MeshSize> {
    MeshPlan::new(skeleton, options)?.write(skeleton, vertices, indices)
}

/// [`write_mesh`] into uninitialised memory, such as a mapped GPU buffer or a fresh
/// allocation: every slot of the returned counts' prefixes is initialised on success.
pub fn write_mesh_uninit<V: VertexSlot>(
    skeleton: &Skeleton,
    options: &MeshOptions,
    vertices: &mut [V],
    indices: &mut [MaybeUninit<u32>],
) -> Result<MeshSize> {
    MeshPlan::new(skeleton, options)?.write_uninit(skeleton, vertices, indices)
}

/// Fewest branches per thread when a write is split across threads: below this the cost
/// of starting a thread (tens of microseconds) is not won back.
const BRANCHES_PER_THREAD: usize = 16_384;

impl MeshPlan {
    /// Writes the mesh of `skeleton` (the tree the plan was made for) into `vertices` and
    /// `indices`, as [`write_mesh`] does, without recomputing the plan and without
    /// allocating in proportion to the tree.
    pub fn write<V: VertexSlot>(
        &self,
        skeleton: &Skeleton,
        vertices: &mut [V],
        indices: &mut [u32],
    ) -> Result<MeshSize> {
        self.write_with(skeleton, vertices, indices, &mut Run::default())
    }

    /// [`write`](Self::write) into uninitialised memory (a mapped GPU buffer).
    pub fn write_uninit<V: VertexSlot>(
        &self,
        skeleton: &Skeleton,
        vertices: &mut [V],
        indices: &mut [MaybeUninit<u32>],
    ) -> Result<MeshSize> {
        self.write_with(skeleton, vertices, indices, &mut Run::default())
    }

    /// [`write_uninit`](Self::write_uninit) in `run`: on its thread count when it sets one
    /// (a plan serves options that differ only in their thread count), reporting
    /// [`Stage::Mesh`] after every 65,536 branches (and at the end) on the calling thread.
    /// When the callback returns `false` the write stops with
    /// [`Error::Cancelled`](crate::error::Error::Cancelled) and the buffers hold a partial
    /// mesh, not to be drawn.
    pub fn write_uninit_in<V: VertexSlot>(
        &self,
        skeleton: &Skeleton,
        vertices: &mut [V],
        indices: &mut [MaybeUninit<u32>],
        run: &mut Run<'_>,
    ) -> Result<MeshSize> {
        self.write_with(skeleton, vertices, indices, run)
    }

    /// The owned mesh of `skeleton` with the branch ranges.
    pub fn mesh(&self, skeleton: &Skeleton) -> Result<Mesh> {
        self.mesh_in(skeleton, &mut Run::default())
    }

    /// [`mesh`](Self::mesh) in `run`, as [`write_uninit_in`](Self::write_uninit_in).
    ///
    /// The buffers are asked of the allocator zeroed (`calloc`: fresh pages come zeroed
    /// from the system and are not written twice). The C ABI's `arbor_mesh_create` writes
    /// into uninitialised capacity instead, which also spares reused memory its zero fill.
    pub fn mesh_in(&self, skeleton: &Skeleton, run: &mut Run<'_>) -> Result<Mesh> {
        let size = self.size();
        let mut vertices = crate::limits::try_zeroed(size.vertices, "the mesh's vertices")?;
        let mut indices = crate::limits::try_zeroed(size.indices, "the mesh's indices")?;
        self.write_with(skeleton, &mut vertices[..], &mut indices[..], run)?;
        Ok(self.owned_mesh(vertices, indices))
    }

    /// The owned mesh of buffers this plan has filled.
    pub(crate) fn owned_mesh(&self, vertices: Vec<Vertex>, indices: Vec<u32>) -> Mesh {
        Mesh {
            vertices,
            indices,
            topology: self.options.topology,
            ranges: self.ranges(),
        }
    }

    /// Every write's one path: checks the skeleton and the buffers' room, then writes on
    /// the run's threads (by default the machine's cores, at most 8), reporting to its
    /// callback.
    fn write_with<V: VertexSlot, I: Slot<u32> + Send>(
        &self,
        skeleton: &Skeleton,
        vertices: &mut [V],
        indices: &mut [I],
        run: &mut Run<'_>,
    ) -> Result<MeshSize> {
        let threads = run.threads_or(0);
        self.check_skeleton(skeleton)?;
        self.check_format(V::FORMAT)?;
        let size = self.size();
        size.check_capacity(vertices.len(), indices.len())?;
        self.write_all(
            skeleton,
            threads,
            &mut vertices[..size.vertices],
            &mut indices[..size.indices],
            run,
        )?;
        Ok(size)
    }

    /// Rewrites, inside `vertices` that hold this plan's complete mesh of `skeleton`, the
    /// vertices of `branches` (as [`MeshPlan::update_after_edit`] returns them): the result
    /// equals a full [`write`](Self::write) byte for byte. The indices do not change with
    /// an edit and are not touched.
    pub fn rewrite<V: VertexSlot>(
        &self,
        skeleton: &Skeleton,
        branches: &[u32],
        vertices: &mut [V],
    ) -> Result<()> {
        self.rewrite_into(skeleton, branches, vertices)
    }

    /// [`rewrite`](Self::rewrite) into a host's buffer that may hold uninitialised slots
    /// beyond the mesh (a mapped GPU buffer).
    pub fn rewrite_uninit<V: VertexSlot>(
        &self,
        skeleton: &Skeleton,
        branches: &[u32],
        vertices: &mut [V],
    ) -> Result<()> {
        self.rewrite_into(skeleton, branches, vertices)
    }

    fn rewrite_into<V: VertexSlot>(
        &self,
        skeleton: &Skeleton,
        branches: &[u32],
        vertices: &mut [V],
    ) -> Result<()> {
        self.check_skeleton(skeleton)?;
        self.check_format(V::FORMAT)?;
        let size = self.size();
        size.check_capacity(vertices.len(), size.indices)?;
        let n = skeleton.len();
        // Runs of consecutive branches, each written in one call; the indices, which an
        // edit does not change, go to slots that discard them.
        let mut k = 0;
        while k < branches.len() {
            let a = branches[k] as usize;
            let mut b = a + 1;
            k += 1;
            while k < branches.len() && branches[k] as usize == b {
                b += 1;
                k += 1;
            }
            if a >= n || b > n {
                return Err(crate::error::Error::invalid(
                    "branches",
                    format!("branch {} past the {n} branches", b - 1),
                ));
            }
            let ((_, first), (_, end)) = (self.starts(a), self.starts(b));
            let mut discard = vec![Discard; end - first];
            self.write_branches(
                skeleton,
                a..b,
                &mut vertices[..size.vertices],
                0,
                &mut discard,
                first == 0,
                0,
            );
        }
        Ok(())
    }

    /// How many threads a write of this plan uses when `threads` are asked for.
    fn threads(&self, threads: u32) -> usize {
        // A degenerate strip joins each strip to the previous one's last index, so it is
        // written in order on one thread.
        if self.plan.rules.topology == super::Topology::TriangleStripDegenerate {
            return 1;
        }
        let most = self.branch_count / BRANCHES_PER_THREAD;
        if most <= 1 {
            // A small tree: one thread, without asking the system how many there are
            // (on Linux that reads the cgroup's files each time).
            return 1;
        }
        let wanted = match threads {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get().min(8)),
            t => t as usize,
        };
        wanted.min(most).max(1)
    }

    /// Where branch `b`'s vertices and indices start; the ends of the mesh for `b` = the
    /// branch count.
    fn starts(&self, b: usize) -> (usize, usize) {
        let lay = &self.layout;
        match (lay.first_vertex.get(b), lay.first_index.get(b)) {
            (Some(&v), Some(&i)) => (v as usize, i as usize),
            _ => (self.plan.size.vertices, self.plan.size.indices),
        }
    }

    /// Writes every branch; with a callback, in rounds of [`progress::EVERY`] branches,
    /// reporting after each round on the calling thread and stopping when it says so.
    fn write_all<V: Slot<Vertex> + Send, I: Slot<u32> + Send>(
        &self,
        skeleton: &Skeleton,
        threads: u32,
        vertices: &mut [V],
        indices: &mut [I],
        progress: &mut Run<'_>,
    ) -> Result<()> {
        let n = skeleton.len();
        let threads = self.threads(threads);
        if !progress.active() {
            self.write_range(skeleton, threads, 0..n, vertices, indices, 0);
            return Ok(());
        }
        let round = progress::EVERY.max(threads * BRANCHES_PER_THREAD);
        let (mut v_rest, mut i_rest) = (vertices, indices);
        let (mut lo, mut last) = (0, 0);
        loop {
            let hi = (lo + round).min(n);
            let ((v_lo, i_lo), (v_hi, i_hi)) = (self.starts(lo), self.starts(hi));
            let (va, vb) = std::mem::take(&mut v_rest).split_at_mut(v_hi - v_lo);
            let (ia, ib) = std::mem::take(&mut i_rest).split_at_mut(i_hi - i_lo);
            last = self.write_range(skeleton, threads, lo..hi, va, ia, last);
            progress.report(Stage::Mesh, if n == 0 { 1.0 } else { hi as f64 / n as f64 })?;
            if hi == n {
                return Ok(());
            }
            (v_rest, i_rest, lo) = (vb, ib, hi);
        }
    }

    /// Writes branches `range` into `vertices` and `indices`, which start where the plan
    /// puts the range's first branch, on up to `threads` threads; `last` is the last index
    /// written before the range (for a degenerate join), and the range's last is returned.
    fn write_range<V: Slot<Vertex> + Send, I: Slot<u32> + Send>(
        &self,
        skeleton: &Skeleton,
        threads: usize,
        range: std::ops::Range<usize>,
        vertices: &mut [V],
        indices: &mut [I],
        last: u32,
    ) -> u32 {
        let (v0, i0) = self.starts(range.start);
        let count = range.end - range.start;
        let threads = threads.min(count / BRANCHES_PER_THREAD).max(1);
        if threads == 1 {
            return self.write_branches(skeleton, range, vertices, v0, indices, i0 == 0, last);
        }
        // Chunks of branches write disjoint parts of both buffers, split where the plan
        // says each chunk's first branch starts; the calling thread writes the last. Only
        // lists and restart strips are split, and they need no `last`.
        let per = count.div_ceil(threads);
        std::thread::scope(|scope| {
            let (mut v_rest, mut i_rest) = (vertices, indices);
            let (mut v_at, mut i_at) = (v0, i0);
            let mut lo = range.start;
            let mut threads = Vec::new();
            loop {
                let hi = (lo + per).min(range.end);
                let (v_to, i_to) = self.starts(hi);
                let (va, vb) = std::mem::take(&mut v_rest).split_at_mut(v_to - v_at);
                let (ia, ib) = std::mem::take(&mut i_rest).split_at_mut(i_to - i_at);
                let (chunk, v_base, first) = (lo..hi, v_at, i_at == 0);
                if hi < range.end {
                    threads.push(scope.spawn(move || {
                        self.write_branches(skeleton, chunk, va, v_base, ia, first, 0)
                    }));
                } else {
                    let last = self.write_branches(skeleton, chunk, va, v_base, ia, first, 0);
                    // Joined, not left to the scope: each thread has ended, not only its
                    // work, when this returns (a host's leak checker sees none exiting).
                    for t in threads {
                        t.join()
                            .expect("a part of the mesh's thread does not panic");
                    }
                    return last;
                }
                (v_rest, i_rest, v_at, i_at, lo) = (vb, ib, v_to, i_to, hi);
            }
        })
    }

    /// The tube of kept branch `i` as drawn, given the branch's length `len`
    /// ([`length`](super::plan::length)): (radius at its start ring, radius at its end
    /// ring, height from its start ring's center to its end). A branch that shares its
    /// parent's end ring starts at that ring's radius; a lateral's own ring is sunk one
    /// parent radius into the parent, which lengthens its cone.
    #[inline(always)]
    pub(super) fn drawn(&self, skeleton: &Skeleton, i: usize, len: f64) -> (f32, f32, f64) {
        let branches = skeleton.branches();
        let b = &branches[i];
        let end_radius = |k: usize| {
            let c = self.plan.cont[k];
            if self.options.smooth_taper && c != NO_PARENT {
                branches[c as usize].start_radius
            } else {
                branches[k].end_radius
            }
        };
        let r1 = end_radius(i);
        if b.parent == NO_PARENT {
            return (b.start_radius, r1, len);
        }
        let parent = b.parent as usize;
        if self.plan.flags[i] & SHARES_START != 0 {
            (end_radius(parent), r1, len)
        } else {
            let sink = branches[parent].end_radius as f64;
            (b.start_radius, r1, len + sink)
        }
    }

    /// Writes branches `range` into `vertices` (which starts at vertex `v_base` of the mesh)
    /// and `indices` (which starts at the first index of `range`); `first`: no strip of the
    /// mesh comes before; `last`: the index written just before (for a degenerate join).
    /// Returns the last index written.
    #[allow(clippy::too_many_arguments)]
    fn write_branches<V: Slot<Vertex>, I: Slot<u32>>(
        &self,
        skeleton: &Skeleton,
        range: std::ops::Range<usize>,
        vertices: &mut [V],
        v_base: usize,
        indices: &mut [I],
        first: bool,
        last: u32,
    ) -> u32 {
        let (plan, lay) = (&self.plan, &self.layout);
        let mut writer = StripWriter::new(indices, plan.rules, first);
        writer.last = last;
        let mut strip: Vec<u32> = Vec::with_capacity(2 * MAX_RADIAL_SEGMENTS as usize + 2);
        // Where this chunk's indices start in the whole buffer (for the debug check below).
        let index_base = lay.first_index.get(range.start).map_or(0, |&i| i as usize);
        // The last tube's continuation, which the next tube reuses.
        let mut known = None;
        let shared = PerWrite::of(self);
        for i in range {
            if plan.segs[i] == 0 {
                continue;
            }
            debug_assert_eq!(
                writer.pos + index_base,
                lay.first_index[i] as usize,
                "branch {i}"
            );
            let tube = self.tube(skeleton, i, known.as_ref(), &shared);
            known = tube.cont;
            let at = lay.first_vertex[i] as usize - v_base;
            let end = self.starts(i + 1).0 - v_base;
            if plan.inner > 0 {
                self.write_swept(
                    skeleton,
                    &tube,
                    &mut vertices[at..end],
                    &mut writer,
                    &mut strip,
                );
                continue;
            }
            let firsts = tube.write_vertices(self, &mut vertices[at..end]);
            tube.write_indices(&self.options, firsts, &mut writer, &mut strip);
        }
        debug_assert_eq!(writer.pos, writer.out.len());
        writer.last
    }
}

/// An index slot that drops what is written (a rewrite leaves the indices as they are).
#[derive(Clone, Copy)]
struct Discard;

impl Slot<u32> for Discard {
    #[inline(always)]
    fn put(&mut self, _: u32) {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;

    #[test]
    fn bad_options_are_rejected_by_name() {
        let cases: [(&str, MeshOptions); 6] = [
            ("radial_segments", MeshOptions::default().radial_segments(2)),
            (
                "radial_segments",
                MeshOptions::default().radial_segments(65),
            ),
            (
                "min_radial_segments",
                MeshOptions::default().min_radial_segments(9),
            ),
            ("cull_radius", MeshOptions::default().cull_radius(f32::NAN)),
            ("texture_scale", MeshOptions::default().texture_scale(0.0)),
            ("scale", MeshOptions::default().scale(f32::INFINITY)),
        ];
        for (field, o) in cases {
            match mesh_size(&Skeleton::default(), &o) {
                Err(Error::InvalidArgument { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
    }
}
