//! Pruning keeps the organs of kept branches and never leaves a floating subtree.

use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::skeleton::prune::prune_collisions;
use arbor::skeleton::{Branch, LeafSite, NO_PARENT, Polygon, Skeleton, SkeletonParts};

fn branch(start: [f32; 3], end: [f32; 3], parent: u32, birth: u32) -> Branch {
    Branch {
        start,
        end,
        start_radius: 0.5,
        end_radius: 0.5,
        parent,
        birth,
        ..Default::default()
    }
}

fn connected(s: &Skeleton) {
    for (i, b) in s.branches().iter().enumerate() {
        if b.parent != NO_PARENT {
            assert_eq!(
                b.start,
                s.branches()[b.parent as usize].end,
                "branch {i} floats"
            );
        }
    }
}

/// A planar binary tree with a leaf site at every apex: nothing collides, so pruning must
/// keep every site (it used to drop them all).
#[test]
fn pruning_that_removes_nothing_keeps_every_organ() {
    let ls = LSystem::parse(
        "derivation length: 8\nAxiom: !(0.01)A(10)\nA(l) --> F(l)[+(30)A(l*0.5)][-(30)A(l*0.5)]\nhomomorphism\nA(l) --> ~",
    )
    .unwrap();
    let s = ls.skeleton(&LsystemOptions::default()).unwrap();
    let sites = s.leaves().len();
    assert!(sites >= 256, "{sites} sites");
    let pruned = prune_collisions(&s);
    assert_eq!(pruned.removed, 0);
    assert_eq!(pruned.skeleton.leaves(), s.leaves());
    assert_eq!(pruned.skeleton.branches(), s.branches());
}

/// Organs of removed branches go with them; those of kept branches stay, renumbered to the
/// same branch.
#[test]
fn organs_follow_their_branches() {
    // 0: trunk; 1: continues it; 2: a root crossing branch 1; 3: grows from 1.
    let branches = vec![
        branch([0.0, 0.0, 0.0], [0.0, 10.0, 0.0], NO_PARENT, 0),
        branch([0.0, 10.0, 0.0], [0.0, 20.0, 0.0], 0, 1),
        branch([-5.0, 15.0, 0.0], [5.0, 15.0, 0.0], NO_PARENT, 0),
        branch([0.0, 20.0, 0.0], [0.0, 30.0, 0.0], 1, 2),
    ];
    let site = |branch: u32, y: f32| LeafSite {
        position: [0.0, y, 0.0],
        heading: [0.0, 1.0, 0.0],
        up: [0.0, 0.0, -1.0],
        branch,
        birth: 0,
    };
    let parts = SkeletonParts {
        branches,
        leaves: vec![
            site(0, 10.0),
            site(1, 20.0),
            site(2, 15.0),
            site(3, 30.0),
            site(NO_PARENT, 0.0),
        ],
        polygons: vec![
            Polygon {
                first: 0,
                count: 3,
                branch: 2,
                birth: 0,
            },
            Polygon {
                first: 3,
                count: 3,
                branch: 3,
                birth: 0,
            },
        ],
        polygon_points: vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [5.0; 3],
            [6.0, 5.0, 5.0],
            [5.0, 6.0, 5.0],
        ],
        ..Default::default()
    };
    let s = parts.build().unwrap();
    let p = prune_collisions(&s);
    // Branch 1 (one branch from its root) collides with root 2 and goes, with branch 3.
    assert_eq!(p.removed, 2);
    let kept = p.skeleton.branches();
    assert_eq!(kept.len(), 2);
    assert_eq!(kept[1].start, [-5.0, 15.0, 0.0]);
    let leaves = p.skeleton.leaves();
    assert_eq!(leaves.len(), 3, "{leaves:?}");
    for l in leaves {
        if l.branch != NO_PARENT {
            let b = kept[l.branch as usize];
            let on = (b.start[1]..=b.end[1]).contains(&l.position[1])
                || (l.position[1] - b.start[1]).abs() < 1e-6;
            assert!(on, "site {l:?} renumbered to the wrong branch {b:?}");
        }
    }
    assert_eq!(p.skeleton.polygons().len(), 1);
    assert_eq!(p.skeleton.polygons()[0].branch, 1);
    assert_eq!(
        p.skeleton.polygon(&p.skeleton.polygons()[0]),
        &[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    );
    connected(&p.skeleton);
}

/// A child born at an earlier step than its parent (possible in grammars) used to be judged
/// before its removed parent and kept, floating; now a removed branch takes its subtree.
#[test]
fn no_floating_subtree_when_a_child_is_born_before_its_parent() {
    let branches = vec![
        branch([0.0, 0.0, 0.0], [0.0, 10.0, 0.0], NO_PARENT, 0),
        // Born late, collides with the root below.
        branch([0.0, 10.0, 0.0], [0.0, 20.0, 0.0], 0, 5),
        // Its child, born early.
        branch([0.0, 20.0, 0.0], [0.0, 30.0, 0.0], 1, 1),
        branch([-5.0, 15.0, 0.0], [5.0, 15.0, 0.0], NO_PARENT, 0),
    ];
    let s = Skeleton::new(branches).unwrap();
    let p = prune_collisions(&s);
    assert_eq!(p.removed, 2, "{:?}", p.skeleton.branches());
    connected(&p.skeleton);
}
