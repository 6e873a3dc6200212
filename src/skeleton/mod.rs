//! The branch skeleton: the meeting point of every generator and the input of every mesher.

mod adjacency;
mod curves;
pub mod prune;
pub mod twig;

pub use adjacency::Adjacency;

use crate::error::{Error, Result};
use crate::geom::Curve;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// The `parent` of a branch that grows from nothing (a root), and the `branch` of a leaf
/// site or organ on no branch (ARBOR_NO_PARENT in C).
pub const NO_PARENT: u32 = u32::MAX;

/// One internode (one `F` of the turtle): a truncated cone from `start` to `end`.
///
/// 48 bytes; C: ArborBranch, whose field `depth` is `birth` here.
/// Positions are in the model's units (the 1996 presets use a trunk of 100 units), Y up.
///
/// cbindgen:field-names=[start, end, start_radius, end_radius, parent, depth, order, flags]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Branch {
    /// Where the branch starts (at its parent's `end` for a non-root).
    pub start: [f32; 3],
    /// Where the branch ends.
    pub end: [f32; 3],
    /// Radius at `start` (half the turtle's width `!(w)`).
    pub start_radius: f32,
    /// Radius at `end`.
    pub end_radius: f32,
    /// Index of the branch it grows from, always smaller than its own index; NO_PARENT
    /// (ARBOR_NO_PARENT) for a root.
    pub parent: u32,
    /// Its birth: the rewriting step that produced the branch's `F` (axiom modules are step
    /// 0, so the trunk of the 1996 model, made by step 1, has birth 1); for a
    /// self-organized tree, the growth cycle. Not the distance from the root (Rust:
    /// `Adjacency::depth`). Named `depth` in C.
    pub birth: u32,
    /// Branching order: 0 on the trunk axis, +1 for each lateral branch on the way.
    pub order: u32,
    /// Reserved, 0.
    pub flags: u32,
}

const _: () = assert!(std::mem::size_of::<Branch>() == 48);

impl Branch {
    /// `start` as a vector.
    #[inline]
    pub fn start(&self) -> Vec3 {
        Vec3::from_array(self.start)
    }
    /// `end` as a vector.
    #[inline]
    pub fn end(&self) -> Vec3 {
        Vec3::from_array(self.end)
    }
    /// Length of the branch axis.
    #[inline]
    pub fn length(&self) -> f32 {
        (self.end() - self.start()).length()
    }
    /// Whether the branch is a root (has no parent).
    #[inline]
    pub fn is_root(&self) -> bool {
        self.parent == NO_PARENT
    }
}

/// A place where the turtle met `~`: where a leaf (or another organ) goes. 44 bytes; C:
/// ArborLeafSite, whose field `depth` is `birth` here.
///
/// cbindgen:field-names=[position, heading, up, branch, depth]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LeafSite {
    /// Where the turtle stood.
    pub position: [f32; 3],
    /// The turtle's heading H there (unit).
    pub heading: [f32; 3],
    /// The turtle's up vector U there (unit).
    pub up: [f32; 3],
    /// The branch the site sits on (the last one drawn on the turtle's axis), or
    /// NO_PARENT (ARBOR_NO_PARENT).
    pub branch: u32,
    /// The rewriting step that produced the `~` (the C field `depth`).
    pub birth: u32,
}

/// The `kind` of an organ that is a sphere (`@O(d)`; ARBOR_ORGAN_SPHERE in C).
pub const ORGAN_SPHERE: u32 = 0;
/// The `kind` of an organ that is a disc facing the turtle's heading (`@o(d)`, `@c(d)`;
/// ARBOR_ORGAN_DISC in C).
pub const ORGAN_DISC: u32 = 1;

/// A sphere or disc the turtle placed (`@O`, `@o`, `@c`): 56 bytes; C: ArborOrgan, whose
/// field `depth` is `birth` here.
///
/// cbindgen:field-names=[position, heading, up, size, kind, branch, depth, color]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Organ {
    /// Its centre: where the turtle stood.
    pub position: [f32; 3],
    /// The turtle's heading H there (unit): a disc's normal.
    pub heading: [f32; 3],
    /// The turtle's up vector U there (unit).
    pub up: [f32; 3],
    /// Diameter.
    pub size: f32,
    /// ORGAN_SPHERE or ORGAN_DISC (ARBOR_ORGAN_SPHERE, ARBOR_ORGAN_DISC).
    pub kind: u32,
    /// The branch it sits on, or NO_PARENT (ARBOR_NO_PARENT).
    pub branch: u32,
    /// The rewriting step that produced it.
    pub birth: u32,
    /// The turtle's colour index there (`;` and `,`).
    pub color: u32,
}

const _: () = assert!(std::mem::size_of::<Organ>() == 56);

/// A polygon the turtle traced between `{` and `}` (a leaf blade, a petal).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Polygon {
    /// Index of the first point in [`Skeleton::polygon_points`].
    pub first: u32,
    /// Number of points (at least 3).
    pub count: u32,
    /// The branch the polygon sits on, or [`NO_PARENT`].
    pub branch: u32,
    /// The rewriting step that produced the `{`.
    pub birth: u32,
}

/// A tree as a flat array of branches, parents before children, with the leaf sites and
/// polygons the turtle recorded, the turtle's frame per branch where the generator had
/// one, one cubic Bezier curve per branch, and the children and axes of every branch
/// (built once, on first use, and shared by every stage that needs them).
///
/// Invariants (checked by [`SkeletonParts::build`], kept by every generator): every
/// coordinate and radius is finite, radii are non-negative, `parent` is [`NO_PARENT`] or
/// the index of an earlier branch, every organ's branch is in range, and every polygon has
/// at least three points inside `polygon_points`.
#[derive(Clone, Debug, Default)]
pub struct Skeleton {
    branches: Vec<Branch>,
    leaves: Vec<LeafSite>,
    polygons: Vec<Polygon>,
    polygon_points: Vec<[f32; 3]>,
    /// The turtle's up vector when each branch was drawn; empty when the generator had no
    /// frame (a host's own skeleton).
    ups: Vec<[f32; 3]>,
    /// The inner control points (p1, p2) of each branch's curve; empty while every branch
    /// is straight.
    curves: Vec<[[f32; 3]; 2]>,
    organs: Vec<Organ>,
    /// The colour index (`;` `,`) of each branch; empty when the generator set none.
    colors: Vec<u32>,
    adjacency: std::sync::OnceLock<Adjacency>,
}

impl PartialEq for Skeleton {
    /// Equal content; whether the adjacency has been built yet does not matter.
    fn eq(&self, other: &Self) -> bool {
        self.branches == other.branches
            && self.leaves == other.leaves
            && self.polygons == other.polygons
            && self.polygon_points == other.polygon_points
            && self.ups == other.ups
            && self.curves == other.curves
            && self.organs == other.organs
            && self.colors == other.colors
    }
}

/// Everything a skeleton is made of, for hosts and generators that bring their own:
/// [`build`](SkeletonParts::build) checks every invariant and names the first element that
/// breaks one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SkeletonParts {
    /// The branches, parents before children.
    pub branches: Vec<Branch>,
    /// Leaf sites; each `branch` is [`NO_PARENT`] or a branch index.
    pub leaves: Vec<LeafSite>,
    /// Polygons; each at least 3 points of `polygon_points`.
    pub polygons: Vec<Polygon>,
    /// The points of all polygons.
    pub polygon_points: Vec<[f32; 3]>,
    /// Empty, or one up vector per branch (the turtle's U when the branch was drawn):
    /// the mesher starts its rings' seams there.
    pub ups: Vec<[f32; 3]>,
    /// Empty (every branch straight), or the inner control points (p1, p2) of each
    /// branch's cubic Bezier curve from `start` to `end`.
    pub curves: Vec<[[f32; 3]; 2]>,
    /// Spheres and discs; each `branch` is [`NO_PARENT`] or a branch index.
    pub organs: Vec<Organ>,
    /// Empty, or one colour index per branch.
    pub colors: Vec<u32>,
}

/// Finite and within [`MAX_COORDINATE`](crate::limits::MAX_COORDINATE).
fn finite3(p: &[f32; 3]) -> bool {
    p.iter()
        .all(|v| v.is_finite() && v.abs() <= crate::limits::MAX_COORDINATE)
}

impl SkeletonParts {
    /// Every branch finite, its radii from 0 to 1e15, its parent earlier (or none).
    fn check_branches(&self) -> Result<()> {
        // One pass without early exits (a few instructions a branch); the first branch at
        // fault is looked for only when there is one.
        let m = crate::limits::MAX_COORDINATE;
        let hold = self.branches.iter().enumerate().fold(true, |ok, (i, b)| {
            let ends = b
                .start
                .iter()
                .chain(&b.end)
                .fold(true, |a, v| a & (v.abs() <= m));
            let radii = (b.start_radius >= 0.0)
                & (b.start_radius <= m)
                & (b.end_radius >= 0.0)
                & (b.end_radius <= m);
            let parent = (b.parent == NO_PARENT) | ((b.parent as usize) < i);
            ok & ends & radii & parent
        });
        if hold {
            return Ok(());
        }
        for (i, b) in self.branches.iter().enumerate() {
            if !(finite3(&b.start) && finite3(&b.end)) {
                return Err(Error::invalid(
                    "branches",
                    format!("branch {i} has a non-finite start or end"),
                ));
            }
            for (r, name) in [
                (b.start_radius, "start_radius"),
                (b.end_radius, "end_radius"),
            ] {
                if !(r.is_finite() && (0.0..=crate::limits::MAX_COORDINATE).contains(&r)) {
                    return Err(Error::invalid(
                        "branches",
                        format!("branch {i} has {name} {r}; expected a radius from 0 to 1e15"),
                    ));
                }
            }
            if b.parent != NO_PARENT && b.parent as usize >= i {
                return Err(Error::invalid(
                    "branches",
                    format!(
                        "branch {i} has parent {}; expected an earlier branch or NO_PARENT",
                        b.parent
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Leaf sites, polygons and organs finite, well formed and on a branch (or none).
    fn check_organs(&self) -> Result<()> {
        let n = self.branches.len();
        // An organ sits on a branch of the skeleton or on none.
        let on_branch = |field: &'static str, what: String, branch: u32| {
            if branch == NO_PARENT || (branch as usize) < n {
                Ok(())
            } else {
                Err(Error::invalid(
                    field,
                    format!(
                        "{what} is on branch {branch}; expected one of the {n} branches or NO_PARENT"
                    ),
                ))
            }
        };
        for (i, l) in self.leaves.iter().enumerate() {
            if !(finite3(&l.position) && finite3(&l.heading) && finite3(&l.up)) {
                return Err(Error::invalid(
                    "leaves",
                    format!("leaf site {i} has a non-finite position or direction"),
                ));
            }
            on_branch("leaves", format!("leaf site {i}"), l.branch)?;
        }
        if let Some(i) = self.polygon_points.iter().position(|p| !finite3(p)) {
            return Err(Error::invalid(
                "polygon_points",
                format!("point {i} is not finite"),
            ));
        }
        for (i, p) in self.polygons.iter().enumerate() {
            if p.count < 3 {
                return Err(Error::invalid(
                    "polygons",
                    format!("polygon {i} has {} points; expected at least 3", p.count),
                ));
            }
            if p.first as u64 + p.count as u64 > self.polygon_points.len() as u64 {
                return Err(Error::invalid(
                    "polygons",
                    format!(
                        "polygon {i} reaches past the {} points",
                        self.polygon_points.len()
                    ),
                ));
            }
            on_branch("polygons", format!("polygon {i}"), p.branch)?;
        }
        for (i, o) in self.organs.iter().enumerate() {
            if !(finite3(&o.position) && finite3(&o.heading) && finite3(&o.up)) {
                return Err(Error::invalid(
                    "organs",
                    format!("organ {i} has a non-finite position or direction"),
                ));
            }
            if !(o.size.is_finite() && (0.0..=crate::limits::MAX_COORDINATE).contains(&o.size))
                || o.kind > ORGAN_DISC
            {
                return Err(Error::invalid(
                    "organs",
                    format!(
                        "organ {i} has size {} and kind {}; expected a finite size >= 0 and \
                         ORGAN_SPHERE or ORGAN_DISC",
                        o.size, o.kind
                    ),
                ));
            }
            on_branch("organs", format!("organ {i}"), o.branch)?;
        }
        Ok(())
    }

    /// Ups, curves and colours: none or one per branch, finite.
    fn check_per_branch(&self) -> Result<()> {
        let n = self.branches.len();
        for (field, len) in [
            ("ups", self.ups.len()),
            ("curves", self.curves.len()),
            ("colors", self.colors.len()),
        ] {
            if len != 0 && len != n {
                return Err(Error::invalid(
                    field,
                    format!("{len} entries; expected none or one per branch ({n})"),
                ));
            }
        }
        let m = crate::limits::MAX_COORDINATE;
        let ups_hold = self.ups.iter().fold(true, |ok, u| {
            ok & u.iter().fold(true, |a, v| a & (v.abs() <= m))
        });
        if let Some(i) = (!ups_hold)
            .then(|| self.ups.iter().position(|u| !finite3(u)))
            .flatten()
        {
            return Err(Error::invalid(
                "ups",
                format!("up vector {i} is not finite"),
            ));
        }
        if let Some(i) = self
            .curves
            .iter()
            .position(|c| !(finite3(&c[0]) && finite3(&c[1])))
        {
            return Err(Error::invalid(
                "curves",
                format!("curve {i} has a non-finite control point"),
            ));
        }
        Ok(())
    }

    /// The skeleton, or [`Error::InvalidArgument`] naming the first element that breaks an
    /// invariant.
    pub fn build(self) -> Result<Skeleton> {
        self.check_branches()?;
        self.check_organs()?;
        self.check_per_branch()?;
        Ok(self.build_trusted())
    }

    fn build_trusted(self) -> Skeleton {
        Skeleton {
            branches: self.branches,
            leaves: self.leaves,
            polygons: self.polygons,
            polygon_points: self.polygon_points,
            ups: self.ups,
            curves: self.curves,
            organs: self.organs,
            colors: self.colors,
            adjacency: std::sync::OnceLock::new(),
        }
    }
}

impl Skeleton {
    /// A skeleton from branches a host built itself; fails with
    /// [`Error::InvalidArgument`] naming the first branch that breaks an invariant.
    pub fn new(branches: Vec<Branch>) -> Result<Self> {
        SkeletonParts {
            branches,
            ..Default::default()
        }
        .build()
    }

    /// A skeleton with leaf sites and polygons; checked like [`SkeletonParts::build`].
    pub fn with_organs(
        branches: Vec<Branch>,
        leaves: Vec<LeafSite>,
        polygons: Vec<Polygon>,
        polygon_points: Vec<[f32; 3]>,
    ) -> Result<Self> {
        SkeletonParts {
            branches,
            leaves,
            polygons,
            polygon_points,
            ..Default::default()
        }
        .build()
    }

    /// For generators that keep the invariants by construction (checked in debug builds).
    pub(crate) fn from_trusted(parts: SkeletonParts) -> Self {
        debug_assert!(parts.clone().build().is_ok());
        parts.build_trusted()
    }

    /// Everything the skeleton is made of, to change and build again.
    pub fn into_parts(self) -> SkeletonParts {
        SkeletonParts {
            branches: self.branches,
            leaves: self.leaves,
            polygons: self.polygons,
            polygon_points: self.polygon_points,
            ups: self.ups,
            curves: self.curves,
            organs: self.organs,
            colors: self.colors,
        }
    }

    /// The spheres and discs the turtle placed (`@O`, `@o`, `@c`).
    pub fn organs(&self) -> &[Organ] {
        &self.organs
    }

    /// The colour index (`;` `,`) of each branch; empty when the generator set none.
    pub fn colors(&self) -> &[u32] {
        &self.colors
    }

    /// The turtle's up vector when branch `i` was drawn, if the generator had a turtle.
    #[inline]
    pub fn up(&self, i: usize) -> Option<Vec3> {
        self.ups.get(i).map(|&u| Vec3::from(u))
    }

    /// Whether any branch has a curve of its own (else all are straight).
    pub fn has_curves(&self) -> bool {
        !self.curves.is_empty()
    }

    /// Whether the skeleton carries the turtle's frame per branch.
    pub fn has_frames(&self) -> bool {
        !self.ups.is_empty()
    }

    /// Branch `i`'s curve: a cubic Bezier from its start to its end (straight, control
    /// points at the thirds, unless a generator or an edit bent it).
    pub fn curve(&self, i: usize) -> Curve {
        let b = &self.branches[i];
        match self.curves.get(i) {
            Some([p1, p2]) => Curve {
                p0: b.start(),
                p1: Vec3::from(*p1),
                p2: Vec3::from(*p2),
                p3: b.end(),
            },
            None => Curve::straight(b.start(), b.end()),
        }
    }

    /// Children and axes of every branch, built on first use and kept.
    pub fn adjacency(&self) -> &Adjacency {
        self.adjacency
            .get_or_init(|| Adjacency::new(&self.branches))
    }

    /// Leaf sites recorded by `~`.
    pub fn leaves(&self) -> &[LeafSite] {
        &self.leaves
    }

    /// Polygons recorded by `{ . }`.
    pub fn polygons(&self) -> &[Polygon] {
        &self.polygons
    }

    /// The points of all polygons.
    pub fn polygon_points(&self) -> &[[f32; 3]] {
        &self.polygon_points
    }

    /// The points of one polygon.
    pub fn polygon(&self, p: &Polygon) -> &[[f32; 3]] {
        &self.polygon_points[p.first as usize..(p.first + p.count) as usize]
    }

    /// The branches, parents before children.
    #[inline]
    pub fn branches(&self) -> &[Branch] {
        &self.branches
    }

    /// Number of branches.
    #[inline]
    pub fn len(&self) -> usize {
        self.branches.len()
    }

    /// Whether there are no branches.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.branches.is_empty()
    }

    /// Takes the branches out.
    pub fn into_branches(self) -> Vec<Branch> {
        self.branches
    }

    /// Axis-aligned bounds of all branch end points, `None` when empty. Radii are not
    /// included.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut it = self.branches.iter();
        let first = it.next()?;
        let mut lo = first.start().min(first.end());
        let mut hi = first.start().max(first.end());
        for b in it {
            lo = lo.min(b.start()).min(b.end());
            hi = hi.max(b.start()).max(b.end());
        }
        Some((lo, hi))
    }
}

/// Sets every branch's `order` from `cos_to_parent[i]`, the cosine of the angle between
/// branch `i`'s heading and its parent's (any value for roots): of a branch's children,
/// the one that deviates least continues its axis (same order); the others start lateral
/// axes (order + 1). Ties (within 1e-9) go to the first child. Roots have order 0.
///
/// For the 1996 model this is "the child with the smaller branching angle continues the
/// axis"; for a grammar, `F F` continues an axis and `[+F]` leaves it. Generators pass the
/// cosines of their exact (`f64`) headings, so ties such as ±35 degrees are not broken by the
/// rounding of stored `f32` coordinates.
pub fn assign_axis_orders(branches: &mut [Branch], cos_to_parent: &[f64]) {
    assert_eq!(branches.len(), cos_to_parent.len());
    // The continuing child of each branch: (index, cosine).
    let mut best: Vec<(u32, f64)> = vec![(NO_PARENT, f64::NEG_INFINITY); branches.len()];
    for (i, b) in branches.iter().enumerate() {
        if b.parent == NO_PARENT {
            continue;
        }
        let cos = cos_to_parent[i];
        let slot = &mut best[b.parent as usize];
        if slot.0 == NO_PARENT || cos > slot.1 + 1e-9 {
            *slot = (i as u32, cos);
        }
    }
    for i in 0..branches.len() {
        let p = branches[i].parent;
        branches[i].order = if p == NO_PARENT {
            0
        } else {
            branches[p as usize].order + u32::from(best[p as usize].0 != i as u32)
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn branch(parent: u32) -> Branch {
        Branch {
            end: [0.0, 1.0, 0.0],
            start_radius: 1.0,
            end_radius: 1.0,
            parent,
            ..Branch::default()
        }
    }

    #[test]
    fn new_checks_invariants() {
        assert!(Skeleton::new(vec![branch(NO_PARENT), branch(0)]).is_ok());
        let err = Skeleton::new(vec![branch(NO_PARENT), branch(1)]).unwrap_err();
        assert!(err.to_string().contains("branch 1 has parent 1"), "{err}");
        let mut nan = branch(NO_PARENT);
        nan.end[1] = f32::NAN;
        assert!(Skeleton::new(vec![nan]).is_err());
        let mut neg = branch(NO_PARENT);
        neg.end_radius = -1.0;
        let err = Skeleton::new(vec![neg]).unwrap_err();
        assert!(err.to_string().contains("end_radius"), "{err}");
        // Each invariant fails the one-pass check and is then named, on a later branch too.
        type Spoil = fn(&mut Branch);
        let cases: [(Spoil, &str); 5] = [
            (|b| b.start[0] = f32::INFINITY, "non-finite start or end"),
            (|b| b.end[2] = -2e15, "non-finite start or end"),
            (|b| b.start_radius = f32::NAN, "start_radius NaN"),
            (|b| b.end_radius = 2e15, "end_radius 2000000000000000"),
            (|b| b.parent = 5, "branch 2 has parent 5"),
        ];
        for (spoil, says) in cases {
            let mut bad = branch(0);
            spoil(&mut bad);
            let err = Skeleton::new(vec![branch(NO_PARENT), branch(0), bad]).unwrap_err();
            assert!(err.to_string().contains(says), "{says}: {err}");
        }
        let parts = |up: [f32; 3]| SkeletonParts {
            branches: vec![branch(NO_PARENT), branch(0)],
            ups: vec![[0.0, 0.0, 1.0], up],
            ..Default::default()
        };
        assert!(parts([1.0, 0.0, 0.0]).build().is_ok());
        let err = parts([f32::NAN, 0.0, 0.0]).build().unwrap_err();
        assert!(err.to_string().contains("up vector 1"), "{err}");
    }

    #[test]
    fn bounds_cover_all_points() {
        let mut b = branch(NO_PARENT);
        b.start = [-2.0, 0.0, 1.0];
        let s = Skeleton::new(vec![b, branch(0)]).unwrap();
        let (lo, hi) = s.bounds().unwrap();
        assert_eq!(lo, Vec3::new(-2.0, 0.0, 0.0));
        assert_eq!(hi, Vec3::new(0.0, 1.0, 1.0));
        assert!(Skeleton::default().bounds().is_none());
    }
}
