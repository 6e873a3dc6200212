//! Curves on a skeleton: smoothing every axis into C¹ cubic Béziers, and editing one
//! branch's curve with its subtree carried along.

use super::{NO_PARENT, Skeleton};
use crate::error::{Error, Result};
use crate::geom::Curve;
use glam::Vec3;

impl Skeleton {
    /// Bends every branch into a cubic Bézier so that each axis is C¹ through its joints:
    /// the tangent at a joint is the mean of the two internodes' directions, and the
    /// handles are `tension` × a third of the internode's length (0 leaves the branches
    /// straight; 1 is the usual Catmull–Rom-like choice; up to 2). A lateral branch leaves
    /// its parent with its start tangent turned toward the parent's tangent by
    /// `tension / 2` of the way, so it grows out of the parent smoothly. Joints do not
    /// move: every curve still starts and ends where its branch does.
    pub fn smooth(&mut self, tension: f32) -> Result<()> {
        if !(tension.is_finite() && (0.0..=2.0).contains(&tension)) {
            return Err(Error::invalid(
                "tension",
                format!("{tension}; expected 0..=2"),
            ));
        }
        let n = self.branches.len();
        let dir: Vec<Vec3> = self
            .branches
            .iter()
            .map(|b| (b.end() - b.start()).normalize_or(Vec3::Y))
            .collect();
        let adjacency = self.adjacency().clone();
        let mut curves = Vec::with_capacity(n);
        for (i, b) in self.branches.iter().enumerate() {
            let third = b.length() / 3.0 * tension;
            let start_tangent = match b.parent {
                NO_PARENT => dir[i],
                p => {
                    let p = p as usize;
                    if adjacency.continuation(p) == Some(i as u32) {
                        (dir[p] + dir[i]).normalize_or(dir[i])
                    } else {
                        dir[i]
                            .lerp(dir[p], 0.5 * tension.min(1.0))
                            .normalize_or(dir[i])
                    }
                }
            };
            let end_tangent = match adjacency.continuation(i) {
                Some(c) => (dir[i] + dir[c as usize]).normalize_or(dir[i]),
                None => dir[i],
            };
            curves.push([
                (b.start() + start_tangent * third).to_array(),
                (b.end() - end_tangent * third).to_array(),
            ]);
        }
        self.curves = curves;
        Ok(())
    }

    /// Replaces branch `i`'s curve and radii. `curve.p0` must equal the branch's start
    /// (within 1e-5 of its length); every branch growing from it, directly or not, with
    /// their leaf sites and polygons, is moved by the displacement of `curve.p3`, so the
    /// tree stays connected. Fails by name, changing nothing, for an index past the end,
    /// a non-finite point or radius, a negative radius, or a start that is not the
    /// branch's.
    pub fn set_curve(&mut self, i: usize, curve: &Curve, r0: f32, r1: f32) -> Result<()> {
        let n = self.branches.len();
        if i >= n {
            return Err(Error::invalid(
                "branch",
                format!("{i}; the tree has {n} branches"),
            ));
        }
        let points = [curve.p0, curve.p1, curve.p2, curve.p3];
        let bound = crate::limits::MAX_COORDINATE;
        if !points
            .iter()
            .all(|p| p.is_finite() && p.abs().max_element() <= bound)
        {
            return Err(Error::invalid(
                "curve",
                "every control point must be finite and within 1e15 units",
            ));
        }
        for (name, r) in [("r0", r0), ("r1", r1)] {
            if !(r.is_finite() && (0.0..=bound).contains(&r)) {
                return Err(Error::invalid(
                    name,
                    format!("{r}; expected a radius from 0 to 1e15"),
                ));
            }
        }
        let b = self.branches[i];
        let tolerance = 1e-5 * b.length().max(1.0);
        if curve.p0.distance(b.start()) > tolerance {
            return Err(Error::invalid(
                "curve",
                format!(
                    "p0 {} is not the start {} of branch {i}; a curve must start where its branch does",
                    curve.p0,
                    b.start()
                ),
            ));
        }
        let moved = curve.p3 - b.end();
        if self.curves.is_empty() {
            self.curves = (0..n)
                .map(|k| {
                    let c = self.curve(k);
                    [c.p1.to_array(), c.p2.to_array()]
                })
                .collect();
        }
        // Descendants, in index order (parents come first).
        let mut above = vec![false; n];
        for k in i + 1..n {
            let p = self.branches[k].parent;
            above[k] = p != NO_PARENT && (p as usize == i || above[p as usize]);
        }
        if moved != Vec3::ZERO {
            let shift = |p: &mut [f32; 3]| *p = (Vec3::from(*p) + moved).to_array();
            for k in (i + 1..n).filter(|&k| above[k]) {
                shift(&mut self.branches[k].start);
                shift(&mut self.branches[k].end);
                for c in &mut self.curves[k] {
                    shift(c);
                }
            }
            for l in &mut self.leaves {
                if l.branch != NO_PARENT && above[l.branch as usize] {
                    shift(&mut l.position);
                }
            }
            for o in &mut self.organs {
                if o.branch != NO_PARENT && above[o.branch as usize] {
                    shift(&mut o.position);
                }
            }
            for poly in 0..self.polygons.len() {
                let p = self.polygons[poly];
                if p.branch != NO_PARENT && above[p.branch as usize] {
                    for q in
                        &mut self.polygon_points[p.first as usize..(p.first + p.count) as usize]
                    {
                        shift(q);
                    }
                }
            }
        }
        let b = &mut self.branches[i];
        b.end = curve.p3.to_array();
        b.start_radius = r0;
        b.end_radius = r1;
        self.curves[i] = [curve.p1.to_array(), curve.p2.to_array()];
        Ok(())
    }

    /// The curves of every branch, in branch order.
    pub fn curves(&self) -> impl Iterator<Item = Curve> + '_ {
        (0..self.branches.len()).map(|i| self.curve(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::honda::{self, HondaParams};

    #[test]
    fn smoothing_keeps_joints_and_makes_axes_c1() {
        let mut s = honda::build(&HondaParams::preset('b').unwrap()).unwrap();
        let before = s.branches().to_vec();
        s.smooth(1.0).unwrap();
        assert!(s.has_curves());
        assert_eq!(s.branches(), &before[..], "no joint moves");
        let adjacency = s.adjacency().clone();
        let mut joints = 0;
        for i in 0..s.len() {
            let c = s.curve(i);
            assert_eq!(c.p0, s.branches()[i].start());
            assert_eq!(c.p3, s.branches()[i].end());
            if let Some(k) = adjacency.continuation(i) {
                let next = s.curve(k as usize);
                // The sine of the angle (acos loses precision near 0 in f32).
                let (a, b) = (c.tangent(1.0).normalize(), next.tangent(0.0).normalize());
                let angle = a.cross(b).length();
                assert!(
                    a.dot(b) > 0.0 && angle < 1e-4,
                    "branch {i}: tangents {angle} rad apart"
                );
                joints += 1;
            }
        }
        assert!(joints > 100);
        assert!(s.smooth(f32::NAN).is_err());
        s.smooth(0.0).unwrap();
        assert!(s.curves().all(|c| c.p1 == c.p0 && c.p2 == c.p3));
    }

    #[test]
    fn an_edit_carries_the_subtree_and_bad_edits_change_nothing() {
        let mut s = honda::build(&HondaParams::preset('a').unwrap()).unwrap();
        let before = s.clone();
        let i = 1; // the trunk's continuation: almost the whole tree grows from it
        let old = s.curve(i);
        let moved = Vec3::new(5.0, -2.0, 1.0);
        let edited = Curve {
            p1: old.p1 + Vec3::X,
            p3: old.p3 + moved,
            ..old
        };
        s.set_curve(i, &edited, 3.0, 2.0).unwrap();
        let b = s.branches();
        for (k, x) in b.iter().enumerate() {
            if x.parent != NO_PARENT {
                assert_eq!(
                    x.start, b[x.parent as usize].end,
                    "branch {k} stays connected"
                );
            }
        }
        assert_eq!(s.curve(i), edited);
        assert_eq!((b[i].start_radius, b[i].end_radius), (3.0, 2.0));
        let grandchild = s.adjacency().children(i)[0] as usize;
        assert_eq!(
            b[grandchild].end(),
            before.branches()[grandchild].end() + moved,
            "the subtree moved with the end"
        );
        assert_eq!(b[0], before.branches()[0], "the trunk did not move");
        // Bad edits are refused by name and change nothing.
        let snapshot = s.clone();
        let bad_start = Curve {
            p0: edited.p0 + Vec3::Y,
            ..edited
        };
        let err = s
            .set_curve(i, &bad_start, 1.0, 1.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("start"), "{err}");
        let nan = Curve {
            p2: Vec3::NAN,
            ..edited
        };
        assert!(s.set_curve(i, &nan, 1.0, 1.0).is_err());
        assert!(
            s.set_curve(i, &edited, -1.0, 1.0)
                .unwrap_err()
                .to_string()
                .contains("r0")
        );
        assert!(
            s.set_curve(99_999, &edited, 1.0, 1.0)
                .unwrap_err()
                .to_string()
                .contains("branch")
        );
        assert_eq!(s, snapshot);
    }
}
