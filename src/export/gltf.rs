//! glTF 2.0: `.glb` (binary) or `.gltf` (JSON with the buffer embedded as a data URI),
//! as every engine and DCC tool reads it.
//!
//! One node, one mesh: the bark as a primitive with a bark material, and the baked leaves
//! (leaf quads, polygons, spheres, surfaces) as a second primitive with a double-sided
//! leaf material when leaf options are given. Vertices are interleaved (position, normal,
//! uv; stride 32) as arbor writes them; indices are 32-bit triangle lists (glTF has no
//! restart index). glTF is right-handed, Y up, counter-clockwise: the mesh options'
//! topology, winding and up axis are overridden to that, whatever they ask; their scale,
//! sides, joints, tips and curve rings stand. The generator's settings are in
//! `asset.extras`.

use crate::error::{Error, Result};
use crate::mesh::{self, LeafOptions, Mesh, MeshOptions, Topology, UpAxis, Winding};
use crate::skeleton::Skeleton;
use std::fmt::Write as _;
use std::path::Path;

/// A primitive of the file: its name, mesh, material (0 bark, 1 leaves) and, for bark,
/// the animation stream (custom attributes `_GROWTH` and `_WIND`).
type Primitive = (
    &'static str,
    Mesh,
    usize,
    Option<Vec<mesh::AnimationVertex>>,
);

/// The options glTF needs: triangle lists, counter-clockwise, Y up.
fn gltf_options(options: &MeshOptions) -> MeshOptions {
    MeshOptions {
        topology: Topology::TriangleList,
        winding: Winding::CounterClockwise,
        up_axis: UpAxis::Y,
        ..*options
    }
}

/// The meshes a glTF file of `skeleton` holds.
fn primitives(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: Option<&LeafOptions>,
) -> Result<(MeshOptions, Vec<Primitive>)> {
    let o = gltf_options(options);
    let anim = mesh::animation(skeleton, &o)?;
    let mut out = vec![("bark", mesh::tubes(skeleton, &o)?, 0, Some(anim))];
    if let Some(l) = leaves {
        out.push(("leaves", mesh::leaf_mesh(skeleton, l, &o)?, 1, None));
    }
    out.retain(|p| !p.1.indices.is_empty());
    Ok((o, out))
}

fn pad4(v: &mut Vec<u8>, byte: u8) {
    while v.len() % 4 != 0 {
        v.push(byte);
    }
}

fn base64(data: &[u8]) -> String {
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

fn num(v: f32) -> String {
    // Shortest round-trip form; glTF's JSON has no NaN or infinity (never produced).
    let s = format!("{v:?}");
    if s.contains("inf") || s.contains("NaN") {
        "0".into()
    } else {
        s
    }
}

/// The file's bytes: GLB when `binary`, else glTF JSON with the buffer embedded.
pub fn gltf_bytes(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: Option<&LeafOptions>,
    binary: bool,
) -> Result<Vec<u8>> {
    let (o, prims) = primitives(skeleton, options, leaves)?;
    let extras = format!(
        "{{\"generator\":\"arbor\",\"branches\":{},\"radial_segments\":{},\"curve_rings\":{},\"scale\":{},\"leaves\":{}}}",
        skeleton.len(),
        o.radial_segments,
        o.curve_rings,
        num(o.scale),
        leaves.is_some()
    );
    encode(prims, &extras, binary, NO_INSTANCES)
}

/// [`gltf_bytes`] with the leaves as instances of one leaf mesh (the leaf options'
/// prefab, else the quad) through `EXT_mesh_gpu_instancing`, declared used, not required:
/// engines that draw instances get one small mesh and a transform per leaf; a viewer
/// without the extension draws a single leaf at the node, so export baked leaves
/// ([`gltf_bytes`]) for those. Only the leaf sites are instanced (no polygons or spheres).
pub fn gltf_bytes_instanced(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: &LeafOptions,
    binary: bool,
) -> Result<Vec<u8>> {
    let (o, prims) = primitives(skeleton, options, None)?;
    let instances = mesh::leaf_instances(skeleton, leaves, &o)?;
    let prefab = leaves.prefab.clone().unwrap_or_else(mesh::LeafPrefab::quad);
    let quad = Mesh {
        vertices: prefab.vertices.clone(),
        indices: prefab.triangles.iter().flatten().copied().collect(),
        topology: Topology::TriangleList,
        ranges: Vec::new(),
    };
    let extras = format!(
        "{{\"generator\":\"arbor\",\"branches\":{},\"radial_segments\":{},\"leaf_instances\":{}}}",
        skeleton.len(),
        o.radial_segments,
        instances.len()
    );
    encode(prims, &extras, binary, Some((quad, instances)))
}

/// A forest as glTF: the trees merged into one bark mesh (one draw call), as
/// [`crate::forest::merged`] places them.
pub fn gltf_forest_bytes(
    placed: &[crate::forest::Placed<'_>],
    options: &MeshOptions,
    binary: bool,
) -> Result<Vec<u8>> {
    let o = gltf_options(options);
    let m = crate::forest::merged(placed, &o)?;
    let extras = format!(
        "{{\"generator\":\"arbor\",\"trees\":{},\"radial_segments\":{},\"scale\":{}}}",
        placed.len(),
        o.radial_segments,
        num(o.scale)
    );
    let prims = if m.indices.is_empty() {
        Vec::new()
    } else {
        vec![("forest", m, 0, None)]
    };
    encode(prims, &extras, binary, NO_INSTANCES)
}

/// Leaves drawn as instances of one prefab (`EXT_mesh_gpu_instancing`).
type Instanced = (Mesh, Vec<mesh::LeafInstance>);

const NO_INSTANCES: Option<Instanced> = None;

fn encode(
    prims: Vec<Primitive>,
    extras: &str,
    binary: bool,
    instanced: Option<Instanced>,
) -> Result<Vec<u8>> {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = String::new();
    let mut accessors = String::new();
    let mut prim_json = String::new();
    let (mut nview, mut nacc) = (0usize, 0usize);
    for (k, (_, m, material, anim)) in prims.iter().enumerate() {
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for v in &m.vertices {
            for c in 0..3 {
                lo[c] = lo[c].min(v.position[c]);
                hi[c] = hi[c].max(v.position[c]);
            }
        }
        let vstart = bin.len();
        bin.extend_from_slice(bytemuck::cast_slice(&m.vertices));
        let vlen = bin.len() - vstart;
        pad4(&mut bin, 0);
        let istart = bin.len();
        bin.extend_from_slice(bytemuck::cast_slice(&m.indices));
        let ilen = bin.len() - istart;
        pad4(&mut bin, 0);
        let sep = |s: &String| if s.is_empty() { "" } else { "," };
        let _ = write!(
            views,
            "{}{{\"buffer\":0,\"byteOffset\":{vstart},\"byteLength\":{vlen},\"byteStride\":32,\"target\":34962}},\
             {{\"buffer\":0,\"byteOffset\":{istart},\"byteLength\":{ilen},\"target\":34963}}",
            sep(&views)
        );
        let n = m.vertices.len();
        let _ = write!(
            accessors,
            "{}{{\"bufferView\":{nview},\"byteOffset\":0,\"componentType\":5126,\"count\":{n},\"type\":\"VEC3\",\
             \"min\":[{},{},{}],\"max\":[{},{},{}]}},\
             {{\"bufferView\":{nview},\"byteOffset\":12,\"componentType\":5126,\"count\":{n},\"type\":\"VEC3\"}},\
             {{\"bufferView\":{nview},\"byteOffset\":24,\"componentType\":5126,\"count\":{n},\"type\":\"VEC2\"}},\
             {{\"bufferView\":{},\"byteOffset\":0,\"componentType\":5125,\"count\":{},\"type\":\"SCALAR\"}}",
            sep(&accessors),
            num(lo[0]),
            num(lo[1]),
            num(lo[2]),
            num(hi[0]),
            num(hi[1]),
            num(hi[2]),
            nview + 1,
            m.indices.len()
        );
        // The animation stream: growth time, and (order, along, phase) for wind.
        let mut custom = String::new();
        if let Some(a) = anim.as_ref().filter(|a| a.len() == n) {
            let astart = bin.len();
            bin.extend_from_slice(bytemuck::cast_slice(a));
            let alen = bin.len() - astart;
            let _ = write!(
                views,
                ",{{\"buffer\":0,\"byteOffset\":{astart},\"byteLength\":{alen},\"byteStride\":16,\"target\":34962}}"
            );
            let _ = write!(
                accessors,
                ",{{\"bufferView\":{},\"byteOffset\":0,\"componentType\":5126,\"count\":{n},\"type\":\"SCALAR\"}},\
                 {{\"bufferView\":{},\"byteOffset\":4,\"componentType\":5126,\"count\":{n},\"type\":\"VEC3\"}}",
                nview + 2,
                nview + 2
            );
            let _ = write!(custom, ",\"_GROWTH\":{},\"_WIND\":{}", nacc + 4, nacc + 5);
        }
        let _ = write!(
            prim_json,
            "{}{{\"attributes\":{{\"POSITION\":{},\"NORMAL\":{},\"TEXCOORD_0\":{}{custom}}},\"indices\":{},\"material\":{material},\"mode\":4}}",
            if k == 0 { "" } else { "," },
            nacc,
            nacc + 1,
            nacc + 2,
            nacc + 3
        );
        let extra = if custom.is_empty() { 0 } else { 1 };
        nview += 2 + extra;
        nacc += 4 + 2 * extra;
    }
    // The instanced leaves: the prefab as a mesh of its own, and per instance its
    // translation, rotation and scale (tightly packed, as the extension reads them).
    let mut inst = String::new();
    let mut inst_ext = String::new();
    let instanced = instanced.filter(|(m, i)| !m.indices.is_empty() && !i.is_empty());
    if let Some((m, instances)) = &instanced {
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for v in &m.vertices {
            for c in 0..3 {
                lo[c] = lo[c].min(v.position[c]);
                hi[c] = hi[c].max(v.position[c]);
            }
        }
        let push = |bytes: &[u8], target: &str, bin: &mut Vec<u8>, views: &mut String| {
            let start = bin.len();
            bin.extend_from_slice(bytes);
            let len = bin.len() - start;
            pad4(bin, 0);
            let _ = write!(
                views,
                "{}{{\"buffer\":0,\"byteOffset\":{start},\"byteLength\":{len}{target}}}",
                if views.is_empty() { "" } else { "," }
            );
        };
        let n = m.vertices.len();
        push(
            bytemuck::cast_slice(&m.vertices),
            ",\"byteStride\":32,\"target\":34962",
            &mut bin,
            &mut views,
        );
        push(
            bytemuck::cast_slice(&m.indices),
            ",\"target\":34963",
            &mut bin,
            &mut views,
        );
        let t: Vec<[f32; 3]> = instances.iter().map(|l| l.position).collect();
        let r: Vec<[f32; 4]> = instances.iter().map(|l| l.rotation).collect();
        let sc: Vec<[f32; 3]> = instances.iter().map(|l| [l.scale; 3]).collect();
        push(bytemuck::cast_slice(&t), "", &mut bin, &mut views);
        push(bytemuck::cast_slice(&r), "", &mut bin, &mut views);
        push(bytemuck::cast_slice(&sc), "", &mut bin, &mut views);
        let k = instances.len();
        let _ = write!(
            accessors,
            "{}{{\"bufferView\":{nview},\"byteOffset\":0,\"componentType\":5126,\"count\":{n},\"type\":\"VEC3\",\
             \"min\":[{},{},{}],\"max\":[{},{},{}]}},\
             {{\"bufferView\":{nview},\"byteOffset\":12,\"componentType\":5126,\"count\":{n},\"type\":\"VEC3\"}},\
             {{\"bufferView\":{nview},\"byteOffset\":24,\"componentType\":5126,\"count\":{n},\"type\":\"VEC2\"}},\
             {{\"bufferView\":{},\"byteOffset\":0,\"componentType\":5125,\"count\":{},\"type\":\"SCALAR\"}},\
             {{\"bufferView\":{},\"componentType\":5126,\"count\":{k},\"type\":\"VEC3\"}},\
             {{\"bufferView\":{},\"componentType\":5126,\"count\":{k},\"type\":\"VEC4\"}},\
             {{\"bufferView\":{},\"componentType\":5126,\"count\":{k},\"type\":\"VEC3\"}}",
            if accessors.is_empty() { "" } else { "," },
            num(lo[0]),
            num(lo[1]),
            num(lo[2]),
            num(hi[0]),
            num(hi[1]),
            num(hi[2]),
            nview + 1,
            m.indices.len(),
            nview + 2,
            nview + 3,
            nview + 4
        );
        inst = format!(
            "{{\"name\":\"leaf\",\"primitives\":[{{\"attributes\":{{\"POSITION\":{},\"NORMAL\":{},\"TEXCOORD_0\":{}}},\"indices\":{},\"material\":1,\"mode\":4}}]}}",
            nacc,
            nacc + 1,
            nacc + 2,
            nacc + 3
        );
        inst_ext = format!(
            "\"extensions\":{{\"EXT_mesh_gpu_instancing\":{{\"attributes\":{{\"TRANSLATION\":{},\"ROTATION\":{},\"SCALE\":{}}}}}}}",
            nacc + 4,
            nacc + 5,
            nacc + 6
        );
    }
    let mut used: Vec<usize> = prims.iter().map(|p| p.2).collect();
    if instanced.is_some() {
        used.push(1);
    }
    // Materials in index order; a file without leaves still lists both, so indices stay
    // fixed (an unused material is fine for the validator only if referenced: list only
    // what is used, renumbered).
    let mut materials = String::new();
    let mut remap = [usize::MAX; 2];
    for (slot, m) in [0usize, 1].into_iter().enumerate() {
        if !used.contains(&m) {
            continue;
        }
        remap[slot] = materials.matches("\"name\"").count();
        let _ = write!(
            materials,
            "{}{}",
            if materials.is_empty() { "" } else { "," },
            if m == 0 {
                "{\"name\":\"bark\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.36,0.24,0.14,1.0],\"metallicFactor\":0.0,\"roughnessFactor\":0.9}}"
            } else {
                "{\"name\":\"leaves\",\"doubleSided\":true,\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.22,0.52,0.16,1.0],\"metallicFactor\":0.0,\"roughnessFactor\":0.8}}"
            }
        );
    }
    let remat = |j: String| {
        j.replace("\"material\":0,", &format!("\"material\":{},", remap[0]))
            .replace("\"material\":1,", &format!("\"material\":{},", remap[1]))
    };
    let prim_json = remat(prim_json);
    let inst = remat(inst);
    let uri = if binary {
        String::new()
    } else {
        format!(
            ",\"uri\":\"data:application/octet-stream;base64,{}\"",
            base64(&bin)
        )
    };
    let mut json = format!(
        "{{\"asset\":{{\"version\":\"2.0\",\"generator\":\"arbor {}\",\"extras\":{extras}}}",
        env!("CARGO_PKG_VERSION")
    );
    // Meshes and the nodes that hold them: the tree, then the instanced leaves.
    let mut meshes = Vec::new();
    let mut nodes = Vec::new();
    if !prims.is_empty() {
        nodes.push(format!("{{\"name\":\"tree\",\"mesh\":{}}}", meshes.len()));
        meshes.push(format!(
            "{{\"name\":\"tree\",\"primitives\":[{prim_json}]}}"
        ));
    }
    if !inst.is_empty() {
        nodes.push(format!(
            "{{\"name\":\"leaves\",\"mesh\":{},{inst_ext}}}",
            meshes.len()
        ));
        meshes.push(inst);
        // Used, not required: a viewer without the extension draws one leaf at the
        // node; export baked leaves (save_gltf) for such viewers.
        json.push_str(",\"extensionsUsed\":[\"EXT_mesh_gpu_instancing\"]");
    }
    if nodes.is_empty() {
        json.push_str(",\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"name\":\"tree\"}]}");
    } else {
        let list: Vec<String> = (0..nodes.len()).map(|k| k.to_string()).collect();
        let _ = write!(
            json,
            ",\"scene\":0,\"scenes\":[{{\"nodes\":[{}]}}],\"nodes\":[{}],\
             \"meshes\":[{}],\"materials\":[{materials}],\
             \"accessors\":[{accessors}],\"bufferViews\":[{views}],\"buffers\":[{{\"byteLength\":{}{uri}}}]}}",
            list.join(","),
            nodes.join(","),
            meshes.join(","),
            bin.len()
        );
    }
    if !binary {
        return Ok(json.into_bytes());
    }
    let mut j = json.into_bytes();
    pad4(&mut j, b' ');
    let with_bin = !bin.is_empty();
    let total = 12 + 8 + j.len() + if with_bin { 8 + bin.len() } else { 0 };
    let total32 = u32::try_from(total).map_err(|_| Error::LimitExceeded {
        limit_name: "glb size",
        what: "bytes of the .glb file",
        limit: u32::MAX as u64,
        requested: total as u64,
        step: None,
    })?;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total32.to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    if with_bin {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
    }
    Ok(out)
}

/// Writes a forest ([`gltf_forest_bytes`]) to `path` (`.glb` or `.gltf`).
pub fn save_gltf_forest(
    placed: &[crate::forest::Placed<'_>],
    options: &MeshOptions,
    path: impl AsRef<Path>,
) -> Result<()> {
    let path = path.as_ref();
    let bytes = gltf_forest_bytes(placed, options, binary_by_extension(path)?)?;
    write(path, bytes)
}

fn binary_by_extension(path: &Path) -> Result<bool> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("glb") => Ok(true),
        Some("gltf") => Ok(false),
        _ => Err(Error::invalid(
            "path",
            format!("`{}`: expected a .glb or .gltf file name", path.display()),
        )),
    }
}

fn write(path: &Path, bytes: Vec<u8>) -> Result<()> {
    std::fs::write(path, bytes).map_err(|e| {
        Error::Io(std::io::Error::new(
            e.kind(),
            format!("cannot write {}: {e}", path.display()),
        ))
    })
}

/// Writes `skeleton` as glTF 2.0 to `path`: `.glb` binary, `.gltf` JSON with the buffer
/// embedded (chosen by the extension, case-insensitive; anything else is
/// [`Error::InvalidArgument`]).
pub fn save_gltf(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: Option<&LeafOptions>,
    path: impl AsRef<Path>,
) -> Result<()> {
    let path = path.as_ref();
    let bytes = gltf_bytes(skeleton, options, leaves, binary_by_extension(path)?)?;
    write(path, bytes)
}
