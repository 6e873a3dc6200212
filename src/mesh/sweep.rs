//! Swept branches: a branch drawn along its curve with inner rings on
//! rotation-minimising frames (`curve_rings` > 0).

use super::plan::{BASE_CAP, MITRE_END, MeshPlan, TIP};
use super::rings::{Affine, to_f32};
use super::strips::{Slot, StripWriter};
use super::tube::Tube;
use super::{Tip, Vertex};
use crate::skeleton::Skeleton;
use glam::Vec3;

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
}
