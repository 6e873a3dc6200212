//! The compact vertex format: 20 bytes a vertex instead of 32.
//!
//! Position stays f32; the unit normal is octahedral-encoded into two snorm16; u and v are
//! unorm16, v over the mesh's `v_scale` (a power of two at least the mesh's largest v, so
//! the stored v is v / v_scale in [0, 1]). The mesh writers already produce v divided by
//! that scale when the options ask for compact vertices, so each vertex is encoded where it
//! is written, with no second pass over the mesh: a ring four vertices at a time, in
//! vector lanes ([`encode_lanes`]), anything else one by one.

use super::quantize::{SNORM_MAGIC, UNORM_MAGIC, unorm16};
use super::rings::{Affine, Circle, Slot};
use super::{Vertex, VertexFormat};
use bytemuck::{Pod, Zeroable};
use glam::Vec4;
use std::mem::MaybeUninit;

/// One compact mesh vertex (C: ArborVertexCompact), 20 bytes, interleaved: position (3 x
/// f32) at offset 0, normal (2 x snorm16, octahedral) at 12, uv (2 x unorm16) at 16;
/// stride 20.
///
/// Decode a normal as `p = max(normal / 32767, -1)`, `n = (p.x, p.y, 1 - |p.x| - |p.y|)`,
/// and where `n.z < 0`, `n.x = (1 - |p.y|) * sign(p.x)` and `n.y = (1 - |p.x|) *
/// sign(p.y)`; then normalise. Decode uv as `uv / 65535 * (1, v_scale)`, with the mesh's
/// v_scale (`MeshPlan::v_scale` in Rust, arbor_mesh_v_scale() in C).
/// [`VertexCompact::decode`] does both.
///
/// Precision against the 32-byte [`Vertex`] of the same mesh: normals within 0.01 degrees,
/// u within 1/131070 and v within v_scale/131070 (at most 1/65535 of the mesh's v range,
/// as v_scale is less than twice the largest v). `tests/compact.rs` measures both.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct VertexCompact {
    /// Position in the skeleton's units, as in [`Vertex`].
    pub position: [f32; 3],
    /// The unit normal, octahedral, snorm16 (-32767..=32767 for -1..=1).
    pub normal: [i16; 2],
    /// u (0..=65535 for 0..=1) and v (0..=65535 for 0..=v_scale), unorm16.
    pub uv: [u16; 2],
}

const _: () = {
    assert!(std::mem::size_of::<VertexCompact>() == 20);
    assert!(std::mem::offset_of!(VertexCompact, position) == 0);
    assert!(std::mem::offset_of!(VertexCompact, normal) == 12);
    assert!(std::mem::offset_of!(VertexCompact, uv) == 16);
};

impl VertexCompact {
    /// `vertex` in the compact format, its v divided by `v_scale` (values outside
    /// 0..=v_scale are clamped).
    pub fn encode(vertex: &Vertex, v_scale: f32) -> Self {
        let [u, v] = vertex.uv;
        Self::from_scaled(Vertex {
            uv: [u, v / v_scale],
            ..*vertex
        })
    }

    /// The vertex this one stands for in a mesh of `v_scale`.
    pub fn decode(&self, v_scale: f32) -> Vertex {
        let [x, y] = self.normal.map(|c| (c as f32 / 32767.0).max(-1.0));
        let z = 1.0 - x.abs() - y.abs();
        let (x, y) = if z < 0.0 {
            ((1.0 - y.abs()).copysign(x), (1.0 - x.abs()).copysign(y))
        } else {
            (x, y)
        };
        let n = glam::Vec3::new(x, y, z).normalize_or_zero();
        let [u, v] = self.uv.map(|c| c as f32 / 65535.0);
        Vertex {
            position: self.position,
            normal: n.to_array(),
            uv: [u, v * v_scale],
        }
    }

    /// A vertex whose v is already divided by the mesh's v_scale, one at a time (tips and
    /// other vertices outside a ring; rings go four at a time through [`encode_lanes`],
    /// which rounds the same way).
    #[inline(always)]
    fn from_scaled(vertex: Vertex) -> Self {
        let [x, y, z] = vertex.normal;
        let l1 = x.abs() + y.abs() + z.abs();
        // A zero normal (none is written) encodes as (0, 0): zero times a finite inverse.
        let inv = 1.0 / l1.max(f32::MIN_POSITIVE);
        let (px, py) = (x * inv, y * inv);
        let (fx, fy) = ((1.0 - py.abs()).copysign(px), (1.0 - px.abs()).copysign(py));
        let (ox, oy) = if z < 0.0 { (fx, fy) } else { (px, py) };
        // Rounded to nearest (ties to even) as the four-lane path does; |ox| and |oy| are
        // at most 1 but for rounding, which the rounding to an integer absorbs.
        let snorm = |c: f32| (c * 32767.0 + SNORM_MAGIC).to_bits() as u16 as i16;
        VertexCompact {
            position: vertex.position,
            normal: [snorm(ox), snorm(oy)],
            uv: vertex.uv.map(unorm16),
        }
    }
}

/// The smallest power of two at least `v_max` and at least 1: the compact format's
/// v_scale for a mesh whose v reaches `v_max`.
pub(crate) fn v_scale_for(v_max: f32) -> f32 {
    let mut s = 1.0f32;
    // f32 powers of two reach 2^127; v is clamped below f32::MAX.
    while s < v_max && s < 2f32.powi(127) {
        s *= 2.0;
    }
    s
}

/// Encodes four vertices given as lanes (position x, y, z, normal x, y, z, u, v; v already
/// divided by the mesh's v_scale): the arithmetic of [`VertexCompact::from_scaled`], four
/// vertices to a vector, so a ring costs one vector division per four vertices.
#[inline(always)]
pub(crate) fn encode_lanes(l: &[Vec4; 8]) -> [VertexCompact; 4] {
    let [px, py, pz, x, y, z, u, v] = *l;
    interleave(
        [px, py, pz],
        octahedral([x, y, z]),
        pack16(unorm(u), unorm(v)),
    )
}

/// Four normals' octahedral snorm16 pairs, each pair in one 32-bit lane (x low).
#[inline(always)]
fn octahedral([x, y, z]: [Vec4; 3]) -> [u32; 4] {
    let l1 = x.abs() + y.abs() + z.abs();
    let inv = Vec4::ONE / l1.max(Vec4::splat(f32::MIN_POSITIVE));
    let (qx, qy) = (x * inv, y * inv);
    let (fx, fy) = (
        (Vec4::ONE - qy.abs()).copysign(qx),
        (Vec4::ONE - qx.abs()).copysign(qy),
    );
    let down = z.cmplt(Vec4::ZERO);
    let (ox, oy) = (Vec4::select(down, fx, qx), Vec4::select(down, fy, qy));
    // Each lane's 16-bit value in the low bits of a float's mantissa (see UNORM_MAGIC).
    let snorm = |c: Vec4| c * 32767.0 + SNORM_MAGIC;
    pack16(snorm(ox), snorm(oy))
}

/// Texture coordinates in [0, 1] as unorm16, each in the low bits of a float's mantissa
/// (see [`UNORM_MAGIC`]).
#[inline(always)]
fn unorm(c: Vec4) -> Vec4 {
    c.clamp(Vec4::ZERO, Vec4::ONE) * 65535.0 + UNORM_MAGIC
}

/// Per lane, the low 16 bits of `lo`'s float and, above them, the low 16 bits of `hi`'s.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn pack16(lo: Vec4, hi: Vec4) -> [u32; 4] {
    use safe_arch::{
        bitand_m128i, bitor_m128i, cast_to_m128i_from_m128, m128, m128i, shl_imm_u32_m128i,
    };
    let bits = |v: Vec4| cast_to_m128i_from_m128(m128(v.into()));
    let low = m128i::from([0xffff_i32; 4]);
    bytemuck::cast(bitor_m128i(
        bitand_m128i(bits(lo), low),
        shl_imm_u32_m128i::<16>(bits(hi)),
    ))
}

/// [`pack16`] lane by lane: where SSE2 is not there, and as its reference.
#[cfg_attr(target_arch = "x86_64", cfg_attr(not(test), allow(dead_code)))]
#[inline(always)]
fn pack16_lanes(lo: Vec4, hi: Vec4) -> [u32; 4] {
    std::array::from_fn(|k| (lo[k].to_bits() & 0xffff) | (hi[k].to_bits() << 16))
}

#[cfg(not(target_arch = "x86_64"))]
use pack16_lanes as pack16;

/// Four compact vertices from their lanes: positions, and the normal's and uv's two
/// 16-bit values each packed into one 32-bit lane ([`pack16`]). With SSE2 (every x86-64)
/// the five lanes are transposed in registers into the 80 bytes of the four vertices
/// (four unpacks, four moves and eight shuffles), stored as five 16-byte vectors.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn interleave([px, py, pz]: [Vec4; 3], n: [u32; 4], uv: [u32; 4]) -> [VertexCompact; 4] {
    use safe_arch::{
        cast_to_m128_from_m128i, m128, m128i, move_high_low_m128 as hl, move_low_high_m128 as lh,
        shuffle_abi_f32_all_m128 as shuf, unpack_high_m128, unpack_low_m128,
    };
    let m = |v: Vec4| m128(v.into());
    let packed = |v: [u32; 4]| cast_to_m128_from_m128i(bytemuck::cast::<_, m128i>(v));
    let (n, uv) = (packed(n), packed(uv));
    let (px, py, pz) = (m(px), m(py), m(pz));
    // Each vertex's first 16 bytes (x, y, z, normal): a 4 x 4 transpose.
    let (t0, t1) = (unpack_low_m128(px, py), unpack_low_m128(pz, n));
    let (t2, t3) = (unpack_high_m128(px, py), unpack_high_m128(pz, n));
    let (r0, r1, r2, r3) = (lh(t0, t1), hl(t1, t0), lh(t2, t3), hl(t3, t2));
    // shufps: lanes i and j of its first operand, then k and l of its second.
    const fn pick(i: i32, j: i32, k: i32, l: i32) -> i32 {
        i | (j << 2) | (k << 4) | (l << 6)
    }
    // Each vertex's uv after its first 16 bytes: the 80 bytes as five vectors.
    let w1 = shuf::<{ pick(0, 1, 1, 2) }>(unpack_low_m128(uv, r1), r1);
    let w2 = shuf::<{ pick(0, 2, 0, 1) }>(shuf::<{ pick(3, 3, 1, 1) }>(r1, uv), r2);
    let w3 = shuf::<{ pick(2, 3, 0, 2) }>(r2, shuf::<{ pick(2, 2, 0, 0) }>(uv, r3));
    let w4 = shuf::<{ pick(1, 2, 0, 2) }>(r3, shuf::<{ pick(3, 3, 3, 3) }>(r3, uv));
    bytemuck::cast([r0, w1, w2, w3, w4])
}

/// [`interleave`] lane by lane: where SSE2 is not there, and as the reference the SSE2
/// form is tested against.
#[cfg_attr(target_arch = "x86_64", cfg_attr(not(test), allow(dead_code)))]
#[inline(always)]
fn interleave_lanes([px, py, pz]: [Vec4; 3], n: [u32; 4], uv: [u32; 4]) -> [VertexCompact; 4] {
    let (px, py, pz) = (px.to_array(), py.to_array(), pz.to_array());
    std::array::from_fn(|k| VertexCompact {
        position: [px[k], py[k], pz[k]],
        normal: [n[k] as u16 as i16, (n[k] >> 16) as u16 as i16],
        uv: [uv[k] as u16, (uv[k] >> 16) as u16],
    })
}

#[cfg(not(target_arch = "x86_64"))]
use interleave_lanes as interleave;

/// Writes the ring `ring` as compact vertices, four at a time in lanes (position, normal and
/// uv of four vertices, each component one vector), handing each four to `store4` (and
/// each vertex of a last, partial four and the seam to `store`). The
/// octahedral encoding divides by the normal's L1 norm, so a normal needs no unit length
/// first: a mitred ring is written as its plain affine form. Positions and uv are those
/// of the f32 writer bit for bit (the same terms summed in the same order). A tube's ring
/// (u the circle's, v one value: [`Affine::tube_v`]) takes its u from the circle's
/// encoded u and its v encoded once (the same bits: `0 + 0·c + 0·s + 1·u` is u, and
/// `v + 0·c + 0·s + 0·u` is v but for the sign of a zero, which unorm16 does not keep).
#[inline(always)]
fn put_compact<S>(
    ring: &Affine,
    out: &mut [S],
    table: &Circle,
    tube_v: Option<f32>,
    store: impl Fn(&mut S, VertexCompact),
    store4: impl Fn(&mut [S; 4], [VertexCompact; 4]),
) {
    let terms = ring.component_terms();
    let quads = table.quads.iter().zip(&table.u_quads).zip(&table.u_unorm);
    // The seam (point 0 again with u = 1) is vertex 0 with u and v plus e's terms
    // (`Affine::seam_of`).
    let (body, seam) = table.body(out.len());
    let mut first = None;
    // A tube's v, and its unorm16 in the high half of a uv lane.
    let tube = tube_v.map(|v| (v, (unorm16(v) as u32) << 16));
    for (slots, ((&[c, s], &u), &u16s)) in out[..body].chunks_mut(4).zip(quads) {
        let lane = |k: usize| {
            let [a, b, d, e] = terms[k];
            let x = a + b * c + d * s;
            // Only u and v have a term in u (a ring's e is zero elsewhere).
            if k >= 6 { x + e * u } else { x }
        };
        let (encoded, u0, v0) = match tube {
            Some((v, high)) => {
                let (p, n) = ([lane(0), lane(1), lane(2)], [lane(3), lane(4), lane(5)]);
                let uv = u16s.map(|u| u | high);
                (interleave(p, octahedral(n), uv), u.x, v)
            }
            None => {
                let l: [Vec4; 8] = std::array::from_fn(lane);
                (encode_lanes(&l), l[6].x, l[7].x)
            }
        };
        first.get_or_insert((encoded[0], u0, v0));
        if let Ok(four) = <&mut [S; 4]>::try_from(&mut *slots) {
            store4(four, encoded);
        } else {
            for (slot, e) in slots.iter_mut().zip(encoded) {
                store(slot, e);
            }
        }
    }
    if let (true, Some((v0, u, v))) = (seam, first) {
        let [_, hi] = ring.seam_of([Vec4::ZERO, Vec4::new(0.0, 0.0, u, v)]);
        let uv = [unorm16(hi.z), unorm16(hi.w)];
        store(&mut out[body], VertexCompact { uv, ..v0 });
    }
}

impl Slot<Vertex> for VertexCompact {
    #[inline(always)]
    fn put(&mut self, value: Vertex) {
        *self = VertexCompact::from_scaled(value);
    }

    #[inline(always)]
    fn put_affine(out: &mut [Self], ring: &Affine, table: &Circle, _: bool) -> bool {
        put_compact(
            ring,
            out,
            table,
            ring.tube_v(),
            |slot, e| *slot = e,
            |four, e| *four = e,
        );
        true
    }
}

impl Slot<Vertex> for MaybeUninit<VertexCompact> {
    #[inline(always)]
    fn put(&mut self, value: Vertex) {
        self.write(VertexCompact::from_scaled(value));
    }

    #[inline(always)]
    fn put_affine(out: &mut [Self], ring: &Affine, table: &Circle, _: bool) -> bool {
        put_compact(
            ring,
            out,
            table,
            ring.tube_v(),
            |slot, e| {
                slot.write(e);
            },
            |four, e| *four = e.map(MaybeUninit::new),
        );
        true
    }
}

/// Elements a mesh can be written into: [`Vertex`] and [`VertexCompact`], initialised or
/// not (a mapped GPU buffer). Sealed: arbor's writers know how to fill each.
pub trait VertexSlot: Slot<Vertex> + Send + private::Sealed {
    /// The format these elements hold, which the mesh options' `vertex_format` must name.
    const FORMAT: VertexFormat;
}

mod private {
    pub trait Sealed {}
    impl Sealed for super::Vertex {}
    impl Sealed for std::mem::MaybeUninit<super::Vertex> {}
    impl Sealed for super::VertexCompact {}
    impl Sealed for std::mem::MaybeUninit<super::VertexCompact> {}
}

impl VertexSlot for Vertex {
    const FORMAT: VertexFormat = VertexFormat::F32;
}
impl VertexSlot for MaybeUninit<Vertex> {
    const FORMAT: VertexFormat = VertexFormat::F32;
}
impl VertexSlot for VertexCompact {
    const FORMAT: VertexFormat = VertexFormat::Compact;
}
impl VertexSlot for MaybeUninit<VertexCompact> {
    const FORMAT: VertexFormat = VertexFormat::Compact;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn v_scale_is_the_power_of_two_at_or_above() {
        for (v, s) in [
            (0.0, 1.0),
            (0.5, 1.0),
            (1.0, 1.0),
            (1.5, 2.0),
            (402.9, 512.0),
        ] {
            assert_eq!(v_scale_for(v), s, "{v}");
        }
        assert_eq!(v_scale_for(512.0), 512.0);
        assert_eq!(v_scale_for(f32::NAN), 1.0);
    }

    /// Random lanes: positions, normals with zeros of either sign, zero normals and
    /// normals below the horizon, texture coordinates past [0, 1].
    fn random_lanes(rng: &mut crate::rng::Rng) -> [Vec4; 8] {
        let mut x = || {
            let r = rng.next_f64() as f32;
            match (r * 16.0) as u32 {
                0 => 0.0,
                1 => -0.0,
                2 => 1.0,
                3 => -1.0,
                _ => r * 4.0 - 2.0,
            }
        };
        std::array::from_fn(|_| Vec4::new(x(), x(), x(), x()))
    }

    #[test]
    fn four_lanes_encode_as_four_single_vertices() {
        let mut rng = crate::rng::Rng::new(31);
        for _ in 0..20_000 {
            let l = random_lanes(&mut rng);
            let lanes = encode_lanes(&l);
            for (k, got) in lanes.iter().enumerate() {
                let c = |j: usize| l[j][k];
                let one = VertexCompact::from_scaled(Vertex {
                    position: [c(0), c(1), c(2)],
                    normal: [c(3), c(4), c(5)],
                    uv: [c(6), c(7)],
                });
                assert_eq!(*got, one, "lane {k} of {l:?}");
            }
        }
    }

    #[test]
    fn the_interleave_in_registers_is_the_one_lane_by_lane() {
        let mut rng = crate::rng::Rng::new(32);
        for _ in 0..1_000 {
            let [a, b, c, d, e, f, g, _] = random_lanes(&mut rng);
            // Any bits in the 16-bit fields' floats: only their low halves are kept.
            let (n, uv) = (pack16(d, e), pack16(f, g));
            assert_eq!((n, uv), (pack16_lanes(d, e), pack16_lanes(f, g)));
            assert_eq!(
                interleave([a, b, c], n, uv),
                interleave_lanes([a, b, c], n, uv)
            );
        }
    }

    #[test]
    fn a_tubes_ring_encodes_its_uv_once_as_every_ring_does() {
        use glam::Vec3A;
        let mut rng = crate::rng::Rng::new(33);
        let mut f = || rng.next_f64() as f32 * 4.0 - 2.0;
        for sides in [3, 4, 5, 8, 9, 12] {
            let table = super::super::rings::circle(sides);
            for _ in 0..300 {
                let mut v3 = || Vec3A::new(f(), f(), f());
                let (c, p, q, n, np, nq) = (v3(), v3(), v3(), v3(), v3(), v3());
                let v = match (f() * 4.0) as i32 {
                    0 => 0.0,
                    1 => -0.0,
                    _ => f().abs() * 0.3,
                };
                let ring =
                    Affine::new(c, p, q, n, np, nq, [0.0, v], [0.0; 2], [0.0; 2], [1.0, 0.0]);
                assert_eq!(ring.tube_v(), Some(v));
                for n in [table.len(), table.len() - 1, 5.min(table.len())] {
                    let (mut once, mut each) = (
                        vec![VertexCompact::default(); n],
                        vec![VertexCompact::default(); n],
                    );
                    put_compact(
                        &ring,
                        &mut once,
                        &table,
                        Some(v),
                        |s, e| *s = e,
                        |s, e| *s = e,
                    );
                    put_compact(&ring, &mut each, &table, None, |s, e| *s = e, |s, e| *s = e);
                    assert_eq!(once, each, "{sides} sides, {n} vertices, v {v}");
                }
            }
            // A cap's texture coordinates are no tube's.
            let cap = Affine::new(
                Vec3A::ZERO,
                Vec3A::X,
                Vec3A::Z,
                Vec3A::Y,
                Vec3A::ZERO,
                Vec3A::ZERO,
                [0.5, 0.5],
                [0.5, 0.0],
                [0.0, 0.5],
                [0.0; 2],
            );
            assert_eq!(cap.tube_v(), None);
        }
    }

    #[test]
    fn axis_normals_survive_the_round_trip() {
        for n in [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ] {
            let v = Vertex {
                normal: n,
                ..Vertex::default()
            };
            let back = VertexCompact::encode(&v, 1.0).decode(1.0);
            let d = glam::Vec3::from(back.normal).dot(glam::Vec3::from(n));
            assert!(d > 1.0 - 1e-6, "{n:?} came back as {:?}", back.normal);
        }
    }
}
