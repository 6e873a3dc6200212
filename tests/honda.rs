//! The facts of the 1996 model that every preset must satisfy.

use approx::assert_abs_diff_eq;
use arbor::Error;
use arbor::models::honda::{self, HondaParams, PRESET_NAMES};
use arbor::skeleton::{NO_PARENT, Skeleton};
use glam::Vec3;

const COUNTS: [(char, usize); 9] = [
    ('a', 1023),
    ('b', 2223),
    ('c', 510),
    ('d', 1023),
    ('e', 1990),
    ('f', 5027),
    ('g', 1023),
    ('h', 919),
    ('i', 1586),
];

fn preset(name: char) -> HondaParams {
    HondaParams::preset(name).unwrap()
}

fn tree(name: char) -> Skeleton {
    honda::build(&preset(name)).unwrap()
}

#[test]
fn internode_counts_match_the_paper() {
    for (name, count) in COUNTS {
        let p = preset(name);
        assert_eq!(tree(name).len(), count, "tree {name}");
        assert_eq!(p.branch_count(), count as u64, "tree {name} counted");
    }
}

#[test]
fn with_min_zero_the_count_is_two_to_the_n_minus_one() {
    for n in [0, 1, 2, 5, 11] {
        let mut p = preset('g');
        p.steps = n;
        assert_eq!(
            honda::build(&p).unwrap().len(),
            (1usize << n) - 1,
            "n = {n}"
        );
    }
}

#[test]
fn trunk_runs_from_origin_to_100_up() {
    for name in PRESET_NAMES {
        let p = preset(name);
        let t = tree(name).branches()[0];
        assert_eq!(t.start, [0.0, 0.0, 0.0], "tree {name}");
        assert_eq!(t.end, [0.0, 100.0, 0.0], "tree {name}");
        assert_eq!(t.parent, NO_PARENT);
        assert_eq!((t.birth, t.order), (1, 0));
        assert_eq!(
            t.start_radius,
            p.trunk_width / 2.0,
            "radius is half the width"
        );
        assert_eq!(t.end_radius, p.trunk_width / 2.0);
    }
}

#[test]
fn every_branch_starts_where_its_parent_ends() {
    for name in PRESET_NAMES {
        let s = tree(name);
        let b = s.branches();
        for (i, br) in b.iter().enumerate().skip(1) {
            assert!((br.parent as usize) < i, "tree {name} branch {i}");
            let parent = &b[br.parent as usize];
            assert_eq!(br.start, parent.end, "tree {name} branch {i}");
            assert_eq!(br.birth, parent.birth + 1, "tree {name} branch {i}");
        }
        // Only the trunk is a root.
        assert_eq!(b.iter().filter(|br| br.is_root()).count(), 1);
    }
}

#[test]
fn lengths_and_radii_follow_the_ratios() {
    for name in PRESET_NAMES {
        let p = preset(name);
        let f1 = (p.q as f64).powf(p.e as f64);
        let f2 = (1.0 - p.q as f64).powf(p.e as f64);
        let s = tree(name);
        let b = s.branches();
        for br in &b[1..] {
            let parent = &b[br.parent as usize];
            let ratio = br.length() as f64 / parent.length() as f64;
            let w = br.start_radius as f64 / parent.start_radius as f64;
            let first = (ratio - p.r1 as f64).abs() < 1e-4 && (w - f1).abs() < 1e-4;
            let second = (ratio - p.r2 as f64).abs() < 1e-4 && (w - f2).abs() < 1e-4;
            assert!(first || second, "tree {name}: ratio {ratio}, width {w}");
            assert_eq!(br.start_radius, br.end_radius);
            assert!(br.length() as f64 >= p.min_length as f64 * 0.9999);
        }
    }
}

#[test]
fn trees_a_to_f_are_planar_and_g_to_i_are_not() {
    for name in PRESET_NAMES {
        let s = tree(name);
        let max_z = s
            .branches()
            .iter()
            .map(|b| b.end[2].abs())
            .fold(0.0f32, f32::max);
        if name <= 'f' {
            assert!(max_z < 1e-3, "tree {name} leaves the plane: {max_z}");
        } else {
            assert!(max_z > 10.0, "tree {name} is flat: {max_z}");
        }
    }
}

/// Children of each branch in index order: the first child's subtree comes first.
fn children(s: &Skeleton) -> Vec<Vec<usize>> {
    let mut c = vec![Vec::new(); s.len()];
    for (i, b) in s.branches().iter().enumerate() {
        if !b.is_root() {
            c[b.parent as usize].push(i);
        }
    }
    c
}

/// The mirror image of each branch: first and second children swapped all the way down.
fn mirror_map(s: &Skeleton) -> Vec<usize> {
    let c = children(s);
    let mut m = vec![usize::MAX; s.len()];
    m[0] = 0;
    for i in 0..s.len() {
        let (mine, theirs) = (&c[i], &c[m[i]]);
        assert_eq!(mine.len(), theirs.len());
        if mine.len() == 2 {
            m[mine[0]] = theirs[1];
            m[mine[1]] = theirs[0];
        }
    }
    m
}

fn mirrored(v: Vec3) -> Vec3 {
    Vec3::new(-v.x, v.y, v.z)
}

#[test]
fn tree_a_is_mirror_symmetric() {
    // Directions and radii mirror exactly (α2 = −α1, q = 0.5); lengths differ only by
    // r1 = 0.75 vs r2 = 0.77, so with r2 set to r1 the positions mirror too.
    let s = tree('a');
    let m = mirror_map(&s);
    let b = s.branches();
    for (i, &j) in m.iter().enumerate() {
        let di = (b[i].end() - b[i].start()).normalize();
        let dj = (b[j].end() - b[j].start()).normalize();
        assert!(mirrored(di).abs_diff_eq(dj, 1e-5), "branch {i} vs {j}");
        assert_eq!(b[i].start_radius, b[j].start_radius);
    }
    let mut p = preset('a');
    p.r2 = p.r1;
    let even = honda::build(&p).unwrap();
    let b = even.branches();
    for (i, &j) in m.iter().enumerate() {
        assert!(
            mirrored(b[i].end()).abs_diff_eq(b[j].end(), 1e-3),
            "branch {i} vs {j}"
        );
    }
    // The real preset is close to symmetric as a whole.
    let (lo, hi) = s.bounds().unwrap();
    assert_abs_diff_eq!(-lo.x, hi.x, epsilon = 0.15 * hi.x);
}

#[test]
fn the_child_with_the_smaller_angle_continues_the_axis() {
    for name in PRESET_NAMES {
        let p = preset(name);
        let s = tree(name);
        let c = children(&s);
        let b = s.branches();
        let continuing = if p.alpha2.abs() < p.alpha1.abs() {
            1
        } else {
            0
        };
        for (i, kids) in c.iter().enumerate() {
            if kids.len() != 2 {
                continue;
            }
            assert_eq!(b[kids[continuing]].order, b[i].order, "tree {name}");
            assert_eq!(b[kids[1 - continuing]].order, b[i].order + 1, "tree {name}");
        }
        // In a tree whose apexes never stop (min = 0) the trunk axis has n internodes.
        if p.min_length == 0.0 {
            let axis = b.iter().filter(|br| br.order == 0).count();
            assert_eq!(axis, p.steps as usize, "tree {name}");
        }
    }
}

#[test]
fn a_growth_bomb_is_refused_at_once() {
    let mut p = preset('a');
    p.steps = 60;
    let e = honda::build(&p).unwrap_err();
    match e {
        Error::LimitExceeded { step, limit, .. } => {
            assert_eq!(limit, honda::DEFAULT_MAX_BRANCHES as u64);
            // 2^25 − 1 > 2^24 first at step 25.
            assert_eq!(step, Some(25));
        }
        other => panic!("expected LimitExceeded, got {other}"),
    }
    assert!(e_text(&p).contains("max_branches"));
    let a = preset('a');
    assert!(honda::build_with_limit(&a, 1022).is_err());
    assert_eq!(honda::build_with_limit(&a, 1023).unwrap().len(), 1023);
}

fn e_text(p: &HondaParams) -> String {
    honda::build(p).unwrap_err().to_string()
}

#[test]
fn bad_parameters_name_their_field() {
    type Setter = fn(&mut HondaParams, f32);
    let fields: [(&str, Setter, &[f32]); 11] = [
        ("trunk_length", |p, v| p.trunk_length = v, &[0.0, -1.0]),
        ("trunk_width", |p, v| p.trunk_width = v, &[0.0, -1.0]),
        ("r1", |p, v| p.r1 = v, &[0.0, -0.5]),
        ("r2", |p, v| p.r2 = v, &[-0.5]),
        ("alpha1", |p, v| p.alpha1 = v, &[]),
        ("alpha2", |p, v| p.alpha2 = v, &[]),
        ("phi1", |p, v| p.phi1 = v, &[]),
        ("phi2", |p, v| p.phi2 = v, &[]),
        ("q", |p, v| p.q = v, &[-0.1, 1.5]),
        ("e", |p, v| p.e = v, &[-1.0]),
        ("min_length", |p, v| p.min_length = v, &[-1.0]),
    ];
    for (field, set, extra) in fields {
        for &v in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY]
            .iter()
            .chain(extra)
        {
            let mut p = preset('b');
            set(&mut p, v);
            match honda::build(&p) {
                Err(Error::InvalidArgument { field: f, .. }) => assert_eq!(f, field, "{v}"),
                other => panic!("{field} = {v}: {other:?}"),
            }
        }
    }
    let mut p = preset('b');
    p.steps = honda::MAX_STEPS + 1;
    assert!(e_text(&p).contains("`steps`"));
}

#[test]
fn huge_angles_give_a_defined_tree() {
    let mut p = preset('g');
    p.alpha1 = 1e30;
    p.phi2 = -1e30;
    let s = honda::build(&p).unwrap();
    assert_eq!(s.len(), 1023);
    assert!(
        s.branches()
            .iter()
            .all(|b| b.end.iter().all(|v| v.is_finite()))
    );
}

#[test]
fn coordinates_beyond_f32_are_an_error() {
    let mut p = preset('a');
    p.trunk_length = 1e30;
    p.r1 = 10.0;
    p.r2 = 10.0;
    p.steps = 12;
    let e = e_text(&p);
    assert!(e.contains("overflow"), "{e}");
}

#[test]
fn building_is_deterministic_and_zero_steps_is_empty() {
    for name in PRESET_NAMES {
        assert_eq!(tree(name), tree(name));
    }
    let mut p = preset('a');
    p.steps = 0;
    assert!(honda::build(&p).unwrap().is_empty());
}
