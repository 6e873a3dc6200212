//! A forest built at once (in parallel with the `parallel` feature) equals the serial
//! build tree by tree, byte by byte.

use arbor::forest::{self, Item, Source};
use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::mesh::MeshOptions;
use arbor::models::honda::HondaParams;

#[test]
fn forest_equals_the_serial_build() {
    let path = format!(
        "{}/examples/grammars/stochastic_4.l",
        env!("CARGO_MANIFEST_DIR")
    );
    // Without its seed line the grammar takes each item's seed.
    let text: String = std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with("seed:"))
        .collect::<Vec<_>>()
        .join("\n");
    let ls = LSystem::parse(&text).unwrap();
    let mut items = Vec::new();
    for k in 0..24u64 {
        let source = if k % 2 == 0 {
            Source::Honda(HondaParams::preset((b'a' + (k % 9) as u8) as char).unwrap())
        } else {
            Source::Grammar(&ls, LsystemOptions::default())
        };
        items.push(Item { source, seed: k });
    }
    let options = MeshOptions::default();
    let serial = forest::build_serial(&items, &options).unwrap();
    let at_once = forest::build(&items, &options).unwrap();
    assert_eq!(serial.len(), 24);
    for (k, (a, b)) in serial.iter().zip(&at_once).enumerate() {
        assert_eq!(
            bytemuck::cast_slice::<_, u8>(&a.vertices),
            bytemuck::cast_slice::<_, u8>(&b.vertices),
            "tree {k}"
        );
        assert_eq!(a.indices, b.indices, "tree {k}");
    }
    // Different seeds grow different stochastic trees.
    assert_ne!(serial[1].vertices.len(), 0);
    let distinct: std::collections::HashSet<usize> = (1..24)
        .step_by(2)
        .map(|k| serial[k].vertices.len())
        .collect();
    assert!(distinct.len() > 3, "seeds vary the stochastic trees");
    // An error is reported, not a panic.
    let mut bad = HondaParams::preset('a').unwrap();
    bad.r1 = f32::NAN;
    let e = forest::build(
        &[Item {
            source: Source::Honda(bad),
            seed: 0,
        }],
        &options,
    );
    assert!(e.is_err());
}

use arbor::forest::Placed;
use arbor::mesh::Topology;

fn canonical(t: [u32; 3]) -> [u32; 3] {
    let k = (0..3).min_by_key(|&k| t[k]).unwrap();
    [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
}

#[test]
fn merged_and_instanced_forests_agree() {
    let place = |name: char, seed: u64, x: f32, rotation: f32, scale: f32| Placed {
        item: Item {
            source: Source::Honda(HondaParams::preset(name).unwrap()),
            seed,
        },
        position: [x, 0.0, -x],
        rotation,
        scale,
    };
    let placed = [
        place('a', 1, 0.0, 0.0, 1.0),
        place('g', 2, 300.0, 90.0, 0.5),
        place('a', 1, -300.0, 45.0, 2.0),
        place('c', 0, 100.0, 10.0, 1.0),
    ];
    let o = MeshOptions::default();
    let merged = forest::merged(&placed, &o).unwrap();
    let (meshes, instances) = forest::instanced(&placed, &o).unwrap();
    assert_eq!(meshes.len(), 3, "trees a/1 placed twice share one mesh");
    assert_eq!(
        instances.iter().map(|i| i.0).collect::<Vec<_>>(),
        vec![0, 1, 0, 2]
    );
    // The merged mesh is each instance's mesh moved by its transform.
    let mut at = 0;
    for (k, t) in &instances {
        let m = &meshes[*k as usize];
        let t = glam::Mat4::from_cols_array(t);
        for v in &m.vertices {
            let want = t.transform_point3(glam::Vec3::from(v.position));
            let got = glam::Vec3::from(merged.vertices[at].position);
            assert!(got.abs_diff_eq(want, 1e-3 * want.length().max(1.0)));
            at += 1;
        }
    }
    assert_eq!(at, merged.vertices.len());
    let triangles: usize = instances
        .iter()
        .map(|(k, _)| meshes[*k as usize].triangles().count())
        .sum();
    assert_eq!(merged.triangles().count(), triangles);
    // Every topology joins the trees into the same triangles (each topology orders them
    // for the vertex cache in its own way).
    let sorted = |m: &arbor::mesh::Mesh| {
        let mut t: Vec<[u32; 3]> = m.triangles().map(canonical).collect();
        t.sort_unstable();
        t
    };
    let list = sorted(&merged);
    for topology in [
        Topology::TriangleStripRestart,
        Topology::TriangleStripDegenerate,
    ] {
        let m = forest::merged(&placed, &o.topology(topology)).unwrap();
        assert_eq!(sorted(&m), list, "{topology:?}");
    }
    let mut bad = placed;
    bad[1].scale = 0.0;
    assert!(forest::merged(&bad, &o).is_err());
}

/// A grammar that fixes its own `seed:` (stochastic_4.l does) still grows a distinct tree
/// for each item seed; seed 0 grows the file's tree as written.
#[test]
fn item_seeds_vary_a_grammar_that_sets_its_own_seed() {
    let path = format!(
        "{}/examples/grammars/stochastic_4.l",
        env!("CARGO_MANIFEST_DIR")
    );
    let ls = LSystem::parse(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert!(ls.seed().is_some(), "the grammar sets its own seed");
    let options = MeshOptions::default();
    let items: Vec<Item<'_>> = (0..6u64)
        .map(|seed| Item {
            source: Source::Grammar(&ls, LsystemOptions::default()),
            seed,
        })
        .collect();
    let meshes = forest::build_serial(&items, &options).unwrap();
    let as_written =
        arbor::mesh::tubes(&ls.skeleton(&LsystemOptions::default()).unwrap(), &options).unwrap();
    assert_eq!(meshes[0], as_written, "seed 0: the file's own tree");
    for a in 0..meshes.len() {
        for b in a + 1..meshes.len() {
            assert_ne!(
                meshes[a].vertices, meshes[b].vertices,
                "items {a} and {b} grew alike"
            );
        }
    }
}

/// The merged forest written into caller buffers equals the owned merged mesh, and a
/// forest past `max_vertices` is refused by name before anything is written.
#[test]
fn merged_forest_into_buffers_and_its_limit() {
    let placed: Vec<forest::Placed<'_>> = (0..4)
        .map(|k| forest::Placed {
            item: Item {
                source: Source::Honda(HondaParams::preset('b').unwrap()),
                seed: k,
            },
            position: [k as f32 * 50.0, 0.0, 0.0],
            rotation: 30.0 * k as f32,
            scale: 1.0,
        })
        .collect();
    for topology in arbor::Topology::ALL {
        let options = MeshOptions::default().topology(topology);
        let owned = forest::merged(&placed, &options).unwrap();
        let size = forest::merged_size(&placed, &options).unwrap();
        assert_eq!(
            (size.vertices, size.indices),
            (owned.vertices.len(), owned.indices.len())
        );
        let mut v = vec![arbor::Vertex::default(); size.vertices];
        let mut i = vec![7u32; size.indices];
        forest::write_merged(&placed, &options, &mut v, &mut i).unwrap();
        assert_eq!(v, owned.vertices, "{topology:?}");
        assert_eq!(i, owned.indices, "{topology:?}");
        let limited = options.max_vertices(size.vertices - 1);
        let err = forest::merged_size(&placed, &limited).unwrap_err();
        assert!(err.to_string().contains("max_vertices"), "{err}");
        let err = forest::write_merged(&placed, &limited, &mut v, &mut i).unwrap_err();
        assert!(err.to_string().contains("max_vertices"), "{err}");
    }
}

/// A forest of self-organizing trees: each grows alone in its own world, so the forest
/// built at once equals the serial build and each tree equals the one its source grows;
/// placements of one species and seed share one mesh, another seed or species does not.
#[test]
fn forests_hold_self_organizing_trees() {
    use arbor::models::growth::{GrowthParams, Species};
    let species = [
        GrowthParams::preset(Species::Excurrent),
        GrowthParams::preset(Species::Bush),
    ];
    let items: Vec<Item> = (0..6u64)
        .map(|k| Item {
            source: Source::Growth(species[(k % 2) as usize], 8),
            seed: k / 4,
        })
        .collect();
    let options = MeshOptions::default();
    let serial = forest::build_serial(&items, &options).unwrap();
    let at_once = forest::build(&items, &options).unwrap();
    for (k, ((a, b), item)) in serial.iter().zip(&at_once).zip(&items).enumerate() {
        assert_eq!(a, b, "tree {k}");
        let alone = arbor::mesh::tubes(&item.source.grow(item.seed).unwrap(), &options).unwrap();
        assert_eq!(*a, alone, "tree {k} as its source grows it");
        assert!(
            a.indices.len() > 100,
            "tree {k} grew: {} indices",
            a.indices.len()
        );
    }
    assert_ne!(serial[0], serial[1], "two species differ");
    assert_ne!(serial[0], serial[4], "two seeds differ");
    let placed: Vec<forest::Placed> = items
        .iter()
        .enumerate()
        .map(|(k, &item)| forest::Placed {
            item,
            position: [k as f32 * 5.0, 0.0, 0.0],
            rotation: 0.0,
            scale: 1.0,
        })
        .collect();
    let (meshes, which) = forest::instanced(&placed, &options).unwrap();
    // Items 0, 2 (excurrent, seed 0), 1, 3 (bush, seed 0), 4 (excurrent, seed 1), 5 (bush, seed 1).
    assert_eq!(meshes.len(), 4);
    let ids: Vec<u32> = which.iter().map(|w| w.0).collect();
    assert_eq!(ids, [0, 1, 0, 1, 2, 3]);
}
