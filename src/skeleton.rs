//! The branch skeleton: the meeting point of every generator and the input of every mesher.

use crate::error::{Error, Result};
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// `parent` value of a branch that grows from nothing (a root).
pub const NO_PARENT: u32 = u32::MAX;

/// One internode (one `F` of the turtle): a truncated cone from `start` to `end`.
///
/// 48 bytes, `#[repr(C)]`, with exactly the layout of the C type `ArborBranch`.
/// Positions are in the model's units (the 1996 presets use a trunk of 100 units), Y up.
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
    /// Index of the branch it grows from, always smaller than its own index; [`NO_PARENT`]
    /// for a root.
    pub parent: u32,
    /// The rewriting step that produced the branch's `F` (axiom modules are step 0, so the
    /// trunk of the 1996 model, made by step 1, has depth 1).
    pub depth: u32,
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

/// A tree as a flat array of branches, parents before children.
///
/// Invariants (checked by [`Skeleton::new`], kept by every generator): every coordinate and
/// radius is finite, radii are non-negative, and `parent` is [`NO_PARENT`] or the index of an
/// earlier branch.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skeleton {
    branches: Vec<Branch>,
}

impl Skeleton {
    /// A skeleton from branches a host built itself; fails with
    /// [`Error::InvalidArgument`] naming the first branch that breaks an invariant.
    pub fn new(branches: Vec<Branch>) -> Result<Self> {
        for (i, b) in branches.iter().enumerate() {
            let finite = b.start.iter().chain(&b.end).all(|v| v.is_finite());
            if !finite {
                return Err(Error::invalid(
                    "branches",
                    format!("branch {i} has a non-finite start or end"),
                ));
            }
            for (r, name) in [
                (b.start_radius, "start_radius"),
                (b.end_radius, "end_radius"),
            ] {
                if !(r.is_finite() && r >= 0.0) {
                    return Err(Error::invalid(
                        "branches",
                        format!("branch {i} has {name} {r}; expected a finite radius >= 0"),
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
        Ok(Skeleton { branches })
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
