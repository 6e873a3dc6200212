//! The tube mesher: every branch a truncated cone, axes joined into watertight tubes.

use super::plan::{BASE_CAP, BranchRange, MITRE_END, MeshPlan, SHARES_START, TIP, length};
use super::rings::{Affine, Out, to_f32};
use super::strips::{Slot, StripWriter, zigzag};
use super::{MAX_RADIAL_SEGMENTS, Mesh, MeshOptions, MeshSize, Tip, Vertex};
use crate::error::Result;
use crate::progress::{self, Progress, ProgressFn, Stage};
use crate::skeleton::{NO_PARENT, Skeleton};
use glam::{Vec2, Vec3};
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
pub fn write_mesh(
    skeleton: &Skeleton,
    options: &MeshOptions,
    vertices: &mut [Vertex],
    indices: &mut [u32],
) -> Result<MeshSize> {
    MeshPlan::new(skeleton, options)?.write(skeleton, vertices, indices)
}

/// [`write_mesh`] into uninitialised memory, such as a mapped GPU buffer or a fresh
/// allocation: every slot of the returned counts' prefixes is initialised on success.
pub fn write_mesh_uninit(
    skeleton: &Skeleton,
    options: &MeshOptions,
    vertices: &mut [MaybeUninit<Vertex>],
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
    pub fn write(
        &self,
        skeleton: &Skeleton,
        vertices: &mut [Vertex],
        indices: &mut [u32],
    ) -> Result<MeshSize> {
        let threads = self.options.threads;
        self.write_on_with(
            skeleton,
            threads,
            vertices,
            indices,
            &mut Progress::default(),
        )
    }

    /// [`write`](Self::write) into uninitialised memory (a mapped GPU buffer).
    pub fn write_uninit(
        &self,
        skeleton: &Skeleton,
        vertices: &mut [MaybeUninit<Vertex>],
        indices: &mut [MaybeUninit<u32>],
    ) -> Result<MeshSize> {
        self.write_uninit_on(skeleton, self.options.threads, vertices, indices)
    }

    /// [`write_uninit`](Self::write_uninit) on up to `threads` threads (as
    /// [`MeshOptions::threads`]) instead of the plan's own setting: a plan serves options
    /// that differ only in their thread count.
    pub fn write_uninit_on(
        &self,
        skeleton: &Skeleton,
        threads: u32,
        vertices: &mut [MaybeUninit<Vertex>],
        indices: &mut [MaybeUninit<u32>],
    ) -> Result<MeshSize> {
        self.write_on_with(
            skeleton,
            threads,
            vertices,
            indices,
            &mut Progress::default(),
        )
    }

    /// [`write_uninit_on`](Self::write_uninit_on), reporting [`Stage::Mesh`] to
    /// `progress` after every 65,536 branches (and at the end) on the calling thread; when
    /// it returns `false` the write stops with [`Error::Cancelled`](crate::error::Error::Cancelled)
    /// and the buffers hold a partial mesh, not to be drawn.
    pub fn write_uninit_with_progress(
        &self,
        skeleton: &Skeleton,
        threads: u32,
        vertices: &mut [MaybeUninit<Vertex>],
        indices: &mut [MaybeUninit<u32>],
        progress: ProgressFn<'_>,
    ) -> Result<MeshSize> {
        self.write_uninit_reporting(skeleton, threads, vertices, indices, Some(progress))
    }

    /// [`write_uninit_on`](Self::write_uninit_on) with an optional callback (the C ABI's
    /// may be NULL).
    pub(crate) fn write_uninit_reporting(
        &self,
        skeleton: &Skeleton,
        threads: u32,
        vertices: &mut [MaybeUninit<Vertex>],
        indices: &mut [MaybeUninit<u32>],
        progress: Option<ProgressFn<'_>>,
    ) -> Result<MeshSize> {
        let mut p = Progress::new(progress);
        self.write_on_with(skeleton, threads, vertices, indices, &mut p)
    }

    /// [`mesh`](Self::mesh), reporting [`Stage::Mesh`] as
    /// [`write_uninit_with_progress`](Self::write_uninit_with_progress) does.
    pub fn mesh_with_progress(
        &self,
        skeleton: &Skeleton,
        progress: ProgressFn<'_>,
    ) -> Result<Mesh> {
        self.mesh_reporting(skeleton, self.options.threads, Some(progress))
    }

    /// The owned mesh of `skeleton` with the branch ranges.
    pub fn mesh(&self, skeleton: &Skeleton) -> Result<Mesh> {
        self.mesh_on(skeleton, self.options.threads)
    }

    /// [`mesh`](Self::mesh) on up to `threads` threads (as [`MeshOptions::threads`]).
    pub fn mesh_on(&self, skeleton: &Skeleton, threads: u32) -> Result<Mesh> {
        self.mesh_reporting(skeleton, threads, None)
    }

    /// [`mesh_on`](Self::mesh_on) with an optional callback, as
    /// [`mesh_with_progress`](Self::mesh_with_progress).
    pub(crate) fn mesh_reporting(
        &self,
        skeleton: &Skeleton,
        threads: u32,
        progress: Option<ProgressFn<'_>>,
    ) -> Result<Mesh> {
        let size = self.size();
        let mut vertices =
            crate::limits::try_zeroed::<Vertex>(size.vertices, "the mesh's vertices")?;
        let mut indices = crate::limits::try_zeroed::<u32>(size.indices, "the mesh's indices")?;
        let mut p = Progress::new(progress);
        self.write_on_with(skeleton, threads, &mut vertices, &mut indices, &mut p)?;
        Ok(Mesh {
            vertices,
            indices,
            topology: self.options.topology,
            ranges: self.ranges(),
        })
    }

    /// Every write's one path: checks the skeleton and the buffers' room, then writes on
    /// up to `threads` threads, reporting to `progress`.
    fn write_on_with<V: Slot<Vertex> + Send, I: Slot<u32> + Send>(
        &self,
        skeleton: &Skeleton,
        threads: u32,
        vertices: &mut [V],
        indices: &mut [I],
        progress: &mut Progress<'_>,
    ) -> Result<MeshSize> {
        self.check_skeleton(skeleton)?;
        let size = self.size();
        size.check_capacity(vertices.len(), indices.len())?;
        self.write_all(
            skeleton,
            threads,
            &mut vertices[..size.vertices],
            &mut indices[..size.indices],
            progress,
        )?;
        Ok(size)
    }

    /// Rewrites, inside `vertices` that hold this plan's complete mesh of `skeleton`, the
    /// vertices of `branches` (as [`MeshPlan::update_after_edit`] returns them): the result
    /// equals a full [`write`](Self::write) byte for byte. The indices do not change with
    /// an edit and are not touched.
    pub fn rewrite(
        &self,
        skeleton: &Skeleton,
        branches: &[u32],
        vertices: &mut [Vertex],
    ) -> Result<()> {
        self.rewrite_into(skeleton, branches, vertices)
    }

    /// [`rewrite`](Self::rewrite) into a host's buffer that may hold uninitialised slots
    /// beyond the mesh (a mapped GPU buffer).
    pub fn rewrite_uninit(
        &self,
        skeleton: &Skeleton,
        branches: &[u32],
        vertices: &mut [MaybeUninit<Vertex>],
    ) -> Result<()> {
        self.rewrite_into(skeleton, branches, vertices)
    }

    fn rewrite_into<V: Slot<Vertex>>(
        &self,
        skeleton: &Skeleton,
        branches: &[u32],
        vertices: &mut [V],
    ) -> Result<()> {
        self.check_skeleton(skeleton)?;
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
        let wanted = match threads {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get().min(8)),
            t => t as usize,
        };
        wanted.min(self.branch_count / BRANCHES_PER_THREAD).max(1)
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
        progress: &mut Progress<'_>,
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
            loop {
                let hi = (lo + per).min(range.end);
                let (v_to, i_to) = self.starts(hi);
                let (va, vb) = std::mem::take(&mut v_rest).split_at_mut(v_to - v_at);
                let (ia, ib) = std::mem::take(&mut i_rest).split_at_mut(i_to - i_at);
                let (chunk, v_base, first) = (lo..hi, v_at, i_at == 0);
                if hi < range.end {
                    scope.spawn(move || {
                        self.write_branches(skeleton, chunk, va, v_base, ia, first, 0)
                    });
                } else {
                    return self.write_branches(skeleton, chunk, va, v_base, ia, first, 0);
                }
                (v_rest, i_rest, v_at, i_at, lo) = (vb, ib, v_to, i_to, hi);
            }
        })
    }

    /// The tube of kept branch `i` as drawn: (radius at its start ring, radius at its end
    /// ring, height from its start ring's center to its end). A branch that shares its
    /// parent's end ring starts at that ring's radius; a lateral's own ring is sunk one
    /// parent radius into the parent, which lengthens its cone.
    #[inline(always)]
    fn drawn(&self, skeleton: &Skeleton, i: usize) -> (f32, f32, f64) {
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
            return (b.start_radius, r1, length(b));
        }
        let parent = b.parent as usize;
        if self.plan.flags[i] & SHARES_START != 0 {
            (end_radius(parent), r1, length(b))
        } else {
            let sink = branches[parent].end_radius as f64;
            (b.start_radius, r1, length(b) + sink)
        }
    }

    /// (radial, axial) parts of the unit outward normal of kept branch `i`'s cone as
    /// drawn: radial·h + axis·(r0 − r1), normalised (in f64 when the f32 sum of squares
    /// overflows).
    #[inline(always)]
    fn slope(&self, skeleton: &Skeleton, i: usize) -> (f32, f32) {
        let (r0, r1, h) = self.drawn(skeleton, i);
        let slope = Vec2::new(h as f32, r0 - r1);
        match slope.try_normalize() {
            Some(n) => (n.x, n.y),
            None if slope == Vec2::ZERO => (1.0, 0.0),
            None => {
                let dr = (r0 - r1) as f64;
                let slant = (h * h + dr * dr).sqrt();
                ((h / slant) as f32, (dr / slant) as f32)
            }
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
        for i in range {
            if plan.segs[i] == 0 {
                continue;
            }
            debug_assert_eq!(
                writer.pos + index_base,
                lay.first_index[i] as usize,
                "branch {i}"
            );
            let tube = self.tube(skeleton, i);
            let at = lay.first_vertex[i] as usize - v_base;
            let end = at + plan.counts(i, self.options.tip, &mut false).0;
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
            let firsts = tube.write_vertices(self, skeleton, &mut vertices[at..end]);
            tube.write_indices(&self.options, firsts, &mut writer, &mut strip);
        }
        debug_assert_eq!(writer.pos, writer.out.len());
        writer.last
    }

    /// Writes a branch swept along its curve (`curve_rings` > 0): its own start ring
    /// unless shared, `k` inner rings at equal curve parameters framed by rotation-
    /// minimising frames, its end ring (mitred with the continuation when shared), caps;
    /// then the `k + 1` tube segments between consecutive rings and the caps' indices.
    fn write_swept<V: Slot<Vertex>, I: Slot<u32>>(
        &self,
        skeleton: &Skeleton,
        t: &Tube<'_>,
        out: &mut [V],
        writer: &mut StripWriter<'_, I>,
        strip: &mut Vec<u32>,
    ) {
        let (plan, lay, o) = (&self.plan, &self.layout, &self.options);
        let i = t.i;
        let (s, ring, table, f) = (t.segments, t.segments + 1, t.table, t.flags);
        let rot = |v: Vec3| Vec3::from_array(t.out.dir(v));
        let pos = |v: Vec3| Vec3::from_array(t.out.pos(v));
        let k = plan.inner;
        let curve = skeleton.curve(i);
        let (t0, t1) = (plan.t0[i], plan.t1[i]);
        let scale = t.out.scale;
        // The ring of the sweep at a point: radial·r in the frame (p, tangent × p), normal
        // radial·nc + tangent·na.
        let ring_at = |center: Vec3, tangent: Vec3, p: Vec3, r: f32, v: f32| {
            let (po, qo, to) = (rot(p), rot(tangent.cross(p)), rot(tangent));
            Affine::new(
                pos(center),
                po * (r * scale),
                qo * (r * scale),
                to * t.na,
                po * t.nc,
                qo * t.nc,
                [0.0, v],
                [0.0; 2],
                [0.0; 2],
                [1.0, 0.0],
            )
        };
        let mut at = 0;
        let mut rings: Vec<u32> = Vec::with_capacity(k + 2);
        let start_center = match t.shared_start {
            Some(shared) => {
                rings.push(shared);
                t.start
            }
            None => {
                let c0 = t.start - t0 * t.sink;
                let v = to_f32(t.v0 as f64 - t.sink as f64 * t.inv_ts);
                ring_at(c0, t0, lay.frame_p[i], t.r0, v).put(&mut out[..ring], table);
                rings.push(t.first_vertex);
                at += ring;
                c0
            }
        };
        let mut end_frame = lay.frame_p[i];
        curve.rotation_minimising_frames(t0, lay.frame_p[i], k + 1, |j, x, tangent, p, arc| {
            if j == 0 || j > k {
                end_frame = p;
                return;
            }
            let u = j as f32 / (k + 1) as f32;
            let r = t.r0 + (t.r1 - t.r0) * u;
            let v = to_f32(t.v0 as f64 + arc as f64 * t.inv_ts);
            ring_at(x, tangent, p, r, v).put(&mut out[at..at + ring], table);
            rings.push(t.first_vertex + at as u32);
            at += ring;
        });
        debug_assert_eq!(t.first_vertex + at as u32, t.end_ring);
        let end_out = &mut out[at..at + ring];
        if f & MITRE_END != 0 {
            let c = plan.cont[i] as usize;
            let frame = (rot(end_frame), rot(t1.cross(end_frame)));
            t.mitre_with(self, skeleton, c, frame, t1, plan.t0[c])
                .put_normalized(end_out, table);
        } else {
            ring_at(t.end, t1, end_frame, t.r1, t.v1).put(end_out, table);
        }
        rings.push(t.end_ring);
        at += ring;
        let base_first = t.first_vertex + at as u32;
        if f & BASE_CAP != 0 {
            let (po, qo) = (rot(lay.frame_p[i]), rot(t0.cross(lay.frame_p[i])));
            Affine::new(
                pos(start_center),
                po * (t.r0 * scale),
                qo * (t.r0 * scale),
                -rot(t0),
                Vec3::ZERO,
                Vec3::ZERO,
                [0.5, 0.5],
                [0.5, 0.0],
                [0.0, -0.5],
                [0.0; 2],
            )
            .put(&mut out[at..at + s], table);
            at += s;
        }
        let tip_first = t.first_vertex + at as u32;
        if f & TIP != 0 {
            let (po, qo, d_o) = (rot(end_frame), rot(t1.cross(end_frame)), rot(t1));
            let tip = &mut out[at..at + s];
            match o.tip {
                Tip::Cap => Affine::new(
                    pos(t.end),
                    po * (t.r1 * scale),
                    qo * (t.r1 * scale),
                    d_o,
                    Vec3::ZERO,
                    Vec3::ZERO,
                    [0.5, 0.5],
                    [0.5, 0.0],
                    [0.0, 0.5],
                    [0.0; 2],
                )
                .put(tip, table),
                _ => {
                    let apex = pos(t.end + t1 * t.r1);
                    let v = to_f32(t.v1 as f64 + t.r1 as f64 * t.inv_ts);
                    for (j, slot) in tip.iter_mut().enumerate() {
                        let (c0, s0, u0) = table[j];
                        let (c1, s1, u1) = table[j + 1];
                        let radial = (po * (c0 + c1) + qo * (s0 + s1)).normalize_or_zero();
                        slot.put(Vertex {
                            position: apex.to_array(),
                            normal: (radial + d_o).normalize().to_array(),
                            uv: [0.5 * (u0 + u1), v],
                        });
                    }
                }
            }
            at += s;
        }
        debug_assert_eq!(at, out.len());
        for w in rings.windows(2) {
            writer.tube(w[1], w[0], ring as u32);
        }
        t.write_indices_caps(o, base_first, tip_first, writer, strip);
    }

    /// Everything the writer needs of kept branch `i`, in output space.
    #[inline(always)]
    fn tube(&self, skeleton: &Skeleton, i: usize) -> Tube<'_> {
        let (o, plan, lay) = (&self.options, &self.plan, &self.layout);
        let out = o.out();
        // The output conventions are linear: apply them to each branch's centers and frame
        // vectors once, so the per-vertex loops are a few multiply-adds.
        let rot = |v: Vec3| Vec3::from_array(out.dir(v));
        let b = &skeleton.branches()[i];
        let s = plan.segs[i] as usize;
        let (d, p) = (plan.dir[i], lay.frame_p[i]);
        let (r0, r1, _) = self.drawn(skeleton, i);
        let (nc, na) = self.slope(skeleton, i);
        let parent = (b.parent != NO_PARENT).then_some(b.parent as usize);
        Tube {
            i,
            segments: s,
            table: &self.tables[s],
            flags: plan.flags[i],
            out,
            po: rot(p),
            qo: rot(d.cross(p)),
            d_o: rot(d),
            d,
            nc,
            na,
            r0,
            r1,
            v0: parent.map_or(0.0, |p| lay.v_end[p]),
            v1: lay.v_end[i],
            // In f64: a tiny texture scale must not turn v infinite.
            inv_ts: 1.0 / o.texture_scale as f64,
            first_vertex: lay.first_vertex[i],
            end_ring: lay.end_ring[i],
            shared_start: parent
                .filter(|_| plan.flags[i] & SHARES_START != 0)
                .map(|p| lay.end_ring[p]),
            sink: parent.map_or(0.0, |p| skeleton.branches()[p].end_radius),
            start: b.start(),
            end: b.end(),
        }
    }
}

/// An index slot that drops what is written (a rewrite leaves the indices as they are).
#[derive(Clone, Copy)]
struct Discard;

impl Slot<u32> for Discard {
    #[inline(always)]
    fn put(&mut self, _: u32) {}
}

/// One kept branch's tube as the writer sees it: frame and centers in output space, the
/// cone's slope, radii, texture v and where its rings go.
struct Tube<'a> {
    i: usize,
    segments: usize,
    /// The unit circle: (cos, sin, u) per vertex of a ring.
    table: &'a [(f32, f32, f32)],
    flags: u8,
    out: Out,
    /// Ring frame and axis in output space.
    po: Vec3,
    qo: Vec3,
    d_o: Vec3,
    /// The axis in model space.
    d: Vec3,
    /// Radial and axial parts of the cone's unit normal.
    nc: f32,
    na: f32,
    /// Radii as drawn (model units).
    r0: f32,
    r1: f32,
    v0: f32,
    v1: f32,
    inv_ts: f64,
    first_vertex: u32,
    end_ring: u32,
    /// The parent's end ring, when this branch starts on it.
    shared_start: Option<u32>,
    /// How far an own start ring sinks into the parent.
    sink: f32,
    start: Vec3,
    end: Vec3,
}

/// First vertex of each part of a tube's vertices: (start ring, base cap, tip).
type Firsts = (u32, u32, u32);

impl Tube<'_> {
    #[inline(always)]
    fn pos(&self, v: Vec3) -> Vec3 {
        Vec3::from_array(self.out.pos(v))
    }

    /// A ring of the cone: radial·r around the center, normal radial·nc + axis·na.
    #[inline(always)]
    fn cone(&self, center: Vec3, r: f32, v: f32) -> Affine {
        Affine::new(
            center,
            self.po * r,
            self.qo * r,
            self.d_o * self.na,
            self.po * self.nc,
            self.qo * self.nc,
            [0.0, v],
            [0.0; 2],
            [0.0; 2],
            [1.0, 0.0],
        )
    }

    /// A disc of radius r facing `normal`, uv a unit disc around (0.5, 0.5) (`flip`
    /// mirrors v, so a base cap seen from below is not mirrored).
    #[inline(always)]
    fn disc(&self, center: Vec3, r: f32, normal: Vec3, flip: bool) -> Affine {
        Affine::new(
            center,
            self.po * r,
            self.qo * r,
            normal,
            Vec3::ZERO,
            Vec3::ZERO,
            [0.5, 0.5],
            [0.5, 0.0],
            [0.0, if flip { -0.5 } else { 0.5 }],
            [0.0; 2],
        )
    }

    /// The end ring shared with the continuing branch `c`, in the plane bisecting the bend.
    /// Each point of the circle slides along d onto that plane: the position gives up
    /// `slide · (radial · m)`. The point lies on a generator line of both cones (this
    /// branch's, and the continuing branch's at the transported angle), along which each
    /// cone's normal is constant: the vertex normal is the mean of the two, normalised per
    /// vertex.
    fn mitre(&self, plan: &MeshPlan, skeleton: &Skeleton, c: usize) -> Affine {
        self.mitre_with(
            plan,
            skeleton,
            c,
            (self.po, self.qo),
            self.d,
            plan.plan.dir[c],
        )
    }

    /// [`mitre`](Self::mitre) with the end ring's frame (output space) and the two axes at
    /// the joint (model space) given: this branch's at its end, the continuation's at its
    /// start (the curves' tangents in a sweep).
    fn mitre_with(
        &self,
        plan: &MeshPlan,
        skeleton: &Skeleton,
        c: usize,
        (po, qo): (Vec3, Vec3),
        d: Vec3,
        dc: Vec3,
    ) -> Affine {
        let rot = |v: Vec3| Vec3::from_array(self.out.dir(v));
        let d_o = rot(d);
        let r1s = self.r1 * self.out.scale;
        let m = rot((d + dc).normalize());
        let slide = d_o * (r1s / d_o.dot(m));
        let (pm, qm) = (po.dot(m), qo.dot(m));
        let (nc_c, na_c) = plan.slope(skeleton, c);
        // The cross product in arbor's space, then mapped: a mirror flips one taken after.
        let p_c = plan.layout.frame_p[c];
        let (pc, qc, dc) = (rot(p_c), rot(dc.cross(p_c)), rot(dc));
        Affine::new(
            self.pos(self.end),
            po * r1s - slide * pm,
            qo * r1s - slide * qm,
            (d_o * self.na + dc * na_c) * 0.5,
            (po * self.nc + pc * nc_c) * 0.5,
            (qo * self.nc + qc * nc_c) * 0.5,
            [0.0, self.v1],
            [0.0; 2],
            [0.0; 2],
            [1.0, 0.0],
        )
    }

    /// Writes the tube's own vertices (`out` holds exactly them): its start ring unless
    /// shared, its end ring, a base cap, a tip. Returns where each part starts.
    #[inline(always)]
    fn write_vertices<V: Slot<Vertex>>(
        &self,
        plan: &MeshPlan,
        skeleton: &Skeleton,
        out: &mut [V],
    ) -> Firsts {
        let (s, ring, table, f) = (self.segments, self.segments + 1, self.table, self.flags);
        let scale = self.out.scale;
        let mut pos = 0;
        let start_center = match self.shared_start {
            Some(_) => self.start,
            None => {
                let c0 = self.start - self.d * self.sink;
                let v = to_f32(self.v0 as f64 - self.sink as f64 * self.inv_ts);
                self.cone(self.pos(c0), self.r0 * scale, v)
                    .put(&mut out[..ring], table);
                pos += ring;
                c0
            }
        };
        let start_ring = self.shared_start.unwrap_or(self.first_vertex);
        debug_assert_eq!(self.first_vertex + pos as u32, self.end_ring);
        let ring_out = &mut out[pos..pos + ring];
        if f & MITRE_END != 0 {
            let c = plan.plan.cont[self.i] as usize;
            self.mitre(plan, skeleton, c)
                .put_normalized(ring_out, table);
        } else {
            self.cone(self.pos(self.end), self.r1 * scale, self.v1)
                .put(ring_out, table);
        }
        pos += ring;
        let base_first = self.first_vertex + pos as u32;
        if f & BASE_CAP != 0 {
            self.disc(self.pos(start_center), self.r0 * scale, -self.d_o, true)
                .put(&mut out[pos..pos + s], table);
            pos += s;
        }
        let tip_first = self.first_vertex + pos as u32;
        if f & TIP != 0 {
            let tip = &mut out[pos..pos + s];
            match plan.options.tip {
                Tip::Cap => self
                    .disc(self.pos(self.end), self.r1 * scale, self.d_o, false)
                    .put(tip, table),
                _ => self.point_tip(tip),
            }
            pos += s;
        }
        debug_assert_eq!(pos, out.len());
        (start_ring, base_first, tip_first)
    }

    /// The apexes of a cone one radius beyond the end, one per side (each with the
    /// normal of its facet's middle).
    fn point_tip<V: Slot<Vertex>>(&self, out: &mut [V]) {
        let apex = self.pos(self.end + self.d * self.r1);
        let v = to_f32(self.v1 as f64 + self.r1 as f64 * self.inv_ts);
        for (j, slot) in out.iter_mut().enumerate() {
            let (c0, s0, u0) = self.table[j];
            let (c1, s1, u1) = self.table[j + 1];
            let radial = (self.po * (c0 + c1) + self.qo * (s0 + s1)).normalize_or_zero();
            slot.put(Vertex {
                position: apex.to_array(),
                normal: (radial + self.d_o).normalize().to_array(),
                uv: [0.5 * (u0 + u1), v],
            });
        }
    }

    /// Writes the tube's indices: the tube between its rings, then the caps.
    #[inline(always)]
    fn write_indices<I: Slot<u32>>(
        &self,
        o: &MeshOptions,
        (start_ring, base_first, tip_first): Firsts,
        writer: &mut StripWriter<'_, I>,
        strip: &mut Vec<u32>,
    ) {
        writer.tube(self.end_ring, start_ring, self.segments as u32 + 1);
        self.write_indices_caps(o, base_first, tip_first, writer, strip);
    }

    /// The caps' indices (base cap, then tip).
    #[inline(always)]
    fn write_indices_caps<I: Slot<u32>>(
        &self,
        o: &MeshOptions,
        base_first: u32,
        tip_first: u32,
        writer: &mut StripWriter<'_, I>,
        strip: &mut Vec<u32>,
    ) {
        let s = self.segments;
        if self.flags & BASE_CAP != 0 {
            zigzag(s, |k| base_first + ((s - k) % s) as u32, strip);
            writer.strip(strip);
        }
        if self.flags & TIP != 0 {
            if o.tip == Tip::Cap {
                zigzag(s, |k| tip_first + k as u32, strip);
                writer.strip(strip);
            } else {
                for j in 0..s as u32 {
                    writer.strip(&[tip_first + j, self.end_ring + j, self.end_ring + j + 1]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;

    #[test]
    fn bad_options_are_rejected_by_name() {
        let cases: [(&str, MeshOptions); 6] = [
            (
                "radial_segments",
                MeshOptions {
                    radial_segments: 2,
                    ..Default::default()
                },
            ),
            (
                "radial_segments",
                MeshOptions {
                    radial_segments: 65,
                    ..Default::default()
                },
            ),
            (
                "min_radial_segments",
                MeshOptions {
                    min_radial_segments: 9,
                    ..Default::default()
                },
            ),
            (
                "cull_radius",
                MeshOptions {
                    cull_radius: f32::NAN,
                    ..Default::default()
                },
            ),
            (
                "texture_scale",
                MeshOptions {
                    texture_scale: 0.0,
                    ..Default::default()
                },
            ),
            (
                "scale",
                MeshOptions {
                    scale: f32::INFINITY,
                    ..Default::default()
                },
            ),
        ];
        for (field, o) in cases {
            match mesh_size(&Skeleton::default(), &o) {
                Err(Error::InvalidArgument { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
    }
}
