//! One kept branch's tube as the writer sees it, and the writing of its rings, caps and
//! indices.

use super::plan::{BASE_CAP, MITRE_END, MeshPlan, SHARES_START, TIP, axis};
use super::rings::Slot;
use super::rings::{Affine, Circle, Out, to_f32};
use super::strips::{StripWriter, zigzag};
use super::{MeshOptions, Tip, Vertex};
use crate::geom::lanes::{cross3, dot3, unit3, unit3_or_zero};
use crate::skeleton::{NO_PARENT, Skeleton};
use glam::Vec3A;

impl MeshPlan {
    /// Everything the writer needs of kept branch `i`, in output space. `known` is what
    /// the previous tube worked out about its continuation (along an axis, the next
    /// branch): used when it is branch `i`. `shared` is the write's [`PerWrite`].
    #[inline(always)]
    pub(super) fn tube(
        &self,
        skeleton: &Skeleton,
        i: usize,
        known: Option<&Known>,
        shared: &PerWrite,
    ) -> Tube<'_> {
        let (plan, lay) = (&self.plan, &self.layout);
        let out = shared.out;
        // The output conventions are linear: apply them to each branch's centers and frame
        // vectors once, so the per-vertex loops are a few multiply-adds.
        let rot = |v: Vec3A| out.dir_a(v);
        let b = &skeleton.branches()[i];
        let s = plan.segs[i] as usize;
        let p = Vec3A::from(lay.frame_p[i]);
        let (d, (r0, r1), (nc, na)) = match known {
            Some(k) if k.i == i => (k.d, k.radii, k.slope),
            _ => {
                let (d, len) = axis(b);
                let (r0, r1, h) = self.drawn(skeleton, i, len);
                (Vec3A::from(d), (r0, r1), slope_of(r0, r1, h))
            }
        };
        let parent = (b.parent != NO_PARENT).then_some(b.parent as usize);
        let flags = plan.flags[i];
        let PerWrite { vk, inv_ts, .. } = *shared;
        // The continuing branch's direction, radii and slope, for the mitred end ring.
        let cont = if flags & MITRE_END != 0 {
            let c = plan.cont[i] as usize;
            let (d, len) = axis(&skeleton.branches()[c]);
            let (r0, r1, h) = self.drawn(skeleton, c, len);
            Some(Known {
                i: c,
                d: Vec3A::from(d),
                radii: (r0, r1),
                slope: slope_of(r0, r1, h),
            })
        } else {
            None
        };
        let (cont_slope, cont_dir) = cont.as_ref().map_or(((1.0, 0.0), d), |k| (k.slope, k.d));
        Tube {
            i,
            segments: s,
            table: if self.plan.wrap(i) < 0.0 {
                &self.mirrored_tables[s]
            } else {
                &self.tables[s]
            },
            flags,
            out,
            po: rot(p),
            qo: rot(cross3(d, p)),
            d_o: rot(d),
            d,
            nc,
            na,
            cont_slope,
            cont_dir,
            r0,
            r1,
            // v divided by the plan's v_scale (a power of two: exact), for compact vertices.
            v0: parent.map_or(0.0, |p| lay.v_end[p]) * vk,
            v1: lay.v_end[i] * vk,
            inv_ts,
            vk,
            wrap: self.plan.wrap(i).abs(),
            cont,
            first_vertex: lay.first_vertex[i],
            end_ring: self.end_ring(i),
            shared_start: parent
                .filter(|_| plan.flags[i] & SHARES_START != 0)
                .map(|p| self.end_ring(p)),
            sink: parent.map_or(0.0, |p| skeleton.branches()[p].end_radius),
            start: Vec3A::from(b.start()),
            end: Vec3A::from(b.end()),
        }
    }
}

/// What a tube works out about the branch that continues it, which the next tube reuses
/// when it is that branch.
#[derive(Clone, Copy)]
pub(super) struct Known {
    pub(super) i: usize,
    /// Unit axis (model space).
    pub(super) d: Vec3A,
    /// Radii as drawn.
    pub(super) radii: (f32, f32),
    /// Radial and axial parts of the cone's unit normal.
    pub(super) slope: (f32, f32),
}

/// What every tube of a write shares, worked out once per write: the output conventions,
/// `vk`, 1 / the plan's v_scale (an exact power of two), and `inv_ts`, `vk` / the texture
/// scale in f64 (a tiny texture scale must not turn v infinite).
#[derive(Clone, Copy)]
pub(super) struct PerWrite {
    pub(super) out: Out,
    pub(super) vk: f32,
    pub(super) inv_ts: f64,
}

impl PerWrite {
    pub(super) fn of(plan: &MeshPlan) -> Self {
        let vk = 1.0 / plan.v_scale;
        PerWrite {
            out: plan.options.out(),
            vk,
            inv_ts: vk as f64 / plan.options.texture_scale as f64,
        }
    }
}

/// One kept branch's tube as the writer sees it: frame and centers in output space, the
/// cone's slope, radii, texture v and where its rings go.
pub(super) struct Tube<'a> {
    pub(super) i: usize,
    pub(super) segments: usize,
    /// The unit circle: (cos, sin, u) per vertex of a ring.
    pub(super) table: &'a Circle,
    pub(super) flags: u8,
    pub(super) out: Out,
    /// Ring frame and axis in output space.
    pub(super) po: Vec3A,
    pub(super) qo: Vec3A,
    pub(super) d_o: Vec3A,
    /// The axis in model space.
    pub(super) d: Vec3A,
    /// Radial and axial parts of the cone's unit normal.
    pub(super) nc: f32,
    pub(super) na: f32,
    /// The continuing branch's (nc, na), when the end ring is mitred.
    pub(super) cont_slope: (f32, f32),
    /// The continuing branch's direction (model space), when the end ring is mitred.
    pub(super) cont_dir: Vec3A,
    /// Radii as drawn (model units).
    pub(super) r0: f32,
    pub(super) r1: f32,
    pub(super) v0: f32,
    pub(super) v1: f32,
    pub(super) inv_ts: f64,
    /// 1 / the plan's v_scale: what a cap's v is multiplied by.
    pub(super) vk: f32,
    /// How many times u wraps around the tube (once without `even_texels`).
    pub(super) wrap: f32,
    /// The continuing branch, when the end ring is mitred.
    pub(super) cont: Option<Known>,
    pub(super) first_vertex: u32,
    pub(super) end_ring: u32,
    /// The parent's end ring, when this branch starts on it.
    pub(super) shared_start: Option<u32>,
    /// How far an own start ring sinks into the parent.
    pub(super) sink: f32,
    pub(super) start: Vec3A,
    pub(super) end: Vec3A,
}

/// First vertex of each part of a tube's vertices: (start ring, base cap, tip).
type Firsts = (u32, u32, u32);

impl Tube<'_> {
    #[inline(always)]
    pub(super) fn pos(&self, v: Vec3A) -> Vec3A {
        self.out.pos_a(v)
    }

    /// A ring of the cone: radial·r around the center, normal radial·nc + axis·na.
    #[inline(always)]
    pub(super) fn cone(&self, center: Vec3A, r: f32, v: f32) -> Affine {
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
            [self.wrap, 0.0],
        )
    }

    /// A disc of radius r facing `normal`, uv a unit disc around (0.5, 0.5) (`flip`
    /// mirrors v, so a base cap seen from below is not mirrored).
    #[inline(always)]
    pub(super) fn disc(&self, center: Vec3A, r: f32, normal: Vec3A, flip: bool) -> Affine {
        self.disc_framed(center, (self.po, self.qo), r, normal, flip)
    }

    /// [`disc`](Self::disc) on the frame `(po, qo)` (output space), as a sweep's ends have.
    #[inline(always)]
    pub(super) fn disc_framed(
        &self,
        center: Vec3A,
        (po, qo): (Vec3A, Vec3A),
        r: f32,
        normal: Vec3A,
        flip: bool,
    ) -> Affine {
        Affine::new(
            center,
            po * r,
            qo * r,
            normal,
            Vec3A::ZERO,
            Vec3A::ZERO,
            [0.5, 0.5 * self.vk],
            [0.5, 0.0],
            [0.0, if flip { -0.5 } else { 0.5 } * self.vk],
            [0.0; 2],
        )
    }

    /// The end ring shared with the continuing branch `c`, in the plane bisecting the bend.
    /// Each point of the circle slides along d onto that plane: the position gives up
    /// `slide · (radial · m)`. The point lies on a generator line of both cones (this
    /// branch's, and the continuing branch's at the transported angle), along which each
    /// cone's normal is constant: the vertex normal is the mean of the two, normalised per
    /// vertex.
    #[inline(always)]
    pub(super) fn mitre(&self, plan: &MeshPlan, c: usize) -> Affine {
        self.mitre_with(plan, c, (self.po, self.qo), self.d, self.cont_dir)
    }

    /// [`mitre`](Self::mitre) with the end ring's frame (output space) and the two axes at
    /// the joint (model space) given: this branch's at its end, the continuation's at its
    /// start (the curves' tangents in a sweep).
    #[inline(always)]
    pub(super) fn mitre_with(
        &self,
        plan: &MeshPlan,
        c: usize,
        (po, qo): (Vec3A, Vec3A),
        d: Vec3A,
        dc: Vec3A,
    ) -> Affine {
        let rot = |v: Vec3A| self.out.dir_a(v);
        let d_o = rot(d);
        let r1s = self.r1 * self.out.scale;
        let m = rot(unit3(d + dc));
        let slide = d_o * (r1s / dot3(d_o, m));
        let (pm, qm) = (dot3(po, m), dot3(qo, m));
        let (nc_c, na_c) = self.cont_slope;
        // The cross product in arbor's space, then mapped: a mirror flips one taken after.
        let p_c = Vec3A::from(plan.layout.frame_p[c]);
        let (pc, qc, dc) = (rot(p_c), rot(cross3(dc, p_c)), rot(dc));
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
            [self.wrap, 0.0],
        )
    }

    /// Writes the tube's own vertices (`out` holds exactly them): its start ring unless
    /// shared, its end ring, a base cap, a tip. Returns where each part starts.
    #[inline(always)]
    pub(super) fn write_vertices<V: Slot<Vertex>>(&self, plan: &MeshPlan, out: &mut [V]) -> Firsts {
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
            self.mitre(plan, c).put_normalized(ring_out, table);
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
    pub(super) fn point_tip<V: Slot<Vertex>>(&self, out: &mut [V]) {
        let apex = self.pos(self.end + self.d * self.r1);
        let v = to_f32(self.v1 as f64 + self.r1 as f64 * self.inv_ts);
        for (j, slot) in out.iter_mut().enumerate() {
            let (c0, s0, u0) = self.table[j];
            let (c1, s1, u1) = self.table[j + 1];
            let radial = unit3_or_zero(self.po * (c0 + c1) + self.qo * (s0 + s1));
            slot.put(Vertex {
                position: apex.to_array(),
                normal: unit3(radial + self.d_o).to_array(),
                uv: [0.5 * (u0 + u1), v],
            });
        }
    }

    /// Writes the tube's indices: the tube between its rings, then the caps.
    #[inline(always)]
    pub(super) fn write_indices<I: Slot<u32>>(
        &self,
        o: &MeshOptions,
        (start_ring, base_first, tip_first): Firsts,
        writer: &mut StripWriter<'_, I>,
        strip: &mut Vec<u32>,
    ) {
        writer.tube(
            self.end_ring,
            start_ring,
            self.segments as u32 + 1,
            self.shared_start.is_none(),
        );
        self.write_indices_caps(o, base_first, tip_first, writer, strip);
    }

    /// The caps' indices (base cap, then tip).
    #[inline(always)]
    pub(super) fn write_indices_caps<I: Slot<u32>>(
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

/// (radial, axial) parts of the unit outward normal of a cone with radii `r0`, `r1` and
/// height `h`: radial·h + axis·(r0 − r1), normalised (in f64 when the f32 sum of squares
/// overflows).
#[inline(always)]
pub(super) fn slope_of(r0: f32, r1: f32, h: f64) -> (f32, f32) {
    let slope = glam::Vec2::new(h as f32, r0 - r1);
    match slope.try_normalize() {
        Some(n) => (n.x, n.y),
        None if slope == glam::Vec2::ZERO => (1.0, 0.0),
        None => {
            let dr = (r0 - r1) as f64;
            let slant = (h * h + dr * dr).sqrt();
            ((h / slant) as f32, (dr / slant) as f32)
        }
    }
}
