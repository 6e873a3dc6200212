//! Noise that tiles: value noise and cellular noise on a lattice that wraps, so a texture
//! drawn from them repeats without a seam.
//!
//! Textures are drawn a row at a time: a noise is sampled at the pixel centres of an image
//! of known width ([`Value::columns`]), so each pixel's lattice columns and weights are
//! found once per image and each row interpolates one lattice line (the row's two lattice
//! rows blended once). A pixel of an octave costs two loads and a blend.

/// A 32-bit integer hash of a lattice point and a seed (arbor's own: the bytes of every
/// texture depend on it, so it is fixed here rather than borrowed from a crate that may
/// change it).
#[inline]
pub(super) fn hash(x: u32, y: u32, seed: u32) -> u32 {
    let mut h =
        x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841) ^ seed.wrapping_mul(0xcb1a_b31f);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297a_2d39);
    h ^ (h >> 15)
}

/// `hash` as a number in [0, 1).
#[inline]
pub(super) fn unit(x: u32, y: u32, seed: u32) -> f32 {
    (hash(x, y, seed) >> 8) as f32 / (1u32 << 24) as f32
}

/// The centre of pixel `k` of `n` in tile units.
#[inline]
pub(super) fn centre(k: u32, n: u32) -> f32 {
    (k as f32 + 0.5) / n as f32
}

/// Where the pixels of a row fall on a lattice of `n` cells: each pixel's two lattice
/// columns and its smoothed weight between them.
struct Lerp {
    k0: Vec<u32>,
    k1: Vec<u32>,
    t: Vec<f32>,
}

impl Lerp {
    fn new(n: u32, width: u32) -> Self {
        let mut l = Lerp {
            k0: Vec::with_capacity(width as usize),
            k1: Vec::with_capacity(width as usize),
            t: Vec::with_capacity(width as usize),
        };
        for x in 0..width {
            let (k0, k1, t) = cell(centre(x, width), n);
            l.k0.push(k0);
            l.k1.push(k1);
            l.t.push(t);
        }
        l
    }
}

/// The lattice cell of `u` in tile units on `n` cells that wrap, the next one, and the
/// smoothed weight between them.
#[inline]
fn cell(u: f32, n: u32) -> (u32, u32, f32) {
    let x = u * n as f32;
    let f = x.floor();
    let k0 = wrap(f as i32, n);
    let k1 = if k0 + 1 == n { 0 } else { k0 + 1 };
    (k0, k1, smooth(x - f))
}

/// Value noise with `px` × `py` lattice cells over the tile, smoothly interpolated, in
/// [0, 1]; the lattice values are tabulated once.
pub(super) struct Value {
    px: u32,
    py: u32,
    table: Vec<f32>,
}

impl Value {
    pub(super) fn new(px: u32, py: u32, seed: u32) -> Self {
        let table = (0..py)
            .flat_map(|y| (0..px).map(move |x| unit(x, y, seed)))
            .collect();
        Value { px, py, table }
    }

    /// The lattice line at `v` (tile units): the two lattice rows blended, `px` values.
    fn line(&self, v: f32, out: &mut Vec<f32>) {
        let (y0, y1, t) = cell(v, self.py);
        let px = self.px as usize;
        let r0 = &self.table[y0 as usize * px..][..px];
        let r1 = &self.table[y1 as usize * px..][..px];
        out.clear();
        out.extend(r0.iter().zip(r1).map(|(a, b)| a + (b - a) * t));
    }
}

/// Several octaves of [`Value`] noise, each twice the lattice of the one before and half
/// its weight, normalised to [0, 1].
pub(super) struct Fractal {
    octaves: Vec<Value>,
}

impl Fractal {
    pub(super) fn new(px: u32, py: u32, octaves: u32, seed: u32) -> Self {
        Fractal {
            octaves: (0..octaves)
                .map(|k| Value::new(px << k, py << k, seed.wrapping_add(k * 7919)))
                .collect(),
        }
    }

    /// The noise sampled at the pixel centres of rows `width` pixels wide.
    pub(super) fn columns(&self, width: u32) -> Sampled<'_> {
        let total: f32 = (0..self.octaves.len()).map(|k| 0.5f32.powi(k as i32)).sum();
        Sampled {
            octaves: self
                .octaves
                .iter()
                .enumerate()
                .map(|(k, o)| (o, Lerp::new(o.px, width), 0.5f32.powi(k as i32) / total))
                .collect(),
        }
    }
}

/// A [`Fractal`] sampled at the pixel centres of rows of one width.
pub(super) struct Sampled<'a> {
    octaves: Vec<(&'a Value, Lerp, f32)>,
}

impl Sampled<'_> {
    /// The noise along the row at `v` (tile units), one value a pixel, into `out`
    /// (`line` is scratch).
    pub(super) fn row(&self, v: f32, out: &mut [f32], line: &mut Vec<f32>) {
        out.fill(0.0);
        for (value, lerp, weight) in &self.octaves {
            value.line(v, line);
            for (((o, &k0), &k1), &t) in out.iter_mut().zip(&lerp.k0).zip(&lerp.k1).zip(&lerp.t) {
                let a = line[k0 as usize];
                *o += (a + (line[k1 as usize] - a) * t) * weight;
            }
        }
    }
}

/// Cellular noise: one jittered point per cell of a `px` × `py` lattice that wraps; gives
/// the distances (in cells) to the nearest and second-nearest point and the nearest
/// point's cell hash.
pub(super) struct Cells {
    px: u32,
    py: u32,
    /// Each cell's point (within the cell, in cells) and hash, row by row.
    points: Vec<(f32, f32, u32)>,
}

impl Cells {
    pub(super) fn new(px: u32, py: u32, seed: u32) -> Self {
        let points = (0..py)
            .flat_map(|y| {
                (0..px).map(move |x| {
                    let h = hash(x, y, seed);
                    let jx = (h & 0xffff) as f32 / 65536.0;
                    let jy = (h >> 16) as f32 / 65536.0;
                    (0.15 + 0.7 * jx, 0.15 + 0.7 * jy, h)
                })
            })
            .collect();
        Cells { px, py, points }
    }

    /// Along the row at `v` (tile units), at the centres of `out.len()` pixels: each
    /// pixel's distances to its nearest and second-nearest point and the nearest point's
    /// hash. `near` is scratch: for each lattice column, the nine points around the row's
    /// cells there (x in cells, squared y distance to the row, hash).
    pub(super) fn row(&self, v: f32, out: &mut [(f32, f32, u32)], near: &mut Vec<Near>) {
        let y = v * self.py as f32;
        let cy = y as i32;
        near.clear();
        for cx in 0..self.px as i32 {
            let mut n = Near {
                x: [0.0; 9],
                dy2: [0.0; 9],
                hash: [0; 9],
            };
            for k in 0..9 {
                let (gx, gy) = (cx - 1 + (k % 3) as i32, cy - 1 + (k / 3) as i32);
                let (px, py) = (wrap(gx, self.px), wrap(gy, self.py));
                let (jx, jy, h) = self.points[(py * self.px + px) as usize];
                let dy = gy as f32 + jy - y;
                (n.x[k], n.dy2[k], n.hash[k]) = (gx as f32 + jx, dy * dy, h);
            }
            near.push(n);
        }
        let width = out.len() as u32;
        for (x, o) in out.iter_mut().enumerate() {
            let u = centre(x as u32, width) * self.px as f32;
            // `u` is not negative: truncation is its floor.
            let n = &near[(u as usize).min(self.px as usize - 1)];
            let d: [f32; 9] = std::array::from_fn(|k| (n.x[k] - u) * (n.x[k] - u) + n.dy2[k]);
            let (mut d1, mut d2, mut id) = (f32::MAX, f32::MAX, 0);
            for (&d, &h) in d.iter().zip(&n.hash) {
                if d < d1 {
                    (d2, d1, id) = (d1, d, h);
                } else if d < d2 {
                    d2 = d;
                }
            }
            *o = (d1.sqrt(), d2.sqrt(), id);
        }
    }
}

/// The nine cellular points around one lattice column of a row (see [`Cells::row`]).
pub(super) struct Near {
    x: [f32; 9],
    dy2: [f32; 9],
    hash: [u32; 9],
}

/// `k` modulo `n`: a compare or two for the lattice steps the tiles take (k within one
/// period of [0, n)), the remainder otherwise.
#[inline(always)]
fn wrap(k: i32, n: u32) -> u32 {
    let n = n as i32;
    if (0..n).contains(&k) {
        k as u32
    } else if (n..2 * n).contains(&k) {
        (k - n) as u32
    } else if (-n..0).contains(&k) {
        (k + n) as u32
    } else {
        k.rem_euclid(n) as u32
    }
}

#[inline]
fn smooth(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

/// A function on [0, 1] tabulated at 256 steps and read by linear interpolation: the
/// textures' tone curves (powers, roots) at the cost of a multiply and two loads.
pub(super) struct Curve {
    table: [f32; 257],
}

impl Curve {
    pub(super) fn new(f: impl Fn(f32) -> f32) -> Self {
        Curve {
            table: std::array::from_fn(|k| f(k as f32 / 256.0)),
        }
    }

    /// The function at `x`, clamped to [0, 1].
    #[inline]
    pub(super) fn at(&self, x: f32) -> f32 {
        let s = x.clamp(0.0, 1.0) * 256.0;
        let k = (s as usize).min(255);
        let a = self.table[k];
        a + (self.table[k + 1] - a) * (s - k as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sampled_fractal_is_smooth_and_in_range_and_wraps() {
        let f = Fractal::new(5, 3, 3, 11);
        let s = f.columns(64);
        let (mut row, mut line) = (vec![0.0; 64], Vec::new());
        let mut rows = Vec::new();
        for y in 0..64 {
            s.row(centre(y, 64), &mut row, &mut line);
            assert!(row.iter().all(|v| (0.0..=1.0).contains(v)), "{row:?}");
            rows.push(row.clone());
        }
        // Neighbours differ by little; so do the last and first pixels (the wrap).
        for r in &rows {
            for x in 0..64 {
                assert!((r[x] - r[(x + 1) % 64]).abs() < 0.2, "{x}: {r:?}");
            }
        }
        for (last, first) in rows[63].iter().zip(&rows[0]) {
            assert!((last - first).abs() < 0.2);
        }
        // It varies.
        let (lo, hi) = rows
            .iter()
            .flatten()
            .fold((1.0f32, 0.0f32), |(a, b), &v| (a.min(v), b.max(v)));
        assert!(hi - lo > 0.3, "{lo}..{hi}");
    }

    #[test]
    fn a_curve_reads_its_function() {
        let c = Curve::new(|x| x.powf(0.6));
        for k in 0..=100 {
            let x = k as f32 / 100.0;
            assert!((c.at(x) - x.powf(0.6)).abs() < 0.02, "{x}");
        }
        assert_eq!(c.at(-1.0), 0.0);
        assert!((c.at(2.0) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn cells_find_the_nearest_point() {
        let c = Cells::new(4, 5, 3);
        let (mut out, mut near) = (vec![(0.0, 0.0, 0); 37], Vec::new());
        for y in 0..41 {
            let v = centre(y, 41);
            c.row(v, &mut out, &mut near);
            for (x, &(d1, d2, id)) in out.iter().enumerate() {
                let u = centre(x as u32, 37);
                assert!(d1 <= d2);
                // Brute force over every point and its wrapped copies.
                let mut all = Vec::new();
                for (i, &(jx, jy, h)) in c.points.iter().enumerate() {
                    let (gx, gy) = ((i % 4) as f32 + jx, (i / 4) as f32 + jy);
                    for ox in [-4.0, 0.0, 4.0] {
                        for oy in [-5.0, 0.0, 5.0] {
                            let (dx, dy) = (gx + ox - u * 4.0, gy + oy - v * 5.0);
                            all.push(((dx * dx + dy * dy).sqrt(), h));
                        }
                    }
                }
                all.sort_by(|a, b| a.0.total_cmp(&b.0));
                assert!(
                    (all[0].0 - d1).abs() < 1e-4,
                    "{x},{y}: {:?} vs {d1}",
                    all[0]
                );
                assert!(
                    (all[1].0 - d2).abs() < 1e-4,
                    "{x},{y}: {:?} vs {d2}",
                    all[1]
                );
                assert_eq!(all[0].1, id);
            }
        }
    }
}
