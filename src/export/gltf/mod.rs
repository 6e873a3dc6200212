//! glTF 2.0: `.glb` (binary) or `.gltf` (JSON with the buffer embedded as a data URI),
//! as every engine and DCC tool reads it.
//!
//! One node, one mesh: the bark as a primitive with a bark material, and the baked leaves
//! (leaf quads, polygons, spheres, surfaces) as a second primitive with a double-sided
//! leaf material when leaf options are given. Vertices are interleaved (position, normal,
//! uv; stride 32) as arbor writes them; indices are 32-bit triangle lists (glTF has no
//! restart index). glTF is right-handed, Y up, counter-clockwise: the mesh options'
//! topology, winding and up axis are overridden to that, whatever they ask; their scale,
//! sides, joints, tips and curve rings stand. Options that contradict themselves (an engine
//! preset with another up axis or winding) are refused with the mesh writer's error; the
//! f32 range of positions is checked in the space written. The generator's settings are in
//! `asset.extras`.

use crate::error::{Error, Result};
use crate::mesh::{self, Axes, LeafOptions, Mesh, MeshOptions, Topology, UpAxis, Winding};
use crate::progress::Run;
use crate::skeleton::Skeleton;
use std::path::Path;

mod buffers;
mod json;
use buffers::{ARRAY_BUFFER, Buffers, FLOAT, pad4};
use json::Extras;

/// A primitive of the file: its mesh, its material, and for bark the animation stream
/// (custom attributes `_GROWTH` and `_WIND`).
struct Primitive {
    mesh: Mesh,
    material: Material,
    anim: Option<Vec<mesh::AnimationVertex>>,
}

#[derive(Clone, Copy, PartialEq)]
enum Material {
    Bark,
    Leaves,
}

impl Material {
    fn json(self) -> json::Material {
        let (name, double_sided, base_color_factor, roughness_factor) = match self {
            Material::Bark => ("bark", false, [0.36, 0.24, 0.14, 1.0], 0.9),
            Material::Leaves => ("leaves", true, [0.22, 0.52, 0.16, 1.0], 0.8),
        };
        json::Material {
            name,
            double_sided,
            pbr_metallic_roughness: json::Pbr {
                base_color_factor,
                metallic_factor: 0.0,
                roughness_factor,
            },
        }
    }
}

/// The options glTF needs: triangle lists, counter-clockwise, Y up, arbor's axes. Each
/// field is checked as given first, so a set that contradicts itself (an engine preset with
/// another up axis, say) is refused with the mesh writer's error; the limits that depend
/// on the output space (positions in the f32 range) are those of the space glTF is written
/// in. The vertices are written as f32 whatever `vertex_format` asks.
fn gltf_options(options: &MeshOptions) -> Result<MeshOptions> {
    mesh::check_fields(options)?;
    Ok(MeshOptions {
        vertex_format: mesh::VertexFormat::F32,
        topology: Topology::TriangleList,
        winding: Winding::CounterClockwise,
        up_axis: UpAxis::Y,
        axes: Axes::Arbor,
        ..*options
    })
}

/// The meshes a glTF file of `skeleton` holds. The bark's mesh and animation stream come
/// from one plan.
fn primitives(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: Option<&LeafOptions>,
    run: &mut Run<'_>,
) -> Result<(MeshOptions, Vec<Primitive>)> {
    let o = gltf_options(options)?;
    let plan = mesh::MeshPlan::new(skeleton, &o)?;
    let bark = plan.mesh_in(skeleton, run)?;
    let mut out = vec![Primitive {
        mesh: bark,
        material: Material::Bark,
        anim: Some(plan.animation(skeleton)?),
    }];
    if let Some(l) = leaves {
        out.push(Primitive {
            mesh: mesh::leaf_mesh(skeleton, l, &o)?,
            material: Material::Leaves,
            anim: None,
        });
    }
    out.retain(|p| !p.mesh.indices.is_empty());
    Ok((o, out))
}

/// The file's bytes: GLB when `binary`, else glTF JSON with the buffer embedded.
pub fn gltf_bytes(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: Option<&LeafOptions>,
    binary: bool,
) -> Result<Vec<u8>> {
    gltf_bytes_with(skeleton, options, leaves, binary, &mut Run::default())
}

fn gltf_bytes_with(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: Option<&LeafOptions>,
    binary: bool,
    run: &mut Run<'_>,
) -> Result<Vec<u8>> {
    let (o, prims) = primitives(skeleton, options, leaves, run)?;
    let extras = Extras {
        branches: Some(skeleton.len()),
        radial_segments: o.radial_segments,
        curve_rings: Some(o.curve_rings),
        scale: Some(o.scale),
        // Whether the file holds leaf geometry (asked for and found somewhere to go).
        leaves: Some(prims.iter().any(|p| matches!(p.material, Material::Leaves))),
        ..Extras::arbor()
    };
    encode(
        one_tree(prims),
        extras,
        Form::of(options, binary),
        NO_INSTANCES,
    )
}

/// [`gltf_bytes_instanced`] saved to `path` (`.glb` or `.gltf` by the extension), whole or
/// not at all.
pub fn save_gltf_instanced(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: &LeafOptions,
    path: impl AsRef<Path>,
) -> Result<()> {
    save_gltf_instanced_in(skeleton, options, leaves, path, &mut Run::default())
}

/// [`save_gltf_instanced`] in `run`: the run's threads mesh the bark, and it hears
/// [`Stage::Write`](crate::progress::Stage::Write) as the file is written; `false` stops
/// with `Cancelled` and leaves an existing file as it was.
pub fn save_gltf_instanced_in(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: &LeafOptions,
    path: impl AsRef<Path>,
    run: &mut Run<'_>,
) -> Result<()> {
    let o = MeshOptions {
        threads: run.threads_or(options.threads),
        ..*options
    };
    save(path.as_ref(), run, |binary, _| {
        gltf_bytes_instanced(skeleton, &o, leaves, binary)
    })
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
    let (o, prims) = primitives(skeleton, options, None, &mut Run::default())?;
    let instances = mesh::leaf_instances(skeleton, leaves, &o)?;
    let prefab = leaves
        .prefab
        .clone()
        .unwrap_or_else(|| std::sync::Arc::new(mesh::LeafPrefab::quad()));
    let quad = Mesh {
        vertices: prefab.vertices.clone(),
        indices: prefab.triangles.iter().flatten().copied().collect(),
        topology: Topology::TriangleList,
        ranges: Vec::new(),
    };
    let extras = Extras {
        branches: Some(skeleton.len()),
        radial_segments: o.radial_segments,
        leaf_instances: Some(instances.len()),
        ..Extras::arbor()
    };
    encode(
        one_tree(prims),
        extras,
        Form::of(options, binary),
        Some((quad, instances)),
    )
}

/// A forest as glTF: the trees merged into one bark mesh (one draw call), as
/// [`crate::forest::merged`] places them.
pub fn gltf_forest_bytes(
    placed: &[crate::forest::Placed<'_>],
    options: &MeshOptions,
    binary: bool,
) -> Result<Vec<u8>> {
    let o = gltf_options(options)?;
    let m = crate::forest::merged(placed, &o)?;
    let extras = Extras {
        trees: Some(placed.len()),
        radial_segments: o.radial_segments,
        scale: Some(o.scale),
        ..Extras::arbor()
    };
    let prims = if m.indices.is_empty() {
        Vec::new()
    } else {
        vec![Primitive {
            mesh: m,
            material: Material::Bark,
            anim: None,
        }]
    };
    encode(
        one_tree(prims),
        extras,
        Form::of(options, binary),
        NO_INSTANCES,
    )
}

/// A forest as one node per placed tree: one mesh per distinct tree (same source and
/// seed, as [`forest::instanced`](crate::forest::instanced) finds them), shared by every
/// node that places it, each node with the placement's translation, rotation about Y and
/// uniform scale. Smaller than the merged file when trees repeat, and an engine keeps
/// each tree a node of its own (to move, cull or swap); [`gltf_forest_bytes`] merges.
pub fn gltf_forest_nodes_bytes(
    placed: &[crate::forest::Placed<'_>],
    options: &MeshOptions,
    binary: bool,
) -> Result<Vec<u8>> {
    let o = gltf_options(options)?;
    let (meshes, which) = crate::forest::instanced(placed, &o)?;
    let trees: Vec<Vec<Primitive>> = meshes
        .into_iter()
        .map(|mesh| {
            vec![Primitive {
                mesh,
                material: Material::Bark,
                anim: None,
            }]
        })
        .collect();
    let nodes = placed
        .iter()
        .zip(which)
        .enumerate()
        .map(|(k, (p, (mesh, _)))| {
            let q = crate::geom::rotation::axis_angle(glam::Vec3::Y, p.rotation.to_radians());
            Node {
                name: format!("tree {k}"),
                mesh: mesh as usize,
                trs: Some((p.position, q.to_array(), p.scale)),
            }
        })
        .collect();
    let extras = Extras {
        trees: Some(placed.len()),
        distinct_trees: Some(trees.len()),
        radial_segments: o.radial_segments,
        scale: Some(o.scale),
        ..Extras::arbor()
    };
    encode(
        (trees, nodes),
        extras,
        Form::of(options, binary),
        NO_INSTANCES,
    )
}

/// Writes [`gltf_forest_nodes_bytes`] to `path` (`.glb` or `.gltf`, as [`save_gltf`]).
pub fn save_gltf_forest_nodes(
    placed: &[crate::forest::Placed<'_>],
    options: &MeshOptions,
    path: impl AsRef<Path>,
) -> Result<()> {
    save(path.as_ref(), &mut Run::default(), |binary, _| {
        gltf_forest_nodes_bytes(placed, options, binary)
    })
}

/// Leaves drawn as instances of one prefab (`EXT_mesh_gpu_instancing`).
type Instanced = (Mesh, Vec<mesh::LeafInstance>);

const NO_INSTANCES: Option<Instanced> = None;

/// A node of the scene: which tree mesh it draws and where (none: the identity).
struct Node {
    name: String,
    mesh: usize,
    trs: Option<([f32; 3], [f32; 4], f32)>,
}

/// One tree mesh drawn by one node at the origin, as single-tree files are.
fn one_tree(prims: Vec<Primitive>) -> (Vec<Vec<Primitive>>, Vec<Node>) {
    let node = Node {
        name: "tree".into(),
        mesh: 0,
        trs: None,
    };
    (vec![prims], vec![node])
}

/// Bytes of the buffer the meshes and instances make (what the file is made from).
fn buffer_bytes(trees: &[Vec<Primitive>], instanced: Option<&Instanced>) -> usize {
    trees
        .iter()
        .flatten()
        .map(|p| {
            std::mem::size_of_val(p.mesh.vertices.as_slice())
                + std::mem::size_of_val(p.mesh.indices.as_slice())
                + p.anim
                    .as_ref()
                    .map_or(0, |a| std::mem::size_of_val(a.as_slice()))
        })
        .sum::<usize>()
        + instanced.as_ref().map_or(0, |(m, i)| {
            std::mem::size_of_val(m.vertices.as_slice())
                + std::mem::size_of_val(m.indices.as_slice())
                + i.len() * 40
        })
}

/// The materials in use, bark first.
fn materials_in_use(trees: &[Vec<Primitive>], leaves: bool) -> Vec<Material> {
    let mut materials: Vec<Material> = Vec::new();
    for m in trees
        .iter()
        .flatten()
        .map(|p| p.material)
        .chain(leaves.then_some(Material::Leaves))
    {
        if !materials.contains(&m) {
            materials.push(m);
        }
    }
    materials.sort_by_key(|m| *m == Material::Leaves);
    materials
}

/// A node of the file: its name, its mesh (none for a tree without triangles) and
/// placement.
fn node_json(n: &Node, mesh: Option<usize>) -> json::Node {
    let mut node = json::Node::new(n.name.clone(), mesh);
    if let Some((t, r, sc)) = n.trs {
        node.translation = Some(t);
        node.rotation = Some(r);
        node.scale = Some([sc; 3]);
    }
    node
}

/// The instanced leaves: the prefab as a mesh of its own (number `mesh`, material
/// `material`), and a node that draws it per instance with its translation, rotation and
/// scale (tightly packed, as EXT_mesh_gpu_instancing reads them). Returns the node's JSON
/// and the mesh's.
fn instanced_leaves(
    b: &mut Buffers,
    m: &Mesh,
    instances: &[mesh::LeafInstance],
    mesh: usize,
    material: usize,
) -> (json::Node, json::Mesh) {
    // The prefab as a mesh of its own, and per instance its translation, rotation and
    // scale (tightly packed, as the extension reads them).
    let (attributes, indices, _) = b.mesh(m);
    let t: Vec<[f32; 3]> = instances.iter().map(|l| l.position).collect();
    let r: Vec<[f32; 4]> = instances.iter().map(|l| l.rotation).collect();
    let sc: Vec<[f32; 3]> = instances.iter().map(|l| [l.scale; 3]).collect();
    let count = instances.len();
    let mut per_instance = |bytes: &[u8], kind: &'static str| {
        let v = b.view(bytes, None, None);
        b.push(json::Accessor::new(v, None, (FLOAT, kind), count))
    };
    let attributes_of_instances = json::InstanceAttributes {
        translation: per_instance(bytemuck::cast_slice(&t), "VEC3"),
        rotation: per_instance(bytemuck::cast_slice(&r), "VEC4"),
        scale: per_instance(bytemuck::cast_slice(&sc), "VEC3"),
    };
    let mut node = json::Node::new("leaves", Some(mesh));
    node.extensions = Some(json::NodeExtensions {
        instancing: json::Instancing {
            attributes: attributes_of_instances,
        },
    });
    let mesh = json::Mesh {
        name: "leaf",
        primitives: vec![json::Primitive {
            attributes,
            indices,
            material,
            mode: 4,
        }],
    };
    (node, mesh)
}

/// The file's `extensionsUsed` and `extensionsRequired`. Quantized attributes are
/// required: a reader without the extension cannot read them as floats. Instancing is
/// used, not required: a viewer without it draws one leaf at the node (export baked
/// leaves, save_gltf, for such viewers).
fn extensions(quantized: bool, instanced: bool) -> (Vec<&'static str>, Vec<&'static str>) {
    let used = [
        (quantized, "KHR_mesh_quantization"),
        (instanced, "EXT_mesh_gpu_instancing"),
    ]
    .into_iter()
    .filter_map(|(on, name)| on.then_some(name))
    .collect();
    let required = if quantized {
        vec!["KHR_mesh_quantization"]
    } else {
        Vec::new()
    };
    (used, required)
}

/// How a file is written: `.glb` or `.gltf`, and with quantized vertices (the options
/// asked for [`VertexFormat::Compact`](mesh::VertexFormat::Compact)).
#[derive(Clone, Copy)]
struct Form {
    binary: bool,
    quantized: bool,
}

impl Form {
    fn of(options: &MeshOptions, binary: bool) -> Self {
        Form {
            binary,
            quantized: options.vertex_format == mesh::VertexFormat::Compact,
        }
    }
}

fn encode(
    (trees, placements): (Vec<Vec<Primitive>>, Vec<Node>),
    extras: Extras,
    Form { binary, quantized }: Form,
    instanced: Option<Instanced>,
) -> Result<Vec<u8>> {
    let instanced = instanced.filter(|(m, i)| !m.indices.is_empty() && !i.is_empty());
    // The buffer and the file are made from it: ask for their memory once, fallibly,
    // before building them (binary: the buffer and the .glb; JSON: the buffer, its base64
    // text and the copies that make the file).
    let meshes_bytes = buffer_bytes(&trees, instanced.as_ref());
    crate::limits::check_available(
        meshes_bytes.saturating_mul(if binary { 2 } else { 6 }),
        "the glTF buffer and file",
    )?;
    let materials = materials_in_use(&trees, instanced.is_some());
    let material = |m: Material| {
        materials
            .iter()
            .position(|&x| x == m)
            .expect("listed above")
    };
    let mut b = Buffers {
        quantized,
        ..Buffers::default()
    };
    // Meshes and the nodes that hold them: the trees (a tree without triangles gets no
    // mesh, and its node none), then the instanced leaves.
    let mut meshes = Vec::new();
    let mut mesh_of = Vec::with_capacity(trees.len());
    for prims in &trees {
        let mut primitives = Vec::new();
        for p in prims.iter().filter(|p| !p.mesh.indices.is_empty()) {
            let (mut attributes, indices, n) = b.mesh(&p.mesh);
            // The animation stream: growth time, and (order, along, phase) for wind.
            if let Some(a) = p.anim.as_ref().filter(|a| a.len() == n) {
                let av = b.view(bytemuck::cast_slice(a), Some(16), Some(ARRAY_BUFFER));
                attributes.growth = Some(b.accessor(av, 0, n, "SCALAR"));
                attributes.wind = Some(b.accessor(av, 4, n, "VEC3"));
            }
            primitives.push(json::Primitive {
                attributes,
                indices,
                material: material(p.material),
                mode: 4,
            });
        }
        if primitives.is_empty() {
            mesh_of.push(None);
        } else {
            mesh_of.push(Some(meshes.len()));
            meshes.push(json::Mesh {
                name: "tree",
                primitives,
            });
        }
    }
    let mut nodes = Vec::new();
    for n in &placements {
        nodes.push(node_json(n, mesh_of.get(n.mesh).copied().flatten()));
    }
    if let Some((m, instances)) = &instanced {
        let leaf = material(Material::Leaves);
        let (node, mesh) = instanced_leaves(&mut b, m, instances, meshes.len(), leaf);
        nodes.push(node);
        meshes.push(mesh);
    }
    let (extensions_used, extensions_required) = extensions(quantized, instanced.is_some());
    if nodes.is_empty() {
        nodes.push(json::Node::new("tree", None));
    }
    // glTF has no empty arrays: a file without triangles has nodes only.
    let (materials, buffers) = if meshes.is_empty() {
        (Vec::new(), Vec::new())
    } else {
        let uri = (!binary).then(|| {
            use base64::Engine as _;
            format!(
                "data:application/octet-stream;base64,{}",
                base64::engine::general_purpose::STANDARD.encode(&b.bin)
            )
        });
        let buffer = json::Buffer {
            byte_length: b.bin.len(),
            uri,
        };
        (materials.iter().map(|m| m.json()).collect(), vec![buffer])
    };
    let root = json::Root {
        asset: json::Asset {
            version: "2.0",
            generator: format!("arbor {}", env!("CARGO_PKG_VERSION")),
            extras,
        },
        extensions_used,
        extensions_required,
        scene: 0,
        scenes: [json::Scene {
            nodes: (0..nodes.len()).collect(),
        }],
        nodes,
        meshes,
        materials,
        // Accessors and views come only with meshes (none when there are none).
        accessors: b.accessors,
        buffer_views: b.views,
        buffers,
    };
    let json = serde_json::to_vec(&root).map_err(|e| Error::invalid("glTF", e.to_string()))?;
    if !binary {
        return Ok(json);
    }
    glb(json, &b.bin)
}

/// The GLB container: header, the JSON chunk (padded with spaces), the BIN chunk.
fn glb(mut j: Vec<u8>, bin: &[u8]) -> Result<Vec<u8>> {
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
        out.extend_from_slice(bin);
    }
    Ok(out)
}

/// Writes a forest ([`gltf_forest_bytes`]) to `path` (`.glb` or `.gltf`).
pub fn save_gltf_forest(
    placed: &[crate::forest::Placed<'_>],
    options: &MeshOptions,
    path: impl AsRef<Path>,
) -> Result<()> {
    save(path.as_ref(), &mut Run::default(), |binary, _| {
        gltf_forest_bytes(placed, options, binary)
    })
}

/// Writes the bytes `make` gives for the form `path`'s extension asks (binary or not); a
/// bad extension fails before anything is made. `run` goes to `make` (mesh writes) and
/// then to the file's write.
fn save(
    path: &Path,
    run: &mut Run<'_>,
    make: impl FnOnce(bool, &mut Run<'_>) -> Result<Vec<u8>>,
) -> Result<()> {
    let binary = binary_by_extension(path)?;
    let bytes = make(binary, run)?;
    super::atomic::write_atomic(path, run, |w, p| {
        p.report(crate::progress::Stage::Write, 0.0)?;
        use std::io::Write;
        w.write_all(&bytes)
            .map_err(|e| super::atomic::io(path, "write", e))
    })
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

/// Writes `skeleton` as glTF 2.0 to `path`: `.glb` binary, `.gltf` JSON with the buffer
/// embedded (chosen by the extension, case-insensitive; anything else is
/// [`Error::InvalidArgument`]).
pub fn save_gltf(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: Option<&LeafOptions>,
    path: impl AsRef<Path>,
) -> Result<()> {
    save_gltf_in(skeleton, options, leaves, path, &mut Run::default())
}

/// [`save_gltf`] in `run`: the bark is meshed on the run's threads, reporting
/// [`Stage::Mesh`](crate::progress::Stage::Mesh) as
/// [`MeshPlan::write_uninit_in`](crate::mesh::MeshPlan::write_uninit_in) does, then
/// [`Stage::Write`](crate::progress::Stage::Write); `false` stops with
/// [`Error::Cancelled`](crate::error::Error::Cancelled) and leaves an existing file as it was.
pub fn save_gltf_in(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: Option<&LeafOptions>,
    path: impl AsRef<Path>,
    run: &mut Run<'_>,
) -> Result<()> {
    save(path.as_ref(), run, |binary, run| {
        gltf_bytes_with(skeleton, options, leaves, binary, run)
    })
}
