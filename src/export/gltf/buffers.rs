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
pub(super) const UNSIGNED_SHORT: u32 = 5123;
pub(super) const UNSIGNED_BYTE: u32 = 5121;
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
        (self.accessors[pos].min, self.accessors[pos].max) = (Some(lo.to_vec()), Some(hi.to_vec()));
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
            tangent: None,
            growth: None,
            wind: None,
            joints: None,
            weights: None,
            color_0: None,
            texcoord_1: None,
            texcoord_2: None,
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

/// Per-vertex tangents (x, y, z, w) of a triangle-list mesh for a normal map: the
/// direction of increasing u, from each triangle's uv derivatives summed over the
/// triangles at the vertex, made perpendicular to the normal; w (±1) says whether the
/// bitangent is n × t or its opposite (glTF's convention). A vertex whose triangles give
/// no direction takes one perpendicular to its normal.
pub(super) fn tangents(m: &Mesh) -> Vec<[f32; 4]> {
    use glam::Vec3;
    let n = m.vertices.len();
    let (mut t, mut b) = (vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]);
    for tri in m.indices.chunks_exact(3) {
        let [i0, i1, i2] = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
        let (v0, v1, v2) = (&m.vertices[i0], &m.vertices[i1], &m.vertices[i2]);
        let e1 = Vec3::from(v1.position) - Vec3::from(v0.position);
        let e2 = Vec3::from(v2.position) - Vec3::from(v0.position);
        let (du1, dv1) = (v1.uv[0] - v0.uv[0], v1.uv[1] - v0.uv[1]);
        let (du2, dv2) = (v2.uv[0] - v0.uv[0], v2.uv[1] - v0.uv[1]);
        let det = du1 * dv2 - du2 * dv1;
        if det.abs() < 1e-20 {
            continue;
        }
        let r = 1.0 / det;
        let tangent = (e1 * dv2 - e2 * dv1) * r;
        let bitangent = (e2 * du1 - e1 * du2) * r;
        for i in [i0, i1, i2] {
            t[i] += tangent;
            b[i] += bitangent;
        }
    }
    m.vertices
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let normal = Vec3::from(v.normal).normalize_or(Vec3::Y);
            let mut tangent = (t[i] - normal * normal.dot(t[i])).normalize_or_zero();
            if tangent == Vec3::ZERO {
                tangent = normal.any_orthonormal_vector();
            }
            let w = if normal.cross(tangent).dot(b[i]) < 0.0 {
                -1.0
            } else {
                1.0
            };
            [tangent.x, tangent.y, tangent.z, w]
        })
        .collect()
}
