//! glTF 2.0 export: trees a–i, a grammar tree with leaves, and a self-organized tree are
//! written as `.glb` and `.gltf`, read back with the `gltf` crate (counts and values equal
//! arbor's triangle-list meshes), and checked with the Khronos glTF-Validator when it is
//! required
//! (`tools/test` installs it; 0 errors and 0 warnings).

use arbor::lsystem::LSystem;
use arbor::mesh::{self, LeafOptions, MeshOptions, Topology, UpAxis, Winding};
use arbor::models::growth::{GrowthParams, World, WorldOptions};
use arbor::models::honda::{self, HondaParams};
use arbor::skeleton::Skeleton;
use std::path::{Path, PathBuf};

#[path = "common/validator.rs"]
mod validator;

fn out_dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf");
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn decode_base64(s: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let mut out = Vec::new();
    for chunk in s.as_bytes().chunks(4) {
        let n = chunk.iter().take_while(|&&c| c != b'=').count();
        let mut v = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            v |= (if c == b'=' { 0 } else { value(c) } as u32) << (18 - 6 * k);
        }
        out.extend_from_slice(&v.to_be_bytes()[1..n]);
    }
    out
}

/// The file's one buffer: the GLB's binary chunk, or the `.gltf`'s base64 data URI.
fn blob(g: &gltf::Gltf) -> Vec<u8> {
    match g.blob.clone() {
        Some(b) => b,
        None => {
            let b = g.document.buffers().next().unwrap();
            match b.source() {
                gltf::buffer::Source::Uri(uri) => {
                    decode_base64(uri.split_once("base64,").unwrap().1)
                }
                gltf::buffer::Source::Bin => unreachable!(),
            }
        }
    }
}

/// One primitive read back: positions, normals, uvs, indices.
type Read = (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<u32>);

/// Reads a written file back, per primitive.
fn read_back(path: &Path) -> Vec<Read> {
    let bytes = std::fs::read(path).unwrap();
    let g = gltf::Gltf::from_slice(&bytes).unwrap();
    assert!(g.document.as_json().asset.version == "2.0");
    let buffer = blob(&g);
    let mut out = Vec::new();
    for m in g.document.meshes() {
        for p in m.primitives() {
            assert_eq!(p.mode(), gltf::mesh::Mode::Triangles);
            let r = p.reader(|_| Some(&buffer[..]));
            let pos: Vec<[f32; 3]> = r.read_positions().unwrap().collect();
            let nor: Vec<[f32; 3]> = r.read_normals().unwrap().collect();
            let uv: Vec<[f32; 2]> = r.read_tex_coords(0).unwrap().into_f32().collect();
            let idx: Vec<u32> = r.read_indices().unwrap().into_u32().collect();
            out.push((pos, nor, uv, idx));
        }
    }
    out
}

fn list_options() -> MeshOptions {
    MeshOptions::default()
        .topology(Topology::TriangleList)
        .winding(Winding::CounterClockwise)
        .up_axis(UpAxis::Y)
}

/// Writes both forms and checks the read-back against arbor's own meshes.
fn export_and_check(name: &str, s: &Skeleton, leaves: Option<&LeafOptions>) -> Vec<PathBuf> {
    // Options that glTF overrides: strips, clockwise, Z up.
    let asked = MeshOptions::default()
        .topology(Topology::TriangleStripRestart)
        .winding(Winding::Clockwise)
        .up_axis(UpAxis::Z);
    let bark = mesh::tubes(s, &list_options()).unwrap();
    let leaf = leaves.map(|l| mesh::leaf_mesh(s, l, &list_options()).unwrap());
    let mut files = Vec::new();
    for ext in ["glb", "gltf"] {
        let path = out_dir().join(format!("{name}.{ext}"));
        arbor::export::save_gltf(s, &asked, leaves, &path).unwrap();
        let prims = read_back(&path);
        let mut expect = vec![&bark];
        if let Some(l) = leaf.as_ref().filter(|l| !l.indices.is_empty()) {
            expect.push(l);
        }
        assert_eq!(prims.len(), expect.len(), "{name}.{ext}");
        for ((pos, nor, uv, idx), m) in prims.iter().zip(expect) {
            assert_eq!(pos.len(), m.vertices.len(), "{name}.{ext}");
            assert_eq!(idx, &m.indices, "{name}.{ext}");
            for (k, v) in m.vertices.iter().enumerate() {
                assert_eq!((pos[k], nor[k], uv[k]), (v.position, v.normal, v.uv));
            }
        }
        files.push(path);
    }
    files
}

#[test]
fn exported_files_read_back_and_pass_the_validator() {
    let mut files = Vec::new();
    for name in "abcdefghi".chars() {
        let s = honda::build(&HondaParams::preset(name).unwrap()).unwrap();
        files.extend(export_and_check(&format!("tree_{name}"), &s, None));
    }
    // A grammar tree with leaves and organs.
    let ls = LSystem::parse(
        "derivation length: 5\nangle increment: 25\nAxiom: !(0.4)A\n\
         A --> F[+A~][-A@O(0.6)]F{.+f.+f.+f.}A\n",
    )
    .unwrap();
    let s = ls.skeleton(&Default::default()).unwrap();
    files.extend(export_and_check(
        "grammar_leaves",
        &s,
        Some(&LeafOptions::default()),
    ));
    // A self-organized tree.
    let mut w = World::new(&WorldOptions::default()).unwrap();
    w.plant(&GrowthParams::default(), [0.0, 0.0, 0.0], 5)
        .unwrap();
    w.step(8).unwrap();
    let s = w.tree(0).unwrap();
    files.extend(export_and_check(
        "self_organized",
        &s,
        Some(&LeafOptions::default()),
    ));
    // Leaves as instances of one quad (EXT_mesh_gpu_instancing, used, not required).
    let leafy = ls.skeleton(&Default::default()).unwrap();
    let instances = mesh::leaf_instances(&leafy, &LeafOptions::default(), &list_options()).unwrap();
    assert!(!instances.is_empty());
    for (ext, binary) in [("glb", true), ("gltf", false)] {
        let bytes = arbor::export::gltf_bytes_instanced(
            &leafy,
            &MeshOptions::default(),
            &LeafOptions::default(),
            binary,
        )
        .unwrap();
        let path = out_dir().join(format!("instanced.{ext}"));
        std::fs::write(&path, &bytes).unwrap();
        let g = gltf::Gltf::from_slice(&bytes).unwrap();
        let json = g.document.as_json();
        assert_eq!(
            json.extensions_used,
            vec!["EXT_mesh_gpu_instancing".to_string()]
        );
        assert!(json.extensions_required.is_empty());
        assert_eq!(g.document.meshes().count(), 2);
        let prims = read_back(&path);
        assert_eq!(prims[1].0.len(), 4, "the leaf quad");
        // The instance counts: TRANSLATION, ROTATION and SCALE accessors hold one each.
        let last: Vec<usize> = g.document.accessors().map(|a| a.count()).collect();
        assert_eq!(&last[last.len() - 3..], &[instances.len(); 3]);
        files.push(path);
    }
    // A forest of nine trees merged into one mesh.
    let presets: Vec<HondaParams> = "abcdefghi"
        .chars()
        .map(|c| HondaParams::preset(c).unwrap())
        .collect();
    let placed: Vec<arbor::forest::Placed> = presets
        .iter()
        .enumerate()
        .map(|(k, p)| arbor::forest::Placed {
            item: arbor::forest::Item {
                source: arbor::forest::Source::Honda(*p),
                seed: k as u64,
            },
            position: [(k % 3) as f32 * 400.0, 0.0, (k / 3) as f32 * 400.0],
            rotation: k as f32 * 40.0,
            scale: 1.0,
        })
        .collect();
    for ext in ["glb", "gltf"] {
        let path = out_dir().join(format!("forest.{ext}"));
        save_forest(arbor::scene::Scene::forest, &placed, &path);
        let merged = arbor::forest::merged(&placed, &list_options()).unwrap();
        let prims = read_back(&path);
        assert_eq!(prims.len(), 1);
        assert_eq!(prims[0].0.len(), merged.vertices.len());
        assert_eq!(prims[0].3, merged.indices);
        files.push(path);
    }
    // The same forest as one node per placed tree sharing meshes: twelve placements of
    // three distinct trees (two presets, one of them with two seeds).
    let shared: Vec<arbor::forest::Placed> = (0..12)
        .map(|k| arbor::forest::Placed {
            item: arbor::forest::Item {
                source: arbor::forest::Source::Honda(presets[[0, 6, 6][k % 3]]),
                seed: [0, 0, 1][k % 3],
            },
            position: [(k % 4) as f32 * 300.0, 0.0, (k / 4) as f32 * 300.0],
            rotation: k as f32 * 30.0,
            scale: 0.5 + k as f32 * 0.1,
        })
        .collect();
    let (distinct, which) = arbor::forest::instanced(&shared, &list_options()).unwrap();
    assert_eq!(distinct.len(), 3);
    for ext in ["glb", "gltf"] {
        let path = out_dir().join(format!("forest_nodes.{ext}"));
        save_forest(arbor::scene::Scene::forest_nodes, &shared, &path);
        let prims = read_back(&path);
        assert_eq!(prims.len(), 3, "one mesh per distinct tree");
        for (p, m) in prims.iter().zip(&distinct) {
            assert_eq!(p.0.len(), m.vertices.len());
            assert_eq!(p.3, m.indices);
        }
        let g = gltf::Gltf::from_slice(&std::fs::read(&path).unwrap()).unwrap();
        let nodes: Vec<_> = g.document.nodes().collect();
        assert_eq!(nodes.len(), 12, "one node per placement");
        for ((n, p), w) in nodes.iter().zip(&shared).zip(&which) {
            assert_eq!(n.mesh().map(|m| m.index()), Some(w.0 as usize));
            let (t, r, sc) = n.transform().decomposed();
            assert_eq!(t, p.position);
            assert_eq!(sc, [p.scale; 3]);
            let q = glam::Quat::from_rotation_y(p.rotation.to_radians());
            assert!(
                glam::Quat::from_array(r).abs_diff_eq(q, 1e-6),
                "{r:?} vs {q:?}"
            );
        }
        files.push(path);
    }
    // Settings in asset.extras, the animation stream as custom attributes; a bad
    // extension is refused by name.
    let text = std::fs::read_to_string(out_dir().join("tree_a.gltf")).unwrap();
    assert!(text.contains("\"extras\":{\"generator\":\"arbor\",\"branches\":1023"));
    assert!(
        text.contains("\"_GROWTH\":4,\"_WIND\":5"),
        "custom attributes"
    );
    let g = gltf::Gltf::from_slice(&std::fs::read(out_dir().join("tree_a.glb")).unwrap()).unwrap();
    let blob = g.blob.clone().unwrap();
    // Accessor 4 is `_GROWTH` (checked in the JSON above).
    let growth = g.document.accessors().nth(4).expect("_GROWTH");
    let view = growth.view().unwrap();
    let s = honda::build(&HondaParams::preset('a').unwrap()).unwrap();
    let anim = mesh::animation(&s, &list_options()).unwrap();
    assert_eq!(growth.count(), anim.len());
    for (k, a) in anim.iter().enumerate().step_by(97) {
        let at = view.offset() + k * view.stride().unwrap();
        let v = f32::from_le_bytes(blob[at..at + 4].try_into().unwrap());
        assert_eq!(v, a.growth);
    }
    assert!(
        arbor::export::save_gltf(&s, &MeshOptions::default(), None, out_dir().join("x.fbx"))
            .is_err()
    );

    validator::assert_valid(&files);
}

/// The bytes of accessor `a`'s element `k` (its view's stride, or the element size).
fn element<'b>(blob: &'b [u8], a: &gltf::Accessor<'_>, k: usize) -> &'b [u8] {
    let view = a.view().unwrap();
    let stride = view.stride().unwrap_or(a.size());
    let at = view.offset() + a.offset() + k * stride;
    &blob[at..at + a.size()]
}

/// `--compact-vertices` / `VertexFormat::Compact`: files with KHR_mesh_quantization
/// (required), normals in snorm16 (uv stays f32: see `quantized_vertices`), 28 bytes a
/// vertex, that decode to the f32 mesh within the documented precision and pass the
/// validator.
#[test]
fn compact_exports_are_quantized_and_pass_the_validator() {
    let compact = list_options().vertex_format(mesh::VertexFormat::Compact);
    let leaves = LeafOptions::default();
    let mut files = Vec::new();
    for name in ['a', 'g'] {
        let s = honda::build(&HondaParams::preset(name).unwrap()).unwrap();
        let bark = mesh::tubes(&s, &list_options()).unwrap();
        for ext in ["glb", "gltf"] {
            let path = out_dir().join(format!("compact_{name}.{ext}"));
            arbor::export::save_gltf(&s, &compact, Some(&leaves), &path).unwrap();
            let bytes = std::fs::read(&path).unwrap();
            let g = gltf::Gltf::from_slice_without_validation(&bytes).unwrap();
            let json = g.document.as_json();
            assert_eq!(json.extensions_required, ["KHR_mesh_quantization"]);
            assert!(
                json.extensions_used
                    .iter()
                    .any(|e| e == "KHR_mesh_quantization")
            );
            let blob = blob(&g);
            let p = g
                .document
                .meshes()
                .next()
                .unwrap()
                .primitives()
                .next()
                .unwrap();
            let get = |s: gltf::Semantic| p.get(&s).unwrap();
            let (pos, nor, uv) = (
                get(gltf::Semantic::Positions),
                get(gltf::Semantic::Normals),
                get(gltf::Semantic::TexCoords(0)),
            );
            use gltf::accessor::{DataType, Dimensions};
            assert_eq!(
                (pos.data_type(), pos.dimensions()),
                (DataType::F32, Dimensions::Vec3)
            );
            assert_eq!((nor.data_type(), nor.normalized()), (DataType::I16, true));
            assert_eq!(
                (uv.data_type(), uv.dimensions()),
                (DataType::F32, Dimensions::Vec2)
            );
            assert_eq!(pos.view().unwrap().stride(), Some(28), "28 bytes a vertex");
            assert_eq!(pos.count(), bark.vertices.len());
            for (k, v) in bark.vertices.iter().enumerate() {
                let p3: [f32; 3] = bytemuck::pod_read_unaligned(element(&blob, &pos, k));
                assert_eq!(p3, v.position);
                let n: [i16; 3] = bytemuck::pod_read_unaligned(element(&blob, &nor, k));
                let n = glam::Vec3::from(n.map(|c| (c as f32 / 32767.0).max(-1.0))).normalize();
                let f = glam::Vec3::from(v.normal);
                let deg = f.cross(n).length().atan2(f.dot(n)).to_degrees();
                assert!(deg < 0.1, "{name}.{ext} vertex {k}: normal {deg}°");
                let t: [f32; 2] = bytemuck::pod_read_unaligned(element(&blob, &uv, k));
                assert_eq!(t, v.uv);
            }
            files.push(path);
        }
    }
    validator::assert_valid(&files);
}

/// Saves a forest's scene, built in glTF's conventions from the default options.
fn save_forest(
    scene: fn(&[arbor::forest::Placed<'_>], &MeshOptions) -> arbor::Result<arbor::scene::Scene>,
    placed: &[arbor::forest::Placed<'_>],
    path: &std::path::Path,
) {
    let o = MeshOptions::default();
    let s = scene(placed, &arbor::export::gltf_mesh_options(&o).unwrap()).unwrap();
    arbor::export::save_gltf_scene(&s, &o, path).unwrap();
}
