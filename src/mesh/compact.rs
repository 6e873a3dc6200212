//! The compact vertex format: 20 bytes a vertex instead of 32.
//!
//! Position stays f32; the unit normal is octahedral-encoded into two snorm16; u and v are
//! unorm16, v over the mesh's `v_scale` (a power of two at least the mesh's largest v, so
//! the stored v is v / v_scale in [0, 1]). The mesh writers already produce v divided by
//! that scale when the options ask for compact vertices, so each vertex is encoded where it
//! is written, with no second pass over the mesh.

use super::strips::Slot;
use super::{Vertex, VertexFormat};
use bytemuck::{Pod, Zeroable};
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

    /// A vertex whose v is already divided by the mesh's v_scale.
    #[inline(always)]
    fn from_scaled(vertex: Vertex) -> Self {
        let [x, y, z] = vertex.normal;
        let l1 = x.abs() + y.abs() + z.abs();
        let (mut px, mut py) = if l1 > 0.0 {
            (x / l1, y / l1)
        } else {
            (0.0, 0.0)
        };
        if z < 0.0 {
            (px, py) = ((1.0 - py.abs()).copysign(px), (1.0 - px.abs()).copysign(py));
        }
        let snorm = |c: f32| (c.clamp(-1.0, 1.0) * 32767.0).round() as i16;
        let unorm = |c: f32| (c.clamp(0.0, 1.0) * 65535.0).round() as u16;
        VertexCompact {
            position: vertex.position,
            normal: [snorm(px), snorm(py)],
            uv: vertex.uv.map(unorm),
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

impl Slot<Vertex> for VertexCompact {
    #[inline(always)]
    fn put(&mut self, value: Vertex) {
        *self = VertexCompact::from_scaled(value);
    }
}

impl Slot<Vertex> for MaybeUninit<VertexCompact> {
    #[inline(always)]
    fn put(&mut self, value: Vertex) {
        self.write(VertexCompact::from_scaled(value));
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
