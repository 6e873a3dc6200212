//! The binary buffer of a glTF file and the JSON of its views and accessors, as meshes are
//! added: f32 vertices, or quantized ones (KHR_mesh_quantization).

use crate::mesh::Mesh;

pub(super) fn pad4(v: &mut Vec<u8>, byte: u8) {
    while v.len() % 4 != 0 {
        v.push(byte);
    }
}

pub(super) fn base64(data: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(data.len().div_ceil(3) * 4);
    for c in data.chunks(3) {
        let b = [c[0], *c.get(1).unwrap_or(&0), *c.get(2).unwrap_or(&0)];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for k in 0..4 {
            if k <= c.len() {
                s.push(T[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

pub(super) fn num(v: f32) -> String {
    // Shortest round-trip form; glTF's JSON has no NaN or infinity (never produced).
    let s = format!("{v:?}");
    if s.contains("inf") || s.contains("NaN") {
        "0".into()
    } else {
        s
    }
}

/// glTF componentType values.
pub(super) const FLOAT: u32 = 5126;
pub(super) const SHORT: u32 = 5122;

/// The binary buffer and the JSON of its views and accessors, as they are added.
#[derive(Default)]
pub(super) struct Buffers {
    pub(super) bin: Vec<u8>,
    pub(super) views: Vec<String>,
    pub(super) accessors: Vec<String>,
    /// Vertices as KHR_mesh_quantization allows: normals in snorm16, uv in unorm16.
    pub(super) quantized: bool,
}

impl Buffers {
    /// Appends `bytes` (padded to 4) as a buffer view; returns its index.
    pub(super) fn view(&mut self, bytes: &[u8], stride_target: &str) -> usize {
        let start = self.bin.len();
        self.bin.extend_from_slice(bytes);
        let len = bytes.len();
        pad4(&mut self.bin, 0);
        self.views.push(format!(
            "{{\"buffer\":0,\"byteOffset\":{start},\"byteLength\":{len}{stride_target}}}"
        ));
        self.views.len() - 1
    }

    /// Adds a float accessor into `view`; returns its index.
    pub(super) fn accessor(
        &mut self,
        view: usize,
        offset: usize,
        count: usize,
        ty: &str,
        extra: &str,
    ) -> usize {
        self.accessor_of(view, offset, count, (FLOAT, ty), extra)
    }

    /// Adds an accessor of `component` (a glTF componentType) into `view`; returns its
    /// index.
    pub(super) fn accessor_of(
        &mut self,
        view: usize,
        offset: usize,
        count: usize,
        (component, ty): (u32, &str),
        extra: &str,
    ) -> usize {
        self.accessors.push(format!(
            "{{\"bufferView\":{view},\"byteOffset\":{offset},\"componentType\":{component},\"count\":{count},\"type\":\"{ty}\"{extra}}}"
        ));
        self.accessors.len() - 1
    }

    /// A triangle-list mesh's vertices and indices: the primitive's attributes and
    /// indices as JSON (`"attributes":{...},"indices":n`) and its vertex count.
    pub(super) fn mesh(&mut self, m: &Mesh) -> (String, usize) {
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for v in &m.vertices {
            for c in 0..3 {
                lo[c] = lo[c].min(v.position[c]);
                hi[c] = hi[c].max(v.position[c]);
            }
        }
        let n = m.vertices.len();
        let bounds = format!(
            ",\"min\":[{},{},{}],\"max\":[{},{},{}]",
            num(lo[0]),
            num(lo[1]),
            num(lo[2]),
            num(hi[0]),
            num(hi[1]),
            num(hi[2])
        );
        let (pos, nor, uv) = if self.quantized {
            self.quantized_vertices(m, &bounds)
        } else {
            let vv = self.view(
                bytemuck::cast_slice(&m.vertices),
                ",\"byteStride\":32,\"target\":34962",
            );
            let pos = self.accessor(vv, 0, n, "VEC3", &bounds);
            let nor = self.accessor(vv, 12, n, "VEC3", "");
            let uv = self.accessor(vv, 24, n, "VEC2", "");
            (pos, nor, uv)
        };
        let iv = self.view(bytemuck::cast_slice(&m.indices), ",\"target\":34963");
        self.accessors.push(format!(
            "{{\"bufferView\":{iv},\"byteOffset\":0,\"componentType\":5125,\"count\":{},\"type\":\"SCALAR\"}}",
            m.indices.len()
        ));
        let idx = self.accessors.len() - 1;
        (
            format!(
                "\"attributes\":{{\"POSITION\":{pos},\"NORMAL\":{nor},\"TEXCOORD_0\":{uv}}},\"indices\":{idx}"
            ),
            n,
        )
    }

    /// The vertices as KHR_mesh_quantization allows, 28 bytes each: position in f32 at 0,
    /// the normal in snorm16 x 3 at 12 (two bytes of padding keep each attribute 4-byte
    /// aligned), uv in f32 at 20. The uv stays f32: a quantized TEXCOORD reads as 0..1 in
    /// every importer, and glTF scales it back only through a texture's
    /// KHR_texture_transform, which an untextured file has nowhere to put. Returns the
    /// position, normal and uv accessors.
    fn quantized_vertices(&mut self, m: &Mesh, bounds: &str) -> (usize, usize, usize) {
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
        let vv = self.view(&bytes, ",\"byteStride\":28,\"target\":34962");
        (
            self.accessor(vv, 0, n, "VEC3", bounds),
            self.accessor_of(vv, 12, n, (SHORT, "VEC3"), ",\"normalized\":true"),
            self.accessor(vv, 20, n, "VEC2", ""),
        )
    }
}
