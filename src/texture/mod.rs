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

pub use bark::{BarkKind, BarkLook, BarkTextures, bark_textures, bark_textures_in};
pub(crate) use bark::{BarkMap, bark_map};
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

    /// The image halved (each pixel the mean of four, alpha too) until neither side is
    /// over `most` pixels (at least 1): a small copy to sample where the full one would
    /// not stay in the cache (arbor's rasterizer draws many small views of a tree).
    pub fn downsampled(&self, most: u32) -> Image {
        let mut img = self.clone();
        while (img.width > most || img.height > most) && img.width >= 2 && img.height >= 2 {
            let (w, h) = (img.width / 2, img.height / 2);
            let mut pixels = vec![0u8; (w * h * 4) as usize];
            for y in 0..h {
                for x in 0..w {
                    for c in 0..4 {
                        let at = |dx: u32, dy: u32| {
                            img.pixels[(((2 * y + dy) * img.width + 2 * x + dx) * 4 + c) as usize]
                                as u32
                        };
                        pixels[((y * w + x) * 4 + c) as usize] =
                            ((at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1) + 2) / 4) as u8;
                    }
                }
            }
            img = Image {
                width: w,
                height: h,
                pixels,
            };
        }
        img
    }

    /// The pixel at column `x`, row `y` (inlined: the rasterizer reads a texel a pixel).
    #[inline]
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let k = (y as usize * self.width as usize + x as usize) * 4;
        let p = &self.pixels[k..k + 4];
        [p[0], p[1], p[2], p[3]]
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

/// A `width` × `height` grid drawn a row at a time, rows from the top: `draw(scratch, y,
/// row)` fills row `y`, with `scratch` made by `init` once per thread. Drawn on the run's
/// threads when large (the result does not depend on the split).
fn grid_rows<T: Copy + Default + Send, S>(
    width: u32,
    height: u32,
    run: &Run<'_>,
    init: impl Fn() -> S + Sync,
    draw: impl Fn(&mut S, u32, &mut [T]) + Sync,
) -> Vec<T> {
    let w = width as usize;
    let mut out = vec![T::default(); w * height as usize];
    let draw_rows = |scratch: &mut S, first: usize, chunk: &mut [T]| {
        for (dy, row) in chunk.chunks_exact_mut(w).enumerate() {
            draw(scratch, (first + dy) as u32, row);
        }
    };
    // The run's thread count (0: the cores, at most 8); small images on the calling thread.
    let threads = match run.threads_or(0) {
        _ if out.len() < 1 << 16 => 1,
        0 => std::thread::available_parallelism().map_or(1, |n| n.get().min(8)),
        t => t as usize,
    };
    if threads <= 1 {
        draw_rows(&mut init(), 0, &mut out);
        return out;
    }
    // More bands than threads, handed out in turn, so a band of costly rows (a leaf
    // atlas' cells differ) does not keep one thread busy while the others wait.
    let bands = (threads * 8).min(height as usize).max(1);
    let rows_each = (height as usize).div_ceil(bands);
    let queue = std::sync::Mutex::new(out.chunks_mut(rows_each * w).enumerate());
    std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut scratch = init();
                    loop {
                        let next = queue
                            .lock()
                            .unwrap_or_else(std::sync::PoisonError::into_inner)
                            .next();
                        let Some((k, chunk)) = next else { break };
                        draw_rows(&mut scratch, k * rows_each, chunk);
                    }
                })
            })
            .collect();
        // Joined, not left to the scope: each thread has ended, not only its work, when
        // this returns (a host's leak checker then sees no thread still exiting).
        for w in workers {
            w.join().expect("a texture band's thread does not panic");
        }
    });
    out
}

/// An RGBA8 image drawn a row at a time (see [`grid_rows`]).
fn fill_rows<S>(
    width: u32,
    height: u32,
    run: &Run<'_>,
    init: impl Fn() -> S + Sync,
    draw: impl Fn(&mut S, u32, &mut [[u8; 4]]) + Sync,
) -> Image {
    let px = grid_rows(width, height, run, init, draw);
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

/// `a` to `b` by `t` in 0..=1, per channel, in floats (0..=255).
#[inline]
fn lerp(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    let t = t.clamp(0.0, 1.0);
    std::array::from_fn(|k| a[k] + (b[k] - a[k]) * t)
}

/// A float colour (0..=255 a channel) times `f`, rounded to bytes, saturating.
#[inline]
fn rgb(c: [f32; 3], f: f32) -> [u8; 3] {
    let f = f.max(0.0);
    c.map(|v| (v * f + 0.5).min(255.0) as u8)
}

/// `c` times `f` per channel, saturating.
fn scale(c: [u8; 3], f: f32) -> [u8; 3] {
    c.map(|v| (v as f32 * f.max(0.0) + 0.5).min(255.0) as u8)
}

#[cfg(test)]
mod tests;
