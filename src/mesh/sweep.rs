//! Swept branches: a branch drawn along its curve with inner rings on
//! rotation-minimising frames (`curve_rings` > 0).

use super::plan::{BASE_CAP, MITRE_END, MeshPlan, TIP};
use super::rings::Slot;
use super::rings::{Affine, to_f32};
use super::strips::StripWriter;
use super::tube::Tube;
use super::{Tip, Vertex};
use crate::geom::lanes::{cross3, unit3, unit3_or_zero};
use crate::skeleton::Skeleton;
use glam::{Vec3, Vec3A};

/// The ring of a sweep at a point: radial·r in the frame (p, tangent × p), normal
/// radial·nc + tangent·na, in the output's conventions.
fn ring_at(t: &Tube<'_>, center: Vec3A, tangent: Vec3A, p: Vec3A, r: f32, v: f32) -> Affine {
    let rot = |v: Vec3A| t.out.dir_a(v);
    let (po, qo, to) = (rot(p), rot(cross3(tangent, p)), rot(tangent));
    let rs = r * t.out.scale;
    Affine::new(
        t.out.pos_a(center),
        po * rs,
        qo * rs,
        to * t.na,
        po * t.nc,
        qo * t.nc,
        [0.0, v],
        [0.0; 2],
        [0.0; 2],
        [t.wrap, 0.0],
    )
}

impl MeshPlan {
    /// Writes a branch swept along its curve (`curve_rings` > 0): its own start ring
    /// unless shared, `k` inner rings at equal curve parameters framed by rotation-
    /// minimising frames, its end ring (mitred with the continuation when shared), caps;
    /// then the `k + 1` tube segments between consecutive rings and the caps' indices.
    pub(super) fn write_swept<V: Slot<Vertex>, I: Slot<u32>>(
        &self,
        skeleton: &Skeleton,
        t: &Tube<'_>,
        out: &mut [V],
        writer: &mut StripWriter<'_, I>,
        strip: &mut Vec<u32>,
    ) {
        let ring = t.segments + 1;
        let (start_center, end_frame, mut at) = self.swept_rings(skeleton, t, out);
        let base_first = t.first_vertex + at as u32;
        if t.flags & BASE_CAP != 0 {
            self.swept_base_cap(t, start_center, &mut out[at..at + t.segments]);
            at += t.segments;
        }
        let tip_first = t.first_vertex + at as u32;
        if t.flags & TIP != 0 {
            self.swept_tip(t, end_frame, &mut out[at..at + t.segments]);
            at += t.segments;
        }
        debug_assert_eq!(at, out.len());
        // The rings follow one another from the start ring (shared or the branch's own).
        let own = if t.shared_start.is_some() { 0 } else { ring };
        let mut previous = t.shared_start.unwrap_or(t.first_vertex);
        for j in 0..=self.plan.inner {
            let next = t.first_vertex + (own + j * ring) as u32;
            // Only the first tube can start on a ring made before it (or on its own).
            let fresh = j == 0 && t.shared_start.is_none();
            writer.tube(next, previous, ring as u32, fresh);
            previous = next;
        }
        debug_assert_eq!(previous, t.end_ring);
        t.write_indices_caps(&self.options, base_first, tip_first, writer, strip);
    }

    /// The rings of a swept branch into `out`: its own start ring (unless shared), the
    /// inner rings and the end ring. Returns the start ring's center, the end's frame
    /// vector and the vertices written.
    fn swept_rings<V: Slot<Vertex>>(
        &self,
        skeleton: &Skeleton,
        t: &Tube<'_>,
        out: &mut [V],
    ) -> (Vec3A, Vec3, usize) {
        let (plan, lay) = (&self.plan, &self.layout);
        let (i, k, ring, table) = (t.i, plan.inner, t.segments + 1, t.table);
        let (t0, t1) = (Vec3A::from(plan.t0[i]), Vec3A::from(plan.t1[i]));
        let frame_p = Vec3A::from(lay.frame_p[i]);
        let mut at = 0;
        let start_center = match t.shared_start {
            Some(_) => t.start,
            None => {
                let c0 = t.start - t0 * t.sink;
                let v = to_f32(t.v0 as f64 - t.sink as f64 * t.inv_ts);
                ring_at(t, c0, t0, frame_p, t.r0, v).put(&mut out[..ring], table);
                at += ring;
                c0
            }
        };
        let mut end_frame = lay.frame_p[i];
        let curve = skeleton.curve(i);
        curve.rotation_minimising_frames(
            t0.into(),
            lay.frame_p[i],
            k + 1,
            |j, x, tangent, p, arc| {
                if j == 0 || j > k {
                    end_frame = p;
                    return;
                }
                let u = j as f32 / (k + 1) as f32;
                let r = t.r0 + (t.r1 - t.r0) * u;
                let v = to_f32(t.v0 as f64 + arc as f64 * t.inv_ts);
                ring_at(t, x.into(), tangent.into(), p.into(), r, v)
                    .put(&mut out[at..at + ring], table);
                at += ring;
            },
        );
        debug_assert_eq!(t.first_vertex + at as u32, t.end_ring);
        let end_out = &mut out[at..at + ring];
        if t.flags & MITRE_END != 0 {
            let rot = |v: Vec3A| t.out.dir_a(v);
            let c = plan.cont[i] as usize;
            let end_frame = Vec3A::from(end_frame);
            let frame = (rot(end_frame), rot(cross3(t1, end_frame)));
            t.mitre_with(self, c, frame, t1, plan.t0[c].into())
                .put_normalized(end_out, table);
        } else {
            ring_at(t, t.end, t1, end_frame.into(), t.r1, t.v1).put(end_out, table);
        }
        (start_center, end_frame, at + ring)
    }

    /// The base cap of a swept branch, facing back along its start tangent.
    fn swept_base_cap<V: Slot<Vertex>>(&self, t: &Tube<'_>, center: Vec3A, out: &mut [V]) {
        let rot = |v: Vec3A| t.out.dir_a(v);
        let (frame, t0) = (
            Vec3A::from(self.layout.frame_p[t.i]),
            Vec3A::from(self.plan.t0[t.i]),
        );
        let (po, qo) = (rot(frame), rot(cross3(t0, frame)));
        let center = t.out.pos_a(center);
        t.disc_framed(center, (po, qo), t.r0 * t.out.scale, -rot(t0), true)
            .put(out, t.table);
    }

    /// The tip of a swept branch along its end tangent: a cap or a point.
    fn swept_tip<V: Slot<Vertex>>(&self, t: &Tube<'_>, end_frame: Vec3, tip: &mut [V]) {
        let rot = |v: Vec3A| t.out.dir_a(v);
        let (t1, end_frame) = (Vec3A::from(self.plan.t1[t.i]), Vec3A::from(end_frame));
        let (po, qo, d_o) = (rot(end_frame), rot(cross3(t1, end_frame)), rot(t1));
        match self.options.tip {
            Tip::Cap => {
                let center = t.out.pos_a(t.end);
                t.disc_framed(center, (po, qo), t.r1 * t.out.scale, d_o, false)
            }
            .put(tip, t.table),
            _ => {
                let apex = t.out.pos_a(t.end + t1 * t.r1).to_array();
                let v = to_f32(t.v1 as f64 + t.r1 as f64 * t.inv_ts);
                for (j, slot) in tip.iter_mut().enumerate() {
                    let (c0, s0, u0) = t.table[j];
                    let (c1, s1, u1) = t.table[j + 1];
                    let radial = unit3_or_zero(po * (c0 + c1) + qo * (s0 + s1));
                    slot.put(Vertex {
                        position: apex,
                        normal: unit3(radial + d_o).to_array(),
                        uv: [0.5 * (u0 + u1), v],
                    });
                }
            }
        }
    }
}
