//! The game asset: `arbor export ... --game` writes levels of detail (MSFT_lod and
//! MSFT_screencoverage, nodes NAME_LOD0...), the impostor's atlases or a billboard level,
//! and collision capsules, and the Khronos validator finds nothing wrong with it.

#[path = "common/validator.rs"]
mod validator;

use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("game");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn export(args: &[&str], out: &PathBuf) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_arbor"))
        .arg("export")
        .args(args)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap()
}

fn json_of(path: &PathBuf) -> serde_json::Value {
    let bytes = std::fs::read(path).unwrap();
    let n = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&bytes[20..20 + n]).unwrap()
}

#[test]
fn a_game_asset_has_its_levels_impostor_and_capsules() {
    let oak = tmp("oak.glb");
    let r = export(&["growth:oak", "--game", "--texture-size", "128"], &oak);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let j = json_of(&oak);
    let nodes = j["nodes"].as_array().unwrap();
    let names: Vec<&str> = nodes.iter().map(|n| n["name"].as_str().unwrap()).collect();
    for k in 0..4 {
        assert!(
            names.contains(&format!("tree_LOD{k}").as_str()),
            "{names:?}"
        );
    }
    let first = &nodes[names.iter().position(|n| *n == "tree_LOD0").unwrap()];
    let ids = first["extensions"]["MSFT_lod"]["ids"].as_array().unwrap();
    assert_eq!(ids.len(), 3);
    for (k, id) in ids.iter().enumerate() {
        assert_eq!(
            nodes[id.as_u64().unwrap() as usize]["name"],
            format!("tree_LOD{}", k + 1)
        );
    }
    let coverage: Vec<f64> = first["extras"]["MSFT_screencoverage"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap())
        .collect();
    assert_eq!(coverage.len(), 4);
    assert!(coverage.windows(2).all(|w| w[1] <= w[0]), "{coverage:?}");
    assert!(
        j["extensionsUsed"]
            .as_array()
            .unwrap()
            .iter()
            .any(|e| e == "MSFT_lod")
    );
    // The impostor's atlases and how to read them.
    let imp = &first["extras"]["arbor_impostor"];
    assert_eq!(imp["frames"], 12);
    assert_eq!(imp["hemi"], true);
    let textures = j["textures"].as_array().unwrap();
    for key in ["albedo_texture", "normal_texture"] {
        let t = imp[key].as_u64().unwrap() as usize;
        assert!(
            textures[t]["name"]
                .as_str()
                .unwrap()
                .starts_with("impostor")
        );
    }
    // Capsules, named for the tree.
    assert!(names.iter().filter(|n| n.starts_with("UCP_tree_")).count() >= 2);
    // Each level has fewer triangles than the one before, read back by the gltf crate.
    let g = gltf::Gltf::from_slice(&std::fs::read(&oak).unwrap()).unwrap();
    let blob = g.blob.clone().unwrap();
    let tris = |name: &str| -> usize {
        let at = names.iter().position(|n| *n == name).unwrap();
        let node = g.nodes().nth(at).unwrap();
        node.mesh()
            .unwrap()
            .primitives()
            .map(|p| {
                let r = p.reader(|_| Some(&blob[..]));
                r.read_indices().unwrap().into_u32().count() / 3
            })
            .sum()
    };
    let counts: Vec<usize> = (0..4).map(|k| tris(&format!("tree_LOD{k}"))).collect();
    assert!(counts.windows(2).all(|w| w[1] < w[0]), "{counts:?}");
    assert!(
        counts[1] as f64 <= 0.4 * counts[0] as f64 * 1.05,
        "{counts:?}"
    );
    // A billboard as the last level of a 1996 tree, and the impostor refused for OBJ.
    let e = tmp("e.glb");
    let r = export(
        &["e", "--leaves", "--lod", "3", "--impostor", "billboard"],
        &e,
    );
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let j = json_of(&e);
    let names: Vec<String> = j["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["name"].as_str().unwrap().to_string())
        .collect();
    assert!(names.contains(&"tree_LOD3".to_string()), "{names:?}");
    assert!(
        j["materials"]
            .as_array()
            .unwrap()
            .iter()
            .any(|m| m["name"] == "billboard")
    );
    // Godot's names for the capsules.
    let godot = tmp("e_godot.glb");
    let r = export(&["e", "--leaves", "--collision=godot"], &godot);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let j = json_of(&godot);
    let cols: Vec<&str> = j["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["name"].as_str().unwrap())
        .filter(|n| n.ends_with("-convcolonly"))
        .collect();
    assert!(
        cols.len() >= 2 && cols[0] == "tree_col_00-convcolonly",
        "{cols:?}"
    );
    // Every level rides one skin, and a level's vertex the bone its place in the full tree
    // rides.
    levels_share_the_skin(&oak);
    let attributes = export(&["e", "--game", "--wind", "attributes"], &tmp("e_attr.glb"));
    assert!(!attributes.status.success());
    assert!(String::from_utf8_lossy(&attributes.stderr).contains("--wind skin"));
    let obj = export(&["e", "--game"], &tmp("e.obj"));
    assert!(!obj.status.success());
    assert!(String::from_utf8_lossy(&obj.stderr).contains("for glTF"));
    let bad = export(&["e", "--lod", "9"], &tmp("bad.glb"));
    assert!(!bad.status.success());
    validator::assert_valid(&[oak, e, godot]);
}

/// Each `tree_LODk` node of `path` has the one skin; every vertex's weights sum to one;
/// a sample of each lower level's bark vertices mostly ride the bone (the heaviest) of
/// the full tree's bark vertex nearest them.
fn levels_share_the_skin(path: &PathBuf) {
    let g = gltf::Gltf::from_slice(&std::fs::read(path).unwrap()).unwrap();
    let blob = g.blob.clone().unwrap();
    assert_eq!(g.skins().count(), 1);
    assert_eq!(g.animations().count(), 1);
    let j = json_of(path);
    let names: Vec<&str> = j["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["name"].as_str().unwrap())
        .collect();
    let bark_of = |k: usize| -> Vec<([f32; 3], u16)> {
        let at = names
            .iter()
            .position(|n| *n == format!("tree_LOD{k}"))
            .unwrap();
        let node = g.nodes().nth(at).unwrap();
        assert_eq!(node.skin().map(|s| s.index()), Some(0), "tree_LOD{k}");
        let mut bark = Vec::new();
        for (i, p) in node.mesh().unwrap().primitives().enumerate() {
            let r = p.reader(|_| Some(&blob[..]));
            let w: Vec<[f32; 4]> = r.read_weights(0).unwrap().into_f32().collect();
            let j: Vec<[u16; 4]> = r.read_joints(0).unwrap().into_u16().collect();
            let pos: Vec<[f32; 3]> = r.read_positions().unwrap().collect();
            assert_eq!(w.len(), pos.len());
            for w in &w {
                assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-4, "{w:?}");
            }
            if i == 0 {
                for ((p, w), j) in pos.iter().zip(&w).zip(&j) {
                    let top = (0..4).max_by(|&a, &b| w[a].total_cmp(&w[b])).unwrap();
                    bark.push((*p, j[top]));
                }
            }
        }
        bark
    };
    let full = bark_of(0);
    for k in 1..4 {
        let level = bark_of(k);
        let step = (level.len() / 300).max(1);
        let (mut same, mut n) = (0, 0);
        for &(p, b) in level.iter().step_by(step) {
            let d = |q: [f32; 3]| (0..3).map(|i| (p[i] - q[i]).powi(2)).sum::<f32>();
            let nearest = full
                .iter()
                .min_by(|x, y| d(x.0).total_cmp(&d(y.0)))
                .unwrap();
            same += usize::from(nearest.1 == b);
            n += 1;
        }
        assert!(
            same as f32 >= 0.85 * n as f32,
            "level {k}: {same} of {n} vertices on the full tree's bone"
        );
    }
}

#[test]
fn a_skinned_tree_sways_in_a_loop() {
    let oak = tmp("oak_wind.glb");
    let r = export(
        &["growth:oak", "--wind", "skin", "--texture-size", "64"],
        &oak,
    );
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let e = tmp("e_wind.glb");
    let r = export(&["e", "--leaves", "--wind", "skin", "--collision"], &e);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    for path in [&oak, &e] {
        let g = gltf::Gltf::from_slice(&std::fs::read(path).unwrap()).unwrap();
        let blob = g.blob.clone().unwrap();
        let skin = g.skins().next().expect("a skin");
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        assert!((5..=32).contains(&joints.len()), "{} joints", joints.len());
        // Every vertex's weights sum to one; every bone moves some vertex.
        let tree = g.nodes().next().unwrap();
        assert_eq!(tree.skin().unwrap().index(), 0);
        let mut used = vec![false; joints.len()];
        for p in tree.mesh().unwrap().primitives() {
            let reader = p.reader(|_| Some(&blob[..]));
            let w: Vec<[f32; 4]> = reader.read_weights(0).unwrap().into_f32().collect();
            let j: Vec<[u16; 4]> = reader.read_joints(0).unwrap().into_u16().collect();
            assert_eq!(w.len(), j.len());
            for (w, j) in w.iter().zip(&j) {
                assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-4, "{w:?}");
                for (&x, &b) in w.iter().zip(j) {
                    if x > 0.0 {
                        used[b as usize] = true;
                    }
                }
            }
        }
        assert!(used.iter().all(|&u| u), "{used:?}");
        // One clip: a rotation channel per bone, its last key its first.
        let anim = g.animations().next().expect("a clip");
        assert_eq!(anim.channels().count(), joints.len());
        for ch in anim.channels() {
            assert!(joints.contains(&ch.target().node().index()));
            let reader = ch.reader(|_| Some(&blob[..]));
            let times: Vec<f32> = reader.read_inputs().unwrap().collect();
            assert_eq!(times[0], 0.0);
            assert!((times.last().unwrap() - 4.0).abs() < 1e-6);
            let rot: Vec<[f32; 4]> = match reader.read_outputs().unwrap() {
                gltf::animation::util::ReadOutputs::Rotations(r) => r.into_f32().collect(),
                _ => panic!("rotations"),
            };
            let (a, b) = (rot[0], *rot.last().unwrap());
            let dot: f32 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            assert!(dot.abs() > 1.0 - 1e-6, "{a:?} {b:?}");
        }
    }
    validator::assert_valid(&[oak, e]);
}

#[test]
fn wind_attributes_in_standard_attributes() {
    let e = tmp("e_attr.glb");
    let r = export(&["e", "--leaves", "--wind", "attributes"], &e);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let g = gltf::Gltf::from_slice(&std::fs::read(&e).unwrap()).unwrap();
    let blob = g.blob.clone().unwrap();
    let tree = g.nodes().next().unwrap();
    let prims: Vec<_> = tree.mesh().unwrap().primitives().collect();
    assert_eq!(prims.len(), 2, "bark and leaves");
    for (k, p) in prims.iter().enumerate() {
        let reader = p.reader(|_| Some(&blob[..]));
        let n = reader.read_positions().unwrap().count();
        let colors: Vec<[u8; 4]> = reader.read_colors(0).unwrap().into_rgba_u8().collect();
        let uv1: Vec<[f32; 2]> = reader.read_tex_coords(1).unwrap().into_f32().collect();
        assert_eq!((colors.len(), uv1.len()), (n, n));
        // Phases vary; stiffness and along are in range.
        assert!(colors.iter().any(|c| c[0] != colors[0][0]));
        assert!(
            uv1.iter()
                .all(|u| (0.0..=1.0).contains(&u[0]) && (0.0..=1.0).contains(&u[1]))
        );
        let flutter: Vec<u8> = colors.iter().map(|c| c[3]).collect();
        if k == 0 {
            // Bark does not flutter; the trunk's base is the stiffest wood.
            assert!(flutter.iter().all(|&f| f == 0));
            assert!(colors.iter().any(|c| c[1] == 255));
        } else {
            // A leaf card flutters from none at its stem to all at its tip.
            assert!(
                flutter.contains(&0) && flutter.contains(&255),
                "{flutter:?}"
            );
        }
    }
    let lod = export(
        &["e", "--leaves", "--wind", "attributes", "--lod", "2"],
        &tmp("no.glb"),
    );
    assert!(!lod.status.success());
    validator::assert_valid(&[e]);
}
