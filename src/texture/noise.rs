//! Noise that tiles: value noise and cellular noise on a lattice that wraps, so a texture
//! drawn from them repeats without a seam.

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

    /// The noise at (u, v) in tile units ([0, 1) wraps).
    #[inline]
    pub(super) fn at(&self, u: f32, v: f32) -> f32 {
        let (x, y) = (u * self.px as f32, v * self.py as f32);
        let (xf, yf) = (x.floor(), y.floor());
        let (tx, ty) = (smooth(x - xf), smooth(y - yf));
        // The tile's coordinates are in [0, 1) (a little outside at most): wrap without a
        // division.
        let x0 = wrap(xf as i32, self.px);
        let y0 = wrap(yf as i32, self.py);
        let x1 = if x0 + 1 == self.px { 0 } else { x0 + 1 };
        let y1 = if y0 + 1 == self.py { 0 } else { y0 + 1 };
        let t = |x: u32, y: u32| self.table[(y * self.px + x) as usize];
        let a = t(x0, y0) + (t(x1, y0) - t(x0, y0)) * tx;
        let b = t(x0, y1) + (t(x1, y1) - t(x0, y1)) * tx;
        a + (b - a) * ty
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

    #[inline]
    pub(super) fn at(&self, u: f32, v: f32) -> f32 {
        let (mut sum, mut weight, mut total) = (0.0, 1.0, 0.0);
        for o in &self.octaves {
            sum += o.at(u, v) * weight;
            total += weight;
            weight *= 0.5;
        }
        sum / total
    }
}

/// Cellular noise: one jittered point per cell of a `px` × `py` lattice that wraps; gives
/// the distances (in cells) to the nearest and second-nearest point and the nearest
/// point's cell hash.
pub(super) struct Cells {
    px: u32,
    py: u32,
    seed: u32,
}

impl Cells {
    pub(super) fn new(px: u32, py: u32, seed: u32) -> Self {
        Cells { px, py, seed }
    }

    #[inline]
    pub(super) fn at(&self, u: f32, v: f32) -> (f32, f32, u32) {
        let (x, y) = (u * self.px as f32, v * self.py as f32);
        let (cx, cy) = (x.floor() as i64, y.floor() as i64);
        let (mut d1, mut d2, mut id) = (f32::MAX, f32::MAX, 0);
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (gx, gy) = (cx + dx, cy + dy);
                let (wx, wy) = (wrap(gx as i32, self.px), wrap(gy as i32, self.py));
                let h = hash(wx, wy, self.seed);
                let jx = (h & 0xffff) as f32 / 65536.0;
                let jy = (h >> 16) as f32 / 65536.0;
                let (ddx, ddy) = (
                    gx as f32 + 0.15 + 0.7 * jx - x,
                    gy as f32 + 0.15 + 0.7 * jy - y,
                );
                let d = (ddx * ddx + ddy * ddy).sqrt();
                if d < d1 {
                    (d2, d1, id) = (d1, d, h);
                } else if d < d2 {
                    d2 = d;
                }
            }
        }
        (d1, d2, id)
    }
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
