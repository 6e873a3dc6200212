//! Seeded variation of the 1996 model, and pruning of colliding branches.

use arbor::models::honda::{self, HondaParams, PRESET_NAMES, Variation};
use arbor::skeleton::prune::prune_collisions;
use arbor::skeleton::{Branch, NO_PARENT, Skeleton};
use glam::Vec3;

fn varied(name: char, seed: u64) -> Skeleton {
    let v = Variation::default().seed(seed);
    honda::build_varied(&HondaParams::preset(name).unwrap(), &v).unwrap()
}

/// Mean distance between the end points of corresponding branches (the shorter count).
fn distance(a: &Skeleton, b: &Skeleton) -> f32 {
    let n = a.len().min(b.len());
    a.branches()
        .iter()
        .zip(b.branches())
        .map(|(x, y)| (x.end() - y.end()).length())
        .sum::<f32>()
        / n as f32
}

#[test]
fn variation_is_seeded_connected_and_bounded() {
    for name in PRESET_NAMES {
        let paper = honda::build(&HondaParams::preset(name).unwrap()).unwrap();
        assert_eq!(varied(name, 0), paper, "seed 0 is the paper's tree");
        let (a, b, c) = (varied(name, 7), varied(name, 7), varied(name, 8));
        assert_eq!(a, b, "tree {name}: same seed, same tree");
        let apart = distance(&a, &c);
        assert!(
            apart > 0.5,
            "tree {name}: seeds 7 and 8 differ by only {apart}"
        );
        assert!(distance(&a, &paper) > 0.5);
        for x in a.branches().iter().skip(1) {
            let p = &a.branches()[x.parent as usize];
            assert_eq!(x.start, p.end, "tree {name}: connected");
        }
    }
    // Branch lengths stay within the stated fraction of the paper's ratios.
    let p = HondaParams::preset('g').unwrap();
    let a = varied('g', 3);
    for x in a.branches().iter().skip(1) {
        let ratio = x.length() / a.branches()[x.parent as usize].length();
        assert!(
            ratio >= p.r1 * 0.94 - 1e-4 && ratio <= p.r1 * 1.06 + 1e-4,
            "{ratio}"
        );
    }
    let bad = Variation::default().seed(1).length(1.5);
    assert!(honda::build_varied(&HondaParams::preset('a').unwrap(), &bad).is_err());
}

fn branch(start: [f32; 3], end: [f32; 3], r: f32, parent: u32, birth: u32) -> Branch {
    Branch {
        start,
        end,
        start_radius: r,
        end_radius: r,
        parent,
        birth,
        ..Default::default()
    }
}

fn collides(a: &Branch, b: &Branch) -> bool {
    // Sampled distance between the two axes, for an independent check.
    let mut best = f32::MAX;
    for i in 0..=16 {
        for j in 0..=16 {
            let p = a.start().lerp(a.end(), i as f32 / 16.0);
            let q = b.start().lerp(b.end(), j as f32 / 16.0);
            best = best.min((p - q).length());
        }
    }
    let r = a.start_radius.max(a.end_radius) + b.start_radius.max(b.end_radius);
    best < r * 0.9
}

fn meet(a: &Branch, b: &Branch) -> bool {
    [a.start, a.end].iter().any(|p| {
        [b.start, b.end]
            .iter()
            .any(|q| Vec3::from(*p).distance(Vec3::from(*q)) < 1e-5)
    })
}

#[test]
fn a_known_collision_is_pruned_with_its_subtree() {
    let s = Skeleton::new(vec![
        branch([0., 0., 0.], [0., 10., 0.], 0.5, NO_PARENT, 1),
        branch([0., 10., 0.], [5., 10., 0.], 0.5, 0, 2),
        branch([0., 10., 0.], [0., 15., 0.], 0.5, 0, 2),
        branch([0., 15., 0.], [5., 10.3, 0.], 0.5, 2, 3), // ends on branch 1
        branch([5., 10.3, 0.], [6., 12., 0.], 0.5, 3, 4), // its child
        branch([0., 15., 0.], [-4., 18., 0.], 0.5, 2, 3), // clear of everything
    ])
    .unwrap();
    let p = prune_collisions(&s);
    assert_eq!(p.removed, 2);
    let b = p.skeleton.branches();
    assert_eq!(b.len(), 4);
    assert_eq!(b[3].end, [-4., 18., 0.]);
    assert_eq!(b[3].parent, 2);
    assert_eq!(
        b[2].end_radius, 0.5,
        "branch 2 keeps a child, so its tip stays open"
    );
    // Remove the clear branch too: now branch 2 loses every child and closes.
    let mut only = s.branches().to_vec();
    only.pop();
    let p = prune_collisions(&Skeleton::new(only).unwrap());
    assert_eq!(p.removed, 2);
    assert_eq!(p.skeleton.branches()[2].end_radius, 0.0);
}

#[test]
fn the_1996_trees_lose_their_overlapping_branches() {
    let mut total = 0;
    for name in PRESET_NAMES {
        let s = honda::build(&HondaParams::preset(name).unwrap()).unwrap();
        let p = prune_collisions(&s);
        total += p.removed;
        println!("tree {name}: {} of {} branches removed", p.removed, s.len());
        assert_eq!(p.skeleton.len() + p.removed, s.len());
        if s.len() > 1100 {
            continue; // the brute-force check below is quadratic
        }
        let b = p.skeleton.branches();
        for i in 0..b.len() {
            for j in 0..i {
                if b[i].parent == j as u32 || meet(&b[i], &b[j]) {
                    continue;
                }
                assert!(
                    !collides(&b[i], &b[j]),
                    "tree {name}: {i} and {j} still collide"
                );
            }
        }
    }
    assert!(total > 0, "some of the paper's trees overlap");
}
