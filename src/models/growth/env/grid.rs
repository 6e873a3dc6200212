//! The shadow grid under an open sky: integer shadow on a lattice anchored at the origin,
//! stored densely over a region that grows with the trees.
//!
//! A cell is known by its lattice coordinates `floor(p / cell_size)`, packed into a
//! [`Key`]; where the grid's storage starts is nobody's business but the grid's. So the
//! same tree grows the same in any world box: the box bounds planting, seeding and
//! markers, and the region only has to hold every cell a shadow reaches (cells outside
//! it have no shadow, which is the truth: nothing casts there). Light comes from above
//! without limit; below the ground layer (the box's floor) there is neither shadow nor
//! light.
//!
//! The shadow is an integer count of `a / 65,536` units: a bud adds `round(65,536 b^−q)`
//! to each cell of its pyramid's layer `q`. Additions of integers are exact and do not
//! depend on their order (the grid wraps rather than saturates, so even an overflowed sum
//! comes back when its buds go), and a flat field has a gradient of exactly zero.

use super::{Error, Result, oom};

/// A cell's lattice coordinates, packed: 21 bits per axis (biased by [`BIAS`]), x lowest,
/// then y, then z; [`DARK`] set where a bud gets no light.
pub(crate) type Key = u64;

/// Set in a [`Key`] where a bud gets no light (below the ground, inside an obstacle, or
/// beyond the lattice's reach).
pub(crate) const DARK: Key = 1 << 63;

/// Added to a lattice coordinate to pack it; the lattice reaches ±(BIAS − 1) cells.
const BIAS: i64 = 1 << 20;
const AXIS: u64 = (1 << 21) - 1;

/// Shadow units per `a` (a bud's shadow in its own cell).
pub(crate) const UNIT: f32 = 65536.0;

/// Packs lattice coordinates; those beyond the lattice's reach are clamped and [`DARK`].
pub(crate) fn key([x, y, z]: [i64; 3]) -> Key {
    let far = [x, y, z].iter().any(|v| v.abs() >= BIAS);
    let c = |v: i64| (v.clamp(-(BIAS - 1), BIAS - 1) + BIAS) as u64;
    c(x) | (c(y) << 21) | (c(z) << 42) | if far { DARK } else { 0 }
}

/// The lattice coordinates of a key.
pub(crate) fn unkey(k: Key) -> [i64; 3] {
    [0, 21, 42].map(|s| ((k >> s) & AXIS) as i64 - BIAS)
}

/// The dense store of the lattice cells `lo .. lo + dims`, x fastest, then z, then y (a
/// layer of a pyramid is rows of x). `lo[1]` is always the ground layer.
#[derive(Clone, Debug, Default)]
pub(crate) struct Grid {
    pub(crate) lo: [i64; 3],
    pub(crate) dims: [usize; 3],
    pub(crate) cells: Vec<i32>,
    /// Buds in each column (x fastest, then z), at any height: what shades the ground.
    pub(crate) columns: Vec<i32>,
}

impl Grid {
    /// A zeroed grid over the lattice box `lo ..= hi`, refused past `max_cells`.
    pub(crate) fn new(lo: [i64; 3], hi: [i64; 3], max_cells: usize) -> Result<Self> {
        let dims = [0, 1, 2].map(|k| (hi[k] - lo[k] + 1).max(1) as usize);
        let cells = Self::count(dims, max_cells)?;
        let mut v = Vec::new();
        // Zeros written now: a lazily zeroed grid would be read through the shared zero
        // page and copied on its first write, two page faults per page, taken inside the
        // cycles' parallel passes.
        reserve(&mut v, cells, cells)?;
        v.resize(cells, 0);
        Ok(Grid {
            lo,
            dims,
            cells: v,
            columns: vec![0; dims[0] * dims[2]],
        })
    }

    /// A grid that stores no cell yet, on the ground layer `ground`.
    pub(crate) fn empty(ground: i64) -> Self {
        Grid {
            lo: [0, ground, 0],
            dims: [0; 3],
            cells: Vec::new(),
            columns: Vec::new(),
        }
    }

    fn count(dims: [usize; 3], max_cells: usize) -> Result<usize> {
        let cells = dims
            .iter()
            .try_fold(1usize, |a, &d| a.checked_mul(d))
            .unwrap_or(usize::MAX);
        let most = max_cells.min(super::MOST_CELLS);
        if cells > most {
            return Err(Error::LimitExceeded {
                limit_name: "max_cells",
                what: "cells of the shadow grid the trees and obstacles reach",
                limit: most as u64,
                requested: cells as u64,
                step: None,
            });
        }
        Ok(cells)
    }

    /// The index of lattice cell `c`, if the grid stores it.
    #[inline]
    pub(crate) fn index(&self, c: [i64; 3]) -> Option<usize> {
        let [nx, ny, nz] = self.dims;
        let x = (c[0] - self.lo[0]) as u64;
        let y = (c[1] - self.lo[1]) as u64;
        let z = (c[2] - self.lo[2]) as u64;
        (x < nx as u64 && y < ny as u64 && z < nz as u64)
            .then(|| ((y as usize * nz) + z as usize) * nx + x as usize)
    }

    /// The shadow of lattice cell `c` (0 where the grid does not reach: nothing casts
    /// there).
    #[inline]
    pub(crate) fn at(&self, c: [i64; 3]) -> i32 {
        self.index(c).map_or(0, |i| self.cells[i])
    }

    /// Grows the store (keeping every value) so that it holds the lattice box
    /// `lo ..= hi` (clipped below at the ground), with room to spare sideways and up;
    /// refused past `max_cells`, the grid unchanged.
    pub(crate) fn cover(&mut self, lo: [i64; 3], hi: [i64; 3], max_cells: usize) -> Result<()> {
        if let Some(relay) = self.reserve(lo, hi, max_cells)? {
            relay.run(self);
        }
        Ok(())
    }

    /// The fallible half of [`cover`](Self::cover): the new extent found, checked and
    /// its memory reserved, the values not yet moved. With a [`Relay`] the grid is not
    /// to be read or changed until the relay has [`run`](Relay::run) on it (cells
    /// elsewhere may be worked out meanwhile: a cell's key does not depend on the
    /// store); refused past `max_cells` or beyond the memory, the grid unchanged.
    pub(crate) fn reserve(
        &mut self,
        lo: [i64; 3],
        hi: [i64; 3],
        max_cells: usize,
    ) -> Result<Option<Relay>> {
        let ground = self.lo[1];
        let lo = [lo[0], lo[1].max(ground), lo[2]];
        if hi[1] < ground {
            return Ok(None);
        }
        if self.cells.is_empty() {
            // The first shade: what is asked, with room around it for a young tree.
            let m = 16;
            *self = Grid::new(
                [lo[0] - m, ground, lo[2] - m],
                [hi[0] + m, hi[1] + m, hi[2] + m],
                max_cells,
            )?;
            return Ok(None);
        }
        let old_hi = [0, 1, 2].map(|k| self.lo[k] + self.dims[k] as i64 - 1);
        if (0..3).all(|k| lo[k] >= self.lo[k] && hi[k] <= old_hi[k]) {
            return Ok(None);
        }
        // A quarter of the present extent to spare on each side that grows (and up), so a
        // crown that keeps widening re-lays the grid a logarithmic number of times.
        let spare = |k: usize| (self.dims[k] as i64 / 4).max(16);
        let mut new_lo = self.lo;
        let mut new_hi = old_hi;
        for k in [0, 2] {
            if lo[k] < self.lo[k] {
                new_lo[k] = lo[k] - spare(k);
            }
            if hi[k] > old_hi[k] {
                new_hi[k] = hi[k] + spare(k);
            }
        }
        if hi[1] > old_hi[1] {
            new_hi[1] = hi[1] + spare(1);
        }
        if new_lo[0] != self.lo[0]
            || new_lo[2] != self.lo[2]
            || new_hi[0] != old_hi[0]
            || new_hi[2] != old_hi[2]
        {
            // A sideways growth moves every row anyway: the sides the crowns are within a
            // spare of grow with it (and the top), so a forest widening every way re-lays
            // the grid once where it would a side at a time.
            for k in [0, 2] {
                if lo[k] - spare(k) < self.lo[k] {
                    new_lo[k] = new_lo[k].min(lo[k] - spare(k));
                }
                if hi[k] + spare(k) > old_hi[k] {
                    new_hi[k] = new_hi[k].max(hi[k] + spare(k));
                }
            }
            if hi[1] + spare(1) > old_hi[1] {
                new_hi[1] = new_hi[1].max(hi[1] + spare(1));
            }
        }
        let dims_of = |l: [i64; 3], h: [i64; 3]| [0, 1, 2].map(|k| (h[k] - l[k] + 1) as usize);
        if Self::count(dims_of(new_lo, new_hi), max_cells).is_err() {
            // No room to spare within `max_cells`: just what is asked.
            new_lo = [0, 1, 2].map(|k| lo[k].min(self.lo[k]));
            new_hi = [0, 1, 2].map(|k| hi[k].max(old_hi[k]));
        }
        let dims = dims_of(new_lo, new_hi);
        let cells = Self::count(dims, max_cells)?;
        let columns = dims[0] * dims[2];
        // Both stores grow in place (the allocator moves their pages rather than copying
        // them; a fresh store would take a page fault per 4 KiB of all of it) and only
        // what they gain is new memory; then the rows move to their new places.
        let more = (cells - self.cells.len(), columns - self.columns.len());
        reserve(&mut self.cells, more.0, cells)?;
        reserve(&mut self.columns, more.1, cells)?;
        let relay = Relay {
            old: self.dims,
            new: dims,
            at: [0, 2].map(|k| (self.lo[k] - new_lo[k]) as usize),
        };
        (self.lo, self.dims) = (new_lo, dims);
        Ok(Some(relay))
    }

    /// Buds in the column of lattice cell `c` (0 where the grid does not reach).
    pub(crate) fn column(&self, c: [i64; 3]) -> i32 {
        let [nx, _, nz] = self.dims;
        let x = (c[0] - self.lo[0]) as u64;
        let z = (c[2] - self.lo[2]) as u64;
        if x < nx as u64 && z < nz as u64 {
            self.columns[z as usize * nx + x as usize]
        } else {
            0
        }
    }

    /// The storage index of a change's cell, or `None` where its whole pyramid is under
    /// the ground (nothing to add).
    #[inline]
    pub(crate) fn change_index(&self, k: Key) -> Option<u32> {
        let c = unkey(k & !DARK);
        if c[1] < self.lo[1] {
            return None;
        }
        let i = self.index(c);
        debug_assert!(
            i.is_some(),
            "a change at {c:?} outside the grid: cover it first"
        );
        i.map(|i| i as u32)
    }
}

/// Counts `changes` (storage index, buds) into `columns`, the columns of a grid of `dims`
/// (apart from its cells, so the two can be worked on at once).
pub(crate) fn count_columns(columns: &mut [i32], dims: [usize; 3], changes: &[(u32, i32)]) {
    if changes.is_empty() {
        return;
    }
    let layer = Divisor::new((dims[0] * dims[2]) as u32);
    for &(c, n) in changes {
        let col = &mut columns[layer.rem(c) as usize];
        *col = col.wrapping_add(n);
    }
}

/// A fixed divisor of 32-bit storage indices, divided by with a multiplication instead
/// of a division instruction (Lemire, Kaser & Kurz, "Faster remainder by direct
/// computation", 2019): with `m = ceil(2^64 / d)`, `floor(a / d)` is the high 64 bits of
/// `m · a` and `a mod d` the high 64 bits of `(m · a mod 2^64) · d`, exact for every
/// 32-bit `a` and `d`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Divisor {
    d: u32,
    /// `ceil(2^64 / d)`; 0 for d = 1 (2^64 does not fit), which divides by itself.
    m: u64,
}

impl Divisor {
    /// Division by `d` (0 is taken as 1: a grid that stores no cell has no index to
    /// divide).
    pub(crate) fn new(d: u32) -> Self {
        let d = d.max(1);
        Divisor {
            d,
            m: (u64::MAX / d as u64).wrapping_add(1),
        }
    }

    /// `a / d`.
    #[inline(always)]
    pub(crate) fn div(self, a: u32) -> u32 {
        if self.m == 0 {
            return a;
        }
        ((self.m as u128 * a as u128) >> 64) as u32
    }

    /// `a % d`.
    #[inline(always)]
    pub(crate) fn rem(self, a: u32) -> u32 {
        let low = self.m.wrapping_mul(a as u64);
        ((low as u128 * self.d as u128) >> 64) as u32
    }
}

/// The values of a grid whose extent [`Grid::reserve`] grew, still where the old extent
/// had them: [`run`](Self::run) moves them (it cannot fail: the memory is reserved).
#[must_use = "the grid holds its old layout until the relay runs"]
#[derive(Debug)]
pub(crate) struct Relay {
    old: [usize; 3],
    new: [usize; 3],
    at: [usize; 2],
}

impl Relay {
    /// Moves the cells and columns of `grid` (the grid [`Grid::reserve`] gave this
    /// relay for) to the new extent's places.
    pub(crate) fn run(self, grid: &mut Grid) {
        let ([nx, _, nz], new) = (self.old, self.new);
        relay(&mut grid.cells, self.old, new, self.at);
        relay(&mut grid.columns, [nx, 1, nz], [new[0], 1, new[2]], self.at);
    }
}

/// Room in `v` for `more` values, or the error of a grid of `cells` cells that the
/// memory cannot hold.
fn reserve(v: &mut Vec<i32>, more: usize, cells: usize) -> Result<()> {
    v.try_reserve_exact(more).map_err(|_| {
        oom(format!(
            "the shadow grid ({cells} cells, {} bytes)",
            cells * 4
        ))
    })
}

/// Re-lays `data`, layers of `old[2]` rows of `old[0]` cells (x fastest) in place as
/// layers of `new[2]` rows of `new[0]`, with `new[1]` layers, an old cell (x, y, z) going
/// to (x + at[0], y, z + at[1]) and every other cell zero. No cell moves down, so the
/// rows move from the last to the first, each into room that is stale or already moved
/// out of, and the gaps between them are cleared on the way.
fn relay(data: &mut Vec<i32>, old: [usize; 3], new: [usize; 3], [ox, oz]: [usize; 2]) {
    let ([nx, ny, nz], [mx, my, mz]) = (old, new);
    let stored = data.len();
    data.resize(mx * my * mz, 0);
    if (nx, nz, ox, oz) == (mx, mz, 0, 0) {
        // Only layers above: the new ones are the zeros just added.
        return;
    }
    // Everything from `end` up is in its place.
    let mut end = stored;
    for y in (0..ny).rev() {
        for z in (0..nz).rev() {
            let (from, to) = ((y * nz + z) * nx, (y * mz + z + oz) * mx + ox);
            if to + nx < end {
                data[to + nx..end].fill(0);
            }
            data.copy_within(from..from + nx, to);
            end = to;
        }
    }
    data[..end].fill(0);
}
