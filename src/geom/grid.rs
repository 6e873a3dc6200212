//! A sparse uniform 3-D grid of item ids, for neighbour queries over boxes (pruning's
//! collision candidates; later, shadow voxels and markers).
//!
//! Its cost is bounded whatever the items: an item whose box would cover more than
//! [`Grid::max_cells_per_item`] cells is kept in one list of large items instead of in
//! cells, and a query whose box covers more cells than the grid holds walks the stored
//! cells instead of the box.

use glam::DVec3;
use rustc_hash::FxHashMap;

/// Cells are cubes of edge `cell`; cell (i, j, k) covers `[i·cell, (i+1)·cell)` on each axis.
#[derive(Clone, Debug)]
pub struct Grid {
    cell: f64,
    max_cells_per_item: u64,
    cells: FxHashMap<[i64; 3], Vec<u32>>,
    large: Vec<u32>,
    /// Boxes of the large items, for queries that walk stored cells.
    large_boxes: Vec<(DVec3, DVec3)>,
}

/// Inclusive cell bounds of a box, and how many cells that is (saturating).
fn span(cell: f64, lo: DVec3, hi: DVec3) -> ([i64; 3], [i64; 3], u64) {
    let key = |v: DVec3| {
        (v / cell)
            .floor()
            .clamp(DVec3::splat(-1e15), DVec3::splat(1e15))
            .as_i64vec3()
            .to_array()
    };
    let (a, b) = (key(lo.min(hi)), key(lo.max(hi)));
    let count = (0..3).fold(1u64, |n, k| n.saturating_mul((b[k] - a[k] + 1) as u64));
    (a, b, count)
}

impl Grid {
    /// An empty grid of cells of edge `cell` (made at least 1e-9), in which one item takes
    /// at most `max_cells_per_item` cells.
    pub fn new(cell: f64, max_cells_per_item: u64) -> Self {
        Grid {
            cell: if cell.is_finite() {
                cell.max(1e-9)
            } else {
                1.0
            },
            max_cells_per_item: max_cells_per_item.max(1),
            cells: FxHashMap::default(),
            large: Vec::new(),
            large_boxes: Vec::new(),
        }
    }

    /// The most cells one item is put in; larger items go to the list of large items.
    pub fn max_cells_per_item(&self) -> u64 {
        self.max_cells_per_item
    }

    /// Number of cells that hold at least one item.
    pub fn cell_count(&self) -> usize {
        self.cells.len()
    }

    /// Adds item `id` to every cell its box `lo..=hi` touches.
    pub fn insert(&mut self, id: u32, lo: DVec3, hi: DVec3) {
        let (a, b, count) = span(self.cell, lo, hi);
        if count > self.max_cells_per_item {
            self.large.push(id);
            self.large_boxes.push((lo.min(hi), lo.max(hi)));
            return;
        }
        for x in a[0]..=b[0] {
            for y in a[1]..=b[1] {
                for z in a[2]..=b[2] {
                    self.cells.entry([x, y, z]).or_default().push(id);
                }
            }
        }
    }

    /// Appends to `out` (cleared first) every item that may touch the box `lo..=hi`: each
    /// once, in increasing order. Items far from the box may be included; none that
    /// touches it is left out.
    pub fn query(&self, lo: DVec3, hi: DVec3, out: &mut Vec<u32>) {
        out.clear();
        let (a, b, count) = span(self.cell, lo, hi);
        if count <= self.cells.len() as u64 {
            for x in a[0]..=b[0] {
                for y in a[1]..=b[1] {
                    for z in a[2]..=b[2] {
                        if let Some(v) = self.cells.get(&[x, y, z]) {
                            out.extend_from_slice(v);
                        }
                    }
                }
            }
        } else {
            let inside = |k: &[i64; 3]| (0..3).all(|i| (a[i]..=b[i]).contains(&k[i]));
            for (k, v) in &self.cells {
                if inside(k) {
                    out.extend_from_slice(v);
                }
            }
        }
        let (lo, hi) = (lo.min(hi), lo.max(hi));
        for (&id, &(l, h)) in self.large.iter().zip(&self.large_boxes) {
            if l.cmple(hi).all() && h.cmpge(lo).all() {
                out.push(id);
            }
        }
        out.sort_unstable();
        out.dedup();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queries_find_every_overlapping_item_once() {
        let mut g = Grid::new(1.0, 64);
        g.insert(0, DVec3::ZERO, DVec3::splat(0.5));
        g.insert(1, DVec3::splat(2.0), DVec3::splat(3.5));
        // Spans 1000 cells on x: goes to the large list.
        g.insert(2, DVec3::new(-500.0, 0.0, 0.0), DVec3::new(500.0, 0.4, 0.4));
        let mut out = Vec::new();
        g.query(DVec3::splat(0.25), DVec3::splat(0.3), &mut out);
        assert_eq!(out, vec![0, 2]);
        g.query(DVec3::splat(3.0), DVec3::splat(3.1), &mut out);
        assert_eq!(out, vec![1]);
        // A huge query walks the stored cells instead of 10^18 cells of the box.
        g.query(DVec3::splat(-1e6), DVec3::splat(1e6), &mut out);
        assert_eq!(out, vec![0, 1, 2]);
        assert_eq!(g.cell_count(), 1 + 8);
    }

    #[test]
    fn an_item_takes_at_most_the_cell_limit() {
        let mut g = Grid::new(1.0, 27);
        g.insert(0, DVec3::ZERO, DVec3::splat(2.5));
        assert_eq!(g.cell_count(), 27);
        g.insert(1, DVec3::ZERO, DVec3::splat(3.5));
        assert_eq!(g.cell_count(), 27, "64 cells > 27: kept as a large item");
    }
}
