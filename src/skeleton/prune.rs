//! Pruning branches that run into each other: where two branches' volumes (capsules from
//! start, end and radius) intersect and the two do not meet at a joint, the one farther
//! from the root (greater depth; the later one on a tie) is removed with its whole
//! subtree, and a parent left with no children gets a closed tip (end radius 0). A uniform
//! grid keeps the pass near linear.

use crate::skeleton::{Branch, NO_PARENT, Skeleton};
use glam::DVec3;
use std::collections::HashMap;

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

/// Removes colliding branches (see the module documentation).
pub fn prune_collisions(skeleton: &Skeleton) -> Pruned {
    let b = skeleton.branches();
    let n = b.len();
    if n == 0 {
        return Pruned {
            skeleton: skeleton.clone(),
            removed: 0,
        };
    }
    // Cell size: the mean capsule extent, so most capsules touch a few cells.
    let extent: f64 = b
        .iter()
        .map(|x| {
            let (p, q, r) = ends(x);
            (q - p).length() + 2.0 * r
        })
        .sum::<f64>()
        / n as f64;
    let cell = extent.max(1e-9);
    let key = |v: DVec3| (v / cell).floor().as_i64vec3().to_array();
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_by_key(|&i| (b[i as usize].birth, i));
    let mut removed = vec![false; n];
    let mut candidates: Vec<u32> = Vec::new();
    for &i in &order {
        let x = &b[i as usize];
        if x.parent != NO_PARENT && removed[x.parent as usize] {
            removed[i as usize] = true;
            continue;
        }
        let (p, q, r) = ends(x);
        let lo = key(p.min(q) - DVec3::splat(r));
        let hi = key(p.max(q) + DVec3::splat(r));
        candidates.clear();
        for cx in lo[0]..=hi[0] {
            for cy in lo[1]..=hi[1] {
                for cz in lo[2]..=hi[2] {
                    if let Some(v) = grid.get(&[cx, cy, cz]) {
                        candidates.extend_from_slice(v);
                    }
                }
            }
        }
        candidates.sort_unstable();
        candidates.dedup();
        let hit = candidates.iter().any(|&j| {
            let y = &b[j as usize];
            if j == x.parent || adjacent(x, y) {
                return false;
            }
            let (p2, q2, r2) = ends(y);
            segment_distance_sq(p, q, p2, q2) < (r + r2) * (r + r2)
        });
        if hit {
            removed[i as usize] = true;
            continue;
        }
        for cx in lo[0]..=hi[0] {
            for cy in lo[1]..=hi[1] {
                for cz in lo[2]..=hi[2] {
                    grid.entry([cx, cy, cz]).or_default().push(i);
                }
            }
        }
    }
    // Renumber the kept branches, close tips that lost every child.
    let mut new_index = vec![NO_PARENT; n];
    let mut kept: Vec<Branch> = Vec::with_capacity(n);
    let (mut had_child, mut has_child) = (vec![false; n], vec![false; n]);
    for (i, x) in b.iter().enumerate() {
        if x.parent != NO_PARENT {
            had_child[x.parent as usize] = true;
            if !removed[i] {
                has_child[x.parent as usize] = true;
            }
        }
    }
    for (i, x) in b.iter().enumerate() {
        if removed[i] {
            continue;
        }
        new_index[i] = kept.len() as u32;
        let mut y = *x;
        if y.parent != NO_PARENT {
            y.parent = new_index[y.parent as usize];
        }
        if had_child[i] && !has_child[i] {
            y.end_radius = 0.0;
        }
        kept.push(y);
    }
    let count = n - kept.len();
    Pruned {
        skeleton: Skeleton::new(kept).expect("pruning keeps parents before children"),
        removed: count,
    }
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
}
