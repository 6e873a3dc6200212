//! Tiling bark: a height field drawn from noise that wraps, coloured between a dark and a
//! light tone and turned into a tangent-space normal map.

use super::noise::{Cells, Fractal, unit};
use super::{Image, check_size, fill, grid, mix, scale};
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
    let (color, normal) = bark_maps(look, size, seed, (true, true), run)?;
    Ok(BarkTextures {
        color: color.expect("asked for"),
        normal: normal.expect("asked for"),
    })
}

/// One of a bark's maps alone (the normal map with `normal`, else the colour map): the
/// same pixels as [`bark_textures`] gives, without drawing the other.
pub(crate) fn bark_map(
    look: &BarkLook,
    size: u32,
    seed: u64,
    normal: bool,
    run: &Run<'_>,
) -> Result<Image> {
    let (color, normal_map) = bark_maps(look, size, seed, (!normal, normal), run)?;
    Ok(color.or(normal_map).expect("one was asked for"))
}

fn bark_maps(
    look: &BarkLook,
    size: u32,
    seed: u64,
    (want_color, want_normal): (bool, bool),
    run: &Run<'_>,
) -> Result<(Option<Image>, Option<Image>)> {
    check_size("size", size)?;
    let seed32 = (seed ^ (seed >> 32)) as u32;
    let n = size as usize;
    let field = Field::new(look.kind, seed32);
    // The height field first (the normals read its neighbours).
    let heights = grid(size, size, run, |x, y| {
        field.height(
            (x as f32 + 0.5) / size as f32,
            (y as f32 + 0.5) / size as f32,
        )
    });
    let h = |x: usize, y: usize| heights[(y % n) * n + (x % n)];
    let fine = Fractal::new(32, 32, 2, seed32 ^ 0xfa11);
    let color = want_color.then(|| {
        fill(size, size, run, |x, y| {
            let (x, y) = (x as usize, y as usize);
            let mut c = field.color(
                look,
                h(x, y),
                (x as f32 + 0.5) / n as f32,
                (y as f32 + 0.5) / n as f32,
            );
            c = scale(
                c,
                0.9 + 0.2 * fine.at(x as f32 / n as f32, y as f32 / n as f32),
            );
            [c[0], c[1], c[2], 255]
        })
    });
    let k = look.relief.clamp(0.0, 1.0) * n as f32 / 64.0;
    let normal = want_normal.then(|| {
        fill(size, size, run, |x, y| {
            let (x, y) = (x as usize, y as usize);
            let gx = (h(x + 1, y) - h(x + n - 1, y)) * 0.5 * k;
            let g_down = (h(x, y + 1) - h(x, y + n - 1)) * 0.5 * k;
            // Up the image is minus rows: the normal leans against the slope.
            let (nx, ny, nz) = (-gx, g_down, 1.0f32);
            let len = (nx * nx + ny * ny + nz * nz).sqrt();
            let enc = |c: f32| ((c / len * 0.5 + 0.5) * 255.0 + 0.5) as u8;
            [enc(nx), enc(ny), enc(nz), 255]
        })
    });
    Ok((color, normal))
}

/// The noises of one bark pattern.
struct Field {
    kind: BarkKind,
    coarse: Fractal,
    detail: Fractal,
    cells: Cells,
    seed: u32,
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
        Field {
            kind,
            coarse,
            detail,
            cells,
            seed,
        }
    }

    /// Height in 0..=1 at (u, v) of the tile: 0 in a furrow, 1 on the surface.
    fn height(&self, u: f32, v: f32) -> f32 {
        match self.kind {
            BarkKind::Furrowed => {
                // Furrows run where the noise crosses its middle: thin, connected lines.
                let n = self.coarse.at(u, v);
                let ridge = ((2.0 * n - 1.0).abs() * 5.0).min(1.0);
                ridge.powf(0.6) * (0.7 + 0.3 * self.detail.at(u, v))
            }
            BarkKind::Smooth => 0.8 + 0.2 * self.detail.at(u, v) - 0.4 * self.lenticel(u, v),
            BarkKind::Plated => {
                let (d1, d2, _) = self.cells.at(u, v);
                let crack = ((d2 - d1) / 0.22).clamp(0.0, 1.0);
                crack.sqrt() * (0.7 + 0.3 * self.detail.at(u, v))
            }
            BarkKind::Fissured => {
                let n = self.coarse.at(u, v);
                let fissure = ((2.0 * n - 1.0).abs() * 7.0).min(1.0);
                (0.35 + 0.65 * fissure) * (0.75 + 0.25 * self.detail.at(u, v))
            }
        }
    }

    /// The colour of the surface at height `h`.
    fn color(&self, look: &BarkLook, h: f32, u: f32, v: f32) -> [u8; 3] {
        match self.kind {
            BarkKind::Smooth => {
                let patch = ((self.coarse.at(u, v) - 0.68) / 0.1).clamp(0.0, 1.0);
                let dark = self.lenticel(u, v).max(patch * 0.85);
                mix(look.light, look.dark, dark)
            }
            BarkKind::Plated => {
                let (_, _, id) = self.cells.at(u, v);
                let tint = 0.85 + 0.3 * ((id >> 8) & 0xff) as f32 / 255.0;
                scale(mix(look.dark, look.light, h), tint)
            }
            _ => mix(look.dark, look.light, h.powf(0.8)),
        }
    }

    /// 1 on a birch's lenticel (a short dark horizontal dash), 0 elsewhere.
    fn lenticel(&self, u: f32, v: f32) -> f32 {
        let rows = 40u32;
        let band = ((v * rows as f32) as u32).min(rows - 1);
        let within = v * rows as f32 - band as f32;
        let mut best = 0.0f32;
        for k in 0..2 {
            let centre = unit(band, k, self.seed);
            let half = 0.02 + 0.06 * unit(band, k + 7, self.seed);
            let du = (u - centre + 1.5).rem_euclid(1.0) - 0.5;
            let thick = 0.22 + 0.1 * unit(band, k + 3, self.seed);
            let along = (1.0 - du.abs() / half).clamp(0.0, 1.0);
            let across = (1.0 - (within - 0.5).abs() / thick).clamp(0.0, 1.0);
            best = best.max((along * 3.0).min(1.0) * (across * 3.0).min(1.0));
        }
        best
    }
}
