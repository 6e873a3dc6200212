//! Golden hashes of the vertex and index buffers of trees a–i and of every shipped
//! grammar: the output must stay byte-identical across runs, thread counts and the
//! `parallel` feature. An intended change of output regenerates `tests/golden/hashes.txt`
//! (`ARBOR_BLESS_GOLDEN=1 cargo test --test golden`) in the same commit, with the reason
//! in the commit message.

use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::mesh::{self, MeshOptions, Tip, Topology};
use arbor::models::honda::{self, HondaParams, PRESET_NAMES};
use arbor::progress::Run;
use arbor::skeleton::Skeleton;

/// FNV-1a, 64 bits.
fn fnv(bytes: &[u8], mut h: u64) -> u64 {
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x100_0000_01b3);
    }
    h
}

fn hash(s: &Skeleton) -> String {
    let options = [
        MeshOptions::default(),
        MeshOptions::default()
            .topology(Topology::TriangleStripRestart)
            .tip(Tip::Point)
            .smooth_taper(true)
            .base_cap(true)
            .radial_segments(5),
    ];
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for o in &options {
        let m = mesh::tubes(s, o).unwrap();
        h = fnv(bytemuck::cast_slice(&m.vertices), h);
        h = fnv(bytemuck::cast_slice(&m.indices), h);
    }
    h = fnv(bytemuck::cast_slice(s.branches()), h);
    format!("{h:016x}")
}

fn all() -> Vec<(String, Skeleton)> {
    let mut out: Vec<(String, Skeleton)> = PRESET_NAMES
        .iter()
        .map(|&n| {
            (
                format!("preset_{n}"),
                honda::build(&HondaParams::preset(n).unwrap()).unwrap(),
            )
        })
        .collect();
    // A larger tree (16,383 branches) beside the presets.
    let mut big = HondaParams::preset('a').unwrap();
    big.steps = 14;
    out.push(("preset_a_n14".to_string(), honda::build(&big).unwrap()));
    let dir = format!("{}/examples/grammars", env!("CARGO_MANIFEST_DIR"));
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "l"))
        .collect();
    paths.sort();
    for p in paths {
        let ls = LSystem::parse(&std::fs::read_to_string(&p).unwrap()).unwrap();
        let s = ls.skeleton(&LsystemOptions::default()).unwrap();
        out.push((p.file_stem().unwrap().to_string_lossy().into_owned(), s));
    }
    out
}

#[test]
fn buffers_match_their_golden_hashes() {
    check_golden("hashes.txt", hash);
}

/// Compares `hash` of every skeleton with `tests/golden/FILE` (a line per skeleton), or
/// writes the file when `ARBOR_BLESS_GOLDEN` is set.
fn check_golden(file: &str, hash: fn(&Skeleton) -> String) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(file);
    let text: String = all()
        .iter()
        .map(|(name, s)| format!("{name} {}\n", hash(s)))
        .collect();
    if std::env::var_os("ARBOR_BLESS_GOLDEN").is_some() {
        std::fs::write(&path, &text).unwrap();
    }
    let golden = std::fs::read_to_string(&path).unwrap_or_default();
    for (got, want) in text.lines().zip(golden.lines()) {
        assert_eq!(
            got, want,
            "{file}: output changed; if intended, bless and say why"
        );
    }
    assert_eq!(text.lines().count(), golden.lines().count(), "{file}");
}

#[test]
fn hashes_are_the_same_on_other_threads() {
    let here: Vec<String> = all().iter().map(|(_, s)| hash(s)).collect();
    let threads: Vec<_> = (0..2)
        .map(|_| std::thread::spawn(|| all().iter().map(|(_, s)| hash(s)).collect::<Vec<_>>()))
        .collect();
    for t in threads {
        assert_eq!(t.join().unwrap(), here);
    }
}

/// A write split across threads (65,535 branches: up to four chunks of 16,384) is the
/// same, byte for byte, as the write on the calling thread alone, in every topology and
/// with the plan reused.
#[test]
fn threaded_writes_equal_the_single_thread_write() {
    let mut p = HondaParams::preset('a').unwrap();
    p.steps = 16;
    let s = honda::build(&p).unwrap();
    for topology in Topology::ALL {
        for tip in [Tip::Open, Tip::Point] {
            let one = MeshOptions::default().topology(topology).tip(tip);
            let want = tubes_on(&s, &one, 1);
            for threads in [2, 3, 4, 0] {
                let run = || Run::default().threads(threads);
                let plan = mesh::MeshPlan::new_in(&s, &one, &run()).unwrap();
                for _ in 0..2 {
                    let got = plan.mesh_in(&s, &mut run()).unwrap();
                    assert!(
                        got.vertices == want.vertices && got.indices == want.indices,
                        "{topology:?} {tip:?} with {threads} threads"
                    );
                }
            }
        }
    }
    // A sweep's texture v comes with its frames, a straight tree's with the offsets: both
    // plans split across threads as they are made.
    for rings in [0, 2] {
        let one = MeshOptions::default().curve_rings(rings);
        let want = tubes_on(&s, &one, 1);
        let got = tubes_on(&s, &one, 2);
        assert!(
            got.vertices == want.vertices
                && got.indices == want.indices
                && got.ranges == want.ranges,
            "{rings} curve rings"
        );
    }
}

/// `s`'s branches in breadth-first order (each generation after the one before, parents
/// still before children), with a turtle up vector per branch: a plan cut in two parts
/// must then work out many earlier ring frames and v itself.
fn breadth_first_with_ups(s: &Skeleton) -> Skeleton {
    let b = s.branches();
    let mut depth = vec![0u32; b.len()];
    for i in 0..b.len() {
        if b[i].parent != arbor::skeleton::NO_PARENT {
            depth[i] = depth[b[i].parent as usize] + 1;
        }
    }
    let mut order: Vec<usize> = (0..b.len()).collect();
    order.sort_by_key(|&i| (depth[i], i));
    let mut new_index = vec![0u32; b.len()];
    for (k, &i) in order.iter().enumerate() {
        new_index[i] = k as u32;
    }
    let branches = order
        .iter()
        .map(|&i| {
            let mut x = b[i];
            if x.parent != arbor::skeleton::NO_PARENT {
                x.parent = new_index[x.parent as usize];
            }
            x
        })
        .collect();
    let ups = order
        .iter()
        .map(|&i| {
            let a = i as f32 * 0.37;
            [a.cos(), 0.3 * a.sin(), a.sin()]
        })
        .collect();
    arbor::skeleton::SkeletonParts {
        branches,
        ups,
        ..Default::default()
    }
    .build()
    .unwrap()
}

/// Plans made on two threads (the branches cut in two parts) equal the plan made on one,
/// whatever the branch order, with culled and thinned branches and with a first part that
/// keeps no branch at all.
#[test]
fn split_plans_equal_the_one_thread_plan_in_any_branch_order() {
    let mut p = HondaParams::preset('a').unwrap();
    p.steps = 16;
    let depth_first = honda::build(&p).unwrap();
    let breadth_first = breadth_first_with_ups(&depth_first);
    // Two trees: the first (half the branches) thin enough to be culled whole.
    let two = {
        let mut thin = depth_first.branches().to_vec();
        for b in &mut thin {
            b.start_radius *= 1e-3;
            b.end_radius *= 1e-3;
        }
        let k = thin.len() as u32;
        thin.extend(depth_first.branches().iter().map(|b| {
            let mut b = *b;
            if b.parent != arbor::skeleton::NO_PARENT {
                b.parent += k;
            }
            b.start[0] += 500.0;
            b.end[0] += 500.0;
            b
        }));
        Skeleton::new(thin).unwrap()
    };
    // Every seventh branch thin enough to be culled, with the subtree it carries, however
    // thick: kept or not is decided along the parents.
    let gaps = {
        let mut parts = breadth_first.clone().into_parts();
        for b in parts.branches.iter_mut().step_by(7) {
            b.start_radius *= 1e-3;
            b.end_radius *= 1e-3;
        }
        parts.build().unwrap()
    };
    let r = depth_first.branches()[0].start_radius;
    let options = [
        MeshOptions::default(),
        MeshOptions::default()
            .topology(Topology::TriangleStripRestart)
            .tip(Tip::Point)
            .base_cap(true)
            .cull_radius(r * 0.05),
        MeshOptions::default()
            .radial_segments(12)
            .min_radial_segments(3)
            .joints(mesh::Joints::Mitred),
    ];
    for (name, s) in [
        ("depth first", &depth_first),
        ("breadth first", &breadth_first),
        ("first tree culled", &two),
        ("thin branches culled", &gaps),
    ] {
        assert!(s.len() >= 65_535);
        for (k, o) in options.iter().enumerate() {
            let o = match name {
                "first tree culled" => o.cull_radius(r * 0.01),
                "thin branches culled" => o.cull_radius(r * 1e-4),
                _ => *o,
            };
            let want = tubes_on(s, &o, 1);
            assert!(!want.indices.is_empty(), "{name}, options {k}");
            let got = tubes_on(s, &o, 2);
            assert!(
                got.vertices == want.vertices
                    && got.indices == want.indices
                    && got.ranges == want.ranges,
                "{name}, options {k}"
            );
        }
    }
}

/// The hash of the swept mesh (curve rings, mitred joints, caps) and of the leaf mesh
/// (tip leaves, leaf sites, polygons and organs) of `s`.
fn swept_and_leaves_hash(s: &Skeleton) -> String {
    let swept = MeshOptions::default()
        .curve_rings(3)
        .joints(mesh::Joints::Mitred)
        .tip(Tip::Cap)
        .base_cap(true);
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for tip in [Tip::Cap, Tip::Point] {
        let m = mesh::tubes(s, &swept.tip(tip)).unwrap();
        h = fnv(bytemuck::cast_slice(&m.vertices), h);
        h = fnv(bytemuck::cast_slice(&m.indices), h);
    }
    let leaves = mesh::LeafOptions::default()
        .tips(true)
        .sites(true)
        .polygons(true)
        .size_jitter(0.2)
        .rotation_jitter(30.0)
        .seed(7);
    let m = mesh::leaf_mesh(s, &leaves, &MeshOptions::default()).unwrap();
    h = fnv(bytemuck::cast_slice(&m.vertices), h);
    h = fnv(bytemuck::cast_slice(&m.indices), h);
    format!("{h:016x}")
}

/// Swept branches and leaf meshes stay byte-identical too (`tests/golden/swept_leaves.txt`,
/// blessed as the hashes above).
#[test]
fn swept_and_leaf_buffers_match_their_golden_hashes() {
    check_golden("swept_leaves.txt", swept_and_leaves_hash);
}

/// The hash of the vertices and of the triangles as a set (each rotated to start at its
/// least index, which keeps its winding; then sorted), in every topology and winding, with
/// caps, tips and swept rings: what the mesh draws, whatever order its triangles come in.
fn triangle_set_hash(s: &Skeleton) -> String {
    let base = MeshOptions::default();
    let options = [
        base,
        base.winding(mesh::Winding::Clockwise).tip(Tip::Point),
        base.topology(Topology::TriangleStripRestart)
            .tip(Tip::Cap)
            .base_cap(true),
        base.topology(Topology::TriangleStripDegenerate)
            .winding(mesh::Winding::Clockwise)
            .radial_segments(5),
        base.curve_rings(2).tip(Tip::Point),
    ];
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for o in &options {
        let m = mesh::tubes(s, o).unwrap();
        h = fnv(bytemuck::cast_slice(&m.vertices), h);
        let mut triangles: Vec<[u32; 3]> = mesh::Triangles::new(&m.indices, o.topology)
            .map(|t| {
                let k = (0..3).min_by_key(|&k| t[k]).unwrap();
                [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
            })
            .collect();
        triangles.sort_unstable();
        h = fnv(bytemuck::cast_slice(&triangles), h);
    }
    format!("{h:016x}")
}

/// The triangles as a set and the vertices stay the same when the order of the triangles
/// changes (`tests/golden/triangle_sets.txt`): a vertex-cache order draws the same mesh.
#[test]
fn triangle_sets_match_their_golden_hashes() {
    check_golden("triangle_sets.txt", triangle_set_hash);
}

/// The tube mesh of `s` planned and written on `threads` threads.
fn tubes_on(s: &arbor::Skeleton, o: &MeshOptions, threads: u32) -> arbor::Mesh {
    let run = || Run::default().threads(threads);
    let plan = mesh::MeshPlan::new_in(s, o, &run()).unwrap();
    plan.mesh_in(s, &mut run()).unwrap()
}
