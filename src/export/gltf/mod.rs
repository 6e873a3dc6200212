//! glTF 2.0: `.glb` (binary) or `.gltf` (JSON with the buffer embedded as a data URI),
//! as every engine and DCC tool reads it, serialized from a [`Scene`].
//!
//! A tree's file is one node and one mesh: the bark as a primitive with a bark material,
//! and the baked leaves (leaf quads, polygons, spheres, surfaces) as a second primitive
//! with a double-sided leaf material when leaf options are given. Vertices are interleaved
//! (position, normal, uv; stride 32) as arbor writes them; indices are 32-bit triangle
//! lists (glTF has no restart index). glTF is right-handed, Y up, counter-clockwise: the
//! mesh options' topology, winding and up axis are overridden to that, whatever they ask
//! ([`gltf_mesh_options`]); their scale, sides, joints, tips and curve rings stand. Options
//! that contradict themselves (an engine preset with another up axis or winding) are
//! refused with the mesh writer's error; the f32 range of positions is checked in the
//! space written. The scene's settings are in `asset.extras`.

use crate::error::{Error, Result};
use crate::mesh::{self, Axes, LeafOptions, MeshOptions, Topology, UpAxis, Winding};
use crate::progress::Run;
use crate::scene::{Material, Node, Scene, Settings};
use crate::skeleton::Skeleton;
use std::path::Path;

mod buffers;
mod json;
use buffers::{ARRAY_BUFFER, Buffers, FLOAT, UNSIGNED_BYTE, UNSIGNED_SHORT, pad4};
use json::Extras;

fn material_json(m: &Material) -> json::Material {
    let info = |t: Option<usize>| t.map(|index| json::TextureInfo { index });
    json::Material {
        name: m.name.clone(),
        double_sided: m.double_sided,
        pbr_metallic_roughness: json::Pbr {
            base_color_factor: m.base_color,
            base_color_texture: info(m.base_color_texture),
            metallic_factor: m.metallic,
            roughness_factor: m.roughness,
            metallic_roughness_texture: info(m.metallic_roughness_texture),
        },
        normal_texture: info(m.normal_texture),
        alpha_mode: m.alpha_cutoff.map(|_| "MASK"),
        alpha_cutoff: m.alpha_cutoff,
    }
}

/// The scene's textures as PNG images in the buffer, one sampler (linear, mipmapped,
/// repeating) and a texture per image; empty when there are none.
fn textures_json(
    b: &mut Buffers,
    scene: &Scene,
) -> Result<(Vec<json::Texture>, Vec<json::Image>, Vec<json::Sampler>)> {
    let (mut textures, mut images) = (Vec::new(), Vec::new());
    for (k, t) in scene.textures.iter().enumerate() {
        let png = t.image.png()?;
        let view = b.view(&png, None, None);
        images.push(json::Image {
            buffer_view: view,
            mime_type: "image/png",
            name: t.name.clone(),
        });
        textures.push(json::Texture {
            sampler: 0,
            source: k,
            name: t.name.clone(),
        });
    }
    let samplers = if textures.is_empty() {
        Vec::new()
    } else {
        // LINEAR, LINEAR_MIPMAP_LINEAR, REPEAT, REPEAT.
        vec![json::Sampler {
            mag_filter: 9729,
            min_filter: 9987,
            wrap_s: 10497,
            wrap_t: 10497,
        }]
    };
    Ok((textures, images, samplers))
}

fn extras(s: &Settings) -> Extras {
    Extras {
        generator: "arbor",
        branches: s.branches,
        trees: s.trees,
        distinct_trees: s.distinct_trees,
        radial_segments: s.radial_segments,
        curve_rings: s.curve_rings,
        scale: s.scale,
        leaves: s.leaves,
        leaf_instances: s.leaf_instances,
    }
}

/// The options glTF needs: triangle lists, counter-clockwise, Y up, arbor's axes. Each
/// field is checked as given first, so a set that contradicts itself (an engine preset with
/// another up axis, say) is refused with the mesh writer's error; the limits that depend
/// on the output space (positions in the f32 range) are those of the space glTF is written
/// in. The vertices are written as f32 whatever `vertex_format` asks.
pub fn gltf_mesh_options(options: &MeshOptions) -> Result<MeshOptions> {
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

/// The file's bytes of one tree: GLB when `binary`, else glTF JSON with the buffer
/// embedded ([`Scene::tree`] in glTF's conventions).
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
    let o = gltf_mesh_options(options)?;
    let scene = Scene::tree_in(skeleton, &o, leaves, run)?;
    gltf_scene_bytes(&scene, options, binary)
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
    save(path.as_ref(), run, |binary, run| {
        let o = gltf_mesh_options(options)?;
        let scene = Scene::tree_instanced_in(skeleton, &o, leaves, run)?;
        gltf_scene_bytes(&scene, options, binary)
    })
}

/// [`gltf_bytes`] with the leaves as instances of one leaf mesh ([`Scene::tree_instanced`])
/// through `EXT_mesh_gpu_instancing`, declared used, not required: engines that draw
/// instances get one small mesh and a transform per leaf; a viewer without the extension
/// draws a single leaf at the node, so export baked leaves ([`gltf_bytes`]) for those.
pub fn gltf_bytes_instanced(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: &LeafOptions,
    binary: bool,
) -> Result<Vec<u8>> {
    let o = gltf_mesh_options(options)?;
    let scene = Scene::tree_instanced(skeleton, &o, leaves)?;
    gltf_scene_bytes(&scene, options, binary)
}

/// A scene's file: GLB when `binary`, else glTF JSON with the buffer embedded. Build the
/// scene with [`gltf_mesh_options`] of `options` (glTF's conventions); `options` says here
/// only whether the vertices are quantized (`vertex_format` compact:
/// `KHR_mesh_quantization`).
///
/// ```
/// use arbor::mesh::MeshOptions;
/// use arbor::scene::Scene;
///
/// let mut p = arbor::HondaParams::preset('g').unwrap();
/// p.steps = 4;
/// let placed: Vec<arbor::forest::Placed> = (0..3)
///     .map(|k| arbor::forest::Placed {
///         item: arbor::forest::Item { source: arbor::forest::Source::Honda(p), seed: 0 },
///         position: [k as f32 * 2.0, 0.0, 0.0],
///         rotation: 0.0,
///         scale: 1.0,
///     })
///     .collect();
/// let options = MeshOptions::default();
/// let scene = Scene::forest_nodes(&placed, &arbor::export::gltf_mesh_options(&options)?)?;
/// let gltf = arbor::export::gltf_scene_bytes(&scene, &options, false)?;
/// assert!(std::str::from_utf8(&gltf).unwrap().contains("tree 2"));
/// # Ok::<(), arbor::Error>(())
/// ```
pub fn gltf_scene_bytes(scene: &Scene, options: &MeshOptions, binary: bool) -> Result<Vec<u8>> {
    encode(scene, Form::of(options, binary))
}

/// [`gltf_scene_bytes`] saved to `path` (`.glb` or `.gltf` by the extension, as
/// [`save_gltf`]), whole or not at all.
pub fn save_gltf_scene(scene: &Scene, options: &MeshOptions, path: impl AsRef<Path>) -> Result<()> {
    save(path.as_ref(), &mut Run::default(), |binary, _| {
        gltf_scene_bytes(scene, options, binary)
    })
}

/// A world's trees (and its ground, with `ground`) as one glTF file at `path` (`.glb` or
/// `.gltf`), each tree a node `NAME_k` ([`Scene::world`]: `names` by species slot,
/// textured where the name is a species with a look, `texture_size` pixels square),
/// whole or not at all.
pub fn save_gltf_world(
    world: &crate::models::growth::World,
    names: &[&str],
    options: &MeshOptions,
    leaves: Option<&LeafOptions>,
    texture_size: u32,
    ground: bool,
    path: impl AsRef<Path>,
) -> Result<()> {
    save(path.as_ref(), &mut Run::default(), |binary, _| {
        let o = gltf_mesh_options(options)?;
        let scene = Scene::world(world, names, &o, leaves, texture_size, ground)?;
        gltf_scene_bytes(&scene, options, binary)
    })
}

/// Bytes of the buffer the scene's meshes and instances make (what the file is made from).
fn buffer_bytes(scene: &Scene) -> usize {
    let meshes: usize = scene
        .meshes
        .iter()
        .flat_map(|m| &m.primitives)
        .map(|p| {
            std::mem::size_of_val(p.mesh.vertices.as_slice())
                + std::mem::size_of_val(p.mesh.indices.as_slice())
                + p.animation
                    .as_ref()
                    .map_or(0, |a| std::mem::size_of_val(a.as_slice()))
        })
        .sum();
    let instances: usize = scene
        .nodes
        .iter()
        .filter_map(|n| n.instances.as_ref())
        .map(|i| i.len() * 40)
        .sum();
    let textures: usize = scene.textures.iter().map(|t| t.image.pixels.len()).sum();
    // Tangents (16 bytes a vertex) of normal-mapped primitives.
    let tangents: usize = scene
        .meshes
        .iter()
        .flat_map(|m| &m.primitives)
        .filter(|p| {
            scene
                .materials
                .get(p.material)
                .is_some_and(|m| m.normal_texture.is_some())
        })
        .map(|p| p.mesh.vertices.len() * 16)
        .sum();
    meshes + instances + textures + tangents
}

/// A node of the file: its name, its mesh and placement, and for instances their
/// translations, rotations and scales (tightly packed, as EXT_mesh_gpu_instancing reads
/// them) written to the buffer.
fn node_json(b: &mut Buffers, n: &Node) -> json::Node {
    let mut node = json::Node::new(n.name.clone(), n.mesh);
    if let Some(t) = n.transform {
        node.translation = Some(t.translation);
        node.rotation = Some(t.rotation);
        node.scale = Some([t.scale; 3]);
    }
    let mut extras = json::NodeExtras::default();
    if let Some(c) = n.capsule {
        extras.arbor_capsule = Some(json::CapsuleExtras {
            a: c.a,
            b: c.b,
            radius: c.radius,
        });
    }
    let mut extensions = json::NodeExtensions::default();
    if let Some(l) = &n.lod {
        extensions.lod = Some(json::MsftLod {
            ids: l.levels.clone(),
        });
        extras.screen_coverage = Some(l.coverage.clone());
    }
    if let Some(i) = &n.impostor {
        extras.arbor_impostor = Some(json::ImpostorExtras {
            frames: i.frames,
            cell: i.cell,
            hemi: i.hemi,
            centre: i.centre,
            radius: i.radius,
            up: i.up,
            albedo_texture: i.albedo,
            normal_texture: i.normal,
            below_coverage: i.below,
        });
    }
    if let Some(instances) = &n.instances {
        let t: Vec<[f32; 3]> = instances.iter().map(|l| l.position).collect();
        let r: Vec<[f32; 4]> = instances.iter().map(|l| l.rotation).collect();
        let sc: Vec<[f32; 3]> = instances.iter().map(|l| [l.scale; 3]).collect();
        let count = instances.len();
        let mut per_instance = |bytes: &[u8], kind: &'static str| {
            let v = b.view(bytes, None, None);
            b.push(json::Accessor::new(v, None, (FLOAT, kind), count))
        };
        let attributes = json::InstanceAttributes {
            translation: per_instance(bytemuck::cast_slice(&t), "VEC3"),
            rotation: per_instance(bytemuck::cast_slice(&r), "VEC4"),
            scale: per_instance(bytemuck::cast_slice(&sc), "VEC3"),
        };
        extensions.instancing = Some(json::Instancing { attributes });
    }
    if let Some(p) = n.pivots.as_ref().filter(|p| !p.is_empty()) {
        let a: Vec<[f32; 4]> = p.iter().map(|r| [r[0], r[1], r[2], r[3]]).collect();
        let c: Vec<[f32; 4]> = p.iter().map(|r| [r[4], r[5], r[6], r[7]]).collect();
        let av = b.view(bytemuck::cast_slice(&a), None, None);
        let cv = b.view(bytemuck::cast_slice(&c), None, None);
        extras.arbor_pivots = Some(json::PivotExtras {
            count: p.len(),
            pivot_length: b.accessor(av, 0, p.len(), "VEC4"),
            axis_parent: b.accessor(cv, 0, p.len(), "VEC4"),
        });
    }
    let has_extras = extras.arbor_pivots.is_some()
        || extras.arbor_capsule.is_some()
        || extras.screen_coverage.is_some()
        || extras.arbor_impostor.is_some();
    node.extras = has_extras.then_some(extras);
    node.extensions =
        (extensions.instancing.is_some() || extensions.lod.is_some()).then_some(extensions);
    node
}

/// A mesh of the file, its vertices, indices and animation streams written to the buffer.
fn mesh_json(b: &mut Buffers, m: &crate::scene::SceneMesh, materials: &[Material]) -> json::Mesh {
    let mut primitives = Vec::with_capacity(m.primitives.len());
    for p in &m.primitives {
        let (mut attributes, indices, n) = b.mesh(&p.mesh);
        // A normal map needs the tangent space it was drawn in.
        if materials
            .get(p.material)
            .is_some_and(|m| m.normal_texture.is_some())
        {
            let t = buffers::tangents(&p.mesh);
            let tv = b.view(bytemuck::cast_slice(&t), None, Some(ARRAY_BUFFER));
            attributes.tangent = Some(b.accessor(tv, 0, n, "VEC4"));
        }
        // The animation stream: growth time, and (order, along, phase) for wind.
        if let Some(a) = p.animation.as_ref().filter(|a| a.len() == n) {
            let av = b.view(bytemuck::cast_slice(a), Some(16), Some(ARRAY_BUFFER));
            attributes.growth = Some(b.accessor(av, 0, n, "SCALAR"));
            attributes.wind = Some(b.accessor(av, 4, n, "VEC3"));
        }
        // The bones each vertex rides (u16 x 4) and their weights (f32 x 4).
        if let Some(skin) = p.skin.as_ref().filter(|k| k.len() == n) {
            let joints: Vec<[u16; 4]> = skin.iter().map(|x| x.0).collect();
            let weights: Vec<[f32; 4]> = skin.iter().map(|x| x.1).collect();
            let jv = b.view(bytemuck::cast_slice(&joints), None, Some(ARRAY_BUFFER));
            attributes.joints =
                Some(b.push(json::Accessor::new(jv, None, (UNSIGNED_SHORT, "VEC4"), n)));
            let wv = b.view(bytemuck::cast_slice(&weights), None, Some(ARRAY_BUFFER));
            attributes.weights = Some(b.accessor(wv, 0, n, "VEC4"));
        }
        // Wind in standard attributes: COLOR_0 (unorm8 x 4) and TEXCOORD_1 (f32 x 2).
        if let Some(w) = p.wind.as_ref().filter(|w| w.len() == n) {
            let colors: Vec<[u8; 4]> = w.iter().map(|x| x.color).collect();
            let uv1: Vec<[f32; 2]> = w.iter().map(|x| x.uv1).collect();
            let cv = b.view(&colors.concat(), None, Some(ARRAY_BUFFER));
            let mut c = json::Accessor::new(cv, None, (UNSIGNED_BYTE, "VEC4"), n);
            c.normalized = true;
            attributes.color_0 = Some(b.push(c));
            let tv = b.view(bytemuck::cast_slice(&uv1), None, Some(ARRAY_BUFFER));
            attributes.texcoord_1 = Some(b.accessor(tv, 0, n, "VEC2"));
            let rows: Vec<[f32; 2]> = w.iter().map(|x| [x.branch as f32, 0.0]).collect();
            let rv = b.view(bytemuck::cast_slice(&rows), None, Some(ARRAY_BUFFER));
            attributes.texcoord_2 = Some(b.accessor(rv, 0, n, "VEC2"));
        }
        primitives.push(json::Primitive {
            attributes,
            indices,
            material: p.material,
            mode: 4,
        });
    }
    json::Mesh {
        name: m.name.clone(),
        primitives,
    }
}

/// The file's `extensionsUsed` and `extensionsRequired`. Quantized attributes are
/// required: a reader without the extension cannot read them as floats. Instancing is
/// used, not required: a viewer without it draws one leaf at the node (export baked
/// leaves, save_gltf, for such viewers).
fn extensions(
    quantized: bool,
    instanced: bool,
    lod: bool,
) -> (Vec<&'static str>, Vec<&'static str>) {
    let used = [
        (quantized, "KHR_mesh_quantization"),
        (instanced, "EXT_mesh_gpu_instancing"),
        (lod, "MSFT_lod"),
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

fn encode(scene: &Scene, Form { binary, quantized }: Form) -> Result<Vec<u8>> {
    // The buffer and the file are made from it: ask for their memory once, fallibly,
    // before building them (binary: the buffer and the .glb; JSON: the buffer, its base64
    // text and the copies that make the file).
    crate::limits::check_available(
        buffer_bytes(scene).saturating_mul(if binary { 2 } else { 6 }),
        "the glTF buffer and file",
    )?;
    let mut b = Buffers {
        quantized,
        ..Buffers::default()
    };
    let meshes: Vec<json::Mesh> = scene
        .meshes
        .iter()
        .map(|m| mesh_json(&mut b, m, &scene.materials))
        .collect();
    let mut nodes: Vec<json::Node> = scene.nodes.iter().map(|n| node_json(&mut b, n)).collect();
    let (textures, images, samplers) = if meshes.is_empty() {
        (Vec::new(), Vec::new(), Vec::new())
    } else {
        textures_json(&mut b, scene)?
    };
    // The rig: a node per bone after the scene's, the skin on its skinned nodes, the clip.
    let mut roots: Vec<usize> = (0..nodes.len()).collect();
    let (mut skins, mut animations) = (Vec::new(), Vec::new());
    if let (Some(rig), false) = (&scene.rig, nodes.is_empty()) {
        let base = nodes.len();
        for (k, bone) in rig.bones.iter().enumerate() {
            let head = glam::Vec3::from(bone.head);
            let parent = rig
                .bones
                .get(bone.parent as usize)
                .map(|p| glam::Vec3::from(p.head));
            let mut node = json::Node::new(format!("bone_{k:02}"), None);
            node.translation = Some((head - parent.unwrap_or(glam::Vec3::ZERO)).to_array());
            node.children = rig
                .bones
                .iter()
                .enumerate()
                .filter(|(_, c)| c.parent as usize == k)
                .map(|(c, _)| base + c)
                .collect();
            if parent.is_none() {
                roots.push(base + k);
            }
            nodes.push(node);
        }
        // Each bone's inverse bind matrix: the translation back from its head.
        let ibm: Vec<[f32; 16]> = rig.bones.iter().map(|b| b.inverse_bind()).collect();
        let v = b.view(bytemuck::cast_slice(&ibm), None, None);
        let ibm = b.push(json::Accessor::new(
            v,
            None,
            (FLOAT, "MAT4"),
            rig.bones.len(),
        ));
        skins.push(json::Skin {
            name: "wind",
            inverse_bind_matrices: ibm,
            joints: (base..base + rig.bones.len()).collect(),
            skeleton: base,
        });
        // Every node whose mesh is skinned (the first, or each level of a chain).
        for (k, n) in scene.nodes.iter().enumerate() {
            let skinned = n
                .mesh
                .is_some_and(|m| scene.meshes[m].primitives.iter().any(|p| p.skin.is_some()));
            if skinned {
                nodes[k].skin = Some(0);
            }
        }
        if let Some(clip) = &rig.clip {
            let tv = b.view(bytemuck::cast_slice(&clip.times), None, None);
            let mut input = json::Accessor::new(tv, None, (FLOAT, "SCALAR"), clip.times.len());
            input.min = Some(vec![clip.times.first().copied().unwrap_or(0.0)]);
            input.max = Some(vec![clip.times.last().copied().unwrap_or(0.0)]);
            let input = b.push(input);
            let (mut channels, mut samplers) = (Vec::new(), Vec::new());
            for (k, r) in clip.rotations.iter().enumerate() {
                let rv = b.view(bytemuck::cast_slice(r), None, None);
                let output = b.push(json::Accessor::new(rv, None, (FLOAT, "VEC4"), r.len()));
                samplers.push(json::AnimationSampler {
                    input,
                    interpolation: "LINEAR",
                    output,
                });
                channels.push(json::Channel {
                    sampler: k,
                    target: json::ChannelTarget {
                        node: base + k,
                        path: "rotation",
                    },
                });
            }
            animations.push(json::Animation {
                name: "wind",
                channels,
                samplers,
            });
        }
    }
    let instanced = scene.nodes.iter().any(|n| n.instances.is_some());
    let lod = scene.nodes.iter().any(|n| n.lod.is_some());
    let (extensions_used, extensions_required) = extensions(quantized, instanced, lod);
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
        (
            scene.materials.iter().map(material_json).collect(),
            vec![buffer],
        )
    };
    let root = json::Root {
        asset: json::Asset {
            version: "2.0",
            generator: format!("arbor {}", env!("CARGO_PKG_VERSION")),
            extras: extras(&scene.settings),
        },
        extensions_used,
        extensions_required,
        scene: 0,
        scenes: [json::Scene { nodes: roots }],
        nodes,
        meshes,
        materials,
        textures,
        images,
        samplers,
        skins,
        animations,
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
