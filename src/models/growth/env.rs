//! The environment a world's trees share: a shadow voxel grid, or attraction markers on a
//! uniform grid, and the obstacles placed in it.

use super::{Environment, GrowthParams, WorldOptions};
use crate::error::{Error, Result};
use glam::Vec3;

/// A shape that casts shadow (shadow worlds) or removes markers (space colonization).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Obstacle {
    /// An axis-aligned box between two corners.
    Box {
        /// Lower corner.
        min: [f32; 3],
        /// Upper corner.
        max: [f32; 3],
    },
    /// A sphere.
    Sphere {
        /// Center.
        center: [f32; 3],
        /// Radius, > 0.
        radius: f32,
    },
}

impl Obstacle {
    pub(crate) fn validate(&self) -> Result<()> {
        let finite = |p: &[f32; 3]| p.iter().all(|v| v.is_finite());
        match self {
            Obstacle::Box { min, max } => {
                if !(finite(min) && finite(max)) || (0..3).any(|k| max[k] < min[k]) {
                    return Err(Error::invalid(
                        "obstacle",
                        format!("box {min:?}..{max:?}; expected finite corners, min <= max"),
                    ));
                }
            }
            Obstacle::Sphere { center, radius } => {
                if !(finite(center) && radius.is_finite() && *radius > 0.0) {
                    return Err(Error::invalid(
                        "obstacle",
                        format!(
                            "sphere at {center:?} radius {radius}; expected a finite center and radius > 0"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    pub(crate) fn contains(&self, p: Vec3) -> bool {
        match *self {
            Obstacle::Box { min, max } => {
                p.cmpge(Vec3::from(min)).all() && p.cmple(Vec3::from(max)).all()
            }
            Obstacle::Sphere { center, radius } => {
                p.distance_squared(Vec3::from(center)) <= radius * radius
            }
        }
    }

    fn bounds(&self) -> (Vec3, Vec3) {
        match *self {
            Obstacle::Box { min, max } => (Vec3::from(min), Vec3::from(max)),
            Obstacle::Sphere { center, radius } => {
                let c = Vec3::from(center);
                (c - Vec3::splat(radius), c + Vec3::splat(radius))
            }
        }
    }
}

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

    /// Places an obstacle: in a shadow world every cell whose center it contains is
    /// opaque: every cell straight below it gets full exposure's worth of shadow (C), and
    /// its pyramid spreads a bud's shadow around that; buds inside it get no light. In a
    /// colonization world the markers inside it are removed.
    ///
    /// Cost in proportion to the cells of its bounds (times the pyramid's depth) and the
    /// columns below them; `progress` (Stage::Growth, layers done) may cancel, and then
    /// nothing has changed. At most [`MAX_OBSTACLES`].
    pub(crate) fn add_obstacle(
        &mut self,
        o: &Obstacle,
        progress: &mut crate::progress::Progress<'_>,
    ) -> Result<()> {
        if self.obstacles.len() >= MAX_OBSTACLES {
            return Err(Error::LimitExceeded {
                limit_name: "MAX_OBSTACLES",
                what: "obstacles of the world",
                limit: MAX_OBSTACLES as u64,
                requested: self.obstacles.len() as u64 + 1,
                step: None,
            });
        }
        let (lo, hi) = o.bounds();
        let (lo, hi) = (self.cell_of(lo), self.cell_of(hi));
        // The buckets the obstacle overlaps list it (made with the first obstacle).
        let [bx, by, bz] = self.bucket_dims();
        if self.buckets.is_empty() {
            let n = bx * by * bz;
            self.buckets
                .try_reserve_exact(n)
                .map_err(|_| oom(format!("the obstacle buckets ({n})")))?;
            self.buckets.resize_with(n, Vec::new);
        }
        match self.kind {
            Environment::Shadow => {
                let (region, delta) = self.obstacle_shadow(o, lo, hi, progress)?;
                let [nx, _, nz] = self.dims;
                let ([x0, z0], [w, h]) = region;
                for (y, layer) in delta.chunks_exact(w * h).enumerate() {
                    for (r, row) in layer.chunks_exact(w).enumerate() {
                        let at = (y * nz + z0 + r) * nx + x0;
                        for (v, d) in self.shadow[at..at + w].iter_mut().zip(row) {
                            *v += d;
                        }
                    }
                }
            }
            Environment::SpaceColonization => {
                // The markers inside are found first (a cancel changes nothing).
                let mut inside = Vec::new();
                for y in lo[1]..=hi[1] {
                    progress.report(
                        crate::progress::Stage::Growth,
                        (y - lo[1]) as f64 / (hi[1] - lo[1] + 1) as f64,
                    )?;
                    for z in lo[2]..=hi[2] {
                        for x in lo[0]..=hi[0] {
                            let c = self.index(x, y, z);
                            for m in self.first[c] as usize..self.first[c + 1] as usize {
                                if o.contains(self.markers[m]) {
                                    inside.push(m);
                                }
                            }
                        }
                    }
                }
                for m in inside {
                    self.alive[m] = false;
                }
            }
        }
        let id = self.obstacles.len() as u32;
        let (b0, b1) = (self.bucket_of(lo), self.bucket_of(hi));
        let ([x0, y0, z0], [x1, y1, z1]) = (
            [b0 % bx, b0 / (bx * bz), (b0 / bx) % bz],
            [b1 % bx, b1 / (bx * bz), (b1 / bx) % bz],
        );
        for y in y0..=y1 {
            for z in z0..=z1 {
                for x in x0..=x1 {
                    self.buckets[(y * bz + z) * bx + x].push(id);
                }
            }
        }
        self.obstacles.push(*o);
        Ok(())
    }

    /// The shadow an obstacle adds, as a block of the grid: x from `region.0[0]`, z from
    /// `region.0[1]`, `region.1` wide and deep, layers from 0 up to the obstacle's top.
    ///
    /// Each opaque cell adds what a bud's shadow change of 1 adds (its pyramid), and full
    /// exposure (C) to every cell below it. Per source layer a summed-area table of its
    /// opaque cells gives every target cell's count within each pyramid level's square
    /// in constant time, so the cost is the bounds' layers × the pyramid's depth × the
    /// area around them, not the opaque cells × the pyramid's cells.
    #[allow(clippy::type_complexity)]
    fn obstacle_shadow(
        &self,
        o: &Obstacle,
        lo: [usize; 3],
        hi: [usize; 3],
        progress: &mut crate::progress::Progress<'_>,
    ) -> Result<(([usize; 2], [usize; 2]), Vec<f32>)> {
        let [nx, _, nz] = self.dims;
        let qmax = self.falloff.len().saturating_sub(1);
        let (bw, bh) = (hi[0] - lo[0] + 1, hi[2] - lo[2] + 1);
        let (rx0, rx1) = (lo[0].saturating_sub(qmax), (hi[0] + qmax).min(nx - 1));
        let (rz0, rz1) = (lo[2].saturating_sub(qmax), (hi[2] + qmax).min(nz - 1));
        let (rw, rh) = (rx1 - rx0 + 1, rz1 - rz0 + 1);
        let layers = hi[1] + 1;
        let total = layers * rw * rh;
        let mut delta: Vec<f32> = Vec::new();
        delta
            .try_reserve_exact(total)
            .map_err(|_| oom(format!("an obstacle's shadow ({total} cells)")))?;
        delta.resize(total, 0.0);
        let mut sat = vec![0u32; (bw + 1) * (bh + 1)];
        let mut above = vec![0u32; bw * bh];
        let (origin, cell) = (self.origin, self.cell);
        let center = |x: usize, y: usize, z: usize| {
            origin + (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * cell
        };
        let full_light = self.full_light;
        for y in (0..=hi[1]).rev() {
            progress.report(
                crate::progress::Stage::Growth,
                (hi[1] - y) as f64 / layers as f64,
            )?;
            let target = &mut delta[y * rw * rh..(y + 1) * rw * rh];
            // Full exposure below every opaque cell above this layer.
            for (k, &n) in above.iter().enumerate() {
                if n > 0 {
                    let (x, z) = (lo[0] + k % bw, lo[2] + k / bw);
                    target[(z - rz0) * rw + x - rx0] += full_light * n as f32;
                }
            }
            if y < lo[1] {
                continue;
            }
            // This layer's opaque cells, as a summed-area table.
            let mut any = false;
            for z in 0..bh {
                let mut run = 0u32;
                for x in 0..bw {
                    let opaque = o.contains(center(lo[0] + x, y, lo[2] + z));
                    run += opaque as u32;
                    above[z * bw + x] += opaque as u32;
                    any |= opaque;
                    sat[(z + 1) * (bw + 1) + x + 1] = sat[z * (bw + 1) + x + 1] + run;
                }
            }
            if !any {
                continue;
            }
            let count = |xa: usize, xb: usize, za: usize, zb: usize| {
                // Opaque cells in bounds-relative [xa, xb) × [za, zb).
                sat[zb * (bw + 1) + xb] + sat[za * (bw + 1) + xa]
                    - sat[za * (bw + 1) + xb]
                    - sat[zb * (bw + 1) + xa]
            };
            for (q, &f) in self.falloff.iter().enumerate() {
                if q > y {
                    break;
                }
                let t = y - q;
                let target = &mut delta[t * rw * rh..(t + 1) * rw * rh];
                let (tz0, tz1) = (lo[2].saturating_sub(q).max(rz0), (hi[2] + q).min(rz1));
                let (tx0, tx1) = (lo[0].saturating_sub(q).max(rx0), (hi[0] + q).min(rx1));
                for z in tz0..=tz1 {
                    let za = z.saturating_sub(q).max(lo[2]) - lo[2];
                    let zb = (z + q).min(hi[2]) + 1 - lo[2];
                    if za >= zb {
                        continue;
                    }
                    let row = &mut target[(z - rz0) * rw..(z - rz0 + 1) * rw];
                    for x in tx0..=tx1 {
                        let xa = x.saturating_sub(q).max(lo[0]) - lo[0];
                        let xb = (x + q).min(hi[0]) + 1 - lo[0];
                        if xa >= xb {
                            continue;
                        }
                        let n = count(xa, xb, za, zb);
                        if n > 0 {
                            row[x - rx0] += f * n as f32;
                        }
                    }
                }
            }
        }
        Ok((([rx0, rz0], [rw, rh]), delta))
    }

    pub(crate) fn kind(&self) -> Environment {
        self.kind
    }
}

/// Sorts the shadow changes of `sources` (in that order) by cell into `sorted`, stably
/// (each cell's changes keep the order they were made in), through `scratch`: a
/// least-significant-digit radix sort of the cell indices (below `cells`). With
/// `parallel` (and the `parallel` feature) two threads each gather and sort the changes
/// of one half of the grid.
fn sort_changes(
    sources: &[&[(u32, f32)]],
    sorted: &mut Vec<(u32, f32)>,
    scratch: &mut Vec<(u32, f32)>,
    cells: usize,
    parallel: bool,
) {
    let total: usize = sources.iter().map(|s| s.len()).sum();
    // Buffers keep their length from flush to flush: every value is written below.
    scratch.resize(total, (0, 0.0));
    #[cfg(feature = "parallel")]
    if parallel && total > 1 << 15 {
        use rayon::prelude::*;
        let mid = (cells / 2) as u32;
        let low: usize = sources
            .par_iter()
            .map(|s| s.iter().filter(|&&(c, _)| c < mid).count())
            .sum();
        sorted.resize(total, (0, 0.0));
        let gather = |out: &mut [(u32, f32)], lower: bool| {
            let mut k = 0;
            for &change in sources.iter().flat_map(|s| s.iter()) {
                if (change.0 < mid) == lower {
                    out[k] = change;
                    k += 1;
                }
            }
        };
        // The halves sort into the same buffer (both take the same passes).
        let (a, b) = sorted.split_at_mut(low);
        let (ta, tb) = scratch.split_at_mut(low);
        let (in_scratch, _) = rayon::join(
            || {
                gather(a, true);
                radix_sort(a, ta, cells)
            },
            || {
                gather(b, false);
                radix_sort(b, tb, cells)
            },
        );
        if in_scratch {
            std::mem::swap(sorted, scratch);
        }
        return;
    }
    let _ = parallel;
    sorted.clear();
    for s in sources {
        sorted.extend_from_slice(s);
    }
    if total < 256 {
        sorted.sort_by_key(|&(c, _)| c);
    } else if radix_sort(sorted, scratch, cells) {
        std::mem::swap(sorted, scratch);
    }
}

/// Sorts `data` by cell (below `cells`), stably, ping-ponging with `tmp` (as long): in at
/// most three passes over digits of up to 13 bits. True when the result ends in `tmp`.
fn radix_sort(data: &mut [(u32, f32)], tmp: &mut [(u32, f32)], cells: usize) -> bool {
    let bits = usize::BITS - cells.saturating_sub(1).max(1).leading_zeros();
    let passes = bits.div_ceil(13);
    let digit = bits.div_ceil(passes);
    let mask = (1u32 << digit) - 1;
    let mut counts = vec![0u32; (passes as usize) << digit];
    for &(c, _) in data.iter() {
        for p in 0..passes {
            counts[((p as usize) << digit) + ((c >> (p * digit)) & mask) as usize] += 1;
        }
    }
    let (mut from, mut to) = (data, tmp);
    for p in 0..passes {
        let count = &mut counts[(p as usize) << digit..((p as usize) + 1) << digit];
        let mut at = 0u32;
        for c in count.iter_mut() {
            let n = *c;
            *c = at;
            at += n;
        }
        for &change in from.iter() {
            let d = ((change.0 >> (p * digit)) & mask) as usize;
            to[count[d] as usize] = change;
            count[d] += 1;
        }
        std::mem::swap(&mut from, &mut to);
    }
    passes % 2 == 1
}

/// Adds the shadow pyramids of `changes` ((cell, buds), sorted by cell) to `layers`, the
/// grid's layers from `first` on (the parts of pyramids outside them are left out). One
/// cell's changes are summed first (buds added and removed cancel), so each changed
/// cell's pyramid is added once, in cell order.
fn apply_changes(
    changes: &[(u32, f32)],
    [nx, _, nz]: [usize; 3],
    falloff: &[f32],
    layers: &mut [&mut [f32]],
    first: usize,
) {
    let mut k = 0;
    while k < changes.len() {
        let cell = changes[k].0;
        let mut count = 0.0;
        while k < changes.len() && changes[k].0 == cell {
            count += changes[k].1;
            k += 1;
        }
        if count == 0.0 {
            continue;
        }
        let c = cell as usize;
        let (cx, cy, cz) = (c % nx, c / (nx * nz), (c / nx) % nz);
        for (q, &f) in falloff.iter().enumerate() {
            if q > cy || cy - q < first {
                break;
            }
            let Some(layer) = layers.get_mut(cy - q - first) else {
                continue;
            };
            let add = f * count;
            let (x0, x1) = (cx.saturating_sub(q), (cx + q).min(nx - 1));
            let (z0, z1) = (cz.saturating_sub(q), (cz + q).min(nz - 1));
            let (w, h) = (x1 - x0 + 1, z1 - z0 + 1);
            let start = z0 * nx + x0;
            // Unclipped squares of the common sizes have a fixed number of fixed-size rows,
            // which the compiler unrolls into vector adds.
            match (w == h).then_some(w) {
                Some(1) => layer[start] += add,
                Some(3) => add_square::<3>(layer, start, nx, add),
                Some(5) => add_square::<5>(layer, start, nx, add),
                Some(7) => add_square::<7>(layer, start, nx, add),
                Some(9) => add_square::<9>(layer, start, nx, add),
                Some(11) => add_square::<11>(layer, start, nx, add),
                Some(13) => add_square::<13>(layer, start, nx, add),
                _ => {
                    for r in 0..h {
                        let o = start + r * nx;
                        for v in &mut layer[o..o + w] {
                            *v += add;
                        }
                    }
                }
            }
        }
    }
}

/// Adds `add` to a `W` × `W` square of a layer whose rows are `stride` apart, from
/// `start`.
#[inline(always)]
fn add_square<const W: usize>(layer: &mut [f32], start: usize, stride: usize, add: f32) {
    let slab = &mut layer[start..start + (W - 1) * stride + W];
    for r in 0..W {
        if let Some(row) = slab[r * stride..].first_chunk_mut::<W>() {
            for v in row {
                *v += add;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shadow obstacles add, from summed-area tables, equals adding each opaque cell's
    /// pyramid and column one by one (the definition), for shapes clipped by the grid's
    /// sides and floor, overlapping, on a small grid; cancelling leaves the grid as it was.
    #[test]
    fn obstacle_shadow_is_each_opaque_cells_pyramid_and_column() {
        let options = WorldOptions {
            min: [-3.0, 0.0, -2.5],
            max: [3.0, 4.0, 2.5],
            cell_size: 0.25,
            ..WorldOptions::default()
        };
        let shapes = [
            Obstacle::Sphere {
                center: [0.3, 2.0, -0.2],
                radius: 0.9,
            },
            Obstacle::Box {
                min: [-4.0, 1.0, 1.5],
                max: [-1.8, 1.6, 4.0],
            },
            Obstacle::Sphere {
                center: [2.8, 0.3, 2.4],
                radius: 0.7,
            },
            Obstacle::Box {
                min: [-1.0, 3.1, -1.0],
                max: [1.0, 3.9, 1.0],
            },
        ];
        let mut fast = Env::new(&options).unwrap();
        let mut slow = Env::new(&options).unwrap();
        let [nx, _, nz] = slow.dims;
        for o in &shapes {
            fast.add_obstacle(o, &mut crate::progress::Progress::new(None))
                .unwrap();
            let (lo, hi) = o.bounds();
            let (lo, hi) = (slow.cell_of(lo), slow.cell_of(hi));
            let (dims, falloff, full) = (slow.dims, slow.falloff.clone(), slow.full_light);
            let mut opaque = 0;
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    for x in lo[0]..=hi[0] {
                        let c = slow.origin
                            + (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * slow.cell;
                        if !o.contains(c) {
                            continue;
                        }
                        opaque += 1;
                        let mut layers: Vec<&mut [f32]> = slow.shadow.chunks_mut(nx * nz).collect();
                        let cell = ((y * nz + z) * nx + x) as u32;
                        apply_changes(&[(cell, 1.0)], dims, &falloff, &mut layers, 0);
                        for layer in &mut layers[..y] {
                            layer[z * nx + x] += full;
                        }
                    }
                }
            }
            assert!(opaque > 4, "{o:?} covers {opaque} cell centers");
        }
        let mut worst = 0.0f32;
        for (a, b) in fast.shadow.iter().zip(&slow.shadow) {
            worst = worst.max((a - b).abs() / b.abs().max(1.0));
        }
        assert!(worst < 1e-5, "largest relative difference {worst}");
        assert!(slow.shadow.iter().filter(|&&v| v > 0.0).count() > 1000);

        // Buds inside an obstacle are dark; beside it they are not.
        assert!(fast.cell_word(Vec3::new(0.3, 2.0, -0.2)) & DARK != 0);
        assert!(fast.cell_word(Vec3::new(-2.0, 1.3, 2.0)) & DARK != 0);
        assert!(fast.cell_word(Vec3::new(0.3, 3.0, -2.0)) & DARK == 0);

        // A callback that stops at its second report: cancelled, nothing changed.
        let before = fast.shadow.clone();
        let mut calls = 0;
        let mut stop = |_: crate::progress::Stage, _: f32| {
            calls += 1;
            calls < 2
        };
        let big = Obstacle::Box {
            min: [-3.0, 0.0, -2.5],
            max: [3.0, 4.0, 2.5],
        };
        let r = fast.add_obstacle(&big, &mut crate::progress::Progress::new(Some(&mut stop)));
        assert!(matches!(r, Err(Error::Cancelled { .. })), "{r:?}");
        assert!(
            fast.shadow == before,
            "a cancelled obstacle changed the shadow"
        );
        assert_eq!(fast.obstacles.len(), shapes.len());
        assert!(fast.cell_word(Vec3::new(0.3, 3.0, -2.0)) & DARK == 0);
    }

    /// A world holds at most MAX_OBSTACLES; the next is refused by name.
    #[test]
    fn obstacles_are_counted() {
        let options = WorldOptions {
            min: [0.0, 0.0, 0.0],
            max: [1.0, 1.0, 1.0],
            cell_size: 1.0,
            ..WorldOptions::default()
        };
        let mut env = Env::new(&options).unwrap();
        let o = Obstacle::Sphere {
            center: [0.5, 0.5, 0.5],
            radius: 0.1,
        };
        let mut none = crate::progress::Progress::new(None);
        for _ in 0..MAX_OBSTACLES {
            env.add_obstacle(&o, &mut none).unwrap();
        }
        let e = env.add_obstacle(&o, &mut none).unwrap_err();
        assert!(e.to_string().contains("MAX_OBSTACLES"), "{e}");
    }

    /// The radix sort orders by cell and keeps each cell's changes in the order made, on
    /// one thread and (with the feature) on two, for grids needing one to three passes.
    #[test]
    fn shadow_changes_sort_stably_by_cell() {
        let mut rng = crate::rng::Rng::new(7);
        for (cells, len) in [
            (100usize, 300usize),
            (5_000, 40_000),
            (4_608_000, 70_000),
            (1 << 31, 50_000),
        ] {
            let changes: Vec<(u32, f32)> = (0..len)
                .map(|k| ((rng.next_u64() % cells as u64) as u32, k as f32))
                .collect();
            let mut expected = changes.clone();
            expected.sort_by_key(|&(c, _)| c);
            for parallel in [false, true] {
                // As a flush gathers them: from several places, in order.
                let (head, tail) = changes.split_at(len / 3);
                let (mut got, mut scratch) = (vec![(9, 9.0); 5], vec![(7, 7.0); len + 9]);
                sort_changes(&[head, &[], tail], &mut got, &mut scratch, cells, parallel);
                let same = got
                    .iter()
                    .zip(&expected)
                    .all(|(a, b)| a.0 == b.0 && a.1.to_bits() == b.1.to_bits());
                assert!(
                    same && got.len() == len,
                    "{cells} cells, {len} changes, parallel {parallel}"
                );
            }
        }
    }
}
