//! Obstacles: shapes that cast shadow or remove markers, and their shadow added in time
//! proportional to their bounds.

use super::*;

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

    pub(super) fn bounds(&self) -> (Vec3, Vec3) {
        match *self {
            Obstacle::Box { min, max } => (Vec3::from(min), Vec3::from(max)),
            Obstacle::Sphere { center, radius } => {
                let c = Vec3::from(center);
                (c - Vec3::splat(radius), c + Vec3::splat(radius))
            }
        }
    }
}

impl Env {
    /// Places an obstacle: in a shadow world every cell whose center it contains is
    /// opaque: every cell straight below it (down to the ground) gets full exposure's
    /// worth of shadow (C), and its pyramid spreads a bud's shadow around that; buds
    /// inside it get no light. The grid grows to hold its shadow (refused past
    /// `max_cells`). In a colonization world the markers inside it are removed.
    ///
    /// Cost in proportion to the cells of its bounds (times the pyramid's depth) and the
    /// columns below them; `progress` (Stage::Growth, layers done) may cancel, and then
    /// nothing has changed. At most [`MAX_OBSTACLES`].
    pub(crate) fn add_obstacle(
        &mut self,
        o: &Obstacle,
        progress: &mut crate::progress::Run<'_>,
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
        let (llo, lhi) = (self.lattice(lo), self.lattice(hi));
        match self.kind {
            Environment::Shadow => {
                let ground = self.grid.lo[1];
                if lhi[1] >= ground {
                    let lo = [llo[0], llo[1].max(ground), llo[2]];
                    let (region, delta) = self.obstacle_shadow(o, lo, lhi, progress)?;
                    let ([x0, z0], [w, h]) = region;
                    self.grid.cover(
                        [x0, ground, z0],
                        [x0 + w as i64 - 1, lhi[1], z0 + h as i64 - 1],
                        self.max_cells,
                    )?;
                    for (y, layer) in delta.chunks_exact(w * h).enumerate() {
                        for (r, row) in layer.chunks_exact(w).enumerate() {
                            let c = [x0, ground + y as i64, z0 + r as i64];
                            let at = self.grid.index(c).expect("the grid covers the obstacle");
                            for (v, d) in self.grid.cells[at..at + w].iter_mut().zip(row) {
                                *v = v.wrapping_add(*d);
                            }
                        }
                    }
                }
            }
            Environment::SpaceColonization => {
                let (lo, hi) = (self.cell_of(lo), self.cell_of(hi));
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
        // The lattice buckets the obstacle's bounds overlap list it.
        let id = self.obstacles.len() as u32;
        let (b0, b1) = (Self::bucket(llo), Self::bucket(lhi));
        let buckets = (b1[0] - b0[0] + 1) * (b1[1] - b0[1] + 1) * (b1[2] - b0[2] + 1);
        if buckets > (self.max_cells / 64).max(1 << 16) as i64 {
            return Err(Error::LimitExceeded {
                limit_name: "max_cells",
                what: "obstacle buckets (8^3 cells each) of the obstacle's bounds",
                limit: (self.max_cells / 64).max(1 << 16) as u64,
                requested: buckets as u64,
                step: None,
            });
        }
        for y in b0[1]..=b1[1] {
            for z in b0[2]..=b1[2] {
                for x in b0[0]..=b1[0] {
                    self.buckets.entry([x, y, z]).or_default().push(id);
                }
            }
        }
        self.obstacles.push(*o);
        Ok(())
    }

    /// The shadow an obstacle adds, as a block of lattice cells: x from `region.0[0]`, z
    /// from `region.0[1]`, `region.1` wide and deep, layers from the ground up to the
    /// obstacle's top; `lo ..= hi` are its bounds' lattice cells (`lo[1]` at or above the
    /// ground).
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
        lo: [i64; 3],
        hi: [i64; 3],
        progress: &mut crate::progress::Run<'_>,
    ) -> Result<(([i64; 2], [usize; 2]), Vec<i32>)> {
        let ground = self.grid.lo[1];
        let qmax = self.falloff.len().saturating_sub(1);
        let q64 = qmax as i64;
        let (bw, bh) = ((hi[0] - lo[0] + 1) as usize, (hi[2] - lo[2] + 1) as usize);
        let (rx0, rz0) = (lo[0] - q64, lo[2] - q64);
        let (rw, rh) = (bw + 2 * qmax, bh + 2 * qmax);
        let layers = (hi[1] - ground + 1) as usize;
        let total = layers
            .checked_mul(rw)
            .and_then(|n| n.checked_mul(rh))
            .filter(|&n| n <= self.max_cells.min(MOST_CELLS))
            .ok_or(Error::LimitExceeded {
                limit_name: "max_cells",
                what: "cells of the shadow an obstacle casts",
                limit: self.max_cells.min(MOST_CELLS) as u64,
                requested: (layers as u64)
                    .saturating_mul(rw as u64)
                    .saturating_mul(rh as u64),
                step: None,
            })?;
        let mut delta: Vec<i32> = Vec::new();
        delta
            .try_reserve_exact(total)
            .map_err(|_| oom(format!("an obstacle's shadow ({total} cells)")))?;
        delta.resize(total, 0);
        let mut sat = vec![0u32; (bw + 1) * (bh + 1)];
        let mut above = vec![0u32; bw * bh];
        let cell = self.cell;
        let center = |x: usize, y: usize, z: usize| {
            let c = [lo[0] + x as i64, ground + y as i64, lo[2] + z as i64];
            (Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) + 0.5) * cell
        };
        // Full exposure, in shadow units.
        let full = (self.full_light / self.strength * UNIT).round() as i32;
        let first = (lo[1] - ground) as usize;
        for y in (0..layers).rev() {
            progress.report(
                crate::progress::Stage::Growth,
                (layers - 1 - y) as f64 / layers as f64,
            )?;
            let target = &mut delta[y * rw * rh..(y + 1) * rw * rh];
            // Full exposure below every opaque cell above this layer.
            for (k, &n) in above.iter().enumerate() {
                if n > 0 {
                    let (x, z) = (qmax + k % bw, qmax + k / bw);
                    let v = &mut target[z * rw + x];
                    *v = v.wrapping_add(full.wrapping_mul(n as i32));
                }
            }
            if y < first {
                continue;
            }
            // This layer's opaque cells, as a summed-area table.
            let mut any = false;
            for z in 0..bh {
                let mut run = 0u32;
                for x in 0..bw {
                    let opaque = o.contains(center(x, y, z));
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
                let target = &mut delta[(y - q) * rw * rh..(y - q + 1) * rw * rh];
                // Target cells (region-relative) within q of the bounds.
                for z in qmax - q..qmax + bh + q {
                    let za = z.saturating_sub(q).max(qmax) - qmax;
                    let zb = (z + q).min(qmax + bh - 1) + 1 - qmax;
                    if za >= zb {
                        continue;
                    }
                    let row = &mut target[z * rw..(z + 1) * rw];
                    for (x, v) in row
                        .iter_mut()
                        .enumerate()
                        .take(qmax + bw + q)
                        .skip(qmax - q)
                    {
                        let xa = x.saturating_sub(q).max(qmax) - qmax;
                        let xb = (x + q).min(qmax + bw - 1) + 1 - qmax;
                        if xa >= xb {
                            continue;
                        }
                        let n = count(xa, xb, za, zb);
                        if n > 0 {
                            *v = v.wrapping_add(f.wrapping_mul(n as i32));
                        }
                    }
                }
            }
        }
        Ok((([rx0, rz0], [rw, rh]), delta))
    }
}
