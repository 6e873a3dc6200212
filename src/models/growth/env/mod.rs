//! The environment a world's trees share: a shadow voxel grid, or attraction markers on a
//! uniform grid, and the obstacles placed in it.

use super::{Environment, GrowthParams, WorldOptions};
use crate::error::{Error, Result};
use glam::Vec3;

mod changes;
mod grid;
mod obstacles;
#[cfg(test)]
mod tests;

#[cfg(test)]
use changes::apply_changes;
#[cfg(test)]
use changes::merge_changes;
use changes::{apply_layers, sort_changes};
pub(crate) use grid::{DARK, Key};
use grid::{Grid, UNIT, key, unkey};
pub use obstacles::Obstacle;

fn oom(what: String) -> Error {
    Error::OutOfMemory { what }
}

/// The box around `points` (none for no points).
pub(crate) fn bounds(points: impl IntoIterator<Item = Vec3>) -> Option<(Vec3, Vec3)> {
    let (lo, hi) = points
        .into_iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p), hi.max(p))
        });
    (lo.x <= hi.x).then_some((lo, hi))
}

/// Most obstacles a world may hold.
pub const MAX_OBSTACLES: usize = 1 << 20;

/// Edge, in cells, of the buckets that list the obstacles overlapping them.
const BUCKET: i64 = 8;

/// Most cells a grid may have.
pub(crate) const MOST_CELLS: usize = 1 << 31;

/// One bud as the environment sees it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bud {
    pub(crate) position: Vec3,
    pub(crate) direction: Vec3,
}

/// Changes a flush applies on the calling thread alone (more pay for waking a second).
#[cfg(feature = "parallel")]
const APPLY_ALONE: usize = 1 << 11;

/// Bands of layers a flush is applied in on several threads.
const BANDS: usize = 4;

/// The shared environment.
#[derive(Clone, Debug)]
pub(crate) struct Env {
    kind: Environment,
    /// The world box's corner and its cells (the markers' grid).
    origin: Vec3,
    inv_cell: f32,
    cell: f32,
    dims: [usize; 3],
    /// The shadow (shadow worlds; see [`grid`]).
    grid: Grid,
    /// round(UNIT·b^−q) for q = 0..=q_max: a bud's shadow in its pyramid's layer q.
    falloff: Vec<i32>,
    full_light: f32,
    strength: f32,
    max_cells: usize,
    /// Markers (space colonization), binned by cell: `markers[first[c]..first[c + 1]]`.
    first: Vec<u32>,
    markers: Vec<Vec3>,
    alive: Vec<bool>,
    min: Vec3,
    max: Vec3,
    /// Shadow changes not applied yet: (cell, buds added there, negative for removed).
    pending: Vec<(Key, i32)>,
    /// The changes of a flush by storage index, sorted, and the radix sort's other
    /// buffers (see [`sort_changes`]).
    sorted: Vec<(u32, i32)>,
    scratch: [Vec<(u32, i32)>; 4],
    /// The 2-D difference arrays of the bands a flush is applied in.
    diff: [Vec<i32>; BANDS],
    obstacles: Vec<Obstacle>,
    /// The ground under the world, or none (the box's floor).
    ground: Option<std::sync::Arc<super::HeightField>>,
    /// A lattice layer at or above the ground's everywhere (its highest sample's, with a
    /// margin for rounding): a cell above it is above the ground wherever it is, with no
    /// height to look up; `i64::MAX` without a height field.
    ground_top: i64,
    /// The obstacles whose bounds overlap each lattice bucket of [`BUCKET`]³ cells, so a
    /// point is tested only against those near it.
    buckets: rustc_hash::FxHashMap<[i64; 3], Vec<u32>>,
}

impl Env {
    pub(crate) fn new(o: &WorldOptions) -> Result<Self> {
        let (min, max) = (Vec3::from(o.min), Vec3::from(o.max));
        let dims = [0, 1, 2].map(|k| (((max[k] - min[k]) / o.cell_size).ceil() as usize).max(1));
        let cells = dims[0] * dims[1] * dims[2];
        let inv_cell = 1.0 / o.cell_size;
        let mut env = Env {
            kind: o.environment,
            origin: min,
            inv_cell,
            cell: o.cell_size,
            dims,
            grid: Grid::default(),
            falloff: (0..=o.shadow_depth)
                .map(|q| (UNIT * libm::powf(o.shadow_falloff, -(q as f32))).round() as i32)
                .collect(),
            full_light: o.full_light,
            strength: o.shadow_strength,
            max_cells: o.max_cells,
            first: Vec::new(),
            markers: Vec::new(),
            alive: Vec::new(),
            min,
            max,
            pending: Vec::new(),
            sorted: Vec::new(),
            scratch: Default::default(),
            diff: Default::default(),
            obstacles: Vec::new(),
            ground: None,
            ground_top: i64::MAX,
            buckets: Default::default(),
        };
        match o.environment {
            Environment::Shadow => {
                // One cell on the ground (the box's floor): the grid grows to hold what
                // the trees and obstacles shade (`cover`), so a world pays for the
                // shadow its trees cast, not for its box.
                env.grid = Grid::empty(env.lattice(min)[1]);
            }
            Environment::SpaceColonization => {
                // One marker per cell, jittered inside it (seeded).
                let mut rng = crate::rng::Rng::new(o.seed ^ 0x3A2C_E125_0000_0001);
                let bytes = cells * (4 + 12 + 1);
                let what = || oom(format!("the markers ({cells} cells, {bytes} bytes)"));
                env.first.try_reserve_exact(cells + 1).map_err(|_| what())?;
                env.markers.try_reserve_exact(cells).map_err(|_| what())?;
                env.alive.try_reserve_exact(cells).map_err(|_| what())?;
                for c in 0..cells {
                    env.first.push(c as u32);
                    let (x, y, z) = env.coords(c);
                    let jitter = Vec3::new(
                        rng.next_f64() as f32,
                        rng.next_f64() as f32,
                        rng.next_f64() as f32,
                    );
                    let p = min + (Vec3::new(x as f32, y as f32, z as f32) + jitter) * o.cell_size;
                    env.markers.push(p.min(max));
                }
                env.first.push(cells as u32);
                env.alive.resize(cells, true);
            }
        }
        Ok(env)
    }

    /// The lattice cell holding `p`: floor(p / cell_size) per axis (saturating; NaN
    /// becomes 0).
    #[inline]
    pub(crate) fn lattice(&self, p: Vec3) -> [i64; 3] {
        // floor, exact for every finite value (`as` truncates toward zero, saturating).
        let floor = |v: f32| {
            let t = v as i64;
            t - i64::from((t as f32) > v)
        };
        let g = p * self.inv_cell;
        [floor(g.x), floor(g.y), floor(g.z)]
    }

    /// The lattice bucket of a lattice cell.
    fn bucket(c: [i64; 3]) -> [i64; 3] {
        c.map(|v| v.div_euclid(BUCKET))
    }

    /// Whether `p` is inside an obstacle: only those listed in its bucket are tested.
    fn in_obstacle(&self, p: Vec3) -> bool {
        if self.obstacles.is_empty() {
            return false;
        }
        self.buckets
            .get(&Self::bucket(self.lattice(p)))
            .is_some_and(|list| list.iter().any(|&i| self.obstacles[i as usize].contains(p)))
    }

    fn coords(&self, c: usize) -> (usize, usize, usize) {
        let [nx, _, nz] = self.dims;
        (c % nx, c / (nx * nz), (c / nx) % nz)
    }

    fn index(&self, x: usize, y: usize, z: usize) -> usize {
        let [nx, _, nz] = self.dims;
        (y * nz + z) * nx + x
    }

    /// The marker grid's cell holding `p`, clamped into the box.
    #[inline]
    fn cell_of(&self, p: Vec3) -> [usize; 3] {
        let g = (p - self.origin) * self.inv_cell;
        // Truncation is the floor for the non-negative values kept (NaN becomes 0).
        let [nx, ny, nz] = self.dims;
        [
            (g.x.max(0.0) as usize).min(nx - 1),
            (g.y.max(0.0) as usize).min(ny - 1),
            (g.z.max(0.0) as usize).min(nz - 1),
        ]
    }

    #[inline]
    pub(crate) fn inside(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Adds (`count` > 0) or removes (< 0) the shadow pyramids of `count` buds whose cell
    /// word is `word` ([`cell_word`](Self::cell_word)), applied at the next
    /// [`flush`](Self::flush). Nothing for markers.
    pub(crate) fn cast(&mut self, word: Key, count: i32) {
        self.pending.extend(self.change(word, count));
    }

    /// The shadow change of `count` buds (negative: removed) whose cell word is `word`,
    /// as a flush takes it; none in a colonization world.
    #[inline]
    pub(crate) fn change(&self, word: Key, count: i32) -> Option<(Key, i32)> {
        (self.kind == Environment::Shadow).then_some((word & !DARK, count))
    }

    /// The cell word of a bud at `p`, found once when its internode is made: in a shadow
    /// world its lattice cell ([`Key`]), with [`DARK`] set where it gets no light (below
    /// the ground or inside an obstacle); 0 in a colonization world. The sky is open:
    /// above the ground, outside the box is as lit as inside it.
    #[inline]
    pub(crate) fn cell_word(&self, p: Vec3) -> Key {
        if self.kind != Environment::Shadow {
            return 0;
        }
        let c = self.lattice(p);
        let k = key(c);
        let below = c[1] <= self.ground_top && c[1] < self.ground_layer(p);
        if !p.is_finite() || below || self.in_obstacle(p) {
            k | DARK
        } else {
            k
        }
    }

    /// The lattice layer of the ground under `p`: below it a bud gets no light (without
    /// a height field, the box's floor: the grid's ground layer).
    #[inline]
    fn ground_layer(&self, p: Vec3) -> i64 {
        match &self.ground {
            None => self.grid.lo[1],
            Some(g) => self.lattice(Vec3::new(p.x, g.height(p.x, p.z), p.z))[1],
        }
    }

    /// Lays a height field under an empty world: the grid's ground layer becomes that
    /// of its lowest sample (shadow), or the markers under it are gone (colonization).
    pub(crate) fn set_ground(&mut self, ground: super::HeightField) {
        let low = ground.range().0;
        match self.kind {
            Environment::Shadow => {
                self.grid = Grid::empty(self.lattice(Vec3::new(0.0, low, 0.0))[1]);
            }
            // No marker lies under the ground: nothing grows toward it.
            Environment::SpaceColonization => {
                for (m, alive) in self.markers.iter().zip(self.alive.iter_mut()) {
                    if m.y < ground.height(m.x, m.z) {
                        *alive = false;
                    }
                }
            }
        }
        // Bilinear heights are at most the highest sample's, but for a few ulps of
        // rounding: the margin covers those.
        let (low, high) = ground.range();
        let margin = (high.abs() + low.abs()) * 1e-5;
        self.ground_top = self.lattice(Vec3::new(0.0, high + margin, 0.0))[1];
        self.ground = Some(std::sync::Arc::new(ground));
    }

    /// The height field under the world, or none.
    pub(crate) fn ground(&self) -> Option<&super::HeightField> {
        self.ground.as_deref()
    }

    /// Whether an obstacle was added.
    pub(crate) fn has_obstacles(&self) -> bool {
        !self.obstacles.is_empty()
    }

    /// Obstacles added.
    pub(crate) fn obstacle_count(&self) -> usize {
        self.obstacles.len()
    }

    /// Makes the grid hold the shadow of buds at every point of `points` (their
    /// pyramids reach `q_max` cells sideways and down): refused with `LimitExceeded`
    /// naming `max_cells` past it, the grid unchanged. Nothing for markers.
    pub(crate) fn cover(&mut self, points: impl IntoIterator<Item = Vec3>) -> Result<()> {
        self.cover_while(bounds(points), false, |_| ())
    }

    /// [`cover`](Self::cover) of the box `bounds` (its points' [`bounds`]), then `f` of
    /// the environment: with `parallel` (and the `parallel` feature), while the grid's
    /// values move to the room it grew (if it did) on another thread. `f` works out cells
    /// and changes (a cell's key does not depend on the grid's store) and must not read
    /// the shadow: meanwhile the grid holds no cell. Refused past `max_cells` or beyond
    /// the memory before `f` runs, the grid unchanged.
    pub(crate) fn cover_while<R: Send>(
        &mut self,
        bounds: Option<(Vec3, Vec3)>,
        parallel: bool,
        f: impl FnOnce(&Env) -> R + Send,
    ) -> Result<R> {
        let Some((min, max)) = bounds.filter(|_| self.kind == Environment::Shadow) else {
            return Ok(f(self));
        };
        // The cells of the corners, as their keys have them (beyond the lattice's reach:
        // clamped).
        let (lo, hi) = (
            unkey(key(self.lattice(min)) & !DARK),
            unkey(key(self.lattice(max)) & !DARK),
        );
        let q = self.falloff.len() as i64 - 1;
        let relay = self.grid.reserve(
            [lo[0] - q, lo[1] - q, lo[2] - q],
            [hi[0] + q, hi[1], hi[2] + q],
            self.max_cells,
        )?;
        let Some(relay) = relay else {
            return Ok(f(self));
        };
        #[cfg(feature = "parallel")]
        if parallel {
            let mut grid = std::mem::take(&mut self.grid);
            let env = &*self;
            let ((), r) = rayon::join(|| relay.run(&mut grid), || f(env));
            self.grid = grid;
            return Ok(r);
        }
        let _ = parallel;
        relay.run(&mut self.grid);
        Ok(f(self))
    }

    /// Cells the shadow grid stores now (it grows with the trees).
    pub(crate) fn grid_cells(&self) -> usize {
        self.grid.cells.len()
    }

    /// Applies the pending shadow changes: buds added and removed in one cell cancel, and
    /// each changed cell's pyramid is applied once, in cell order. The shadow is integer,
    /// so the result does not depend on the order of the changes at all. With `parallel`
    /// (and the `parallel` feature) the changes are sorted on two threads (the lower and
    /// upper halves of the grid) and the grid is updated by two threads owning a band of
    /// layers each.
    pub(crate) fn flush(&mut self, parallel: bool) {
        self.flush_with(&[], parallel);
    }

    /// [`flush`](Self::flush) of the pending changes and those recorded elsewhere
    /// (`changes`: such as each tree's changes of a cycle), read where they are. Every
    /// change's pyramid must be in the grid ([`cover`](Self::cover)).
    pub(crate) fn flush_with(&mut self, changes: &[&[(Key, i32)]], parallel: bool) {
        let pending = std::mem::take(&mut self.pending);
        let mut sources = changes.to_vec();
        sources.push(&pending);
        let (mut sorted, mut scratch) = (
            std::mem::take(&mut self.sorted),
            std::mem::take(&mut self.scratch),
        );
        let grid = &self.grid;
        sort_changes(
            &sources,
            |k| grid.change_index(k),
            &mut sorted,
            &mut scratch,
            grid.cells.len(),
            parallel,
            true,
        );
        self.apply_and_count(&sorted, parallel);
        drop(sources);
        (self.sorted, self.scratch, self.pending) = (sorted, scratch, pending);
        self.pending.clear();
    }

    /// [`apply`](Self::apply) `changes` to the cells and count their buds into the
    /// columns: at once, on two threads, where `apply` would wake a second one (the two
    /// share nothing but the changes).
    fn apply_and_count(&mut self, changes: &[(u32, i32)], parallel: bool) {
        let mut columns = std::mem::take(&mut self.grid.columns);
        let dims = self.grid.dims;
        #[cfg(feature = "parallel")]
        if parallel && changes.len() > APPLY_ALONE {
            rayon::join(
                || self.apply(changes, parallel),
                || grid::count_columns(&mut columns, dims, changes),
            );
            self.grid.columns = columns;
            return;
        }
        self.apply(changes, parallel);
        grid::count_columns(&mut columns, dims, changes);
        self.grid.columns = columns;
    }

    /// Adds the pyramids of merged, sorted `changes` to the grid: with `parallel`, the
    /// `parallel` feature and enough changes to pay for waking a second thread (2,048:
    /// tens of microseconds of work, about what waking a thread costs), in [`BANDS`] bands
    /// of layers of about equal work, taken by the threads as they come free, each band
    /// adding what lands in it; else on this thread.
    fn apply(&mut self, changes: &[(u32, i32)], parallel: bool) {
        if changes.is_empty() {
            return;
        }
        let dims = self.grid.dims;
        let layer = dims[0] * dims[2];
        let falloff = &self.falloff;
        #[cfg(feature = "parallel")]
        if parallel && changes.len() > APPLY_ALONE {
            use rayon::prelude::*;
            // Work by target layer: layer t takes the squares of the changes q layers
            // above it, (2q + 1)² cells each. Bands cut where the work reaches each
            // quantile (more bands than threads: the estimate is rough, and a thread that
            // finishes early takes the next band).
            let ny = dims[1];
            let starts: Vec<usize> = (0..=ny)
                .map(|y| changes.partition_point(|&(c, _)| (c as usize) < y * layer))
                .collect();
            let mut work = vec![0u64; ny + 1];
            for t in 0..ny {
                let cells: u64 = (0..falloff.len())
                    .take_while(|q| t + q < ny)
                    .map(|q| {
                        let side = 2 * q as u64 + 1;
                        (starts[t + q + 1] - starts[t + q]) as u64 * side * side
                    })
                    .sum();
                work[t + 1] = work[t] + cells;
            }
            let mut bounds = vec![0];
            for b in 1..BANDS as u64 {
                let y = work.partition_point(|&w| w < work[ny] * b / BANDS as u64);
                if y > bounds[bounds.len() - 1] && y < ny {
                    bounds.push(y);
                }
            }
            bounds.push(ny);
            let mut rest = &mut self.grid.cells[..];
            let mut bands = Vec::with_capacity(BANDS);
            for w in bounds.windows(2) {
                let (band, tail) = std::mem::take(&mut rest).split_at_mut((w[1] - w[0]) * layer);
                rest = tail;
                // Each band reads only the changes whose squares land in it.
                let reach = (w[1] + falloff.len()).min(ny);
                let band: Vec<&mut [i32]> = band.chunks_mut(layer).collect();
                bands.push((band, w[0], &changes[starts[w[0]]..starts[reach]]));
            }
            bands
                .into_par_iter()
                .zip(self.diff.par_iter_mut())
                .for_each(|((mut band, first, changes), diff)| {
                    apply_layers(changes, dims, falloff, &mut band, first, diff)
                });
            return;
        }
        let _ = parallel;
        let mut all: Vec<&mut [i32]> = self.grid.cells.chunks_mut(layer).collect();
        apply_layers(changes, dims, falloff, &mut all, 0, &mut self.diff[0]);
    }

    /// Light at a bud of a shadow world from its cell word: Q = max(C − s + a, 0) (the
    /// `+ a` takes away the bud's own shadow), 0 where the word is [`DARK`].
    #[inline]
    pub(crate) fn shadow_q(&self, word: Key) -> f32 {
        if word & DARK != 0 {
            return 0.0;
        }
        let s = self.grid.at(unkey(word)) as f32 * (self.strength / UNIT);
        (self.full_light - s + self.strength).max(0.0)
    }

    /// Asks the memory for the shadow [`Env::shadow_q`] of `word` will read.
    #[inline]
    pub(crate) fn prefetch(&self, word: Key) {
        self.prefetch_cell(unkey(word));
    }

    /// Asks the memory for the shadow of lattice cell `c` (x86; elsewhere nothing).
    #[inline]
    fn prefetch_cell(&self, c: [i64; 3]) {
        #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
        if let Some(cell) = self.grid.index(c).and_then(|i| self.grid.cells.get(i)) {
            safe_arch::prefetch_t0(cell);
        }
        #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
        let _ = c;
    }

    /// Asks the memory for the cells [`Env::shadow_v`] of `word` will read (x86; see
    /// [`Env::prefetch`]).
    #[inline]
    pub(crate) fn prefetch_v(&self, word: Key) {
        let [x, y, z] = unkey(word);
        for c in [
            [x, y, z - 1],
            [x, y, z + 1],
            [x, y - 1, z],
            [x, y + 1, z],
            [x, y, z],
        ] {
            self.prefetch_cell(c);
        }
    }

    /// Light on the ground at `p` (a shadow world): full light less a bud's shadow for
    /// every bud above it, at any height, counted over the 5 × 5 columns around its cell
    /// and taken per column: `max(C − a·buds / 25, 0)`; what a seed there gets.
    pub(crate) fn ground_q(&self, p: Vec3) -> f32 {
        let [x, y, z] = self.lattice(p);
        let mut buds = 0i64;
        for dz in -2..=2 {
            for dx in -2..=2 {
                buds += i64::from(self.grid.column([x + dx, y, z + dz]));
            }
        }
        (self.full_light - self.strength * buds as f32 / 25.0).max(0.0)
    }

    /// The optimal direction at a bud of a shadow world: V = −∇s (central differences
    /// of the integer shadow, so exactly zero where flat), normalised (zero where flat or
    /// [`DARK`]). Asked only where a shoot grows.
    pub(crate) fn shadow_v(&self, word: Key) -> Vec3 {
        if word & DARK != 0 {
            return Vec3::ZERO;
        }
        let [x, y, z] = unkey(word);
        let g = &self.grid;
        let d = |a: [i64; 3], b: [i64; 3]| (g.at(a) as i64 - g.at(b) as i64) as f32;
        let grad = Vec3::new(
            d([x + 1, y, z], [x - 1, y, z]),
            d([x, y + 1, z], [x, y - 1, z]),
            d([x, y, z + 1], [x, y, z - 1]),
        );
        (-grad).normalize_or_zero()
    }

    /// Space colonization for every bud of every tree: markers within a bud's occupancy
    /// reach are removed, then each remaining marker inside one or more buds' perception
    /// cones goes to the nearest of them. A bud with markers gets Q = 1 and V the
    /// normalised sum of unit vectors to its markers; others Q = 0.
    pub(crate) fn colonize(
        &mut self,
        buds: &[Vec<Bud>],
        species: &[GrowthParams],
    ) -> Vec<Vec<(f32, Vec3)>> {
        // Occupancy.
        for (tree, p) in buds.iter().zip(species) {
            let reach = p.occupancy_reach * p.internode_length;
            for b in tree {
                self.for_markers(b.position, reach, |env, m| {
                    if env.markers[m].distance_squared(b.position) <= reach * reach {
                        env.alive[m] = false;
                    }
                });
            }
        }
        // Perception: the nearest perceiving bud wins each marker.
        let mut best: rustc_hash::FxHashMap<u32, (f32, u32, u32)> = Default::default();
        for (t, (tree, p)) in buds.iter().zip(species).enumerate() {
            let reach = p.perception_reach * p.internode_length;
            let cos = libm::cosf(p.perception_angle.to_radians());
            for (k, b) in tree.iter().enumerate() {
                // A bud under the ground perceives nothing.
                if self
                    .ground
                    .as_ref()
                    .is_some_and(|g| b.position.y < g.height(b.position.x, b.position.z))
                {
                    continue;
                }
                self.for_markers(b.position, reach, |env, m| {
                    let to = env.markers[m] - b.position;
                    let d2 = to.length_squared();
                    if d2 > reach * reach || d2 == 0.0 {
                        return;
                    }
                    if to.dot(b.direction) < cos * d2.sqrt() {
                        return;
                    }
                    let e = best.entry(m as u32).or_insert((f32::INFINITY, 0, 0));
                    if d2 < e.0 {
                        *e = (d2, t as u32, k as u32);
                    }
                });
            }
        }
        let mut out: Vec<Vec<(f32, Vec3)>> = buds
            .iter()
            .map(|t| vec![(0.0, Vec3::ZERO); t.len()])
            .collect();
        // Sum in marker order so the result does not depend on the map's order.
        let mut won: Vec<(u32, u32, u32)> =
            best.into_iter().map(|(m, (_, t, k))| (m, t, k)).collect();
        won.sort_unstable();
        for (m, t, k) in won {
            let b = &buds[t as usize][k as usize];
            let slot = &mut out[t as usize][k as usize];
            slot.0 = 1.0;
            slot.1 += (self.markers[m as usize] - b.position).normalize_or_zero();
        }
        for tree in &mut out {
            for slot in tree {
                slot.1 = slot.1.normalize_or_zero();
            }
        }
        out
    }

    /// Calls `f` with every living marker in the cells within `reach` of `p`.
    fn for_markers(&mut self, p: Vec3, reach: f32, mut f: impl FnMut(&mut Env, usize)) {
        let lo = self.cell_of(p - Vec3::splat(reach));
        let hi = self.cell_of(p + Vec3::splat(reach));
        for y in lo[1]..=hi[1] {
            for z in lo[2]..=hi[2] {
                for x in lo[0]..=hi[0] {
                    let c = self.index(x, y, z);
                    for m in self.first[c] as usize..self.first[c + 1] as usize {
                        if self.alive[m] {
                            f(self, m);
                        }
                    }
                }
            }
        }
    }

    pub(crate) fn kind(&self) -> Environment {
        self.kind
    }
}
