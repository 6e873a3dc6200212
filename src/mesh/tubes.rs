//! The tube mesher: every branch a truncated cone, axes joined into watertight tubes.

use super::plan::{BASE_CAP, BranchRange, MITRE_END, MeshPlan, SHARES_START, TIP, length};
use super::rings::{Affine, Out, to_f32};
use super::strips::{Slot, StripWriter, zigzag};
use super::{MAX_RADIAL_SEGMENTS, Mesh, MeshOptions, MeshSize, Tip, UpAxis, Vertex};
use crate::error::Result;
use crate::skeleton::{NO_PARENT, Skeleton};
use glam::{Vec2, Vec3};
use std::mem::MaybeUninit;

/// The exact vertex and index counts [`write_mesh`] needs for `skeleton`.
///
/// Fails with [`Error::InvalidArgument`](crate::Error::InvalidArgument) for bad options and
/// [`Error::LimitExceeded`](crate::Error::LimitExceeded) when the vertices or indices could
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
/// A slice shorter than needed gives [`Error::BufferTooSmall`](crate::Error::BufferTooSmall)
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
        self.write_checked(skeleton, vertices, indices)
    }

    /// [`write`](Self::write) into uninitialised memory (a mapped GPU buffer).
    pub fn write_uninit(
        &self,
        skeleton: &Skeleton,
        vertices: &mut [MaybeUninit<Vertex>],
        indices: &mut [MaybeUninit<u32>],
    ) -> Result<MeshSize> {
        self.write_checked(skeleton, vertices, indices)
    }

    /// The owned mesh of `skeleton` with the branch ranges.
    pub fn mesh(&self, skeleton: &Skeleton) -> Result<Mesh> {
        let size = self.size();
        let mut vertices = bytemuck::zeroed_vec::<Vertex>(size.vertices);
        let mut indices = bytemuck::zeroed_vec::<u32>(size.indices);
        self.write(skeleton, &mut vertices, &mut indices)?;
        Ok(Mesh {
            vertices,
            indices,
            topology: self.options.topology,
            ranges: self.ranges(),
        })
    }

    fn write_checked<V: Slot<Vertex> + Send, I: Slot<u32> + Send>(
        &self,
        skeleton: &Skeleton,
        vertices: &mut [V],
        indices: &mut [I],
    ) -> Result<MeshSize> {
        self.check_skeleton(skeleton)?;
        let size = self.size();
        size.check_capacity(vertices.len(), indices.len())?;
        self.write_all(
            skeleton,
            &mut vertices[..size.vertices],
            &mut indices[..size.indices],
        );
        Ok(size)
    }

    /// How many threads a write of this plan uses.
    fn threads(&self) -> usize {
        // A degenerate strip joins each strip to the previous one's last index, so it is
        // written in order on one thread.
        if self.plan.rules.topology == super::Topology::TriangleStripDegenerate {
            return 1;
        }
        let wanted = match self.options.threads {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get().min(8)),
            t => t as usize,
        };
        wanted.min(self.branch_count / BRANCHES_PER_THREAD).max(1)
    }

    fn write_all<V: Slot<Vertex> + Send, I: Slot<u32> + Send>(
        &self,
        skeleton: &Skeleton,
        vertices: &mut [V],
        indices: &mut [I],
    ) {
        let n = skeleton.len();
        let threads = self.threads();
        if threads == 1 {
            self.write_branches(skeleton, 0..n, vertices, 0, indices, true);
            return;
        }
        // Chunks of branches write disjoint parts of both buffers, split where the plan
        // says each chunk's first branch starts; the calling thread writes the last.
        let per = n.div_ceil(threads);
        let lay = &self.layout;
        std::thread::scope(|scope| {
            let (mut v_rest, mut i_rest) = (vertices, indices);
            let (mut v_at, mut i_at) = (0usize, 0usize);
            let mut lo = 0;
            while lo < n {
                let hi = (lo + per).min(n);
                let (v_to, i_to) = if hi < n {
                    (lay.first_vertex[hi] as usize, lay.first_index[hi] as usize)
                } else {
                    (self.plan.size.vertices, self.plan.size.indices)
                };
                let (va, vb) = std::mem::take(&mut v_rest).split_at_mut(v_to - v_at);
                let (ia, ib) = std::mem::take(&mut i_rest).split_at_mut(i_to - i_at);
                let (range, v_base, first) = (lo..hi, v_at, i_at == 0);
                if hi < n {
                    scope
                        .spawn(move || self.write_branches(skeleton, range, va, v_base, ia, first));
                } else {
                    self.write_branches(skeleton, range, va, v_base, ia, first);
                }
                (v_rest, i_rest, v_at, i_at, lo) = (vb, ib, v_to, i_to, hi);
            }
        });
    }

    /// The tube of kept branch `i` as drawn: (radius at its start ring, radius at its end
    /// ring, height from its start ring's center to its end). A branch that shares its
    /// parent's end ring starts at that ring's radius; a lateral's own ring is sunk one
    /// parent radius into the parent, which lengthens its cone.
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
    /// mesh comes before.
    fn write_branches<V: Slot<Vertex>, I: Slot<u32>>(
        &self,
        skeleton: &Skeleton,
        range: std::ops::Range<usize>,
        vertices: &mut [V],
        v_base: usize,
        indices: &mut [I],
        first: bool,
    ) {
        let (o, plan, lay, tables) = (&self.options, &self.plan, &self.layout, &self.tables);
        let branches = skeleton.branches();
        let out = Out {
            scale: o.scale,
            z_up: o.up_axis == UpAxis::Z,
        };
        // The output conventions are linear: apply them to each branch's centers and frame
        // vectors once, so the per-vertex loops are two multiply-adds.
        let rot = |v: Vec3| Vec3::from_array(out.dir(v));
        // In f64: a tiny texture scale must not turn v infinite.
        let inv_ts = 1.0 / o.texture_scale as f64;
        let dir = &plan.dir;
        let mut writer = StripWriter::new(indices, plan.rules, first);
        let mut strip: Vec<u32> = Vec::with_capacity(2 * MAX_RADIAL_SEGMENTS as usize + 2);
        // Where this chunk's indices start in the whole buffer (for the debug check below).
        let index_base = lay.first_index.get(range.start).map_or(0, |&i| i as usize);

        for i in range {
            let b = &branches[i];
            let d = dir[i];
            let s = plan.segs[i] as usize;
            if s == 0 {
                continue;
            }
            let table = &tables[s];
            let ring = s + 1;
            let f = plan.flags[i];
            let first_vertex = lay.first_vertex[i] as usize;
            debug_assert_eq!(
                writer.pos + index_base,
                lay.first_index[i] as usize,
                "branch {i}"
            );
            let start = b.start();
            let end = b.end();
            let root = b.parent == NO_PARENT;
            let p = lay.frame_p[i];
            let q = d.cross(p);
            let (r0, r1, _) = self.drawn(skeleton, i);
            let v0 = if root {
                0.0
            } else {
                lay.v_end[b.parent as usize]
            };
            let v1 = lay.v_end[i];
            let (nc, na) = self.slope(skeleton, i);
            // Output-space frame.
            let (po, qo, d_o) = (rot(p), rot(q), rot(d));
            let tilt = d_o * na;
            let (r0s, r1s) = (r0 * o.scale, r1 * o.scale);
            let mut pos = first_vertex - v_base;
            // A ring of the cone: radial·r around the center, normal radial·nc + tilt.
            let cone = |center: Vec3, r: f32, v: f32| {
                Affine::new(
                    center,
                    po * r,
                    qo * r,
                    tilt,
                    po * nc,
                    qo * nc,
                    [0.0, v],
                    [0.0; 2],
                    [0.0; 2],
                    [1.0, 0.0],
                )
            };

            // Start ring, unless shared with the parent.
            let (start_ring, start_center) = if f & SHARES_START != 0 {
                (lay.end_ring[b.parent as usize], start)
            } else {
                let sink = if root {
                    0.0
                } else {
                    branches[b.parent as usize].end_radius
                };
                let c0 = start - d * sink;
                let co = Vec3::from_array(out.pos(c0));
                let v = to_f32(v0 as f64 - sink as f64 * inv_ts);
                cone(co, r0s, v).put(&mut vertices[pos..pos + ring], table);
                pos += ring;
                (first_vertex as u32, c0)
            };
            // End ring: in the bisecting plane when the next branch of the axis shares it.
            let my_end_ring = lay.end_ring[i];
            debug_assert_eq!(my_end_ring as usize, pos + v_base);
            let eo = Vec3::from_array(out.pos(end));
            let ring_out = &mut vertices[pos..pos + ring];
            if f & MITRE_END != 0 {
                let c = plan.cont[i] as usize;
                let m = rot((d + dir[c]).normalize());
                // Each point of the circle slides along d onto the bisecting plane: the
                // position gives up `slide · (radial · m)`. The point lies on a generator
                // line of both cones (this branch's, and the continuing branch's at the
                // transported angle), along which each cone's normal is constant: the
                // vertex normal is the mean of the two, normalised per vertex.
                let slide = d_o * (r1s / d_o.dot(m));
                let (pm, qm) = (po.dot(m), qo.dot(m));
                let (nc_c, na_c) = self.slope(skeleton, c);
                let pc = rot(lay.frame_p[c]);
                let dc = rot(dir[c]);
                let qc = dc.cross(pc);
                Affine::new(
                    eo,
                    po * r1s - slide * pm,
                    qo * r1s - slide * qm,
                    (tilt + dc * na_c) * 0.5,
                    (po * nc + pc * nc_c) * 0.5,
                    (qo * nc + qc * nc_c) * 0.5,
                    [0.0, v1],
                    [0.0; 2],
                    [0.0; 2],
                    [1.0, 0.0],
                )
                .put_normalized(ring_out, table);
            } else {
                cone(eo, r1s, v1).put(ring_out, table);
            }
            pos += ring;
            // Base cap: a disc facing −d at the start ring.
            let base_first = (pos + v_base) as u32;
            if f & BASE_CAP != 0 {
                let co = Vec3::from_array(out.pos(start_center));
                Affine::new(
                    co,
                    po * r0s,
                    qo * r0s,
                    -d_o,
                    Vec3::ZERO,
                    Vec3::ZERO,
                    [0.5, 0.5],
                    [0.5, 0.0],
                    [0.0, -0.5],
                    [0.0; 2],
                )
                .put(&mut vertices[pos..pos + s], table);
                pos += s;
            }
            // Tip: a disc facing +d, or apexes of a cone one radius beyond the end.
            let tip_first = (pos + v_base) as u32;
            if f & TIP != 0 {
                match o.tip {
                    Tip::Cap => {
                        Affine::new(
                            eo,
                            po * r1s,
                            qo * r1s,
                            d_o,
                            Vec3::ZERO,
                            Vec3::ZERO,
                            [0.5, 0.5],
                            [0.5, 0.0],
                            [0.0, 0.5],
                            [0.0; 2],
                        )
                        .put(&mut vertices[pos..pos + s], table);
                    }
                    _ => {
                        let apex = Vec3::from_array(out.pos(end + d * r1));
                        for (j, slot) in vertices[pos..pos + s].iter_mut().enumerate() {
                            let (c0, s0, u0) = table[j];
                            let (c1, s1, u1) = table[j + 1];
                            let radial = (po * (c0 + c1) + qo * (s0 + s1)).normalize_or_zero();
                            slot.put(Vertex {
                                position: apex.to_array(),
                                normal: (radial + d_o).normalize().to_array(),
                                uv: [0.5 * (u0 + u1), to_f32(v1 as f64 + r1 as f64 * inv_ts)],
                            });
                        }
                    }
                }
                pos += s;
            }

            // Indices: the tube, then the caps.
            writer.tube(my_end_ring, start_ring, ring as u32);
            if f & BASE_CAP != 0 {
                zigzag(s, |k| base_first + ((s - k) % s) as u32, &mut strip);
                writer.strip(&strip);
            }
            if f & TIP != 0 {
                if o.tip == Tip::Cap {
                    zigzag(s, |k| tip_first + k as u32, &mut strip);
                    writer.strip(&strip);
                } else {
                    for j in 0..s as u32 {
                        writer.strip(&[tip_first + j, my_end_ring + j, my_end_ring + j + 1]);
                    }
                }
            }
            debug_assert!(pos <= vertices.len());
        }
        debug_assert_eq!(writer.pos, writer.out.len());
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
