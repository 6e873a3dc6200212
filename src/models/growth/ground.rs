//! The ground a world's trees grow on: a height field (from samples, or a grey-scale PNG
//! height map), and a species map that plants a world from a painted picture.
//!
//! A [`HeightField`] is `columns × rows` heights on a square lattice of `cell_size` in the
//! X–Z plane, sample `(i, j)` at `(origin[0] + i·cell_size, origin[1] + j·cell_size)`;
//! between samples the ground is bilinear, and beyond its edges it keeps the edge's
//! height. Every size is checked before anything is allocated: at most
//! [`MAX_GROUND_SAMPLES`] samples, and a PNG's decoded size is known from its header
//! before a pixel is decoded.

use crate::error::{Error, Result};

/// Most samples a height field or a species map may have (4,096 x 4,096).
pub const MAX_GROUND_SAMPLES: usize = 1 << 24;

/// Most bytes a PNG map may decode to (16-bit RGBA at [`MAX_GROUND_SAMPLES`]).
const MAX_PNG_BYTES: usize = MAX_GROUND_SAMPLES * 8;

/// Heights on a square lattice: `columns × rows` samples `cell_size` apart in the X–Z
/// plane, sample `(i, j)` at `(origin[0] + i·cell_size, origin[1] + j·cell_size)`,
/// bilinear between samples and the edge's height beyond them; the ground
/// [`World::set_ground`](super::World::set_ground) lays under a world.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightField {
    columns: u32,
    rows: u32,
    cell_size: f32,
    origin: [f32; 2],
    heights: Vec<f32>,
    low: f32,
    high: f32,
}

/// Checks a lattice's shape: at least 2 × 2 samples, at most [`MAX_GROUND_SAMPLES`], a
/// finite positive cell and a finite origin; the sample count.
fn lattice(
    what: &'static str,
    columns: u32,
    rows: u32,
    cell_size: f32,
    origin: [f32; 2],
) -> Result<usize> {
    if columns < 2 || rows < 2 {
        return Err(Error::invalid(
            what,
            format!("{columns} x {rows} samples; expected at least 2 x 2"),
        ));
    }
    let n = columns as u64 * rows as u64;
    if n > MAX_GROUND_SAMPLES as u64 {
        return Err(Error::LimitExceeded {
            limit_name: "MAX_GROUND_SAMPLES",
            what: "samples of a ground map",
            limit: MAX_GROUND_SAMPLES as u64,
            requested: n,
            step: None,
        });
    }
    if !(cell_size.is_finite() && cell_size > 0.0) {
        return Err(Error::invalid(
            "cell_size",
            format!("{cell_size}; expected a finite number > 0"),
        ));
    }
    if !origin.iter().all(|v| v.is_finite()) {
        return Err(Error::invalid(
            "origin",
            format!("{origin:?}; expected finite coordinates"),
        ));
    }
    let far = |o: f32, n: u32| (o as f64 + (n - 1) as f64 * cell_size as f64).abs() < 1e30;
    if !(far(origin[0], columns) && far(origin[1], rows)) {
        return Err(Error::invalid(
            "cell_size",
            format!("{cell_size}: the map's far edge leaves the f32 range"),
        ));
    }
    Ok(n as usize)
}

impl HeightField {
    /// A height field of `columns × rows` samples (row by row, x fastest: sample `(i, j)`
    /// is `heights[j·columns + i]`). Errors name what is wrong: fewer than 2 × 2 samples,
    /// more than [`MAX_GROUND_SAMPLES`], a count that does not match, a non-finite
    /// height, cell or origin.
    pub fn new(
        columns: u32,
        rows: u32,
        cell_size: f32,
        origin: [f32; 2],
        heights: Vec<f32>,
    ) -> Result<Self> {
        let n = lattice("heights", columns, rows, cell_size, origin)?;
        if heights.len() != n {
            return Err(Error::invalid(
                "heights",
                format!(
                    "{} heights; expected {columns} x {rows} = {n}",
                    heights.len()
                ),
            ));
        }
        if let Some(k) = heights.iter().position(|h| !h.is_finite()) {
            return Err(Error::invalid(
                "heights",
                format!(
                    "height {} at sample ({}, {}); expected a finite number",
                    heights[k],
                    k % columns as usize,
                    k / columns as usize
                ),
            ));
        }
        let low = heights.iter().copied().fold(f32::INFINITY, f32::min);
        let high = heights.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        Ok(HeightField {
            columns,
            rows,
            cell_size,
            origin,
            heights,
            low,
            high,
        })
    }

    /// A height field whose sample `(i, j)` is `f(i, j)`; the shape is checked before
    /// anything is allocated.
    pub fn from_fn(
        columns: u32,
        rows: u32,
        cell_size: f32,
        origin: [f32; 2],
        f: impl Fn(u32, u32) -> f32,
    ) -> Result<Self> {
        lattice("heights", columns, rows, cell_size, origin)?;
        let heights = (0..rows)
            .flat_map(|j| (0..columns).map(move |i| (i, j)))
            .map(|(i, j)| f(i, j))
            .collect();
        Self::new(columns, rows, cell_size, origin, heights)
    }

    /// A height field from a PNG height map: a pixel a sample (the image's top row at
    /// the lowest z), its grey level (8 or 16 bits; a colour image's mean of red, green
    /// and blue; alpha ignored) from black at `base` to white at `base + height_scale`.
    /// The image's size is read from its header and checked against
    /// [`MAX_GROUND_SAMPLES`] before a pixel is decoded; a file that is not a PNG, or is
    /// cut short, is an error naming `height map`.
    pub fn from_png(
        png: &[u8],
        height_scale: f32,
        base: f32,
        cell_size: f32,
        origin: [f32; 2],
    ) -> Result<Self> {
        if !(height_scale.is_finite() && base.is_finite()) {
            return Err(Error::invalid(
                "height_scale",
                format!("scale {height_scale}, base {base}; expected finite numbers"),
            ));
        }
        let image = decode_png(png, "height map", cell_size, origin)?;
        let heights = image
            .grey()
            .map(|g| base + g * height_scale)
            .collect::<Vec<f32>>();
        Self::new(image.width, image.height, cell_size, origin, heights)
    }

    /// Samples along x.
    pub fn columns(&self) -> u32 {
        self.columns
    }

    /// Samples along z.
    pub fn rows(&self) -> u32 {
        self.rows
    }

    /// The lattice's spacing.
    pub fn cell_size(&self) -> f32 {
        self.cell_size
    }

    /// Sample (0, 0)'s x and z.
    pub fn origin(&self) -> [f32; 2] {
        self.origin
    }

    /// The samples, row by row.
    pub fn heights(&self) -> &[f32] {
        &self.heights
    }

    /// The lowest and highest samples.
    pub fn range(&self) -> (f32, f32) {
        (self.low, self.high)
    }

    /// The far corner's x and z.
    pub fn extent(&self) -> [f32; 2] {
        [
            self.origin[0] + (self.columns - 1) as f32 * self.cell_size,
            self.origin[1] + (self.rows - 1) as f32 * self.cell_size,
        ]
    }

    fn at(&self, i: u32, j: u32) -> f32 {
        self.heights[(j * self.columns + i) as usize]
    }

    /// The cell holding (x, z) and where in it, clamped to the map (NaN: its origin).
    fn locate(&self, x: f32, z: f32) -> (u32, u32, f32, f32) {
        let axis = |v: f32, o: f32, n: u32| {
            let g = ((v - o) / self.cell_size).clamp(0.0, (n - 1) as f32);
            let g = if g.is_nan() { 0.0 } else { g };
            let c = (g as u32).min(n - 2);
            (c, g - c as f32)
        };
        let (i, fx) = axis(x, self.origin[0], self.columns);
        let (j, fz) = axis(z, self.origin[1], self.rows);
        (i, j, fx, fz)
    }

    /// The ground's height at (x, z): bilinear between samples, the edge's height
    /// beyond the map.
    pub fn height(&self, x: f32, z: f32) -> f32 {
        let (i, j, fx, fz) = self.locate(x, z);
        let (a, b) = (self.at(i, j), self.at(i + 1, j));
        let (c, d) = (self.at(i, j + 1), self.at(i + 1, j + 1));
        let near = a + (b - a) * fx;
        let far = c + (d - c) * fx;
        near + (far - near) * fz
    }

    /// The ground's unit normal at (x, z) (up where flat).
    pub fn normal(&self, x: f32, z: f32) -> [f32; 3] {
        let (i, j, fx, fz) = self.locate(x, z);
        let (a, b) = (self.at(i, j), self.at(i + 1, j));
        let (c, d) = (self.at(i, j + 1), self.at(i + 1, j + 1));
        let dx = ((b - a) * (1.0 - fz) + (d - c) * fz) / self.cell_size;
        let dz = ((c - a) * (1.0 - fx) + (d - b) * fx) / self.cell_size;
        let n = glam::Vec3::new(-dx, 1.0, -dz).normalize_or(glam::Vec3::Y);
        n.to_array()
    }

    /// The ground as a mesh: a vertex a sample (position, normal, and uv in cells, so a
    /// texture repeats once a cell), two counter-clockwise triangles a cell seen from
    /// above, 32-bit triangle-list indices.
    pub fn mesh(&self) -> crate::mesh::Mesh {
        let (nx, nz) = (self.columns, self.rows);
        let mut vertices = Vec::with_capacity((nx * nz) as usize);
        for j in 0..nz {
            for i in 0..nx {
                let x = self.origin[0] + i as f32 * self.cell_size;
                let z = self.origin[1] + j as f32 * self.cell_size;
                vertices.push(crate::mesh::Vertex {
                    position: [x, self.at(i, j), z],
                    normal: self.normal(x, z),
                    uv: [i as f32, j as f32],
                });
            }
        }
        let mut indices = Vec::with_capacity(((nx - 1) * (nz - 1) * 6) as usize);
        for j in 0..nz - 1 {
            for i in 0..nx - 1 {
                let a = j * nx + i;
                let (b, c, d) = (a + 1, a + nx, a + nx + 1);
                // Y up, seen from above (+Y): a → c → b turns counter-clockwise.
                indices.extend_from_slice(&[a, c, b, b, c, d]);
            }
        }
        crate::mesh::Mesh {
            vertices,
            indices,
            topology: crate::mesh::Topology::TriangleList,
            ranges: Vec::new(),
        }
    }
}

/// A decoded PNG map: its size and each pixel's channels scaled to 0..=1.
pub(crate) struct MapImage {
    pub(crate) width: u32,
    pub(crate) height: u32,
    /// Channels a pixel (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA).
    channels: usize,
    values: Vec<u16>,
    max: f32,
}

impl MapImage {
    /// Each pixel's grey level, 0..=1 (colour: the mean of red, green and blue).
    pub(crate) fn grey(&self) -> impl Iterator<Item = f32> + '_ {
        let c = self.channels;
        self.values.chunks_exact(c).map(move |p| {
            let v = if c >= 3 {
                (p[0] as f32 + p[1] as f32 + p[2] as f32) / 3.0
            } else {
                p[0] as f32
            };
            v / self.max
        })
    }

    /// Each pixel's colour as 8-bit RGB (grey repeated; 16 bits: the high byte).
    pub(crate) fn rgb(&self) -> impl Iterator<Item = [u8; 3]> + '_ {
        let c = self.channels;
        let shift = if self.max > 255.0 { 8 } else { 0 };
        self.values.chunks_exact(c).map(move |p| {
            let b = |v: u16| (v >> shift) as u8;
            if c >= 3 {
                [b(p[0]), b(p[1]), b(p[2])]
            } else {
                [b(p[0]); 3]
            }
        })
    }
}

/// Decodes a PNG map (`what`: what it is, for errors), its size checked as a lattice of
/// `cell_size` at `origin` before its pixels are decoded.
pub(crate) fn decode_png(
    png: &[u8],
    what: &'static str,
    cell_size: f32,
    origin: [f32; 2],
) -> Result<MapImage> {
    let bad = |e: png::DecodingError| {
        Error::invalid(what, format!("not a PNG image arbor can read: {e}"))
    };
    let mut decoder = png::Decoder::new_with_limits(
        std::io::Cursor::new(png),
        png::Limits {
            bytes: MAX_PNG_BYTES,
        },
    );
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(bad)?;
    let (width, height) = reader.info().size();
    lattice(what, width, height, cell_size, origin)?;
    let size = reader.output_buffer_size().ok_or_else(|| {
        Error::invalid(
            what,
            format!("{width} x {height} pixels: too large to decode"),
        )
    })?;
    if size > MAX_PNG_BYTES {
        return Err(Error::LimitExceeded {
            limit_name: "MAX_GROUND_SAMPLES",
            what: "bytes of a decoded ground map",
            limit: MAX_PNG_BYTES as u64,
            requested: size as u64,
            step: None,
        });
    }
    let mut buf = Vec::new();
    buf.try_reserve_exact(size)
        .map_err(|_| Error::OutOfMemory {
            what: format!("a {what} of {size} bytes"),
        })?;
    buf.resize(size, 0);
    let info = reader.next_frame(&mut buf).map_err(bad)?;
    let channels = info.color_type.samples();
    let wide = info.bit_depth == png::BitDepth::Sixteen;
    let n = width as usize * height as usize * channels;
    let values: Vec<u16> = if wide {
        buf[..n * 2]
            .chunks_exact(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
            .collect()
    } else {
        buf[..n].iter().map(|&b| u16::from(b)).collect()
    };
    Ok(MapImage {
        width,
        height,
        channels,
        values,
        max: if wide { 65535.0 } else { 255.0 },
    })
}

/// Where species grow and how densely: a lattice of cells (like a [`HeightField`]'s
/// samples, cell `(i, j)` covering x from `origin[0] + i·cell_size` and z from
/// `origin[1] + j·cell_size`, one cell on), each with a species slot (an index into the
/// species a world is planted with; [`SpeciesMap::EMPTY`]: nothing grows) and a density
/// in trees per square unit. [`World::plant_map`](super::World::plant_map) plants it.
#[derive(Clone, Debug, PartialEq)]
pub struct SpeciesMap {
    columns: u32,
    rows: u32,
    cell_size: f32,
    origin: [f32; 2],
    slots: Vec<u32>,
    density: Vec<f32>,
}

impl SpeciesMap {
    /// The slot of a cell where nothing is planted.
    pub const EMPTY: u32 = u32::MAX;

    /// A map of `columns × rows` cells (row by row, x fastest), each with its species
    /// slot and its density (trees per square unit, finite, ≥ 0). Errors name a bad
    /// shape, a count that does not match, or a bad density.
    pub fn new(
        columns: u32,
        rows: u32,
        cell_size: f32,
        origin: [f32; 2],
        slots: Vec<u32>,
        density: Vec<f32>,
    ) -> Result<Self> {
        let n = lattice("species map", columns, rows, cell_size, origin)?;
        for (name, len) in [("slots", slots.len()), ("density", density.len())] {
            if len != n {
                return Err(Error::invalid(
                    if name == "slots" { "slots" } else { "density" },
                    format!("{len} cells; expected {columns} x {rows} = {n}"),
                ));
            }
        }
        if let Some(k) = density.iter().position(|d| !(d.is_finite() && *d >= 0.0)) {
            return Err(Error::invalid(
                "density",
                format!(
                    "{} at cell ({}, {}); expected a finite number >= 0 (trees per square unit)",
                    density[k],
                    k % columns as usize,
                    k / columns as usize
                ),
            ));
        }
        Ok(SpeciesMap {
            columns,
            rows,
            cell_size,
            origin,
            slots,
            density,
        })
    }

    /// A map from a PNG picture: a pixel a cell (the top row at the lowest z); a pixel
    /// whose colour is `legend[k].0` (8-bit RGB; 16-bit images by their high bytes) grows
    /// species slot `legend[k].1` at `density` trees per square unit; any other colour
    /// grows nothing. The size is checked before a pixel is decoded.
    pub fn from_png(
        png: &[u8],
        legend: &[([u8; 3], u32)],
        density: f32,
        cell_size: f32,
        origin: [f32; 2],
    ) -> Result<Self> {
        let image = decode_png(png, "species map", cell_size, origin)?;
        let slots: Vec<u32> = image
            .rgb()
            .map(|c| {
                legend
                    .iter()
                    .find(|(colour, _)| *colour == c)
                    .map_or(Self::EMPTY, |&(_, slot)| slot)
            })
            .collect();
        let density = vec![density; slots.len()];
        Self::new(image.width, image.height, cell_size, origin, slots, density)
    }

    /// Cells along x.
    pub fn columns(&self) -> u32 {
        self.columns
    }

    /// Cells along z.
    pub fn rows(&self) -> u32 {
        self.rows
    }

    /// A cell's edge.
    pub fn cell_size(&self) -> f32 {
        self.cell_size
    }

    /// Cell (0, 0)'s lower corner (x, z).
    pub fn origin(&self) -> [f32; 2] {
        self.origin
    }

    /// The cells' species slots, row by row.
    pub fn slots(&self) -> &[u32] {
        &self.slots
    }

    /// The cells' densities, row by row.
    pub fn density(&self) -> &[f32] {
        &self.density
    }

    /// The slot of the cell holding (x, z); [`EMPTY`](Self::EMPTY) off the map.
    pub fn slot_at(&self, x: f32, z: f32) -> u32 {
        let i = ((x - self.origin[0]) / self.cell_size).floor();
        let j = ((z - self.origin[1]) / self.cell_size).floor();
        if !(i >= 0.0 && j >= 0.0 && i < self.columns as f32 && j < self.rows as f32) {
            return Self::EMPTY;
        }
        self.slots[j as usize * self.columns as usize + i as usize]
    }

    /// Where the map plants, seeded: in each cell with a species, as many trees as its
    /// density times its area (the fraction by chance), each at a random point of the
    /// cell; (x, z, slot) in cell order. The same map and seed give the same points.
    /// More than `most` points: `LimitExceeded` naming `max_trees` (nothing returned,
    /// never more than `most` kept).
    pub fn points(&self, seed: u64, most: usize) -> Result<Vec<(f32, f32, u32)>> {
        let mut rng = crate::rng::Rng::new(seed ^ 0x5BEC_1E5A_0000_0001);
        let area = self.cell_size as f64 * self.cell_size as f64;
        let mut out = Vec::new();
        for (k, (&slot, &d)) in self.slots.iter().zip(&self.density).enumerate() {
            if slot == Self::EMPTY || d <= 0.0 {
                continue;
            }
            let expected = d as f64 * area;
            let whole = expected.floor();
            let n = whole as u64 + u64::from(rng.next_f64() < expected - whole);
            let total = out.len() as u64 + n;
            if total > most as u64 {
                return Err(Error::LimitExceeded {
                    limit_name: "max_trees",
                    what: "trees the species map plants",
                    limit: most as u64,
                    requested: total,
                    step: None,
                });
            }
            let (i, j) = (k % self.columns as usize, k / self.columns as usize);
            for _ in 0..n {
                let x = self.origin[0] + (i as f32 + rng.next_f64() as f32) * self.cell_size;
                let z = self.origin[1] + (j as f32 + rng.next_f64() as f32) * self.cell_size;
                out.push((x, z, slot));
            }
        }
        Ok(out)
    }
}
