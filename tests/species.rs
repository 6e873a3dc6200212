//! Named species: each grows to its height with textured bark and leaves, and its file
//! passes the Khronos validator.

#[path = "common/validator.rs"]
mod validator;

use arbor::mesh::MeshOptions;
use arbor::models::growth::Species;
use arbor::species::{Look, tree_scene};
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("species");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn eight_named_species_and_the_five_archetypes_without_a_look() {
    let named: Vec<&str> = Look::all().iter().map(|l| l.species.name()).collect();
    assert_eq!(
        named,
        [
            "oak", "maple", "birch", "willow", "poplar", "pine", "spruce", "shrub"
        ]
    );
    for s in [
        Species::Excurrent,
        Species::Decurrent,
        Species::Columnar,
        Species::Bush,
        Species::Weeping,
    ] {
        assert!(Look::of(s).is_none(), "{s:?}");
    }
}

#[test]
fn every_species_is_a_textured_tree_of_its_height() {
    let options = arbor::export::gltf_mesh_options(&MeshOptions::default()).unwrap();
    let mut files = Vec::new();
    for look in Look::all() {
        let name = look.species.name();
        let skeleton = look.grow(1).unwrap();
        let scene = tree_scene(&look, &skeleton, &options, 64, 1).unwrap();
        // Four images: the bark's colour, normal and roughness maps and the leaf atlas.
        assert_eq!(scene.textures.len(), 4, "{name}");
        let bark = scene.materials.iter().find(|m| m.name == "bark").unwrap();
        assert!(bark.base_color_texture.is_some() && bark.normal_texture.is_some());
        assert!(bark.metallic_roughness_texture.is_some());
        let leaves = scene.materials.iter().find(|m| m.name == "leaves").unwrap();
        assert_eq!(leaves.alpha_cutoff, Some(0.5), "{name}");
        assert!(leaves.double_sided && leaves.base_color_texture.is_some());
        // The bark's height is the species' (the mesh scaled to metres).
        let prims = &scene.meshes[0].primitives;
        let ys = prims[0].mesh.vertices.iter().map(|v| v.position[1]);
        let (lo, hi) = ys.fold((f32::MAX, f32::MIN), |(a, b), y| (a.min(y), b.max(y)));
        let h = hi - lo;
        assert!(
            (h - look.height).abs() <= 0.08 * look.height,
            "{name}: {h} m tall, expected {}",
            look.height
        );
        // Leaves: many, with unit normals, their uvs inside the atlas.
        let leaf = &prims[1].mesh;
        assert!(
            leaf.vertices.len() >= 4 * 500,
            "{name}: {} leaf vertices",
            leaf.vertices.len()
        );
        for v in &leaf.vertices {
            let n = v.normal;
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-3, "{name}: leaf normal {n:?}");
            assert!(
                v.uv.iter().all(|&t| (0.0..=1.0).contains(&t)),
                "{name}: uv {:?}",
                v.uv
            );
        }
        let path = tmp(&format!("{name}.glb"));
        arbor::export::save_gltf_scene(&scene, &options, &path).unwrap();
        files.push(path);
    }
    validator::assert_valid(&files);
}

#[test]
fn a_species_trunk_is_clear_below_its_crown() {
    let look = Look::of(Species::Oak).unwrap();
    let raw = arbor::source::Source::Growth(
        arbor::models::growth::GrowthParams::preset(Species::Oak),
        look.cycles,
    )
    .grow(2)
    .unwrap();
    let ys = raw.branches().iter().flat_map(|x| [x.start[1], x.end[1]]);
    let (base, top) = ys.fold((f32::MAX, f32::MIN), |(a, b), y| (a.min(y), b.max(y)));
    let clear = base + look.clear_trunk * (top - base);
    let tree = look.finish(&raw).unwrap();
    assert_eq!(tree, look.grow(2).unwrap());
    assert!(tree.len() < raw.len());
    let b = tree.branches();
    let mut above = 0;
    for x in b {
        if x.parent != arbor::skeleton::NO_PARENT && x.order > 0 && b[x.parent as usize].order == 0
        {
            assert!(
                x.start[1] >= clear,
                "a branch leaves the trunk at {} below {clear}",
                x.start[1]
            );
            above += 1;
        }
    }
    assert!(above > 0, "no branch left on the trunk");
}

#[test]
fn the_cli_exports_a_species_with_its_textures() {
    let out = tmp("cli_birch.glb");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_arbor"))
        .args(["export", "growth:birch", "--texture-size", "64", "-o"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let bytes = std::fs::read(&out).unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    assert_eq!(json["images"].as_array().unwrap().len(), 4);
    assert_eq!(json["materials"][1]["alphaMode"], "MASK");
    // The bark: colour, normal and roughness maps.
    let bark = &json["materials"][0];
    assert!(bark["normalTexture"]["index"].is_u64());
    assert!(bark["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"].is_u64());
    assert_eq!(json["images"][0]["mimeType"], "image/png");
    // A texture size out of range is refused before anything is written.
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_arbor"))
        .args(["export", "growth:birch", "--texture-size", "8", "-o"])
        .arg(tmp("bad.glb"))
        .output()
        .unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("size"));
}

/// Metres of bark per unit of uv of every bark triangle of `m` (the square root of the
/// ratio of its areas).
fn texel_sizes(m: &arbor::mesh::Mesh) -> Vec<f32> {
    let mut d = Vec::new();
    for t in m.indices.chunks_exact(3) {
        let p = |k: usize| glam::Vec3::from(m.vertices[t[k] as usize].position);
        let u = |k: usize| glam::Vec2::from(m.vertices[t[k] as usize].uv);
        let world = (p(1) - p(0)).cross(p(2) - p(0)).length();
        let (e1, e2) = (u(1) - u(0), u(2) - u(0));
        let uv = (e1.x * e2.y - e1.y * e2.x).abs();
        if uv > 1e-12 && world > 1e-12 {
            d.push((world / uv).sqrt());
        }
    }
    d
}

fn spread(mut d: Vec<f32>) -> (f32, f32) {
    d.sort_by(|a, b| a.total_cmp(b));
    let q = |f: f64| d[((d.len() - 1) as f64 * f) as usize];
    (q(0.1), q(0.9))
}

#[test]
fn bark_texels_are_of_one_size() {
    let (mut even, mut once) = (Vec::new(), Vec::new());
    for look in Look::all() {
        let skeleton = look.grow(1).unwrap();
        let (o, _) = arbor::species::options(&look, &skeleton, &MeshOptions::default()).unwrap();
        assert!(o.even_texels);
        let mesh = arbor::mesh::MeshPlan::new(&skeleton, &o)
            .unwrap()
            .mesh(&skeleton)
            .unwrap();
        let d = texel_sizes(&mesh);
        // Every bark triangle has texels: none (nearly) flat in uv, as a mirrored u turning
        // inside a side (an odd side count) would make it.
        let flat = d.iter().filter(|&&t| t > 10.0 * look.bark.tile).count();
        assert_eq!(flat, 0, "{:?}", look.species);
        let (p10, p90) = spread(d.clone());
        assert!(p90 / p10 <= 1.5, "{:?}: {p10}..{p90}", look.species);
        // About the tile (integer repeats round it by up to a factor √1.5).
        assert!(
            p10 > 0.6 * look.bark.tile && p90 < 1.3 * look.bark.tile,
            "{:?}",
            look.species
        );
        even.extend(d);
        let plain = arbor::mesh::MeshPlan::new(&skeleton, &o.even_texels(false)).unwrap();
        once.extend(texel_sizes(&plain.mesh(&skeleton).unwrap()));
    }
    let (p10, p90) = spread(even);
    eprintln!(
        "bark texel size, 10th to 90th percentile over every species: {p10:.3}..{p90:.3} m ({:.2}x)",
        p90 / p10
    );
    assert!(p90 / p10 <= 1.5, "every species: {p10}..{p90}");
    // Without it, u once around every branch: far from one size.
    let (q10, q90) = spread(once);
    eprintln!("with u once around each branch: {:.2}x", q90 / q10);
    assert!(q90 / q10 > 1.5, "{q10}..{q90}");
}

#[test]
fn even_texels_wrap_u_whole_or_mirrored_without_a_seam() {
    let look = Look::of(Species::Oak).unwrap();
    let skeleton = look.grow(4).unwrap();
    let (o, _) = arbor::species::options(&look, &skeleton, &MeshOptions::default()).unwrap();
    // Every branch with the same sides (no LOD), so each ring is radial_segments + 1.
    let o = o.min_radial_segments(0);
    let plan = arbor::mesh::MeshPlan::new(&skeleton, &o).unwrap();
    let mesh = plan.mesh(&skeleton).unwrap();
    let ring = o.radial_segments as usize + 1;
    let (mut whole, mut mirrored) = (0, 0);
    for r in plan.ranges() {
        let vs =
            &mesh.vertices[r.first_vertex as usize..(r.first_vertex + r.vertex_count) as usize];
        // Each of the branch's own rings: vertex 0 and the seam at the same place, their
        // u equal (mirrored) or a whole number apart.
        for ringv in vs.chunks_exact(ring).take(1) {
            let (u0, us) = (ringv[0].uv[0], ringv[ring - 1].uv[0]);
            assert_eq!(ringv[0].position, ringv[ring - 1].position);
            let gap = us - u0;
            assert!((gap - gap.round()).abs() < 1e-4, "u {u0} .. {us}");
            if gap.round() == 0.0 {
                mirrored += 1;
            } else {
                whole += 1;
            }
        }
    }
    assert!(
        whole > 0 && mirrored > 0,
        "{whole} whole, {mirrored} mirrored"
    );
}

#[test]
fn trunks_flare_and_roots_spread_into_the_ground() {
    let look = Look::of(Species::Oak).unwrap();
    assert!(look.flare > 1.0 && look.roots > 0);
    let raw = arbor::source::Source::Growth(
        arbor::models::growth::GrowthParams::preset(Species::Oak),
        look.cycles,
    )
    .grow(3)
    .unwrap();
    // The same tree without flare or roots.
    let cleared = Look {
        flare: 1.0,
        roots: 0,
        ..look
    }
    .finish(&raw)
    .unwrap();
    let tree = look.finish(&raw).unwrap();
    let trunk = |s: &arbor::skeleton::Skeleton| {
        s.branches()
            .iter()
            .find(|b| b.parent == arbor::skeleton::NO_PARENT)
            .map(|b| (b.start, b.start_radius))
            .unwrap()
    };
    let ((foot, r), (_, flared)) = (trunk(&cleared), trunk(&tree));
    assert!((flared / r - look.flare).abs() < 1e-4, "{flared} vs {r}");
    // Roots: chains of three from the foot, the last ends below the ground.
    let roots: Vec<_> = tree
        .branches()
        .iter()
        .enumerate()
        .filter(|(_, b)| b.parent == arbor::skeleton::NO_PARENT && b.order == 1)
        .collect();
    assert_eq!(roots.len(), look.roots as usize);
    for (i, b) in roots {
        let ends = &tree.branches()[i + 2];
        assert_eq!(ends.parent as usize, i + 1);
        assert!(ends.end[1] < foot[1] - r, "a root ends at {:?}", ends.end);
        let out = ((b.start[0] - foot[0]).powi(2) + (b.start[2] - foot[2]).powi(2)).sqrt();
        assert!(out < r, "a root starts {out} from the trunk's axis");
    }
    // Archetypes and the shrub keep their foot as grown.
    let shrub = Look::of(Species::Shrub).unwrap();
    assert_eq!((shrub.flare, shrub.roots), (1.0, 0));
}

#[test]
fn a_species_as_obj_with_its_materials_and_images() {
    let out = tmp("obj/willow.obj");
    std::fs::create_dir_all(out.parent().unwrap()).unwrap();
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_arbor"))
        .args(["export", "growth:willow", "--texture-size", "32", "-o"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let dir = out.parent().unwrap();
    let mtl = std::fs::read_to_string(dir.join("willow.mtl")).unwrap();
    for line in [
        "newmtl bark",
        "newmtl leaves",
        "map_Kd willow_bark.png",
        "map_Bump willow_bark_normal.png",
        "map_Pr willow_bark_roughness.png",
        "map_Kd willow_leaves.png",
        "map_d willow_leaves.png",
    ] {
        assert!(mtl.contains(line), "{line} not in\n{mtl}");
    }
    for png in [
        "willow_bark.png",
        "willow_bark_normal.png",
        "willow_bark_roughness.png",
        "willow_leaves.png",
    ] {
        let bytes = std::fs::read(dir.join(png)).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{png}");
    }
    let (models, materials) = tobj::load_obj(&out, &tobj::GPU_LOAD_OPTIONS).unwrap();
    let materials = materials.unwrap();
    assert_eq!(materials.len(), 2);
    assert_eq!(models.len(), 2);
    let leaves = models.iter().find(|m| m.name == "leaves").unwrap();
    let m = &materials[leaves.mesh.material_id.unwrap()];
    assert_eq!(m.name, "leaves");
    assert_eq!(m.diffuse_texture.as_deref(), Some("willow_leaves.png"));
    // The images are upside down for OBJ: the atlas' stem row (the top of a glTF image)
    // is the PNG's last row.
    let look = Look::of(Species::Willow).unwrap();
    let atlas = arbor::texture::leaf_atlas(&look.leaf, 32, 0).unwrap();
    let first_row = &atlas.image.pixels[..32 * 4];
    let decoded = decode_rgba(&std::fs::read(dir.join("willow_leaves.png")).unwrap());
    assert_eq!(&decoded[decoded.len() - 32 * 4..], first_row);
    // The roughness map, one channel for MTL: grey.
    let rough = decode_rgba(&std::fs::read(dir.join("willow_bark_roughness.png")).unwrap());
    assert!(rough.chunks_exact(4).all(|p| p[0] == p[1] && p[1] == p[2]));
    assert!(rough.chunks_exact(4).any(|p| p[1] != rough[1]));
}

/// The RGBA8 pixels of a PNG arbor wrote.
fn decode_rgba(bytes: &[u8]) -> Vec<u8> {
    let mut r = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    buf
}

/// Leaf vertices inside the wood of a branch thicker than a twig (radius above 3 cm), in
/// metres: each vertex against every such branch's truncated cone, found through a grid.
fn leaves_in_wood(
    skeleton: &arbor::skeleton::Skeleton,
    scale: f32,
    leaf: &arbor::mesh::Mesh,
) -> usize {
    use glam::Vec3;
    const TWIG: f32 = 0.03;
    let cell = 1.0f32;
    let key = |p: Vec3| (p / cell).floor().as_ivec3();
    let mut grid: std::collections::HashMap<glam::IVec3, Vec<usize>> = Default::default();
    let b = skeleton.branches();
    for (i, x) in b.iter().enumerate() {
        let r = x.start_radius.max(x.end_radius) * scale;
        if r <= TWIG {
            continue;
        }
        let (s, e) = (Vec3::from(x.start) * scale, Vec3::from(x.end) * scale);
        let (lo, hi) = (key(s.min(e) - r), key(s.max(e) + r));
        for z in lo.z..=hi.z {
            for y in lo.y..=hi.y {
                for xx in lo.x..=hi.x {
                    grid.entry(glam::IVec3::new(xx, y, z)).or_default().push(i);
                }
            }
        }
    }
    leaf.vertices
        .iter()
        .filter(|v| {
            let p = Vec3::from(v.position);
            grid.get(&key(p)).is_some_and(|near| {
                near.iter().any(|&i| {
                    let x = &b[i];
                    let (s, e) = (Vec3::from(x.start) * scale, Vec3::from(x.end) * scale);
                    let d = e - s;
                    let t = ((p - s).dot(d) / d.length_squared().max(1e-12)).clamp(0.0, 1.0);
                    let r = (x.start_radius + (x.end_radius - x.start_radius) * t) * scale;
                    // Inside by more than a centimetre (a card's edge may graze the bark).
                    (p - (s + d * t)).length() < r - 0.01
                })
            })
        })
        .count()
}

/// The side view (x, y) of a species' crown above its clear trunk on a 200-pixel grid:
/// the pixels its leaves cover (the atlas' alpha at each card's uv) over the pixels
/// inside its silhouette (leaves or wood, each row filled from its leftmost to its
/// rightmost pixel).
fn crown_coverage(scene: &arbor::scene::Scene, crown_base: f32) -> f64 {
    use glam::{Vec2, Vec3};
    const N: usize = 200;
    let prims = &scene.meshes[0].primitives;
    let (bark, leaf) = (&prims[0].mesh, &prims[1].mesh);
    let atlas = scene
        .textures
        .iter()
        .find(|t| t.name == "leaves")
        .expect("the atlas");
    let (lo, hi) = leaf
        .vertices
        .iter()
        .chain(&bark.vertices)
        .map(|v| Vec3::from(v.position))
        .filter(|p| p.y >= crown_base)
        .fold(
            (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN)),
            |(a, b), p| (a.min(p.truncate()), b.max(p.truncate())),
        );
    let size = (hi - lo).max_element();
    let px = |p: Vec3| (p.truncate() - lo) / size * (N - 1) as f32;
    let (mut leaves, mut any) = (vec![false; N * N], vec![false; N * N]);
    // Rasterise triangles by barycentric tests over their pixel boxes.
    let mut draw = |m: &arbor::mesh::Mesh, is_leaf: bool| {
        for t in m.indices.chunks_exact(3) {
            let v: Vec<_> = t.iter().map(|&k| &m.vertices[k as usize]).collect();
            if v.iter().all(|v| v.position[1] < crown_base) {
                continue;
            }
            let p: Vec<Vec2> = v.iter().map(|v| px(Vec3::from(v.position))).collect();
            let area = (p[1] - p[0]).perp_dot(p[2] - p[0]);
            let (a, b) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
            for y in (a.y.floor().max(0.0) as usize)..=(b.y.ceil() as usize).min(N - 1) {
                for x in (a.x.floor().max(0.0) as usize)..=(b.x.ceil() as usize).min(N - 1) {
                    let q = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                    let w0 = (p[2] - p[1]).perp_dot(q - p[1]) / area;
                    let w1 = (p[0] - p[2]).perp_dot(q - p[2]) / area;
                    let w2 = 1.0 - w0 - w1;
                    let inside = area.abs() > 1e-9 && w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0;
                    if !inside {
                        continue;
                    }
                    let k = y * N + x;
                    any[k] = true;
                    if is_leaf {
                        let uv = Vec2::from(v[0].uv) * w0
                            + Vec2::from(v[1].uv) * w1
                            + Vec2::from(v[2].uv) * w2;
                        let (ix, iy) = (
                            ((uv.x * atlas.image.width as f32) as u32).min(atlas.image.width - 1),
                            ((uv.y * atlas.image.height as f32) as u32).min(atlas.image.height - 1),
                        );
                        leaves[k] |= atlas.image.pixel(ix, iy)[3] >= 128;
                    }
                }
            }
        }
    };
    draw(leaf, true);
    draw(bark, false);
    let (mut covered, mut inside) = (0usize, 0usize);
    for y in 0..N {
        let row = &any[y * N..][..N];
        let (Some(a), Some(b)) = (row.iter().position(|&c| c), row.iter().rposition(|&c| c)) else {
            continue;
        };
        inside += b - a + 1;
        covered += leaves[y * N + a..=y * N + b].iter().filter(|&&c| c).count();
    }
    covered as f64 / inside.max(1) as f64
}

#[test]
fn leaves_stay_out_of_the_wood_and_cover_the_crown() {
    let options = arbor::export::gltf_mesh_options(&MeshOptions::default()).unwrap();
    let mut report = Vec::new();
    for look in Look::all() {
        let name = look.species.name();
        let skeleton = look.grow(1).unwrap();
        let scene = tree_scene(&look, &skeleton, &options, 256, 1).unwrap();
        let (o, _) = arbor::species::options(&look, &skeleton, &options).unwrap();
        let leaf = &scene.meshes[0].primitives[1].mesh;
        let inside = leaves_in_wood(&skeleton, o.scale, leaf);
        assert_eq!(inside, 0, "{name}: {inside} leaf vertices inside the wood");
        for v in &leaf.vertices {
            let n = glam::Vec3::from(v.normal);
            assert!((n.length() - 1.0).abs() < 1e-3, "{name}: leaf normal {n}");
        }
        if matches!(look.leaf.shape, arbor::texture::LeafShape::Needles) {
            continue;
        }
        let base = look.clear_trunk * look.height;
        let f = crown_coverage(&scene, base);
        report.push(format!("{name} {:.0}%", f * 100.0));
        assert!(
            f > 0.5,
            "{name}: leaves cover {:.0}% of the crown's silhouette",
            f * 100.0
        );
    }
    eprintln!("crown silhouette covered by leaves: {}", report.join(", "));
}

#[test]
fn leaf_cards_fold_and_face_the_light() {
    use arbor::mesh::{LeafPrefab, leaf_mesh};
    // The folded card: six vertices, four counter-clockwise triangles, unit normals, its
    // edges raised toward the face.
    let f = LeafPrefab::folded(40.0);
    assert_eq!((f.vertices.len(), f.triangles.len()), (6, 4));
    for t in &f.triangles {
        let p = |k: usize| glam::Vec3::from(f.vertices[t[k] as usize].position);
        let n = (p(1) - p(0)).cross(p(2) - p(0));
        assert!(n.z > 0.0, "{t:?}");
    }
    for v in &f.vertices {
        assert!((glam::Vec3::from(v.normal).length() - 1.0).abs() < 1e-5);
    }
    assert!(f.vertices[0].position[2] > 0.08 && f.vertices[1].position[2] == 0.0);
    // An oak's leaves, turned toward the light or at random: their faces look up more.
    let look = Look::of(Species::Oak).unwrap();
    let tree = look.grow(1).unwrap();
    let (o, leaves) = arbor::species::options(&look, &tree, &MeshOptions::default()).unwrap();
    assert!(leaves.face_light && leaves.fold > 0.0);
    let up = |lo: &arbor::mesh::LeafOptions| {
        let m = leaf_mesh(&tree, lo, &o).unwrap();
        m.vertices.iter().map(|v| v.normal[1]).sum::<f32>() / m.vertices.len() as f32
    };
    let (lit, random) = (up(&leaves), up(&leaves.clone().face_light(false)));
    eprintln!("mean leaf normal y: {lit:.2} facing the light, {random:.2} at random");
    assert!(lit > random + 0.2, "{lit} vs {random}");
    // Folded: 6 vertices a leaf, 4 without the fold (the same leaves: no wood test, which
    // sees the fold's raised edges).
    let all = leaves.clone().wood_clearance(0.0);
    let flat = leaf_mesh(&tree, &all.clone().fold(0.0), &o).unwrap();
    let folded = leaf_mesh(&tree, &all, &o).unwrap();
    assert_eq!(folded.vertices.len() * 4, flat.vertices.len() * 6);
}

#[test]
fn collision_capsules_in_the_file() {
    let mut files = Vec::new();
    for (source, name) in [("growth:oak", "col_oak.glb"), ("g", "col_g.gltf")] {
        let out = tmp(name);
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_arbor"))
            .args([
                "export",
                source,
                "--collision",
                "--texture-size",
                "64",
                "-o",
            ])
            .arg(&out)
            .status()
            .unwrap();
        if source == "g" {
            // --texture-size is for a named species only: refused.
            assert!(!status.success());
            let ok = std::process::Command::new(env!("CARGO_BIN_EXE_arbor"))
                .args(["export", source, "--collision", "--leaves", "-o"])
                .arg(&out)
                .status()
                .unwrap();
            assert!(ok.success());
        } else {
            assert!(status.success());
        }
        let json: serde_json::Value = if name.ends_with(".glb") {
            let bytes = std::fs::read(&out).unwrap();
            let n = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
            serde_json::from_slice(&bytes[20..20 + n]).unwrap()
        } else {
            serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap()
        };
        let nodes = json["nodes"].as_array().unwrap();
        let caps: Vec<_> = nodes
            .iter()
            .filter(|n| n["name"].as_str().unwrap().starts_with("UCP_tree_"))
            .collect();
        assert!(
            (2..=32).contains(&caps.len()),
            "{source}: {} capsules",
            caps.len()
        );
        for c in &caps {
            let e = &c["extras"]["arbor_capsule"];
            assert!(e["radius"].as_f64().unwrap() > 0.0, "{c}");
            assert_eq!(e["a"].as_array().unwrap().len(), 3);
            // Its mesh is the capsule's.
            assert!(c["mesh"].is_u64());
        }
        // Every node is in the scene.
        assert_eq!(
            json["scenes"][0]["nodes"].as_array().unwrap().len(),
            nodes.len()
        );
        files.push(out);
    }
    // OBJ has no nodes: refused.
    let obj = std::process::Command::new(env!("CARGO_BIN_EXE_arbor"))
        .args(["export", "g", "--collision", "-o"])
        .arg(tmp("col.obj"))
        .output()
        .unwrap();
    assert!(!obj.status.success());
    assert!(String::from_utf8_lossy(&obj.stderr).contains("--collision"));
    validator::assert_valid(&files);
}
