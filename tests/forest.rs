//! A forest built at once (in parallel with the `parallel` feature) equals the serial
//! build tree by tree, byte by byte.

use arbor::forest::{self, Item, Source};
use arbor::honda::HondaParams;
use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::mesh::MeshOptions;

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
