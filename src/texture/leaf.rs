//! Leaf atlases: several variants of one species' blade, each in a cell whose shape is the
//! leaf card's (0.5 wide, 1 long: [`LeafPrefab::quad`](crate::mesh::LeafPrefab::quad)), the
//! stem at the cell's top (v = 0, where the card's stem is).

use super::noise::{Fractal, unit};
use super::{Image, check_size, fill, mix, scale};
use crate::error::Result;
use crate::progress::Run;

/// The outline of a blade.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LeafShape {
    /// Egg-shaped, widest below the middle (birch, poplar, most shrubs).
    Ovate,
    /// Long and narrow (willow).
    Lanceolate,
    /// Rounded lobes along both sides (oak).
    Lobed,
    /// Five pointed lobes from one point (maple).
    Palmate,
    /// A cluster of needles from one base (pine, spruce).
    Needles,
}

/// How a species' leaves look.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeafLook {
    /// The outline.
    pub shape: LeafShape,
    /// Mean colour of the blade, sRGB.
    pub color: [u8; 3],
    /// How much the variants and the mottling vary in brightness and hue, 0..=1.
    pub variation: f32,
    /// How much lighter the midrib and veins are, 0..=1.
    pub veins: f32,
    /// The card's length in metres (its width is half of it).
    pub size: f32,
    /// Blades on a card: 1, one leaf filling it; more, a spray of that many on a twig
    /// (alternate, the last at its tip), as trees are drawn with far fewer cards than
    /// they have leaves. 1..=16.
    pub leaves: u32,
}

impl LeafLook {
    /// Lobed, deep green, 12 cm.
    pub fn oak() -> Self {
        LeafLook {
            shape: LeafShape::Lobed,
            color: [62, 96, 34],
            variation: 0.35,
            veins: 0.35,
            size: 0.55,
            leaves: 7,
        }
    }
    /// Palmate, bright green, 14 cm.
    pub fn maple() -> Self {
        LeafLook {
            shape: LeafShape::Palmate,
            color: [78, 118, 36],
            variation: 0.35,
            veins: 0.3,
            size: 0.6,
            leaves: 5,
        }
    }
    /// Small ovate, light green, 6 cm.
    pub fn birch() -> Self {
        LeafLook {
            shape: LeafShape::Ovate,
            color: [96, 132, 44],
            variation: 0.3,
            veins: 0.3,
            size: 0.4,
            leaves: 9,
        }
    }
    /// Lanceolate, grey-green, 10 cm.
    pub fn willow() -> Self {
        LeafLook {
            shape: LeafShape::Lanceolate,
            color: [100, 126, 62],
            variation: 0.3,
            veins: 0.25,
            size: 0.6,
            leaves: 9,
        }
    }
    /// Broad ovate, green, 8 cm.
    pub fn poplar() -> Self {
        LeafLook {
            shape: LeafShape::Ovate,
            color: [70, 110, 38],
            variation: 0.3,
            veins: 0.3,
            size: 0.5,
            leaves: 7,
        }
    }
    /// Long needles in clusters, dark green, 14 cm.
    pub fn pine() -> Self {
        LeafLook {
            shape: LeafShape::Needles,
            color: [44, 78, 36],
            variation: 0.25,
            veins: 0.0,
            size: 0.5,
            leaves: 5,
        }
    }
    /// Short needles, blue-green, 8 cm.
    pub fn spruce() -> Self {
        LeafLook {
            shape: LeafShape::Needles,
            color: [34, 66, 42],
            variation: 0.2,
            veins: 0.0,
            size: 0.6,
            leaves: 7,
        }
    }
    /// Small ovate, mid green, 5 cm.
    pub fn shrub() -> Self {
        LeafLook {
            shape: LeafShape::Ovate,
            color: [66, 104, 38],
            variation: 0.35,
            veins: 0.3,
            size: 0.16,
            leaves: 9,
        }
    }
}

/// Cells across every leaf atlas (its variants: `ATLAS_COLUMNS` × `ATLAS_ROWS`).
pub const ATLAS_COLUMNS: u32 = 4;
/// Cells down every leaf atlas.
pub const ATLAS_ROWS: u32 = 2;
const COLUMNS: u32 = ATLAS_COLUMNS;
const ROWS: u32 = ATLAS_ROWS;

/// Cell `k`'s rectangle (u0, v0, u1, v1) in a grid of `columns` × `rows` cells, row by
/// row, `k` taken modulo the count; v0 is the stem's end.
pub fn atlas_rect(columns: u32, rows: u32, k: usize) -> [f32; 4] {
    let (columns, rows) = (columns.max(1), rows.max(1));
    let k = (k % (columns * rows) as usize) as u32;
    let (c, r) = (k % columns, k / columns);
    let (w, h) = (1.0 / columns as f32, 1.0 / rows as f32);
    [
        c as f32 * w,
        r as f32 * h,
        (c + 1) as f32 * w,
        (r + 1) as f32 * h,
    ]
}

/// A leaf atlas: the image and its grid of variants.
#[derive(Clone, Debug, PartialEq)]
pub struct LeafAtlas {
    /// RGBA8, alpha 0 outside the blades (their colour bled there, so filtered edges do
    /// not darken), 255 inside, one pixel of antialiasing at the outline.
    pub image: Image,
    /// Cells across.
    pub columns: u32,
    /// Cells down.
    pub rows: u32,
}

impl LeafAtlas {
    /// How many variants the atlas holds.
    pub fn variants(&self) -> usize {
        (self.columns * self.rows) as usize
    }

    /// Variant `k`'s rectangle in uv (u0, v0, u1, v1), `k` taken modulo
    /// [`variants`](Self::variants); v0 is the stem's end.
    pub fn rect(&self, k: usize) -> [f32; 4] {
        atlas_rect(self.columns, self.rows, k)
    }
}

/// One variant's shape and tint, drawn from the seed.
#[derive(Clone, Copy)]
struct Variant {
    width: f32,
    length: f32,
    bend: f32,
    tint: f32,
    hue: f32,
    seed: u32,
}

/// Draws a `size` × `size` atlas of `look`'s blades (16..=4096 pixels, checked before any
/// allocation), the variants differing in width, length, curve and tint by `seed`.
pub fn leaf_atlas(look: &LeafLook, size: u32, seed: u64) -> Result<LeafAtlas> {
    leaf_atlas_in(look, size, seed, &Run::default())
}

/// [`leaf_atlas`] on the run's threads (1: the calling thread only); the same pixels.
pub fn leaf_atlas_in(look: &LeafLook, size: u32, seed: u64, run: &Run<'_>) -> Result<LeafAtlas> {
    check_size("size", size)?;
    let seed32 = (seed ^ (seed >> 32)) as u32;
    let var = look.variation.clamp(0.0, 1.0);
    let variants: Vec<Variant> = (0..COLUMNS * ROWS)
        .map(|k| {
            let r = |j: u32| unit(k, j, seed32) * 2.0 - 1.0;
            Variant {
                width: 1.0 + 0.12 * r(1),
                length: 0.96 + 0.04 * r(2),
                bend: 0.04 * r(3),
                tint: 1.0 + 0.22 * var * r(4),
                hue: 0.5 * var * (r(5) + 1.0) * 0.5,
                seed: seed32.wrapping_add(k * 101),
            }
        })
        .collect();
    let mottle = Fractal::new(6, 12, 3, seed32 ^ 0x51ed);
    let (cw, ch) = (size / COLUMNS, size / ROWS);
    let px_per_unit = cw as f32 / 0.5;
    let image = fill(size, size, run, |x, y| {
        let (c, r) = ((x / cw).min(COLUMNS - 1), (y / ch).min(ROWS - 1));
        let v = &variants[(r * COLUMNS + c) as usize];
        let lx = ((x - c * cw) as f32 + 0.5) / cw as f32;
        let ly = ((y - r * ch) as f32 + 0.5) / ch as f32;
        // Card space: x across in [-0.25, 0.25], y from the stem (0) to the tip (1).
        let (cx, cy) = ((lx - 0.5) * 0.5, ly);
        let (inside, vein, twig) = card(look, v, cx, cy);
        let alpha = (inside * px_per_unit + 0.5).clamp(0.0, 1.0);
        let yellow = [
            look.color[0].saturating_add(60),
            look.color[1].saturating_add(30),
            look.color[2],
        ];
        let base = scale(mix(look.color, yellow, v.hue), v.tint);
        if alpha <= 0.0 {
            return [base[0], base[1], base[2], 0];
        }
        let m = mottle.at(lx * 0.25 + c as f32 * 0.25, ly * 0.5 + r as f32 * 0.5);
        let mut col = scale(base, 1.0 + (m - 0.5) * 0.5 * var.max(0.2));
        // Darker toward the outline, lighter along the veins.
        let edge = (inside / 0.02).clamp(0.0, 1.0);
        col = scale(col, 0.82 + 0.18 * edge);
        let light = [
            col[0].saturating_add(70),
            col[1].saturating_add(70),
            col[2].saturating_add(30),
        ];
        col = mix(col, light, vein * look.veins);
        if twig {
            col = [92, 70, 52];
        }
        [col[0], col[1], col[2], (alpha * 255.0 + 0.5) as u8]
    });
    Ok(LeafAtlas {
        image,
        columns: COLUMNS,
        rows: ROWS,
    })
}

/// Where card point (x, y) is on a card of `look`: its distance inside the drawn shape
/// (card units), how much of a vein it is, and whether it is the twig.
fn card(look: &LeafLook, v: &Variant, x: f32, y: f32) -> (f32, f32, bool) {
    let n = look.leaves.clamp(1, 16);
    if n == 1 {
        let (d, vein) = blade(look.shape, v, x, y);
        return (d, vein, false);
    }
    // The twig: from the stem's end to two thirds of the card, slightly bent; the
    // terminal blade reaches on to the card's tip.
    let tip_y = 0.66 * v.length;
    let twig_x = |t: f32| v.bend * 2.0 * t * t;
    let t = (y / tip_y).clamp(0.0, 1.0);
    let twig = if y <= tip_y {
        0.007 * (1.0 - 0.5 * t) - (x - twig_x(t)).abs()
    } else {
        -1.0
    };
    let (mut best, mut vein) = (twig, 0.0f32);
    let mut on_twig = twig > 0.0;
    if look.shape == LeafShape::Needles {
        let (d, on) = bottlebrush(v, x, y, tip_y, n * 6);
        return if d > best {
            (d, 0.0, on)
        } else {
            (best, 0.0, on_twig)
        };
    }
    let size = if look.shape == LeafShape::Palmate {
        0.5
    } else {
        0.36
    };
    for k in 0..n {
        let last = k == n - 1;
        let at = if last {
            1.0
        } else {
            0.22 + 0.7 * k as f32 / (n - 1) as f32
        };
        let side = if k % 2 == 0 { 1.0 } else { -1.0 };
        let jitter = unit(k, 17, v.seed) - 0.5;
        let angle = if last {
            0.0
        } else {
            side * (0.62 + 0.2 * jitter)
        };
        let len = size * (if last { 0.9 } else { 0.75 + 0.25 * at }) * (1.0 + 0.1 * jitter);
        let (px, py) = (twig_x(at), at * tip_y);
        let (dx, dy) = (angle.sin(), angle.cos());
        let (qx, qy) = (x - px, y - py);
        // Far from this leaf: skip it (its blade lies within `len` of its base).
        if qx * qx + qy * qy > len * len * 1.05 {
            continue;
        }
        // Leaf space: along the blade / len, across it / len.
        let ly = (qx * dx + qy * dy) / len;
        let lx = (qx * dy - qy * dx) / len;
        let (d, vn) = blade(look.shape, v, lx, ly);
        let d = d * len;
        if d > best {
            best = d;
            vein = vn;
            on_twig = false;
        }
    }
    (best, vein, on_twig && best == twig)
}

/// Needles all along a twig from the stem's end to `tip_y` (a bottlebrush): `count`
/// needles leaving it alternately on both sides, leaning toward the tip. Returns the
/// distance inside the nearest needle and whether that is none (false: a needle).
fn bottlebrush(v: &Variant, x: f32, y: f32, tip_y: f32, count: u32) -> (f32, bool) {
    let twig_x = |t: f32| v.bend * 2.0 * t * t;
    let mut best = -1.0f32;
    for k in 0..count {
        let at = 0.08 + 0.92 * k as f32 / (count - 1) as f32;
        let side = if k % 2 == 0 { 1.0 } else { -1.0 };
        let jitter = unit(k, 23, v.seed) - 0.5;
        let angle = side * (0.75 + 0.35 * jitter) * (1.0 - 0.5 * at);
        let len = 0.2 * (1.0 - 0.35 * at) * (1.0 + 0.2 * jitter) * v.width;
        let (bx, by) = (twig_x(at), at * tip_y);
        let (qx, qy) = (x - bx, y - by);
        if qx * qx + qy * qy > len * len * 1.1 {
            continue;
        }
        let (dx, dy) = (angle.sin(), angle.cos());
        let t = ((qx * dx + qy * dy) / len).clamp(0.0, 1.0);
        let (ex, ey) = (qx - dx * len * t, qy - dy * len * t);
        let half = 0.006 * (1.0 - 0.6 * t);
        best = best.max(half - (ex * ex + ey * ey).sqrt());
    }
    (best, false)
}

/// Where card point (x, y) is for the blade of `shape`: its distance inside the outline
/// (card units, negative outside) and how much of a vein it is (0..=1).
fn blade(shape: LeafShape, v: &Variant, x: f32, y: f32) -> (f32, f32) {
    let petiole_end = 0.12;
    let stem = 0.006 - x.abs();
    let petiole = if y < petiole_end + 0.02 {
        stem.min(y)
    } else {
        -1.0
    };
    let mid = x - v.bend * y * y;
    if shape == LeafShape::Needles {
        return (needles(v, x, y).max(petiole), 0.0);
    }
    if shape == LeafShape::Palmate {
        let (d, vein) = palmate(v, x, y);
        return (d.max(petiole), vein);
    }
    let top = petiole_end + (1.0 - petiole_end) * v.length - 0.02;
    let t = (y - petiole_end) / (top - petiole_end);
    if !(0.0..=1.0).contains(&t) {
        return (petiole, 0.0);
    }
    let pi = std::f32::consts::PI;
    let hw = v.width
        * match shape {
            LeafShape::Ovate => 0.23 * (pi * t.powf(0.75)).sin(),
            LeafShape::Lanceolate => 0.1 * (pi * t.powf(0.9)).sin().powf(0.8),
            _ => {
                0.22 * (pi * t.powf(0.85)).sin()
                    * (0.66 + 0.34 * (pi * 4.5 * t).sin().abs().powf(0.6))
            }
        };
    let inside = (hw - mid.abs()).max(petiole);
    // Midrib, and lateral veins running out and up from it.
    let midrib = (1.0 - mid.abs() / 0.005).max(0.0);
    let phase = (t - 2.2 * mid.abs()) * 9.0;
    let lateral = (1.0 - (phase - phase.round()).abs() / 0.08).max(0.0) * 0.7;
    (inside, midrib.max(lateral))
}

/// A maple's blade: five pointed lobes around a centre, distance approximated radially.
fn palmate(v: &Variant, x: f32, y: f32) -> (f32, f32) {
    let (cx, cy) = (0.0, 0.5);
    let (dx, dy) = (x, y - cy);
    let r = (dx * dx + dy * dy).sqrt();
    // Angle from the tip direction (+y), 0..pi either side.
    let a = dx.atan2(dy).abs();
    let pi = std::f32::consts::PI;
    if a > 0.86 * pi {
        return (-1.0, 0.0);
    }
    let lobes = (a * 5.0 / (1.72)).cos().abs();
    let reach = 0.25 * v.width.min(1.0) * (0.6 + 0.4 * lobes) * (1.0 - 0.15 * (a / pi));
    let inside = reach - r;
    let _ = cx;
    // Veins: the five lobes' axes.
    let lobe_axis = ((a * 5.0 / 1.72) / pi).fract();
    let vein = (1.0 - (lobe_axis.min(1.0 - lobe_axis) * pi * r) / 0.004).max(0.0);
    (inside, vein)
}

/// A cluster of needles from the stem's end, spread in a fan.
fn needles(v: &Variant, x: f32, y: f32) -> f32 {
    let (bx, by) = (0.0, 0.06);
    let mut best = -1.0f32;
    let n = 11;
    for k in 0..n {
        let s = k as f32 / (n - 1) as f32 * 2.0 - 1.0;
        let jitter = unit(k, 9, v.seed) - 0.5;
        let angle = s * 0.22 * v.width + 0.04 * jitter;
        let len = (0.9 - 0.12 * s.abs() + 0.05 * jitter) * v.length;
        let (tx, ty) = (bx + angle.sin() * len, by + angle.cos() * len);
        // Distance to the segment base → tip, minus the needle's half-width tapering.
        let (sx, sy) = (tx - bx, ty - by);
        let t = (((x - bx) * sx + (y - by) * sy) / (sx * sx + sy * sy)).clamp(0.0, 1.0);
        let (px, py) = (bx + sx * t - x, by + sy * t - y);
        let d = (px * px + py * py).sqrt();
        let half = 0.0075 * (1.0 - 0.7 * t);
        best = best.max(half - d);
    }
    best
}
