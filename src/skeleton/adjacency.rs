//! Children and axes of a skeleton's branches, built once and shared by the mesher, leaves,
//! pruning and animation.

use super::{Branch, NO_PARENT};

/// For every branch: its children (in index order), the child that continues its axis
/// (same branching order), and its depth (branches between it and its root).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Adjacency {
    /// `children[first[i]..first[i + 1]]` are branch i's children.
    first: Vec<u32>,
    children: Vec<u32>,
    continuation: Vec<u32>,
    depth: Vec<u32>,
}

impl Adjacency {
    /// Built in two passes over `branches` (parents before children).
    pub fn new(branches: &[Branch]) -> Self {
        let n = branches.len();
        let mut first = vec![0u32; n + 1];
        for b in branches {
            if b.parent != NO_PARENT {
                first[b.parent as usize + 1] += 1;
            }
        }
        for i in 0..n {
            first[i + 1] += first[i];
        }
        let mut fill = first.clone();
        let mut children = vec![0u32; first[n] as usize];
        let mut continuation = vec![NO_PARENT; n];
        let mut depth = vec![0u32; n];
        for (i, b) in branches.iter().enumerate() {
            if b.parent == NO_PARENT {
                continue;
            }
            let p = b.parent as usize;
            children[fill[p] as usize] = i as u32;
            fill[p] += 1;
            depth[i] = depth[p] + 1;
            if continuation[p] == NO_PARENT && branches[p].order == b.order {
                continuation[p] = i as u32;
            }
        }
        Adjacency {
            first,
            children,
            continuation,
            depth,
        }
    }

    /// The children of branch `i`, in index order.
    #[inline]
    pub fn children(&self, i: usize) -> &[u32] {
        &self.children[self.first[i] as usize..self.first[i + 1] as usize]
    }

    /// The child that continues branch `i`'s axis (its first child of the same order).
    #[inline]
    pub fn continuation(&self, i: usize) -> Option<u32> {
        Some(self.continuation[i]).filter(|&c| c != NO_PARENT)
    }

    /// Branches between branch `i` and its root (0 for a root): its depth in the tree,
    /// unlike [`Branch::birth`], the step that made it.
    #[inline]
    pub fn depth(&self, i: usize) -> u32 {
        self.depth[i]
    }

    /// Whether no branch grows from branch `i`.
    #[inline]
    pub fn is_tip(&self, i: usize) -> bool {
        self.first[i] == self.first[i + 1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b(parent: u32, order: u32) -> Branch {
        Branch {
            parent,
            order,
            ..Default::default()
        }
    }

    #[test]
    fn children_axes_and_depths() {
        // 0 ─ 1 ─ 3      (axis 0 → 1 → 3, order 0)
        //  └─ 2 (lateral, order 1) ─ 4 (order 1)
        let a = Adjacency::new(&[b(NO_PARENT, 0), b(0, 0), b(0, 1), b(1, 0), b(2, 1)]);
        assert_eq!(a.children(0), &[1, 2]);
        assert_eq!(a.children(1), &[3]);
        assert_eq!(a.children(3), &[] as &[u32]);
        assert_eq!(a.continuation(0), Some(1));
        assert_eq!(a.continuation(2), Some(4));
        assert_eq!(a.continuation(3), None);
        assert_eq!((a.depth(0), a.depth(3), a.depth(4)), (0, 2, 2));
        assert!(a.is_tip(3) && a.is_tip(4) && !a.is_tip(2));
    }
}
