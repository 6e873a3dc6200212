//! A tree's internodes as a structure of arrays.

use super::{BUD, Key};
use crate::skeleton::NO_PARENT;
use glam::Vec3;

/// A tree's internodes (metamers), one entry per internode in each array (structure of
/// arrays, so each pass of a cycle streams only the fields it reads). Internode `i` ends
/// in a node that holds a terminal bud (until the main axis grows on) and a lateral bud
/// (until a lateral shoot grows from it). An internode starts where its parent ends (the
/// root at the tree's base), and its lateral bud's direction follows from its heading
/// and phyllotaxis angle ([`lateral`]), so neither is stored.
#[derive(Clone, Debug, Default)]
pub(super) struct Nodes {
    pub(super) end: Vec<Vec3>,
    /// Unit heading.
    pub(super) dir: Vec<Vec3>,
    pub(super) parent: Vec<u32>,
    /// [the internode continuing the axis, the first of the lateral shoot]: an index,
    /// [`BUD`] or [`GONE`].
    pub(super) kids: Vec<[u32; 2]>,
    pub(super) birth: Vec<u32>,
    pub(super) order: Vec<u32>,
    /// Angle of the lateral bud about the heading, degrees.
    pub(super) phyllo: Vec<f32>,
    /// Radius^pipe_exponent; never shrinks.
    pub(super) rn: Vec<f32>,
    /// The cell word of the end, where the buds are ([`Env::cell_word`]).
    pub(super) cell: Vec<Key>,
    /// Internodes before it since its branch left the trunk (along the trunk: from the
    /// root), counted for droop.
    pub(super) along: Vec<u32>,
}

pub(super) struct NodeInit {
    pub(super) end: Vec3,
    pub(super) dir: Vec3,
    pub(super) parent: u32,
    pub(super) birth: u32,
    pub(super) order: u32,
    pub(super) phyllo: f32,
    pub(super) rn: f32,
    pub(super) cell: Key,
    pub(super) along: u32,
}

impl Nodes {
    pub(super) fn len(&self) -> usize {
        self.parent.len()
    }

    /// Whether internode `i` lives: the root, or an internode its parent lists (shed
    /// internodes still stored are listed by none).
    pub(super) fn lives(&self, i: usize) -> bool {
        let p = self.parent[i];
        p == NO_PARENT || self.kids[p as usize].contains(&(i as u32))
    }

    pub(super) fn push(&mut self, n: NodeInit) {
        self.end.push(n.end);
        self.dir.push(n.dir);
        self.parent.push(n.parent);
        self.kids.push([BUD, BUD]);
        self.birth.push(n.birth);
        self.order.push(n.order);
        self.phyllo.push(n.phyllo);
        self.rn.push(n.rn);
        self.cell.push(n.cell);
        self.along.push(n.along);
    }

    /// Moves internodes `from` to start at `to` (`to` ≤ `from.start`), every field.
    pub(super) fn move_run(&mut self, from: std::ops::Range<usize>, to: usize) {
        self.end.copy_within(from.clone(), to);
        self.dir.copy_within(from.clone(), to);
        self.parent.copy_within(from.clone(), to);
        self.kids.copy_within(from.clone(), to);
        self.birth.copy_within(from.clone(), to);
        self.order.copy_within(from.clone(), to);
        self.phyllo.copy_within(from.clone(), to);
        self.rn.copy_within(from.clone(), to);
        self.cell.copy_within(from.clone(), to);
        self.along.copy_within(from, to);
    }

    /// Keeps the first `n` internodes; gives memory back when the arrays are mostly
    /// empty (a tree that shed most of itself), keeping room to grow again.
    pub(super) fn truncate(&mut self, n: usize) {
        fn cut<T>(v: &mut Vec<T>, n: usize) {
            v.truncate(n);
            if v.capacity() > 256 && v.capacity() > 4 * n {
                v.shrink_to(2 * n);
            }
        }
        cut(&mut self.end, n);
        cut(&mut self.dir, n);
        cut(&mut self.parent, n);
        cut(&mut self.kids, n);
        cut(&mut self.birth, n);
        cut(&mut self.order, n);
        cut(&mut self.phyllo, n);
        cut(&mut self.rn, n);
        cut(&mut self.cell, n);
        cut(&mut self.along, n);
    }
}
