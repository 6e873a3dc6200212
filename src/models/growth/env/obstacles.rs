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
        progress: &mut crate::progress::Run<'_>,
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
}
