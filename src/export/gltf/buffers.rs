//! The binary buffer of a glTF file and its views and accessors, as meshes are added: f32
//! vertices, or quantized ones (KHR_mesh_quantization).

use super::json::{Accessor, Attributes, BufferView};
use crate::mesh::Mesh;

pub(super) fn pad4(v: &mut Vec<u8>, byte: u8) {
    while v.len() % 4 != 0 {
        v.push(byte);
    }
}

/// glTF componentType values.
pub(super) const FLOAT: u32 = 5126;
pub(super) const SHORT: u32 = 5122;
const UNSIGNED_INT: u32 = 5125;
/// glTF bufferView targets.
pub(super) const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// The binary buffer and its views and accessors, as they are added.
#[derive(Default)]
pub(super) struct Buffers {
    pub(super) bin: Vec<u8>,
    pub(super) views: Vec<BufferView>,
    pub(super) accessors: Vec<Accessor>,
    /// Vertices as KHR_mesh_quantization allows: normals in snorm16, uv in unorm16.
    pub(super) quantized: bool,
}

impl Buffers {
    /// Appends `bytes` (padded to 4) as a buffer view with this stride and target; returns
    /// its index.
    pub(super) fn view(
        &mut self,
        bytes: &[u8],
        byte_stride: Option<u32>,
        target: Option<u32>,
    ) -> usize {
        let start = self.bin.len();
        self.bin.extend_from_slice(bytes);
        pad4(&mut self.bin, 0);
        self.views.push(BufferView {
            buffer: 0,
            byte_offset: start,
            byte_length: bytes.len(),
            byte_stride,
            target,
        });
        self.views.len() - 1
    }

    /// Adds `accessor`; returns its index.
    pub(super) fn push(&mut self, accessor: Accessor) -> usize {
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Adds a float accessor of `count` elements of `kind` at `offset` in `view`; returns
    /// its index.
    pub(super) fn accessor(
        &mut self,
        view: usize,
        offset: usize,
        count: usize,
        kind: &'static str,
    ) -> usize {
        self.push(Accessor::new(view, Some(offset), (FLOAT, kind), count))
    }

    /// A triangle-list mesh's vertices and indices: the primitive's attributes, its
    /// indices' accessor, and its vertex count.
    pub(super) fn mesh(&mut self, m: &Mesh) -> (Attributes, usize, usize) {
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for v in &m.vertices {
            for c in 0..3 {
                lo[c] = lo[c].min(v.position[c]);
                hi[c] = hi[c].max(v.position[c]);
            }
        }
        let n = m.vertices.len();
        let (pos, nor, uv) = if self.quantized {
            self.quantized_vertices(m)
        } else {
            let vv = self.view(
                bytemuck::cast_slice(&m.vertices),
                Some(32),
                Some(ARRAY_BUFFER),
            );
            let pos = self.accessor(vv, 0, n, "VEC3");
            let nor = self.accessor(vv, 12, n, "VEC3");
            let uv = self.accessor(vv, 24, n, "VEC2");
            (pos, nor, uv)
        };
        (self.accessors[pos].min, self.accessors[pos].max) = (Some(lo), Some(hi));
        let iv = self.view(
            bytemuck::cast_slice(&m.indices),
            None,
            Some(ELEMENT_ARRAY_BUFFER),
        );
        let indices = self.push(Accessor::new(
            iv,
            Some(0),
            (UNSIGNED_INT, "SCALAR"),
            m.indices.len(),
        ));
        let attributes = Attributes {
            position: pos,
            normal: nor,
            texcoord_0: uv,
            growth: None,
            wind: None,
        };
        (attributes, indices, n)
    }

    /// The vertices as KHR_mesh_quantization allows, 28 bytes each: position in f32 at 0,
    /// the normal in snorm16 x 3 at 12 (two bytes of padding keep each attribute 4-byte
    /// aligned), uv in f32 at 20. The uv stays f32: a quantized TEXCOORD reads as 0..1 in
    /// every importer, and glTF scales it back only through a texture's
    /// KHR_texture_transform, which an untextured file has nowhere to put. Returns the
    /// position, normal and uv accessors.
    fn quantized_vertices(&mut self, m: &Mesh) -> (usize, usize, usize) {
        let n = m.vertices.len();
        let mut bytes = Vec::with_capacity(n * 28);
        for v in &m.vertices {
            bytes.extend_from_slice(bytemuck::cast_slice(&v.position));
            let normal = v
                .normal
                .map(|x| (x.clamp(-1.0, 1.0) * 32767.0).round() as i16);
            bytes.extend_from_slice(bytemuck::cast_slice(&normal));
            bytes.extend_from_slice(&[0, 0]);
            bytes.extend_from_slice(bytemuck::cast_slice(&v.uv));
        }
        let vv = self.view(&bytes, Some(28), Some(ARRAY_BUFFER));
        let pos = self.accessor(vv, 0, n, "VEC3");
        let nor = self.push(Accessor {
            normalized: true,
            ..Accessor::new(vv, Some(12), (SHORT, "VEC3"), n)
        });
        let uv = self.accessor(vv, 20, n, "VEC2");
        (pos, nor, uv)
    }
}
