//! The optional animation stream: one element per vertex, growth and wind values that
//! follow the branches, and leaves that carry their branch's values.

use arbor::mesh::{self, Joints, LeafOptions, MeshOptions, Tip, Topology};
use arbor::models::honda::{self, HondaParams, PRESET_NAMES};

#[test]
fn one_element_per_vertex_with_branch_values() {
    for name in PRESET_NAMES {
        let s = honda::build(&HondaParams::preset(name).unwrap()).unwrap();
        for o in [
            MeshOptions::default(),
            MeshOptions::default()
                .joints(Joints::Separate)
                .tip(Tip::Point)
                .base_cap(true)
                .topology(Topology::TriangleStripDegenerate),
            MeshOptions::default()
                .min_radial_segments(3)
                .cull_radius(1.0),
        ] {
            let m = mesh::tubes(&s, &o).unwrap();
            let a = mesh::animation(&s, &o).unwrap();
            assert_eq!(a.len(), m.vertices.len(), "tree {name}");
            for (i, r) in m.ranges.iter().enumerate() {
                let b = &s.branches()[i];
                for k in r.first_vertex..r.first_vertex + r.vertex_count {
                    let v = a[k as usize];
                    assert!((0.0..=1.0).contains(&v.growth) && (0.0..1.0).contains(&v.phase));
                    assert_eq!(v.order, b.order as f32);
                    assert!(v.along == 0.0 || v.along == 1.0);
                }
            }
            // Growth never decreases from a branch's base to its tip, nor from parent to
            // child: the tip of every branch appears no earlier than its parent's tip.
            for (i, b) in s.branches().iter().enumerate().skip(1) {
                let (r, p) = (m.ranges[i], m.ranges[b.parent as usize]);
                if r.vertex_count == 0 || p.vertex_count == 0 {
                    continue;
                }
                let tip = |r: arbor::mesh::BranchRange| {
                    a[(r.first_vertex..r.first_vertex + r.vertex_count)
                        .max_by(|&x, &y| a[x as usize].growth.total_cmp(&a[y as usize].growth))
                        .unwrap() as usize]
                        .growth
                };
                assert!(tip(r) > tip(p), "tree {name} branch {i}");
            }
        }
    }
    // Branches sway out of step.
    let s = honda::build(&HondaParams::preset('g').unwrap()).unwrap();
    let a = mesh::animation(&s, &MeshOptions::default()).unwrap();
    let phases: std::collections::HashSet<u32> = a.iter().map(|v| v.phase.to_bits()).collect();
    assert!(phases.len() > 900);
}

#[test]
fn leaves_carry_their_branch_values() {
    let s = honda::build(&HondaParams::preset('a').unwrap()).unwrap();
    let leaves = LeafOptions::default().tips(true).density(2.0);
    let o = MeshOptions::default();
    let inst = mesh::leaf_instances(&s, &leaves, &o).unwrap();
    let anim = mesh::leaf_animation(&s, &leaves, &mesh::MeshOptions::default()).unwrap();
    assert_eq!(inst.len(), anim.len());
    for (l, v) in inst.iter().zip(&anim) {
        // The leaf sits at the end of a terminal branch of that order and phase.
        let b = s
            .branches()
            .iter()
            .position(|b| b.end == l.position)
            .unwrap();
        assert_eq!(v.order, s.branches()[b].order as f32);
        assert_eq!(v.along, 1.0);
        assert_eq!(v.growth, 1.0, "outer leaves appear last");
    }
}

/// In ABOP 1.24a every internode is born at the last step; growth still runs from the
/// root to the tips (a child's tip appears after its parent's), not all at once.
#[test]
fn growth_runs_from_root_to_tips_when_all_births_are_equal() {
    let path = format!(
        "{}/examples/grammars/abop_1_24a.l",
        env!("CARGO_MANIFEST_DIR")
    );
    let ls = arbor::lsystem::LSystem::parse(&std::fs::read_to_string(path).unwrap()).unwrap();
    let s = ls
        .skeleton(&arbor::lsystem::LsystemOptions::default())
        .unwrap();
    let births: std::collections::HashSet<u32> = s.branches().iter().map(|b| b.birth).collect();
    assert_eq!(births.len(), 1, "one birth step for every internode");
    let o = MeshOptions::default().joints(Joints::Separate);
    let m = mesh::tubes(&s, &o).unwrap();
    let a = mesh::animation(&s, &o).unwrap();
    let end_growth = |i: usize| {
        let r = m.ranges[i];
        // The end ring follows the start ring with separate joints.
        a[(r.first_vertex + r.vertex_count - 1) as usize].growth
    };
    assert!(
        end_growth(0) < 0.2,
        "the first internode finishes early: {}",
        end_growth(0)
    );
    for (i, b) in s.branches().iter().enumerate().skip(1) {
        assert!(end_growth(i) > end_growth(b.parent as usize), "branch {i}");
    }
}
