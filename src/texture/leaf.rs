//! Leaf atlases: several variants of one species' blade, each in a cell whose shape is the
//! leaf card's (0.5 wide, 1 long: [`LeafPrefab::quad`](crate::mesh::LeafPrefab::quad)), the
//! stem at the cell's top (v = 0, where the card's stem is).

use super::noise::{Curve, Fractal, centre, unit};
use super::{Image, check_size, fill_rows, mix, scale};
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
    let profile = Profile::new(look.shape);
    let cards: Vec<Card> = (0..COLUMNS * ROWS)
        .map(|k| {
            let r = |j: u32| unit(k, j, seed32) * 2.0 - 1.0;
            let v = Variant {
                width: 1.0 + 0.12 * r(1),
                length: 0.96 + 0.04 * r(2),
                bend: 0.04 * r(3),
                tint: 1.0 + 0.22 * var * r(4),
                hue: 0.5 * var * (r(5) + 1.0) * 0.5,
                seed: seed32.wrapping_add(k * 101),
            };
            Card::new(look, v, &profile)
        })
        .collect();
    let mottle = Fractal::new(6, 12, 3, seed32 ^ 0x51ed);
    let mottle = mottle.columns(size);
    let (cw, ch) = (size / COLUMNS, size / ROWS);
    let px_per_unit = cw as f32 / 0.5;
    let image = fill_rows(
        size,
        size,
        run,
        || RowScratch::new(size as usize),
        |rs, y, out| {
            mottle.row(centre(y, size), &mut rs.mottle, &mut rs.line);
            let r = (y / ch).min(ROWS - 1);
            let ly = ((y - r * ch) as f32 + 0.5) / ch as f32;
            for c in 0..COLUMNS {
                let card = &cards[(r * COLUMNS + c) as usize];
                let x0 = (c * cw) as usize;
                let x1 = if c + 1 == COLUMNS { size } else { (c + 1) * cw } as usize;
                // Card space: x across in [-0.25, 0.25], y from the stem (0) to the tip.
                let to_card = |x: usize| (((x - x0) as f32 + 0.5) / cw as f32 - 0.5) * 0.5;
                let to_pixel = |cx: f32| x0 as f32 + (cx / 0.5 + 0.5) * cw as f32 - 0.5;
                card.row(ly, x0..x1, to_card, to_pixel, rs);
                for (x, px) in out.iter_mut().enumerate().take(x1).skip(x0) {
                    let inside = rs.best[x];
                    let alpha = (inside * px_per_unit + 0.5).clamp(0.0, 1.0);
                    let twig = !rs.blade[x] && inside > 0.0;
                    *px = card.color(inside, rs.vein[x], twig, alpha, rs.mottle[x]);
                }
            }
        },
    );
    Ok(LeafAtlas {
        image,
        columns: COLUMNS,
        rows: ROWS,
    })
}

/// One thread's scratch for an atlas row: the mottling, and per pixel the distance inside
/// the nearest shape, its vein and whether it is a blade's.
struct RowScratch {
    mottle: Vec<f32>,
    line: Vec<f32>,
    best: Vec<f32>,
    vein: Vec<f32>,
    blade: Vec<bool>,
}

impl RowScratch {
    fn new(n: usize) -> Self {
        RowScratch {
            mottle: vec![0.0; n],
            line: Vec::new(),
            best: vec![0.0; n],
            vein: vec![0.0; n],
            blade: vec![false; n],
        }
    }
}

/// A blade's half-width along its length (0 at the petiole's end, 1 at the tip), for a
/// variant of width 1, tabulated once per shape.
struct Profile {
    half_width: Curve,
    /// A maple's reach by the angle from its tip (in half turns, 0..=0.86).
    lobes: Curve,
}

impl Profile {
    fn new(shape: LeafShape) -> Self {
        let pi = std::f32::consts::PI;
        let half_width = Curve::new(|t| match shape {
            LeafShape::Ovate => 0.23 * (pi * t.powf(0.75)).sin(),
            LeafShape::Lanceolate => 0.1 * (pi * t.powf(0.9)).sin().max(0.0).powf(0.8),
            _ => {
                0.22 * (pi * t.powf(0.85)).sin()
                    * (0.66 + 0.34 * (pi * 4.5 * t).sin().abs().powf(0.6))
            }
        });
        let lobes = Curve::new(|s| {
            let a = s * 0.86 * pi;
            let lobes = (a * 5.0 / 1.72).cos().abs();
            0.25 * (0.6 + 0.4 * lobes) * (1.0 - 0.15 * (a / pi))
        });
        Profile { half_width, lobes }
    }
}

/// A blade on a card, or a needle: its base, unit direction, length, and the quad (card
/// units) it lies in, with a margin for the antialiased edge.
struct Blade {
    base: [f32; 2],
    dir: [f32; 2],
    len: f32,
    quad: [[f32; 2]; 4],
}

impl Blade {
    /// A blade whose outline lies within `across` (leaf units, either side of its axis)
    /// and `behind`..`ahead` along it.
    fn new(base: [f32; 2], angle: f32, len: f32, across: f32, (behind, ahead): (f32, f32)) -> Self {
        let dir = [angle.sin(), angle.cos()];
        let perp = [dir[1], -dir[0]];
        let at = |along: f32, side: f32| {
            [
                base[0] + (dir[0] * along + perp[0] * side) * len,
                base[1] + (dir[1] * along + perp[1] * side) * len,
            ]
        };
        Blade {
            base,
            dir,
            len,
            quad: [
                at(-behind, -across),
                at(ahead, -across),
                at(ahead, across),
                at(-behind, across),
            ],
        }
    }

    /// A needle of half-width at most `half` (card units) along its segment.
    fn needle(base: [f32; 2], angle: f32, len: f32, half: f32) -> Self {
        let pad = (half + 0.004) / len;
        Blade::new(base, angle, len, pad, (pad, 1.0 + pad))
    }

    /// A leaf blade: within 0.34 of its axis, from a little behind its base to a little
    /// past its tip (leaf units).
    fn leaf(base: [f32; 2], angle: f32, len: f32) -> Self {
        Blade::new(base, angle, len, 0.34, (0.06, 1.04))
    }

    /// Where the row at card y `y` crosses the quad: its card x range.
    fn span(&self, y: f32) -> Option<(f32, f32)> {
        let (mut lo, mut hi) = (f32::MAX, f32::MIN);
        for k in 0..4 {
            let (a, b) = (self.quad[k], self.quad[(k + 1) % 4]);
            if (a[1] - y) * (b[1] - y) > 0.0 || a[1] == b[1] {
                continue;
            }
            let x = a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            lo = lo.min(x);
            hi = hi.max(x);
        }
        (lo <= hi).then_some((lo, hi))
    }
}

/// One variant's card: its blades (or needles) laid out once, its twig and its colour.
struct Card<'a> {
    look: &'a LeafLook,
    v: Variant,
    profile: &'a Profile,
    /// Leaf blades (shapes other than needles), in leaf order.
    blades: Vec<Blade>,
    /// Needles: segments with a tapering half-width (`half`, `taper`).
    needles: Vec<Blade>,
    half: f32,
    taper: f32,
    /// Where the twig ends (card units along the card); 0: no twig (one blade).
    tip_y: f32,
    base: [u8; 3],
}

impl<'a> Card<'a> {
    fn new(look: &'a LeafLook, v: Variant, profile: &'a Profile) -> Self {
        let n = look.leaves.clamp(1, 16);
        let yellow = [
            look.color[0].saturating_add(60),
            look.color[1].saturating_add(30),
            look.color[2],
        ];
        let mut card = Card {
            look,
            v,
            profile,
            blades: Vec::new(),
            needles: Vec::new(),
            half: 0.0075,
            taper: 0.7,
            tip_y: 0.0,
            base: scale(mix(look.color, yellow, v.hue), v.tint),
        };
        if n == 1 {
            if look.shape == LeafShape::Needles {
                // A cluster of needles from the stem's end, spread in a fan.
                let k = 11;
                for j in 0..k {
                    let s = j as f32 / (k - 1) as f32 * 2.0 - 1.0;
                    let jitter = unit(j, 9, v.seed) - 0.5;
                    let angle = s * 0.22 * v.width + 0.04 * jitter;
                    let len = (0.9 - 0.12 * s.abs() + 0.05 * jitter) * v.length;
                    card.needles
                        .push(Blade::needle([0.0, 0.06], angle, len, card.half));
                }
            }
            // One blade filling the card: leaf space is card space.
            card.blades
                .push(Blade::new([0.0, 0.0], 0.0, 1.0, 1.0, (1.0, 2.0)));
            return card;
        }
        // The twig: from the stem's end to two thirds of the card, slightly bent; the
        // terminal blade reaches on to the card's tip.
        card.tip_y = 0.66 * v.length;
        if look.shape == LeafShape::Needles {
            // Needles all along the twig (a bottlebrush), leaving it alternately on both
            // sides, leaning toward the tip. A needle is drawn thicker than life (1.3% of
            // the card, 6.5 mm on a pine's 50 cm card): at 0.6% a crown seen whole was
            // the twigs' brown, its needles thinner than a texel of the mipmaps a viewer
            // samples from that far, and cut by the alpha test.
            (card.half, card.taper) = (0.013, 0.6);
            let count = n * 6;
            for k in 0..count {
                let at = 0.08 + 0.92 * k as f32 / (count - 1) as f32;
                let side = if k % 2 == 0 { 1.0 } else { -1.0 };
                let jitter = unit(k, 23, v.seed) - 0.5;
                let angle = side * (0.75 + 0.35 * jitter) * (1.0 - 0.5 * at);
                let len = 0.2 * (1.0 - 0.35 * at) * (1.0 + 0.2 * jitter) * v.width;
                let base = [card.twig_x(at), at * card.tip_y];
                card.needles
                    .push(Blade::needle(base, angle, len, card.half));
            }
            return card;
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
            let base = [card.twig_x(at), at * card.tip_y];
            card.blades.push(Blade::leaf(base, angle, len));
        }
        card
    }

    fn twig_x(&self, t: f32) -> f32 {
        self.v.bend * 2.0 * t * t
    }

    /// Row `y` (card units) of this card over pixels `xs`: for each pixel the distance
    /// inside the drawn shape (card units), how much of a vein it is, and whether a blade
    /// (not the twig) is nearest, into `rs`. Each blade is evaluated only over the pixels
    /// its quad crosses on this row.
    fn row(
        &self,
        y: f32,
        xs: std::ops::Range<usize>,
        to_card: impl Fn(usize) -> f32,
        to_pixel: impl Fn(f32) -> f32,
        rs: &mut RowScratch,
    ) {
        let on_twig = self.tip_y > 0.0 && y <= self.tip_y;
        let t = (y / self.tip_y.max(1e-6)).clamp(0.0, 1.0);
        let (twig_x, twig_half) = (self.twig_x(t), 0.007 * (1.0 - 0.5 * t));
        for x in xs.clone() {
            rs.best[x] = if on_twig {
                twig_half - (to_card(x) - twig_x).abs()
            } else {
                -1.0
            };
            rs.vein[x] = 0.0;
            rs.blade[x] = false;
        }
        let nb = self.blades.len();
        for (k, b) in self.blades.iter().chain(&self.needles).enumerate() {
            let Some((lo, hi)) = b.span(y) else { continue };
            let first = (to_pixel(lo).floor().max(xs.start as f32) as usize).max(xs.start);
            let last = ((to_pixel(hi).ceil() + 1.0).max(0.0) as usize).min(xs.end);
            for x in first..last {
                let (qx, qy) = (to_card(x) - b.base[0], y - b.base[1]);
                let (d, vn) = if k >= nb {
                    // A needle: distance to its segment, minus its tapering half-width.
                    let t = ((qx * b.dir[0] + qy * b.dir[1]) / b.len).clamp(0.0, 1.0);
                    let (ex, ey) = (qx - b.dir[0] * b.len * t, qy - b.dir[1] * b.len * t);
                    (
                        self.half * (1.0 - self.taper * t) - (ex * ex + ey * ey).sqrt(),
                        0.0,
                    )
                } else {
                    // Leaf space: along the blade / len, across it / len.
                    let inv = 1.0 / b.len;
                    let ly = (qx * b.dir[0] + qy * b.dir[1]) * inv;
                    let lx = (qx * b.dir[1] - qy * b.dir[0]) * inv;
                    let (d, vn) = self.blade(lx, ly);
                    (d * b.len, vn)
                };
                if d > rs.best[x] {
                    (rs.best[x], rs.vein[x], rs.blade[x]) = (d, vn, true);
                }
            }
        }
    }

    /// Where leaf point (x, y) is for the blade: its distance inside the outline (leaf
    /// units, negative outside) and how much of a vein it is (0..=1).
    fn blade(&self, x: f32, y: f32) -> (f32, f32) {
        let v = &self.v;
        let petiole_end = 0.12;
        let petiole = if y < petiole_end + 0.02 {
            (0.006 - x.abs()).min(y)
        } else {
            -1.0
        };
        match self.look.shape {
            // A needle fan's blade is its petiole; the needles are drawn as segments.
            LeafShape::Needles => return (petiole, 0.0),
            LeafShape::Palmate => {
                let (d, vein) = self.palmate(x, y);
                return (d.max(petiole), vein);
            }
            _ => {}
        }
        let mid = x - v.bend * y * y;
        let top = petiole_end + (1.0 - petiole_end) * v.length - 0.02;
        let t = (y - petiole_end) / (top - petiole_end);
        if !(0.0..=1.0).contains(&t) {
            return (petiole, 0.0);
        }
        let hw = v.width * self.profile.half_width.at(t);
        let inside = (hw - mid.abs()).max(petiole);
        // Midrib, and lateral veins running out and up from it.
        let midrib = (1.0 - mid.abs() / 0.005).max(0.0);
        let phase = (t - 2.2 * mid.abs()) * 9.0;
        let lateral = (1.0 - (phase - phase.round()).abs() / 0.08).max(0.0) * 0.7;
        (inside, midrib.max(lateral))
    }

    /// A maple's blade: five pointed lobes around a centre, distance approximated
    /// radially.
    fn palmate(&self, x: f32, y: f32) -> (f32, f32) {
        let (dx, dy) = (x, y - 0.5);
        let r2 = dx * dx + dy * dy;
        let reach_max = 0.25 * self.v.width.min(1.0);
        // Beyond the longest lobe: outside, without the angle.
        if r2 > reach_max * reach_max * 1.2 {
            return (reach_max - r2.sqrt(), 0.0);
        }
        let r = r2.sqrt();
        // Angle from the tip direction (+y), 0..pi either side.
        let pi = std::f32::consts::PI;
        let a = atan2(dx.abs(), dy);
        if a > 0.86 * pi {
            return (-1.0, 0.0);
        }
        let inside = self.v.width.min(1.0) * self.profile.lobes.at(a / (0.86 * pi)) - r;
        // Veins: the five lobes' axes.
        let lobe_axis = ((a * 5.0 / 1.72) / pi).fract();
        let vein = (1.0 - (lobe_axis.min(1.0 - lobe_axis) * pi * r) / 0.004).max(0.0);
        (inside, vein)
    }

    /// The pixel's colour: the variant's tone mottled, darker toward the outline, lighter
    /// along the veins; the twig brown; outside, the blade's colour at alpha 0.
    fn color(&self, inside: f32, vein: f32, twig: bool, alpha: f32, mottle: f32) -> [u8; 4] {
        let (look, base) = (self.look, self.base);
        let var = look.variation.clamp(0.0, 1.0);
        if alpha <= 0.0 {
            return [base[0], base[1], base[2], 0];
        }
        if twig {
            return [92, 70, 52, (alpha * 255.0 + 0.5) as u8];
        }
        let edge = (inside / 0.02).clamp(0.0, 1.0);
        let f = (1.0 + (mottle - 0.5) * 0.5 * var.max(0.2)) * (0.82 + 0.18 * edge);
        let mut col = scale(base, f);
        if vein > 0.0 && look.veins > 0.0 {
            let light = [
                col[0].saturating_add(70),
                col[1].saturating_add(70),
                col[2].saturating_add(30),
            ];
            col = mix(col, light, vein * look.veins);
        }
        [col[0], col[1], col[2], (alpha * 255.0 + 0.5) as u8]
    }
}

/// `y.atan2(x)` for `y` ≥ 0 (0..=pi), to within 2e-5 of it: a polynomial on the octant
/// and its reflections, the same bits on every platform (no libm).
fn atan2(y: f32, x: f32) -> f32 {
    use std::f32::consts::{FRAC_PI_2, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = (ax.min(ay), ax.max(ay));
    if hi == 0.0 {
        return 0.0;
    }
    let a = lo / hi;
    let s = a * a;
    // Abramowitz and Stegun 4.4.49: within 1e-5 on [0, 1].
    let mut r =
        a * (0.999_866 + s * (-0.330_299_5 + s * (0.180_141 + s * (-0.085_133 + s * 0.020_835_1))));
    if ay > ax {
        r = FRAC_PI_2 - r;
    }
    if x < 0.0 {
        r = PI - r;
    }
    r
}

#[cfg(test)]
mod tests {
    #[test]
    fn atan2_is_close() {
        for k in 0..=2000 {
            let a = k as f32 / 2000.0 * std::f32::consts::PI;
            let (y, x) = (a.sin().abs() * 0.7, a.cos() * 0.7);
            assert!((super::atan2(y, x) - y.atan2(x)).abs() < 2e-5, "{a}");
        }
        assert_eq!(super::atan2(0.0, 0.0), 0.0);
    }
}
