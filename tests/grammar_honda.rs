//! The 1996 model written as grammar text grows the same skeleton as the direct builder,
//! branch by branch. Keep this test forever.

use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::models::honda::{self, HondaParams, PRESET_NAMES};

fn grammar(name: char) -> LSystem {
    let path = format!(
        "{}/examples/grammars/honda_{name}.l",
        env!("CARGO_MANIFEST_DIR")
    );
    LSystem::parse(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn grammar_and_direct_builder_agree_branch_by_branch() {
    for name in PRESET_NAMES {
        let params = HondaParams::preset(name).unwrap();
        let direct = honda::build(&params).unwrap();
        let ls = grammar(name);
        assert_eq!(ls.derivation_length(), params.steps);
        let from_grammar = ls.skeleton(&LsystemOptions::default()).unwrap();
        assert_eq!(from_grammar.len(), direct.len(), "tree {name}");
        let tol = 1e-4 * params.trunk_length;
        for (i, (g, d)) in from_grammar
            .branches()
            .iter()
            .zip(direct.branches())
            .enumerate()
        {
            let close =
                |a: [f32; 3], b: [f32; 3]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol);
            assert!(
                close(g.start, d.start),
                "tree {name} branch {i}: {:?} vs {:?}",
                g.start,
                d.start
            );
            assert!(
                close(g.end, d.end),
                "tree {name} branch {i}: {:?} vs {:?}",
                g.end,
                d.end
            );
            assert!(
                (g.start_radius - d.start_radius).abs() <= tol,
                "tree {name} branch {i}"
            );
            assert!(
                (g.end_radius - d.end_radius).abs() <= tol,
                "tree {name} branch {i}"
            );
            assert_eq!(
                (g.parent, g.birth, g.order),
                (d.parent, d.birth, d.order),
                "tree {name} branch {i}"
            );
        }
    }
}
