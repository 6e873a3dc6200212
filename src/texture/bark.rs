//! Tiling bark: a height field drawn from noise that wraps, coloured between a dark and a
//! light tone and turned into a tangent-space normal map.

use super::noise::{Cells, Curve, Fractal, Near, Sampled, centre, unit};
use super::{Image, check_size, fill_rows, grid_rows, lerp, rgb};
use crate::error::Result;
use crate::progress::Run;

/// The pattern of a bark.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BarkKind {
    /// Deep vertical furrows between rough ridges (oak, old poplar).
    Furrowed,
    /// Smooth pale bark with dark horizontal lenticels and patches (birch).
    Smooth,
    /// Scaly plates parted by cracks (pine).
    Plated,
    /// Fine, shallow fissures (maple, spruce, shrubs).
    Fissured,
}

/// How a species' bark looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BarkLook {
    /// The pattern.
    pub kind: BarkKind,
    /// The tone of the bark's surface, sRGB.
    pub light: [u8; 3],
    /// The tone of its furrows, sRGB.
    pub dark: [u8; 3],
    /// Metres of bark one repeat of the texture covers (the mesh's `texture_scale`).
    pub tile: f32,
    /// Depth of the relief in the normal map, 0..=1.
    pub relief: f32,
}

impl BarkLook {
    /// Grey-brown, deeply furrowed; a 0.6 m tile.
    pub fn oak() -> Self {
        BarkLook {
            kind: BarkKind::Furrowed,
            light: [112, 102, 90],
            dark: [38, 32, 28],
            tile: 0.6,
            relief: 0.8,
        }
    }
    /// Grey, finely fissured; a 0.5 m tile.
    pub fn maple() -> Self {
        BarkLook {
            kind: BarkKind::Fissured,
            light: [120, 112, 102],
            dark: [58, 52, 46],
            tile: 0.5,
            relief: 0.5,
        }
    }
    /// White with dark lenticels; a 0.5 m tile.
    pub fn birch() -> Self {
        BarkLook {
            kind: BarkKind::Smooth,
            light: [222, 218, 206],
            dark: [40, 36, 34],
            tile: 0.5,
            relief: 0.3,
        }
    }
    /// Dark grey-brown, furrowed; a 0.6 m tile.
    pub fn willow() -> Self {
        BarkLook {
            kind: BarkKind::Furrowed,
            light: [104, 96, 80],
            dark: [44, 38, 30],
            tile: 0.6,
            relief: 0.7,
        }
    }
    /// Pale grey, fissured; a 0.5 m tile.
    pub fn poplar() -> Self {
        BarkLook {
            kind: BarkKind::Fissured,
            light: [150, 146, 132],
            dark: [64, 60, 52],
            tile: 0.5,
            relief: 0.5,
        }
    }
    /// Orange-brown plates; a 0.6 m tile.
    pub fn pine() -> Self {
        BarkLook {
            kind: BarkKind::Plated,
            light: [150, 92, 58],
            dark: [50, 34, 26],
            tile: 0.6,
            relief: 0.7,
        }
    }
    /// Grey-brown, finely scaled; a 0.5 m tile.
    pub fn spruce() -> Self {
        BarkLook {
            kind: BarkKind::Fissured,
            light: [106, 82, 64],
            dark: [46, 34, 28],
            tile: 0.5,
            relief: 0.5,
        }
    }
    /// Brown-grey, fine; a 0.4 m tile.
    pub fn shrub() -> Self {
        BarkLook {
            kind: BarkKind::Fissured,
            light: [104, 90, 74],
            dark: [52, 44, 36],
            tile: 0.4,
            relief: 0.4,
        }
    }
}

/// A bark's tiling maps, of one size.
#[derive(Clone, Debug, PartialEq)]
pub struct BarkTextures {
    /// Base colour, sRGB, alpha 255.
    pub color: Image,
    /// Tangent-space normal map (glTF's convention: +X right, +Y up the image, +Z out).
    pub normal: Image,
    /// Roughness in glTF's metallic-roughness layout: green the roughness (rough in the
    /// furrows and cracks, smoother on the ridges and plates; a birch's white bark
    /// smoothest), blue the metalness (0), red 255, alpha 255; linear.
    pub roughness: Image,
}

/// One of a bark's maps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BarkMap {
    Color,
    Normal,
    Roughness,
}

/// Draws `look`'s bark as `size` × `size` maps (16..=4096 pixels, checked before any
/// allocation) that tile in both directions.
pub fn bark_textures(look: &BarkLook, size: u32, seed: u64) -> Result<BarkTextures> {
    bark_textures_in(look, size, seed, &Run::default())
}

/// [`bark_textures`] on the run's threads (1: the calling thread only); the same pixels.
pub fn bark_textures_in(
    look: &BarkLook,
    size: u32,
    seed: u64,
    run: &Run<'_>,
) -> Result<BarkTextures> {
    let [color, normal, roughness] = bark_maps(look, size, seed, [true; 3], run)?;
    Ok(BarkTextures {
        color: color.expect("asked for"),
        normal: normal.expect("asked for"),
        roughness: roughness.expect("asked for"),
    })
}

/// One of a bark's maps alone: the same pixels as [`bark_textures`] gives, without
/// drawing the others.
pub(crate) fn bark_map(
    look: &BarkLook,
    size: u32,
    seed: u64,
    which: BarkMap,
    run: &Run<'_>,
) -> Result<Image> {
    let want = [
        which == BarkMap::Color,
        which == BarkMap::Normal,
        which == BarkMap::Roughness,
    ];
    let maps = bark_maps(look, size, seed, want, run)?;
    Ok(maps
        .into_iter()
        .flatten()
        .next()
        .expect("one was asked for"))
}

fn bark_maps(
    look: &BarkLook,
    size: u32,
    seed: u64,
    [want_color, want_normal, want_roughness]: [bool; 3],
    run: &Run<'_>,
) -> Result<[Option<Image>; 3]> {
    check_size("size", size)?;
    let seed32 = (seed ^ (seed >> 32)) as u32;
    let n = size as usize;
    let field = Field::new(look.kind, seed32);
    let sampled = field.sample(size);
    // The height field first (the normals read its neighbours), with each pixel's shade:
    // how dark a smooth bark is there, or the tint of a plate.
    let field_rows = grid_rows(
        size,
        size,
        run,
        || Rows::new(n),
        |rows, y, out| field.heights(&sampled, rows, y, out),
    );
    let color = want_color.then(|| {
        let fine = Fractal::new(32, 32, 2, seed32 ^ 0xfa11);
        let fine = fine.columns(size);
        let tone = Curve::new(|h| h.powf(0.8));
        let (dark, light) = (look.dark.map(f32::from), look.light.map(f32::from));
        fill_rows(
            size,
            size,
            run,
            || Rows::new(n),
            |rows, y, out| {
                fine.row(centre(y, size), &mut rows.a, &mut rows.line);
                let field_row = &field_rows[y as usize * n..][..n];
                for ((px, &[h, shade]), &fine) in out.iter_mut().zip(field_row).zip(&rows.a) {
                    // In floats, rounded once.
                    let (t, f) = match field.kind {
                        BarkKind::Smooth => (1.0 - shade, 1.0),
                        BarkKind::Plated => (h, shade),
                        _ => (tone.at(h), 1.0),
                    };
                    let c = rgb(lerp(dark, light, t), f * (0.9 + 0.2 * fine));
                    *px = [c[0], c[1], c[2], 255];
                }
            },
        )
    });
    let k = look.relief.clamp(0.0, 1.0) * n as f32 / 64.0;
    let normal = want_normal.then(|| {
        fill_rows(
            size,
            size,
            run,
            || (),
            |_, y, out| {
                let y = y as usize;
                let row = &field_rows[y * n..][..n];
                let up = &field_rows[(y + n - 1) % n * n..][..n];
                let down = &field_rows[(y + 1) % n * n..][..n];
                for (x, px) in out.iter_mut().enumerate() {
                    let (left, right) = (
                        if x == 0 { row[n - 1] } else { row[x - 1] }[0],
                        if x + 1 == n { row[0] } else { row[x + 1] }[0],
                    );
                    let gx = (right - left) * 0.5 * k;
                    let g_down = (down[x][0] - up[x][0]) * 0.5 * k;
                    // Up the image is minus rows: the normal leans against the slope.
                    let (nx, ny) = (-gx, g_down);
                    let inv = 1.0 / (nx * nx + ny * ny + 1.0).sqrt();
                    let enc = |c: f32| ((c * inv * 0.5 + 0.5) * 255.0 + 0.5) as u8;
                    *px = [enc(nx), enc(ny), enc(1.0), 255];
                }
            },
        )
    });
    let roughness = want_roughness.then(|| {
        // Rough in the furrows (1), the surface's own roughness on top; a birch's
        // lenticels and patches rough like the furrows.
        let surface = match look.kind {
            BarkKind::Smooth => 0.45,
            BarkKind::Plated => 0.7,
            BarkKind::Fissured => 0.78,
            BarkKind::Furrowed => 0.82,
        };
        fill_rows(
            size,
            size,
            run,
            || (),
            |_, y, out| {
                let row = &field_rows[y as usize * n..][..n];
                for (px, &[h, shade]) in out.iter_mut().zip(row) {
                    let mut r = surface + (1.0 - surface) * (1.0 - h).clamp(0.0, 1.0);
                    if look.kind == BarkKind::Smooth {
                        r = r + (0.9 - r) * shade.clamp(0.0, 1.0);
                    }
                    *px = [255, (r * 255.0 + 0.5) as u8, 0, 255];
                }
            },
        )
    });
    Ok([color, normal, roughness])
}

/// One thread's rows of scratch: three noise rows, a lattice line, a row of cells and the
/// points near it.
struct Rows {
    a: Vec<f32>,
    b: Vec<f32>,
    c: Vec<f32>,
    line: Vec<f32>,
    cells: Vec<(f32, f32, u32)>,
    near: Vec<Near>,
}

impl Rows {
    fn new(n: usize) -> Self {
        Rows {
            a: vec![0.0; n],
            b: vec![0.0; n],
            c: vec![0.0; n],
            line: Vec::new(),
            cells: vec![(0.0, 0.0, 0); n],
            near: Vec::new(),
        }
    }
}

/// The noises of one bark pattern.
struct Field {
    kind: BarkKind,
    coarse: Fractal,
    detail: Fractal,
    cells: Cells,
    seed: u32,
    ridge: Curve,
}

/// A [`Field`]'s noises sampled at the pixel centres of one image width.
struct FieldSampled<'a> {
    coarse: Sampled<'a>,
    detail: Sampled<'a>,
    width: u32,
}

impl Field {
    fn new(kind: BarkKind, seed: u32) -> Self {
        let (coarse, detail, cells) = match kind {
            BarkKind::Furrowed => (
                Fractal::new(9, 2, 4, seed),
                Fractal::new(24, 6, 3, seed ^ 0x77),
                Cells::new(6, 3, seed),
            ),
            BarkKind::Smooth => (
                Fractal::new(3, 3, 3, seed),
                Fractal::new(16, 64, 2, seed ^ 0x77),
                Cells::new(4, 4, seed),
            ),
            BarkKind::Plated => (
                Fractal::new(6, 6, 3, seed),
                Fractal::new(24, 24, 2, seed ^ 0x77),
                Cells::new(5, 7, seed),
            ),
            BarkKind::Fissured => (
                Fractal::new(14, 3, 3, seed),
                Fractal::new(48, 12, 2, seed ^ 0x77),
                Cells::new(8, 8, seed),
            ),
        };
        let ridge = match kind {
            BarkKind::Furrowed => Curve::new(|r| r.powf(0.6)),
            _ => Curve::new(f32::sqrt),
        };
        Field {
            kind,
            coarse,
            detail,
            cells,
            seed,
            ridge,
        }
    }

    fn sample(&self, width: u32) -> FieldSampled<'_> {
        FieldSampled {
            coarse: self.coarse.columns(width),
            detail: self.detail.columns(width),
            width,
        }
    }

    /// Row `y`'s heights in 0..=1 (0 in a furrow, 1 on the surface), each with its shade
    /// (smooth bark: how dark, from lenticels and patches; plates: the plate's tint).
    fn heights(&self, s: &FieldSampled<'_>, rows: &mut Rows, y: u32, out: &mut [[f32; 2]]) {
        let v = centre(y, s.width);
        s.detail.row(v, &mut rows.b, &mut rows.line);
        let detail = &rows.b;
        match self.kind {
            BarkKind::Furrowed => {
                // Furrows run where the noise crosses its middle: thin, connected lines.
                s.coarse.row(v, &mut rows.a, &mut rows.line);
                for ((h, &n), &d) in out.iter_mut().zip(&rows.a).zip(detail) {
                    let ridge = (2.0 * n - 1.0).abs() * 5.0;
                    *h = [self.ridge.at(ridge) * (0.7 + 0.3 * d), 0.0];
                }
            }
            BarkKind::Smooth => {
                self.lenticels(v, s.width, &mut rows.c);
                s.coarse.row(v, &mut rows.a, &mut rows.line);
                for (((h, &l), &d), &p) in out.iter_mut().zip(&rows.c).zip(detail).zip(&rows.a) {
                    let patch = ((p - 0.68) / 0.1).clamp(0.0, 1.0) * 0.85;
                    *h = [0.8 + 0.2 * d - 0.4 * l, l.max(patch)];
                }
            }
            BarkKind::Plated => {
                self.cells.row(v, &mut rows.cells, &mut rows.near);
                for ((h, &d), &(d1, d2, id)) in out.iter_mut().zip(detail).zip(&rows.cells) {
                    let crack = (d2 - d1) / 0.22;
                    let tint = 0.85 + 0.3 * ((id >> 8) & 0xff) as f32 / 255.0;
                    *h = [self.ridge.at(crack) * (0.7 + 0.3 * d), tint];
                }
            }
            BarkKind::Fissured => {
                s.coarse.row(v, &mut rows.a, &mut rows.line);
                for ((h, &n), &d) in out.iter_mut().zip(&rows.a).zip(detail) {
                    let fissure = ((2.0 * n - 1.0).abs() * 7.0).min(1.0);
                    *h = [(0.35 + 0.65 * fissure) * (0.75 + 0.25 * d), 0.0];
                }
            }
        }
    }

    /// Along the row at `v`: 1 on a birch's lenticel (a short dark horizontal dash), 0
    /// elsewhere.
    fn lenticels(&self, v: f32, width: u32, out: &mut [f32]) {
        let rows = 40u32;
        let band = ((v * rows as f32) as u32).min(rows - 1);
        let within = v * rows as f32 - band as f32;
        out.fill(0.0);
        for k in 0..2 {
            let centre_u = unit(band, k, self.seed);
            let half = 0.02 + 0.06 * unit(band, k + 7, self.seed);
            let thick = 0.22 + 0.1 * unit(band, k + 3, self.seed);
            let across = ((1.0 - (within - 0.5).abs() / thick).clamp(0.0, 1.0) * 3.0).min(1.0);
            if across <= 0.0 {
                continue;
            }
            for (x, o) in out.iter_mut().enumerate() {
                let mut du = centre(x as u32, width) - centre_u;
                if du > 0.5 {
                    du -= 1.0;
                } else if du < -0.5 {
                    du += 1.0;
                }
                let along = (1.0 - du.abs() / half).clamp(0.0, 1.0);
                *o = o.max((along * 3.0).min(1.0) * across);
            }
        }
    }
}
