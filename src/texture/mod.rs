//! Textures arbor draws itself: leaf atlases (blades with outline, midrib, veins, tint and
//! translucency variation, alpha-cut) and tiling bark (colour and normal maps), as RGBA8
//! images that a scene embeds or a host copies into its own memory.
//!
//! Everything is drawn from a seed, so the same look and seed give the same bytes on every
//! platform (integer hashing and `f32` arithmetic in a fixed order, no platform maths).
//!
//! ```
//! use arbor::texture::{bark_textures, leaf_atlas, BarkLook, LeafLook};
//!
//! let atlas = leaf_atlas(&LeafLook::oak(), 256, 7).unwrap();
//! assert_eq!((atlas.image.width, atlas.image.height), (256, 256));
//! let [u0, v0, u1, v1] = atlas.rect(3);
//! assert!(u0 < u1 && v0 < v1);
//! let bark = bark_textures(&BarkLook::oak(), 128, 7).unwrap();
//! assert_eq!(bark.color.pixels.len(), 128 * 128 * 4);
//! let png = bark.color.png().unwrap();
//! assert_eq!(&png[1..4], b"PNG");
//! ```

mod bark;
mod leaf;
mod noise;

pub(crate) use bark::bark_map;
pub use bark::{BarkKind, BarkLook, BarkTextures, bark_textures, bark_textures_in};
pub use leaf::{
    ATLAS_COLUMNS, ATLAS_ROWS, LeafAtlas, LeafLook, LeafShape, atlas_rect, leaf_atlas,
    leaf_atlas_in,
};

use crate::error::{Error, Result};
use crate::progress::Run;

/// Smallest and largest edge of a drawn texture, in pixels.
pub const MIN_TEXTURE_SIZE: u32 = 16;
/// See [`MIN_TEXTURE_SIZE`]: 4096² RGBA8 is 64 MiB.
pub const MAX_TEXTURE_SIZE: u32 = 4096;

/// An RGBA8 image, rows from the top (glTF's uv origin), 4 bytes a pixel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Pixels a row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width * height * 4` bytes: R, G, B, A per pixel (colour images sRGB, normal maps
    /// linear, +Z out of the surface).
    pub pixels: Vec<u8>,
}

impl Image {
    /// The image as a PNG file (RGBA, 8 bits a channel).
    pub fn png(&self) -> Result<Vec<u8>> {
        let mut out = Vec::new();
        let mut e = png::Encoder::new(&mut out, self.width, self.height);
        e.set_color(png::ColorType::Rgba);
        e.set_depth(png::BitDepth::Eight);
        e.set_compression(png::Compression::Fast);
        let mut w = e
            .write_header()
            .map_err(|err| Error::invalid("image", format!("PNG header: {err}")))?;
        w.write_image_data(&self.pixels)
            .map_err(|err| Error::invalid("image", format!("PNG data: {err}")))?;
        w.finish()
            .map_err(|err| Error::invalid("image", format!("PNG end: {err}")))?;
        Ok(out)
    }

    /// The pixel at column `x`, row `y`.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let k = (y as usize * self.width as usize + x as usize) * 4;
        [
            self.pixels[k],
            self.pixels[k + 1],
            self.pixels[k + 2],
            self.pixels[k + 3],
        ]
    }
}

/// Checks a requested edge before anything is allocated.
pub(crate) fn check_size(field: &'static str, size: u32) -> Result<()> {
    if (MIN_TEXTURE_SIZE..=MAX_TEXTURE_SIZE).contains(&size) {
        Ok(())
    } else {
        Err(Error::invalid(
            field,
            format!("{size}; expected {MIN_TEXTURE_SIZE}..={MAX_TEXTURE_SIZE} pixels"),
        ))
    }
}

/// A `width` × `height` grid of `draw(x, y)`, rows from the top, drawn on the run's
/// threads when large (the result does not depend on the split).
fn grid<T: Copy + Default + Send>(
    width: u32,
    height: u32,
    run: &Run<'_>,
    draw: impl Fn(u32, u32) -> T + Sync,
) -> Vec<T> {
    let w = width as usize;
    let mut out = vec![T::default(); w * height as usize];
    let draw_rows = |first: usize, chunk: &mut [T]| {
        for (dy, row) in chunk.chunks_exact_mut(w).enumerate() {
            let y = (first + dy) as u32;
            for (x, px) in row.iter_mut().enumerate() {
                *px = draw(x as u32, y);
            }
        }
    };
    // The run's thread count (0: the cores, at most 8); small images on the calling thread.
    let threads = match run.threads_or(0) {
        _ if out.len() < 1 << 16 => 1,
        0 => std::thread::available_parallelism().map_or(1, |n| n.get().min(8)),
        t => t as usize,
    };
    if threads <= 1 {
        draw_rows(0, &mut out);
        return out;
    }
    let rows_each = (height as usize).div_ceil(threads);
    std::thread::scope(|s| {
        for (k, chunk) in out.chunks_mut(rows_each * w).enumerate() {
            let draw_rows = &draw_rows;
            s.spawn(move || draw_rows(k * rows_each, chunk));
        }
    });
    out
}

/// An RGBA8 image of `draw(x, y)`.
fn fill(
    width: u32,
    height: u32,
    run: &Run<'_>,
    draw: impl Fn(u32, u32) -> [u8; 4] + Sync,
) -> Image {
    let px = grid(width, height, run, draw);
    Image {
        width,
        height,
        pixels: bytemuck::allocation::cast_vec(px),
    }
}

/// `a` to `b` by `t` in 0..=1, per channel, rounded.
fn mix(a: [u8; 3], b: [u8; 3], t: f32) -> [u8; 3] {
    let t = t.clamp(0.0, 1.0);
    std::array::from_fn(|k| (a[k] as f32 + (b[k] as f32 - a[k] as f32) * t + 0.5) as u8)
}

/// `c` times `f` per channel, saturating.
fn scale(c: [u8; 3], f: f32) -> [u8; 3] {
    c.map(|v| (v as f32 * f.max(0.0) + 0.5).min(255.0) as u8)
}

#[cfg(test)]
mod tests;
