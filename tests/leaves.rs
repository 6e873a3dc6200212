//! Leaf placement, instance data and the baked leaf mesh.

use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::mesh::{
    self, LeafInstance, LeafOptions, LeafPrefab, MeshOptions, Topology, UpAxis, Vertex, Winding,
};
use arbor::models::honda::{self, HondaParams};
use arbor::skeleton::Skeleton;
use glam::{Quat, Vec3};

fn tree(name: char) -> Skeleton {
    honda::build(&HondaParams::preset(name).unwrap()).unwrap()
}

fn grammar(text: &str) -> Skeleton {
    LSystem::parse(text)
        .unwrap()
        .skeleton(&LsystemOptions::default())
        .unwrap()
}

fn terminal_branches(s: &Skeleton, min_birth: u32) -> usize {
    let b = s.branches();
    let mut inner = vec![false; b.len()];
    for x in b {
        if !x.is_root() {
            inner[x.parent as usize] = true;
        }
    }
    b.iter()
        .zip(&inner)
        .filter(|(x, i)| !**i && x.birth >= min_birth)
        .count()
}

fn tips(density: f32, min_birth: u32, seed: u64) -> LeafOptions {
    LeafOptions::default()
        .tips(true)
        .density(density)
        .min_birth(min_birth)
        .seed(seed)
        .size(5.0)
}

#[test]
fn tip_leaves_sit_on_the_outer_levels() {
    let s = tree('a');
    let m = MeshOptions::default();
    for (density, depth) in [(1.0, 0), (3.0, 0), (2.0, 10), (1.0, 11)] {
        let l = mesh::leaf_instances(&s, &tips(density, depth, 1), &m).unwrap();
        assert_eq!(l.len(), terminal_branches(&s, depth) * density as usize);
    }
    // A fractional density gives each tip the whole part and the fraction by chance.
    let n = terminal_branches(&s, 0);
    let l = mesh::leaf_instances(&s, &tips(1.5, 0, 7), &m).unwrap();
    assert!(
        l.len() > n + n / 3 && l.len() < n + 2 * n / 3,
        "{} for {n} tips",
        l.len()
    );
    // Every tip leaf stands at the end of a terminal branch.
    let ends: Vec<[f32; 3]> = s.branches().iter().map(|b| b.end).collect();
    for leaf in &l {
        assert!(ends.contains(&leaf.position));
    }
}

#[test]
fn leaves_are_seeded_and_vary_within_their_ranges() {
    let s = tree('g');
    let m = MeshOptions::default();
    let a = mesh::leaf_instances(&s, &tips(2.0, 0, 3), &m).unwrap();
    let b = mesh::leaf_instances(&s, &tips(2.0, 0, 3), &m).unwrap();
    let c = mesh::leaf_instances(&s, &tips(2.0, 0, 4), &m).unwrap();
    assert_eq!(a, b);
    assert_ne!(a, c);
    for leaf in &a {
        let q = Quat::from_array(leaf.rotation);
        assert!((q.length() - 1.0).abs() < 1e-5);
        assert!(leaf.scale >= 5.0 * 0.8 - 1e-4 && leaf.scale <= 5.0 * 1.2 + 1e-4);
    }
    let scales: std::collections::HashSet<u32> = a.iter().map(|l| l.scale.to_bits()).collect();
    assert!(scales.len() > a.len() / 2, "sizes vary");
}

#[test]
fn site_leaves_follow_the_turtle() {
    let s = grammar("angle increment: 90\nAxiom: F[+F~]F~");
    assert_eq!(s.leaves().len(), 2);
    let o = LeafOptions::default().rotation_jitter(0.0).size_jitter(0.0);
    let l = mesh::leaf_instances(&s, &o, &MeshOptions::default()).unwrap();
    assert_eq!(l.len(), 2);
    for (leaf, site) in l.iter().zip(s.leaves()) {
        assert_eq!(leaf.position, site.position);
        let q = Quat::from_array(leaf.rotation);
        let along = q * Vec3::Y;
        let face = q * Vec3::Z;
        assert!(along.abs_diff_eq(Vec3::from(site.heading), 1e-5), "{along}");
        assert!(face.abs_diff_eq(Vec3::from(site.up), 1e-5), "{face}");
        assert_eq!(leaf.scale, 1.0);
    }
}

fn decoded(m: &arbor::Mesh) -> Vec<[u32; 3]> {
    m.triangles()
        .map(|[a, b, c]| {
            let k = [a, b, c];
            let i = (0..3).min_by_key(|&i| k[i]).unwrap();
            [k[i], k[(i + 1) % 3], k[(i + 2) % 3]]
        })
        .collect()
}

#[test]
fn baked_leaves_match_the_instances_in_every_topology() {
    let s = grammar("angle increment: 60\nAxiom: F[+F~][-F~]F[{.+f.+f.+f.}]~");
    let o = LeafOptions::default().tips(true);
    for up_axis in [UpAxis::Y, UpAxis::Z] {
        let m = MeshOptions::default().up_axis(up_axis).scale(2.0);
        let instances = mesh::leaf_instances(&s, &o, &m).unwrap();
        let leaves = mesh::leaf_mesh(&s, &o, &m).unwrap();
        let polygon_points: usize = s.polygons().iter().map(|p| p.count as usize).sum();
        assert_eq!(leaves.vertices.len(), instances.len() * 4 + polygon_points);
        let polygon_tris: usize = s.polygons().iter().map(|p| p.count as usize - 2).sum();
        assert_eq!(
            leaves.triangles().count(),
            instances.len() * 2 + polygon_tris
        );
        // Each baked quad is its instance's transform of the unit quad.
        let quad = LeafPrefab::quad();
        for (k, leaf) in instances.iter().enumerate() {
            let q = Quat::from_array(leaf.rotation);
            for (j, v) in quad.vertices.iter().enumerate() {
                let want = Vec3::from(leaf.position) + q * (Vec3::from(v.position) * leaf.scale);
                let got = Vec3::from(leaves.vertices[4 * k + j].position);
                assert!(
                    got.abs_diff_eq(want, 1e-4),
                    "leaf {k} corner {j}: {got} vs {want}"
                );
            }
        }
        let list = decoded(&leaves);
        for topology in [
            Topology::TriangleStripRestart,
            Topology::TriangleStripDegenerate,
        ] {
            let strips = mesh::leaf_mesh(&s, &o, &m.topology(topology)).unwrap();
            assert_eq!(strips.vertices, leaves.vertices);
            assert_eq!(decoded(&strips), list, "{topology:?}");
            let size = mesh::leaf_mesh_size(&s, &o, &m.topology(topology)).unwrap();
            assert_eq!(size.indices, strips.indices.len());
        }
        let cw = mesh::leaf_mesh(&s, &o, &m.winding(Winding::Clockwise)).unwrap();
        let flipped: Vec<[u32; 3]> = leaves.triangles().map(|[a, b, c]| [a, c, b]).collect();
        assert_eq!(cw.triangles().collect::<Vec<_>>(), flipped);
        for v in &leaves.vertices {
            assert!((Vec3::from(v.normal).length() - 1.0).abs() < 1e-4);
        }
        // Faces agree with their normals.
        for [a, b, c] in leaves.triangles() {
            let p = |i: u32| Vec3::from(leaves.vertices[i as usize].position);
            let face = (p(b) - p(a)).cross(p(c) - p(a)).normalize();
            assert!(face.dot(Vec3::from(leaves.vertices[a as usize].normal)) > 0.9);
        }
    }
}

#[test]
fn a_prefab_from_an_obj_file_is_baked_per_leaf() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let path = dir.join("blades.obj");
    // Three blades of grass around the stem.
    std::fs::write(
        &path,
        "v -0.05 0 0\nv 0.05 0 0\nv 0 1 0\nv 0 0 -0.05\nv 0 0 0.05\nv 0.2 0.9 0\n\
         v -0.05 0 0.02\nv 0.05 0 -0.02\nv -0.2 0.8 0.1\nvt 0 0\nvt 1 0\nvt 0.5 1\n\
         f 1/1 2/2 3/3\nf 4/1 5/2 6/3\nf 7/1 8/2 9/3\n",
    )
    .unwrap();
    let prefab = LeafPrefab::from_obj(&path).unwrap();
    assert_eq!(prefab.triangles.len(), 3);
    let s = tree('c');
    let o = LeafOptions::default()
        .tips(true)
        .prefab(Some(std::sync::Arc::new(prefab.clone())));
    let m = MeshOptions::default();
    let n = mesh::leaf_instances(&s, &o, &m).unwrap().len();
    let baked = mesh::leaf_mesh(&s, &o, &m).unwrap();
    assert_eq!(baked.vertices.len(), n * prefab.vertices.len());
    assert_eq!(baked.triangles().count(), n * 3);
    assert!(LeafPrefab::from_obj(dir.join("missing.obj")).is_err());
}

#[test]
fn bad_leaf_options_name_their_field() {
    let s = tree('a');
    let m = MeshOptions::default();
    for (field, o) in [
        ("density", LeafOptions::default().density(-1.0)),
        ("density", LeafOptions::default().density(f32::NAN)),
        ("size", LeafOptions::default().size(0.0)),
        ("size_jitter", LeafOptions::default().size_jitter(1.0)),
        (
            "rotation_jitter",
            LeafOptions::default().rotation_jitter(f32::INFINITY),
        ),
    ] {
        match mesh::leaf_instances(&s, &o, &m) {
            Err(arbor::Error::InvalidArgument { field: f, .. }) => assert_eq!(f, field),
            other => panic!("{field}: {other:?}"),
        }
    }
    let sizes = std::mem::size_of::<LeafInstance>();
    assert_eq!(sizes, 32);
    let _ = Vertex::default();
}

/// Leaves go only on branches the mesh keeps: with `cull_radius`, no site or tip leaf
/// floats where its twig was dropped, and the new ends of the culled tree get tip leaves.
#[test]
fn leaves_sit_only_on_kept_branches() {
    // Every internode of a thinning binary tree ends in a `~` site.
    let s = grammar(
        "derivation length: 7\nAxiom: A(10,2)\n\
         A(l,w) --> !(w)F(l)~[+(30)A(l*0.7,w*0.6)][-(30)A(l*0.7,w*0.6)]",
    );
    let full = MeshOptions::default();
    let culled = MeshOptions::default().cull_radius(0.3);
    let ranges = mesh::branch_ranges(&s, &culled).unwrap();
    let kept = |b: u32| ranges[b as usize].vertex_count > 0;
    assert!(
        ranges.iter().any(|r| r.vertex_count == 0),
        "some twigs are culled"
    );
    let sites = LeafOptions::default().tips(false);
    let all = mesh::leaf_instances(&s, &sites, &full).unwrap();
    assert_eq!(all.len(), s.leaves().len());
    let some = mesh::leaf_instances(&s, &sites, &culled).unwrap();
    let on_kept = s.leaves().iter().filter(|l| kept(l.branch)).count();
    assert!(on_kept < s.leaves().len());
    assert_eq!(some.len(), on_kept, "sites of culled twigs are dropped");
    // Tip leaves: at the kept branches whose children were all culled.
    let leaves = tips(1.0, 0, 3);
    let at_tips = mesh::leaf_instances(&s, &leaves.clone().sites(false), &culled).unwrap();
    let new_tips = (0..s.len())
        .filter(|&i| kept(i as u32) && !s.adjacency().children(i).iter().any(|&c| kept(c)))
        .count();
    assert_eq!(at_tips.len(), new_tips);
    for l in &at_tips {
        let p = Vec3::from(l.position);
        let on = s
            .branches()
            .iter()
            .enumerate()
            .any(|(i, b)| kept(i as u32) && b.end().distance(p) < 1e-4);
        assert!(on, "tip leaf at {p} is not at the end of a kept branch");
    }
}

#[test]
fn thinned_leaves_are_the_same_leaves_on_the_same_cells() {
    let t = tree('b');
    let options = MeshOptions::default();
    let full = tips(3.0, 0, 7).atlas_columns(4).atlas_rows(2);
    let all = mesh::leaf_instances(&t, &full, &options).unwrap();
    assert!(all.len() > 200, "{}", all.len());
    let middle = |l: &LeafInstance| {
        Vec3::from(l.position) + Quat::from_array(l.rotation) * (Vec3::new(0.0, 0.5, 0.0) * l.scale)
    };
    // Each leaf of the full crown by its middle and turn.
    let find = |l: &LeafInstance| {
        all.iter()
            .position(|a| a.rotation == l.rotation && (middle(a) - middle(l)).length() < 1e-3)
    };
    let all_cells = mesh::leaf_cells(&t, &full, &options).unwrap();
    let mut previous: Option<Vec<usize>> = None;
    for keep in [0.6f32, 0.3, 0.1] {
        let o = full.clone().keep(keep);
        let thin = mesh::leaf_instances(&t, &o, &options).unwrap();
        let m = (keep as f64 * all.len() as f64 + 1e-3).floor() as usize;
        assert_eq!(thin.len(), m);
        // Every survivor is a leaf of the full crown, no smaller, on the same cell.
        let cells = mesh::leaf_cells(&t, &o, &options).unwrap();
        let mut kept = Vec::new();
        let mut grown = 0;
        for (l, cell) in thin.iter().zip(&cells) {
            let k = find(l).expect("a leaf of the full crown");
            assert!(l.scale >= all[k].scale * (1.0 - 1e-5));
            grown += usize::from(l.scale > all[k].scale * 1.001);
            assert_eq!(*cell, all_cells[k], "leaf {k}");
            kept.push(k);
        }
        // The shell as it was, the inside enlarged.
        assert!(
            grown > 0 && grown < thin.len(),
            "keep {keep}: {grown} of {}",
            thin.len()
        );
        // A smaller keep keeps (nearly) a subset of a larger one's leaves.
        if let Some(p) = &previous {
            let inside = kept.iter().filter(|k| p.contains(k)).count();
            assert!(
                inside as f32 >= 0.9 * kept.len() as f32,
                "keep {keep}: {inside} of {}",
                kept.len()
            );
        }
        previous = Some(kept.clone());
        // Baked, each survivor samples its cell.
        let baked = mesh::leaf_mesh(&t, &o.clone().polygons(false), &options).unwrap();
        for (j, cell) in cells.iter().enumerate() {
            let uv = baked.vertices[4 * j].uv;
            let (cu, cv) = ((uv[0] * 4.0).floor() as u32, (uv[1] * 2.0).floor() as u32);
            assert_eq!(cu.min(3) + 4 * cv.min(1), *cell);
        }
    }
    assert!(LeafOptions::default().keep(0.0).validate().is_err());
    assert!(LeafOptions::default().keep(1.5).validate().is_err());
}

/// `keep_enlarge` sets how much a thinned crown's inside leaves grow: the same leaves in
/// the same places (their middles), the shell as it was, the inside by the inside's
/// leaves over those kept to that power (0.5 keeps the inside's leaf area: the default).
#[test]
fn the_inside_leaves_grow_by_the_power_asked() {
    let t = tree('b');
    let options = MeshOptions::default();
    let full = tips(3.0, 0, 7);
    let all = mesh::leaf_instances(&t, &full, &options).unwrap();
    let middle = |l: &LeafInstance| {
        Vec3::from(l.position) + Quat::from_array(l.rotation) * (Vec3::new(0.0, 0.5, 0.0) * l.scale)
    };
    let thin = |e: f32| {
        mesh::leaf_instances(&t, &full.clone().keep(0.25).keep_enlarge(e), &options).unwrap()
    };
    let (half, less, none) = (thin(0.5), thin(0.4), thin(0.0));
    assert_eq!(
        half,
        mesh::leaf_instances(&t, &full.clone().keep(0.25), &options).unwrap()
    );
    assert_eq!((half.len(), less.len()), (none.len(), none.len()));
    let (mut shell, mut inside) = (0, 0);
    for ((h, l), z) in half.iter().zip(&less).zip(&none) {
        assert!((middle(h) - middle(l)).length() < 1e-4 && (middle(h) - middle(z)).length() < 1e-4);
        let k = all
            .iter()
            .position(|a| a.rotation == z.rotation && (middle(a) - middle(z)).length() < 1e-4)
            .expect("a leaf of the full crown");
        // Not enlarged at the power 0: every leaf as it was.
        assert!((z.scale - all[k].scale).abs() <= 1e-6 * all[k].scale);
        if h.scale > z.scale * 1.001 {
            inside += 1;
            // The growth at 0.4 is the growth at 0.5 to the power 0.8.
            let (gh, gl) = (h.scale / z.scale, l.scale / z.scale);
            assert!((gl - gh.powf(0.8)).abs() < 1e-4, "{gl} vs {gh}");
            assert!(gl > 1.0 && gl < gh);
        } else {
            shell += 1;
            assert_eq!(h.scale, l.scale);
        }
    }
    assert!(
        shell > 0 && inside > 0,
        "{shell} in the shell, {inside} inside"
    );
    for bad in [-0.1, 1.5, f32::NAN] {
        let err = LeafOptions::default()
            .keep_enlarge(bad)
            .validate()
            .unwrap_err();
        assert!(err.to_string().contains("keep_enlarge"), "{err}");
    }
}
