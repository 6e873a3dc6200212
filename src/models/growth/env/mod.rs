//! The environment a world's trees share: a shadow voxel grid, or attraction markers on a
//! uniform grid, and the obstacles placed in it.

use super::{Environment, GrowthParams, WorldOptions};
use crate::error::{Error, Result};
use glam::Vec3;

mod changes;
mod obstacles;
#[cfg(test)]
mod tests;

use changes::{apply_changes, sort_changes};
pub use obstacles::Obstacle;

fn oom(what: String) -> Error {
    Error::OutOfMemory { what }
}

/// Most obstacles a world may hold.
pub const MAX_OBSTACLES: usize = 1 << 20;

/// Edge, in cells, of the buckets that list the obstacles overlapping them.
const BUCKET: usize = 8;

/// Set in a cell word ([`Env::cell_word`]) where a bud gets no light.
pub(crate) const DARK: u32 = 1 << 31;

/// Most cells a grid may have: a cell index and the [`DARK`] bit share 32 bits.
pub(crate) const MOST_CELLS: usize = 1 << 31;

/// One bud as the environment sees it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bud {
    pub(crate) position: Vec3,
    pub(crate) direction: Vec3,
}

/// The shared environment.
#[derive(Clone, Debug)]
pub(crate) struct Env {
    kind: Environment,
    origin: Vec3,
    inv_cell: f32,
    cell: f32,
    dims: [usize; 3],
    /// Shadow per cell, x fastest, then z, then y (a layer of the pyramid is rows of x).
    shadow: Vec<f32>,
    /// a·b^−q for q = 0..=q_max.
    falloff: Vec<f32>,
    full_light: f32,
    strength: f32,
    /// Markers (space colonization), binned by cell: `markers[first[c]..first[c + 1]]`.
    first: Vec<u32>,
    markers: Vec<Vec3>,
    alive: Vec<bool>,
    min: Vec3,
    max: Vec3,
    /// Shadow changes not applied yet: (cell, buds added there, negative for removed).
    pending: Vec<(u32, f32)>,
    /// The changes of a flush, sorted, and the radix sort's second buffer.
    sorted: Vec<(u32, f32)>,
    scratch: Vec<(u32, f32)>,
    obstacles: Vec<Obstacle>,
    /// The obstacles whose bounds overlap each bucket of [`BUCKET`]³ cells (made with the
    /// first obstacle), so a point is tested only against those near it.
    buckets: Vec<Vec<u32>>,
}

impl Env {
    pub(crate) fn new(o: &WorldOptions) -> Result<Self> {
        let (min, max) = (Vec3::from(o.min), Vec3::from(o.max));
        let dims = [0, 1, 2].map(|k| (((max[k] - min[k]) / o.cell_size).ceil() as usize).max(1));
        let cells = dims[0] * dims[1] * dims[2];
        let mut env = Env {
            kind: o.environment,
            origin: min,
            inv_cell: 1.0 / o.cell_size,
            cell: o.cell_size,
            dims,
            shadow: Vec::new(),
            falloff: (0..=o.shadow_depth)
                .map(|q| o.shadow_strength * libm::powf(o.shadow_falloff, -(q as f32)))
                .collect(),
            full_light: o.full_light,
            strength: o.shadow_strength,
            first: Vec::new(),
            markers: Vec::new(),
            alive: Vec::new(),
            min,
            max,
            pending: Vec::new(),
            sorted: Vec::new(),
            scratch: Vec::new(),
            obstacles: Vec::new(),
            buckets: Vec::new(),
        };
        match o.environment {
            Environment::Shadow => {
                // Zeros written now: a lazily zeroed grid would be read through the
                // shared zero page and copied on its first write, two page faults per
                // page, taken inside the cycles' parallel passes.
                env.shadow.try_reserve_exact(cells).map_err(|_| {
                    oom(format!(
                        "the shadow grid ({cells} cells, {} bytes)",
                        cells * 4
                    ))
                })?;
                env.shadow.resize(cells, 0.0);
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

    fn bucket_dims(&self) -> [usize; 3] {
        self.dims.map(|d| d.div_ceil(BUCKET))
    }

    fn bucket_of(&self, [x, y, z]: [usize; 3]) -> usize {
        let [bx, _, bz] = self.bucket_dims();
        ((y / BUCKET) * bz + z / BUCKET) * bx + x / BUCKET
    }

    /// Whether `p` is inside an obstacle: only those listed in its bucket are tested.
    fn in_obstacle(&self, p: Vec3) -> bool {
        if self.obstacles.is_empty() {
            return false;
        }
        self.buckets[self.bucket_of(self.cell_of(p))]
            .iter()
            .any(|&i| self.obstacles[i as usize].contains(p))
    }

    fn coords(&self, c: usize) -> (usize, usize, usize) {
        let [nx, _, nz] = self.dims;
        (c % nx, c / (nx * nz), (c / nx) % nz)
    }

    fn index(&self, x: usize, y: usize, z: usize) -> usize {
        let [nx, _, nz] = self.dims;
        (y * nz + z) * nx + x
    }

    /// The cell holding `p`, clamped into the grid.
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
    pub(crate) fn cast(&mut self, word: u32, count: f32) {
        self.pending.extend(self.change(word, count));
    }

    /// The shadow change of `count` buds (negative: removed) whose cell word is `word`,
    /// as a flush takes it; none in a colonization world.
    #[inline]
    pub(crate) fn change(&self, word: u32, count: f32) -> Option<(u32, f32)> {
        (self.kind == Environment::Shadow).then_some((word & !DARK, count))
    }

    /// The cell word of a bud at `p`, found once when its internode is made: in a shadow
    /// world the index of the cell whose shadow it changes (clamped into the grid), with
    /// [`DARK`] set where it gets no light (outside the box or inside an obstacle); 0 in a
    /// colonization world.
    #[inline]
    pub(crate) fn cell_word(&self, p: Vec3) -> u32 {
        if self.kind != Environment::Shadow {
            return 0;
        }
        let [x, y, z] = self.cell_of(p);
        let cell = self.index(x, y, z) as u32;
        // Trees grow inside the world box, outside obstacles: a bud elsewhere gets no light.
        if !self.inside(p) || self.in_obstacle(p) {
            cell | DARK
        } else {
            cell
        }
    }

    /// Applies the pending shadow changes: buds added and removed in one cell cancel, and
    /// each changed cell's pyramid is applied once, in cell order (so the result does not
    /// depend on the order the changes came in; the counts are small integers, exact in
    /// any order). With `parallel` (and the `parallel` feature) the changes are sorted on
    /// two threads (the lower and upper halves of the grid) and the grid is updated by two
    /// threads owning a band of layers each; every cell still receives its changes in the
    /// same order, so the grid is the same bit for bit.
    pub(crate) fn flush(&mut self, parallel: bool) {
        self.flush_with(&[], parallel);
    }

    /// [`flush`](Self::flush) of the pending changes and those recorded elsewhere
    /// (`changes`: cells without [`DARK`], such as each tree's changes of a cycle), read
    /// where they are.
    pub(crate) fn flush_with(&mut self, changes: &[&[(u32, f32)]], parallel: bool) {
        let pending = std::mem::take(&mut self.pending);
        let mut sources = changes.to_vec();
        sources.push(&pending);
        let (mut sorted, mut scratch) = (
            std::mem::take(&mut self.sorted),
            std::mem::take(&mut self.scratch),
        );
        sort_changes(
            &sources,
            &mut sorted,
            &mut scratch,
            self.shadow.len(),
            parallel,
        );
        self.apply(&sorted, parallel);
        drop(sources);
        (self.sorted, self.scratch, self.pending) = (sorted, scratch, pending);
        self.pending.clear();
    }

    /// Adds the pyramids of sorted `changes` to the grid: with `parallel`, the `parallel`
    /// feature and enough changes to pay for waking a second thread (16,384: about half a
    /// millisecond of work), on two threads, each owning a band of layers and adding the
    /// part of every pyramid that falls in it; else on this one.
    fn apply(&mut self, changes: &[(u32, f32)], parallel: bool) {
        let layer = self.dims[0] * self.dims[2];
        let (dims, falloff) = (self.dims, &self.falloff);
        #[cfg(feature = "parallel")]
        if parallel && changes.len() > 1 << 14 {
            let y_of = |c: u32| c as usize / layer;
            // Band [0, split) takes the changes up to q_max layers above it, band
            // [split, ny) the changes from its first layer up: split where the two take
            // as many.
            let bands = |split: usize| {
                let below = changes.partition_point(|&(c, _)| y_of(c) < split + falloff.len());
                let above = changes.partition_point(|&(c, _)| y_of(c) < split);
                (below, above)
            };
            let split = (1..self.dims[1])
                .min_by_key(|&y| {
                    let (below, above) = bands(y);
                    below.abs_diff(changes.len() - above)
                })
                .unwrap_or(1);
            let (below, above) = bands(split);
            let (low, high) = self.shadow.split_at_mut(split * layer);
            let mut low: Vec<&mut [f32]> = low.chunks_mut(layer).collect();
            let mut high: Vec<&mut [f32]> = high.chunks_mut(layer).collect();
            rayon::join(
                || apply_changes(&changes[..below], dims, falloff, &mut low, 0),
                || apply_changes(&changes[above..], dims, falloff, &mut high, split),
            );
            return;
        }
        let _ = parallel;
        let mut all: Vec<&mut [f32]> = self.shadow.chunks_mut(layer).collect();
        apply_changes(changes, dims, falloff, &mut all, 0);
    }

    /// Shadow at a cell, 0 outside the grid.
    fn s(&self, x: isize, y: isize, z: isize) -> f32 {
        let [nx, ny, nz] = self.dims;
        if x < 0 || y < 0 || z < 0 || x as usize >= nx || y as usize >= ny || z as usize >= nz {
            return 0.0;
        }
        self.shadow[self.index(x as usize, y as usize, z as usize)]
    }

    /// Light at a bud of a shadow world from its cell word: Q = max(C − s + a, 0) (the
    /// `+ a` takes away the bud's own shadow), 0 where the word is [`DARK`].
    #[inline]
    pub(crate) fn shadow_q(&self, word: u32) -> f32 {
        if word & DARK != 0 {
            return 0.0;
        }
        (self.full_light - self.shadow[word as usize] + self.strength).max(0.0)
    }

    /// The optimal direction at a bud of a shadow world: V = −∇s (central differences),
    /// normalised (zero where flat or [`DARK`]). Asked only where a shoot grows.
    pub(crate) fn shadow_v(&self, word: u32) -> Vec3 {
        if word & DARK != 0 {
            return Vec3::ZERO;
        }
        let c = word as usize;
        let (cx, cy, cz) = self.coords(c);
        let [nx, ny, nz] = self.dims;
        let grad = if cx > 0 && cy > 0 && cz > 0 && cx + 1 < nx && cy + 1 < ny && cz + 1 < nz {
            // Inside: neighbours at ±1, ±nx (z) and ±nx·nz (y).
            let (dz, dy) = (nx, nx * nz);
            let g = &self.shadow;
            Vec3::new(
                g[c + 1] - g[c - 1],
                g[c + dy] - g[c - dy],
                g[c + dz] - g[c - dz],
            )
        } else {
            let [x, y, z] = [cx, cy, cz].map(|v| v as isize);
            Vec3::new(
                self.s(x + 1, y, z) - self.s(x - 1, y, z),
                self.s(x, y + 1, z) - self.s(x, y - 1, z),
                self.s(x, y, z + 1) - self.s(x, y, z - 1),
            )
        };
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
        let mut best: std::collections::HashMap<u32, (f32, u32, u32)> = Default::default();
        for (t, (tree, p)) in buds.iter().zip(species).enumerate() {
            let reach = p.perception_reach * p.internode_length;
            let cos = libm::cosf(p.perception_angle.to_radians());
            for (k, b) in tree.iter().enumerate() {
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
