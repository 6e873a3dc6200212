//! Pruning branches that run into each other: where two branches' volumes (capsules from
//! start, end and radius) intersect and the two do not meet at a joint, the one farther
//! from the root (more branches between it and its root; the later one on a tie) is removed with its whole
//! subtree, and a parent left with no children gets a closed tip (end radius 0). A uniform
//! grid keeps the pass near linear.

use crate::geom::grid::Grid;
use crate::skeleton::{Branch, LeafSite, NO_PARENT, Organ, Polygon, Skeleton, SkeletonParts};
use glam::DVec3;

/// What [`prune_collisions`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct Pruned {
    /// The skeleton without the removed branches (indices renumbered, order kept).
    pub skeleton: Skeleton,
    /// How many branches were removed (subtrees included).
    pub removed: usize,
}

/// Squared distance between segments p0–p1 and q0–q1 (Ericson, Real-Time Collision
/// Detection, 5.1.9).
fn segment_distance_sq(p0: DVec3, p1: DVec3, q0: DVec3, q1: DVec3) -> f64 {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.dot(d1), d2.dot(d2), d2.dot(r));
    let eps = 1e-18;
    let (s, t) = if a <= eps && e <= eps {
        (0.0, 0.0)
    } else if a <= eps {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(r);
        if e <= eps {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let mut s = if denom > eps {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    };
    let (cp, cq) = (p0 + d1 * s, q0 + d2 * t);
    (cp - cq).length_squared()
}

fn ends(b: &Branch) -> (DVec3, DVec3, f64) {
    (
        b.start().as_dvec3(),
        b.end().as_dvec3(),
        b.start_radius.max(b.end_radius) as f64,
    )
}

/// Whether two branches meet at a joint (share an end point), where touching is expected.
fn adjacent(a: &Branch, b: &Branch) -> bool {
    let close = |x: [f32; 3], y: [f32; 3]| x.iter().zip(&y).all(|(u, v)| (u - v).abs() <= 1e-5);
    close(a.start, b.start) || close(a.start, b.end) || close(a.end, b.start) || close(a.end, b.end)
}

/// Most grid cells one branch is put in; a longer branch is checked against as one large
/// item, so one long branch cannot fill (length / cell)³ cells.
const MAX_CELLS_PER_BRANCH: u64 = 64;

/// Removes colliding branches (see the module documentation). Leaf sites and polygons of
/// kept branches are kept (renumbered, in order), those of removed branches go with them;
/// so do the turtle's frames and the curves of kept branches.
pub fn prune_collisions(skeleton: &Skeleton) -> Pruned {
    let n = skeleton.len();
    if n == 0 {
        return Pruned {
            skeleton: skeleton.clone(),
            removed: 0,
        };
    }
    let removed = colliding(skeleton);
    let parts = kept_parts(skeleton, &removed);
    let count = n - parts.branches.len();
    Pruned {
        skeleton: Skeleton::from_trusted(parts),
        removed: count,
    }
}

/// Which branches go: each branch that meets one nearer the root (not its parent, not at
/// a joint), and every branch above one that goes.
fn colliding(skeleton: &Skeleton) -> Vec<bool> {
    let b = skeleton.branches();
    let n = b.len();
    let adjacency = skeleton.adjacency();
    // Cell size: the mean capsule extent, so most capsules touch a few cells.
    let extent: f64 = b
        .iter()
        .map(|x| {
            let (p, q, r) = ends(x);
            (q - p).length() + 2.0 * r
        })
        .sum::<f64>()
        / n as f64;
    let mut grid = Grid::new(extent, MAX_CELLS_PER_BRANCH);
    // Nearer the root first (fewer branches between it and its root; the earlier on a
    // tie), so the branch farther from the root is the one removed.
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_by_key(|&i| (adjacency.depth(i as usize), i));
    let mut removed = vec![false; n];
    let mut candidates: Vec<u32> = Vec::new();
    // A capsule identical to one already judged gets the same verdict (it meets the same
    // branches, and its twin at every end point) and is not put in the grid again: many
    // coincident branches (zero-length internodes at one point) stay linear.
    let mut judged: rustc_hash::FxHashMap<([u32; 3], [u32; 3], u32), bool> = Default::default();
    for &i in &order {
        let x = &b[i as usize];
        if x.parent != NO_PARENT && removed[x.parent as usize] {
            removed[i as usize] = true;
            continue;
        }
        let key = (
            x.start.map(f32::to_bits),
            x.end.map(f32::to_bits),
            x.start_radius.max(x.end_radius).to_bits(),
        );
        if let Some(&verdict) = judged.get(&key) {
            removed[i as usize] = verdict;
            continue;
        }
        let (p, q, r) = ends(x);
        let (lo, hi) = (p.min(q) - DVec3::splat(r), p.max(q) + DVec3::splat(r));
        grid.query(lo, hi, &mut candidates);
        let hit = candidates.iter().any(|&j| {
            let y = &b[j as usize];
            if j == x.parent || adjacent(x, y) {
                return false;
            }
            let (p2, q2, r2) = ends(y);
            segment_distance_sq(p, q, p2, q2) < (r + r2) * (r + r2)
        });
        judged.insert(key, hit);
        if hit {
            removed[i as usize] = true;
            continue;
        }
        grid.insert(i, lo, hi);
    }
    // A removed branch takes its whole subtree (parents come before children).
    for i in 0..n {
        let p = b[i].parent;
        if p != NO_PARENT && removed[p as usize] {
            removed[i] = true;
        }
    }
    removed
}

/// The skeleton without the branches that leave the trunk (an order-0 branch) below
/// `height` above its lowest point, with everything they carry: a clear bole, as a tree
/// that grew among others has. `height` 0 (or less) removes nothing.
pub fn clear_trunk(skeleton: &Skeleton, height: f32) -> Pruned {
    let b = skeleton.branches();
    let base = skeleton.bounds().map_or(0.0, |(lo, _)| lo.y);
    let mut removed = vec![false; b.len()];
    for (i, x) in b.iter().enumerate() {
        if x.parent == NO_PARENT {
            continue;
        }
        let p = x.parent as usize;
        // Parents come before children, so a subtree follows its root.
        removed[i] = removed[p] || (x.order > 0 && b[p].order == 0 && x.start[1] < base + height);
    }
    pruned(skeleton, &removed)
}

/// The skeleton without its bare limbs: every branch off its parent's axis (a lateral)
/// whose whole subtree has no branch born at `min_birth` or later, with that subtree: the
/// shaded, dead limbs a tree sheds, which carry no young shoot (and so no leaf).
pub fn shed_bare(skeleton: &Skeleton, min_birth: u32) -> Pruned {
    let b = skeleton.branches();
    // Whether each subtree holds a young branch: children after parents, so backwards.
    let mut young: Vec<bool> = b.iter().map(|x| x.birth >= min_birth).collect();
    for i in (0..b.len()).rev() {
        let p = b[i].parent;
        if p != NO_PARENT && young[i] {
            young[p as usize] = true;
        }
    }
    let mut removed = vec![false; b.len()];
    for (i, x) in b.iter().enumerate() {
        if x.parent == NO_PARENT {
            continue;
        }
        let p = x.parent as usize;
        let lateral = x.order != b[p].order;
        removed[i] = removed[p] || (lateral && !young[i]);
    }
    pruned(skeleton, &removed)
}

/// `skeleton` without the `removed` branches, and how many they are (none removed: the
/// skeleton as it is).
fn pruned(skeleton: &Skeleton, removed: &[bool]) -> Pruned {
    let count = removed.iter().filter(|&&r| r).count();
    if count == 0 {
        return Pruned {
            skeleton: skeleton.clone(),
            removed: 0,
        };
    }
    Pruned {
        skeleton: Skeleton::from_trusted(kept_parts(skeleton, removed)),
        removed: count,
    }
}

/// The skeleton without the `removed` branches: the kept ones renumbered (tips that lost
/// every child closed), with their frames, curves and colours, and the organs, leaf sites
/// and polygons on kept branches (or on none).
fn kept_parts(skeleton: &Skeleton, removed: &[bool]) -> SkeletonParts {
    let adjacency = skeleton.adjacency();
    let (mut parts, new_index) = kept(skeleton, removed);
    for (i, &k) in new_index.iter().enumerate() {
        let lost_every_child =
            !adjacency.is_tip(i) && adjacency.children(i).iter().all(|&c| removed[c as usize]);
        if k != NO_PARENT && lost_every_child {
            parts.branches[k as usize].end_radius = 0.0;
        }
    }
    parts
}

/// The skeleton without the `removed` branches (whose subtrees must be removed too), its
/// kept ones renumbered as they are, with their frames, curves and colours, and the
/// organs, leaf sites and polygons on kept branches (or on none); and each branch's new
/// index ([`NO_PARENT`] for a removed one).
pub(crate) fn kept(skeleton: &Skeleton, removed: &[bool]) -> (SkeletonParts, Vec<u32>) {
    let b = skeleton.branches();
    let mut new_index = vec![NO_PARENT; b.len()];
    let mut parts = SkeletonParts::default();
    for (i, x) in b.iter().enumerate() {
        if removed[i] {
            continue;
        }
        new_index[i] = parts.branches.len() as u32;
        let mut y = *x;
        if y.parent != NO_PARENT {
            y.parent = new_index[y.parent as usize];
        }
        parts.branches.push(y);
        if let Some(u) = skeleton.up(i) {
            parts.ups.push(u.to_array());
        }
        if skeleton.has_curves() {
            let c = skeleton.curve(i);
            parts.curves.push([c.p1.to_array(), c.p2.to_array()]);
        }
        if let Some(&c) = skeleton.colors().get(i) {
            parts.colors.push(c);
        }
    }
    let renumber = |branch: u32| match branch {
        NO_PARENT => Some(NO_PARENT),
        k => Some(new_index[k as usize]).filter(|&j| j != NO_PARENT),
    };
    for l in skeleton.leaves() {
        if let Some(branch) = renumber(l.branch) {
            parts.leaves.push(LeafSite { branch, ..*l });
        }
    }
    for o in skeleton.organs() {
        if let Some(branch) = renumber(o.branch) {
            parts.organs.push(Organ { branch, ..*o });
        }
    }
    for poly in skeleton.polygons() {
        if let Some(branch) = renumber(poly.branch) {
            parts.polygons.push(Polygon {
                first: parts.polygon_points.len() as u32,
                branch,
                ..*poly
            });
            parts
                .polygon_points
                .extend_from_slice(skeleton.polygon(poly));
        }
    }
    (parts, new_index)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distance_cases() {
        let d = |a: [f64; 3], b: [f64; 3], c: [f64; 3], e: [f64; 3]| {
            segment_distance_sq(a.into(), b.into(), c.into(), e.into()).sqrt()
        };
        assert!((d([0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]) - 1.0).abs() < 1e-12);
        assert!(d([0., 0., 0.], [2., 0., 0.], [1., -1., 1.], [1., 1., 1.]) - 1.0 < 1e-12);
        assert!((d([0., 0., 0.], [1., 0., 0.], [3., 0., 0.], [4., 0., 0.]) - 2.0).abs() < 1e-12);
        assert!(d([0., 0., 0.], [0., 0., 0.], [0., 0., 0.], [0., 0., 0.]).abs() < 1e-12);
    }

    #[test]
    fn bare_limbs_are_shed_with_their_subtrees() {
        let b = |parent: u32, order: u32, birth: u32, y: f32| Branch {
            start: [0.0, y, 0.0],
            end: [1.0, y + 1.0, 0.0],
            start_radius: 0.1,
            end_radius: 0.1,
            parent,
            birth,
            order,
            flags: 0,
        };
        let s = Skeleton::new(vec![
            b(NO_PARENT, 0, 0, 0.0), // 0: trunk
            b(0, 0, 1, 1.0),         // 1: trunk, old: stays (the axis)
            b(0, 1, 1, 1.0),         // 2: an old limb with only old wood: shed
            b(2, 1, 2, 2.0),         // 3: on it, old: shed with it
            b(1, 1, 2, 2.0),         // 4: an old limb ...
            b(4, 2, 9, 3.0),         // 5: ... carrying a young shoot: both stay
        ])
        .unwrap();
        let p = shed_bare(&s, 5);
        assert_eq!(p.removed, 2);
        let births: Vec<u32> = p.skeleton.branches().iter().map(|x| x.birth).collect();
        assert_eq!(births, vec![0, 1, 2, 9]);
        // Nothing young anywhere: every lateral goes, the trunk stays.
        assert_eq!(shed_bare(&s, 100).skeleton.len(), 2);
        assert_eq!(shed_bare(&s, 0).removed, 0);
    }
}
