//! Impostors: a tree drawn by arbor's rasterizer ([`crate::raster`]) from many directions
//! into atlases a host draws on one camera-facing quad (octahedral) or on a few crossed
//! quads (a billboard), for the distance where even the last level of detail is too
//! many triangles.
//!
//! **Octahedral.** `frames` × `frames` views, laid out on a grid by the (hemi-)octahedral
//! map of the direction the view is seen *from* (the camera's place, from the tree's
//! centre): cell (i, j) covers grid coordinates `p = ((i + 0.5) / frames, (j + 0.5) /
//! frames)` in [0, 1]², mapped to `q = 2p - 1` in [-1, 1]². With `up` the model's up axis
//! (+Y, or +Z for a Z-up mesh) and `a`, `b` the two other axes in order (Y up: a = X, b =
//! Z; Z up: a = X, b = Y):
//!
//! - hemi-octahedral (the default; the upper half of the sphere): `t = ((q.x + q.y) / 2,
//!   (q.x - q.y) / 2)`, `d = normalize(a * t.x + b * t.y + up * (1 - |t.x| - |t.y|))`;
//! - octahedral (the whole sphere): `d = a * q.x + b * q.y + up * (1 - |q.x| - |q.y|)`,
//!   and where that up component is negative, `(q.x, q.y)` becomes `((1 - |q.y|) *
//!   sign(q.x), (1 - |q.x|) * sign(q.y))` first; then normalized.
//!
//! Each view looks along `-d` at the bounding sphere (its centre, its `radius`): the
//! image's right is `normalize(cross(-d, up))` (or `a` when `d` is `up` itself), its up
//! `cross(right, -d)`, and it spans `2 * radius` both ways. Row 0 of a cell is its top.
//! A shader finds the three cells around the camera's direction on the grid and blends
//! them by their weights on the grid; in each it follows the ray through the quad's pixel
//! across the bounding sphere until it meets the surface that cell saw (the depth in the
//! normal atlas), so the three views line up where the camera's direction lies between
//! them ([`Impostor::picture`]; the reference shader is in
//! `examples/common/impostor.glsl`).
//!
//! **Atlases** (RGBA8, `frames * cell` pixels square): `albedo` (sRGB colour, alpha the
//! share of the pixel covered, from 3 × 3 samples); `normal` (the surface's unit normal in
//! model space as `n * 0.5 + 0.5` in RGB, alpha the depth: 0 at the bounding sphere's
//! near side along the view, 255 at its far side, where covered).
//!
//! **Billboard.** The same renderer draws `planes` (2 or 3) views around the up axis,
//! level, into a row of cells, and [`Billboard::mesh`] is their crossed quads, each
//! sampling its cell: for hosts without an impostor shader.

use crate::error::{Error, Result};
use crate::mesh::{Mesh, Topology, Vertex};
use crate::raster::{Surface, Target, View};
use crate::texture::Image;
use glam::Vec3;

/// Which directions an octahedral impostor covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sphere {
    /// The upper half (trees are seen from the side and above).
    Hemi,
    /// The whole sphere.
    Full,
}

/// An octahedral impostor: its atlases and what a shader needs to draw it.
#[derive(Clone, Debug, PartialEq)]
pub struct Impostor {
    /// Views a side of the grid.
    pub frames: u32,
    /// Pixels a side of one view.
    pub cell: u32,
    /// Which directions the grid covers.
    pub sphere: Sphere,
    /// The bounding sphere's centre, in the mesh's space.
    pub centre: [f32; 3],
    /// The bounding sphere's radius: each view spans twice this.
    pub radius: f32,
    /// The model's up axis the views are framed by.
    pub up: [f32; 3],
    /// Colour and coverage.
    pub albedo: Image,
    /// Normal and depth.
    pub normal: Image,
}

/// The axes a grid direction is built on: up, then the two others (see the module).
fn axes(up: Vec3) -> (Vec3, Vec3, Vec3) {
    if up.z.abs() > up.y.abs() {
        (up, Vec3::X, Vec3::Y)
    } else {
        (up, Vec3::X, Vec3::Z)
    }
}

/// The direction a view is seen from at grid coordinates `q` in [-1, 1]².
pub fn grid_direction(q: [f32; 2], sphere: Sphere, up: Vec3) -> Vec3 {
    let (up, a, b) = axes(up);
    let (x, y) = match sphere {
        Sphere::Hemi => (0.5 * (q[0] + q[1]), 0.5 * (q[0] - q[1])),
        Sphere::Full => (q[0], q[1]),
    };
    let h = 1.0 - x.abs() - y.abs();
    let (x, y) = if h < 0.0 {
        ((1.0 - y.abs()) * x.signum(), (1.0 - x.abs()) * y.signum())
    } else {
        (x, y)
    };
    (a * x + b * y + up * h).normalize_or(up)
}

/// The grid coordinates in [-1, 1]² of direction `d` (the inverse of [`grid_direction`];
/// a direction below the horizon of a hemi-octahedral grid is taken at the horizon).
pub fn grid_coordinates(d: Vec3, sphere: Sphere, up: Vec3) -> [f32; 2] {
    let (up, a, b) = axes(up);
    let (x, y, mut h) = (d.dot(a), d.dot(b), d.dot(up));
    if sphere == Sphere::Hemi {
        h = h.max(0.0);
    }
    let s = (x.abs() + y.abs() + h.abs()).max(f32::MIN_POSITIVE);
    let (mut x, mut y) = (x / s, y / s);
    if h < 0.0 {
        let (ox, oy) = (x, y);
        x = (1.0 - oy.abs()) * ox.signum();
        y = (1.0 - ox.abs()) * oy.signum();
    }
    match sphere {
        Sphere::Hemi => [x + y, x - y],
        Sphere::Full => [x, y],
    }
}

/// The view seen from direction `d` (unit) of the sphere at `centre` of `radius`.
pub fn view_from(d: Vec3, centre: Vec3, radius: f32, up: Vec3) -> View {
    let (up, a, _) = axes(up);
    let forward = -d;
    let mut right = forward.cross(up);
    if right.length_squared() < 1e-10 {
        right = a;
    }
    let right = right.normalize();
    View {
        centre,
        forward,
        right,
        up: right.cross(forward),
        half: radius,
    }
}

/// Samples a pixel's side when an impostor view is drawn.
const SAMPLES: u32 = 3;

/// One view drawn at `SAMPLES`² samples a pixel into one cell's `albedo` and `normal`
/// pixels (`cell` a side, rows from the top).
fn draw_cell(
    surfaces: &[Surface<'_>],
    view: &View,
    cell: u32,
    albedo: &mut [[u8; 4]],
    normal: &mut [[u8; 4]],
) {
    let side = cell * SAMPLES;
    let mut t = Target::new(side, side);
    t.draw(view, surfaces);
    let n = SAMPLES * SAMPLES;
    let half = view.half.max(f32::MIN_POSITIVE);
    for y in 0..cell {
        for x in 0..cell {
            let (mut rgb, mut nrm, mut depth, mut covered) = ([0u32; 3], Vec3::ZERO, 0.0f32, 0u32);
            for sy in 0..SAMPLES {
                for sx in 0..SAMPLES {
                    let k = ((y * SAMPLES + sy) * side + x * SAMPLES + sx) as usize;
                    if t.depth[k].is_finite() {
                        covered += 1;
                        for (sum, &c) in rgb.iter_mut().zip(&t.color[k]) {
                            *sum += c as u32;
                        }
                        let v = t.normal[k];
                        nrm += Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32) / 127.5 - 1.0;
                        depth += t.depth[k];
                    }
                }
            }
            let o = (y * cell + x) as usize;
            if covered == 0 {
                albedo[o] = [0; 4];
                normal[o] = [128, 128, 128, 255];
                continue;
            }
            let c = covered;
            albedo[o] = [
                (rgb[0] / c) as u8,
                (rgb[1] / c) as u8,
                (rgb[2] / c) as u8,
                ((covered * 255 + n / 2) / n) as u8,
            ];
            let m = nrm.normalize_or(-view.forward);
            let d = ((depth / c as f32 / half) * 0.5 + 0.5).clamp(0.0, 1.0);
            normal[o] = [
                (m.x * 127.5 + 127.5) as u8,
                (m.y * 127.5 + 127.5) as u8,
                (m.z * 127.5 + 127.5) as u8,
                (d * 255.0).round() as u8,
            ];
        }
    }
    dilate(albedo, cell);
}

/// Gives the empty texels of a `cell`-square albedo next to covered ones the mean colour
/// of those (their alpha stays 0), twice over: a host's bilinear filter then blends a
/// leaf's edge with its own colour, not with black.
fn dilate(albedo: &mut [[u8; 4]], cell: u32) {
    let n = cell as i64;
    for _ in 0..2 {
        let before = albedo.to_vec();
        for y in 0..n {
            for x in 0..n {
                let o = (y * n + x) as usize;
                if before[o][3] != 0 || before[o][..3] != [0, 0, 0] {
                    continue;
                }
                let (mut sum, mut count) = ([0u32; 3], 0u32);
                for (dx, dy) in [
                    (-1, 0),
                    (1, 0),
                    (0, -1),
                    (0, 1),
                    (-1, -1),
                    (1, -1),
                    (-1, 1),
                    (1, 1),
                ] {
                    let (nx, ny) = (x + dx, y + dy);
                    if !(0..n).contains(&nx) || !(0..n).contains(&ny) {
                        continue;
                    }
                    let t = before[(ny * n + nx) as usize];
                    if t[3] != 0 || t[..3] != [0, 0, 0] {
                        for (s, &c) in sum.iter_mut().zip(&t) {
                            *s += c as u32;
                        }
                        count += 1;
                    }
                }
                if count > 0 {
                    let mean = sum.map(|s| s.checked_div(count).unwrap_or(0) as u8);
                    albedo[o] = [mean[0], mean[1], mean[2], 0];
                }
            }
        }
    }
}

/// One drawn cell: its albedo and normal pixels.
type Cell = (Vec<[u8; 4]>, Vec<[u8; 4]>);

/// Cells drawn on the machine's cores: `draw(k, albedo, normal)` fills cell `k`.
fn draw_cells(
    count: usize,
    cell: u32,
    threads: usize,
    draw: impl Fn(usize, &mut [[u8; 4]], &mut [[u8; 4]]) + Sync,
) -> Vec<Cell> {
    let px = (cell * cell) as usize;
    let mut out: Vec<Cell> = (0..count)
        .map(|_| (vec![[0; 4]; px], vec![[0; 4]; px]))
        .collect();
    let threads = threads.clamp(1, count.max(1));
    if threads == 1 {
        for (k, (a, n)) in out.iter_mut().enumerate() {
            draw(k, a, n);
        }
        return out;
    }
    let per = count.div_ceil(threads);
    std::thread::scope(|s| {
        let threads: Vec<_> = out
            .chunks_mut(per.max(1))
            .enumerate()
            .map(|(t, chunk)| {
                let draw = &draw;
                s.spawn(move || {
                    for (j, (a, n)) in chunk.iter_mut().enumerate() {
                        draw(t * per + j, a, n);
                    }
                })
            })
            .collect();
        // Joined, not left to the scope: each thread has ended, not only its work, when
        // this returns (a host's leak checker then sees no thread still exiting).
        for t in threads {
            t.join().expect("a view's thread does not panic");
        }
    });
    out
}

/// Lays cells out `columns` a row into images of `columns * cell` by `rows * cell`.
fn atlas(cells: &[Cell], columns: u32, rows: u32, cell: u32) -> (Image, Image) {
    let (w, h) = (columns * cell, rows * cell);
    let mut a = vec![0u8; (w * h * 4) as usize];
    let mut n = vec![0u8; (w * h * 4) as usize];
    for (k, (ca, cn)) in cells.iter().enumerate() {
        let (cx, cy) = (k as u32 % columns, k as u32 / columns);
        for y in 0..cell {
            for x in 0..cell {
                let src = (y * cell + x) as usize;
                let dst = (((cy * cell + y) * w + cx * cell + x) * 4) as usize;
                a[dst..dst + 4].copy_from_slice(&ca[src]);
                n[dst..dst + 4].copy_from_slice(&cn[src]);
            }
        }
    }
    (
        Image {
            width: w,
            height: h,
            pixels: a,
        },
        Image {
            width: w,
            height: h,
            pixels: n,
        },
    )
}

/// The threads a bake uses: the machine's cores, at most 16.
fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get().min(16))
}

/// Checks a bake's sizes before any memory is spent.
fn check(frames: u32, cell: u32, most_frames: u32) -> Result<()> {
    if !(1..=most_frames).contains(&frames) {
        return Err(Error::invalid(
            "frames",
            format!("{frames}; expected 1..={most_frames}"),
        ));
    }
    if !(8..=1024).contains(&cell) || frames * cell > crate::texture::MAX_TEXTURE_SIZE {
        return Err(Error::invalid(
            "cell",
            format!(
                "{cell} pixels by {frames} frames; expected 8..=1024 pixels a cell and at most \
                 {} pixels a side",
                crate::texture::MAX_TEXTURE_SIZE
            ),
        ));
    }
    Ok(())
}

/// Bakes the octahedral impostor of `surfaces` (a mesh's bark and leaves, in one space
/// whose up axis is `up`): `frames` × `frames` views (1..=32) of `cell` pixels (8..=1024;
/// the atlas at most 4096 pixels a side), on every core.
pub fn octahedral(
    surfaces: &[Surface<'_>],
    up: Vec3,
    frames: u32,
    cell: u32,
    sphere: Sphere,
) -> Result<Impostor> {
    octahedral_on(surfaces, up, frames, cell, sphere, 0)
}

/// [`octahedral`] on `threads` threads (0: the machine's cores, at most 16).
pub fn octahedral_on(
    surfaces: &[Surface<'_>],
    up: Vec3,
    frames: u32,
    cell: u32,
    sphere: Sphere,
    threads: u32,
) -> Result<Impostor> {
    check(frames, cell, 32)?;
    let (centre, radius) = crate::raster::bounds(surfaces)
        .ok_or_else(|| Error::invalid("surfaces", "no vertices; expected a tree"))?;
    let up = up.normalize_or(Vec3::Y);
    let threads = if threads == 0 {
        cores()
    } else {
        threads as usize
    };
    let cells = draw_cells((frames * frames) as usize, cell, threads, |k, a, n| {
        let d = cell_direction(k as u32 % frames, k as u32 / frames, frames, sphere, up);
        draw_cell(surfaces, &view_from(d, centre, radius, up), cell, a, n);
    });
    let (albedo, normal) = atlas(&cells, frames, frames, cell);
    Ok(Impostor {
        frames,
        cell,
        sphere,
        centre: centre.to_array(),
        radius,
        up: up.to_array(),
        albedo,
        normal,
    })
}

impl Impostor {
    /// The direction cell (`i`, `j`) of the grid was drawn from (see the module).
    pub fn frame_direction(&self, i: u32, j: u32) -> Vec3 {
        cell_direction(i, j, self.frames, self.sphere, Vec3::from(self.up))
    }

    /// The three cells around direction `d` on the grid, with their weights (summing to
    /// one): the triangle of cell centres `d`'s grid position falls in.
    pub fn frames_around(&self, d: Vec3) -> [((u32, u32), f32); 3] {
        let q = grid_coordinates(d, self.sphere, Vec3::from(self.up));
        let last = self.frames.saturating_sub(1);
        let f = self.frames.max(1) as f32;
        // Grid position in frames, centred on the cells.
        let p = [
            ((q[0] * 0.5 + 0.5) * f - 0.5).clamp(0.0, f - 1.0),
            ((q[1] * 0.5 + 0.5) * f - 0.5).clamp(0.0, f - 1.0),
        ];
        let (i, j) = (p[0].floor(), p[1].floor());
        let (fx, fy) = (p[0] - i, p[1] - j);
        let at = |di: f32, dj: f32| (((i + di) as u32).min(last), ((j + dj) as u32).min(last));
        if fx + fy < 1.0 {
            [
                (at(0.0, 0.0), 1.0 - fx - fy),
                (at(1.0, 0.0), fx),
                (at(0.0, 1.0), fy),
            ]
        } else {
            [
                (at(1.0, 1.0), fx + fy - 1.0),
                (at(1.0, 0.0), 1.0 - fy),
                (at(0.0, 1.0), 1.0 - fx),
            ]
        }
    }

    /// The coverage (0..=1) of a `pixels`-square picture of the impostor seen from
    /// direction `d` (unit, toward the camera), as the reference shader draws it (see
    /// [`picture`](Self::picture)).
    pub fn coverage(&self, d: Vec3, pixels: u32) -> Vec<f32> {
        self.picture(d, pixels)
            .iter()
            .map(|p| p[3] as f32 / 255.0)
            .collect()
    }

    /// The `pixels`-square picture of the impostor seen from direction `d`, as the
    /// reference shader draws it: for each pixel, the ray through it (along `-d`, across
    /// the bounding sphere) is followed in each of the three cells around `d` until it
    /// meets the surface that cell saw (its depth, within [`SHELL_STEPS`] steps behind
    /// it), the albedo there is filtered as a host's bilinear sampler filters it (within
    /// the cell), and the three are blended by the cells' weights. sRGB colour and
    /// coverage, RGBA8, rows from the top.
    ///
    /// An impostor whose atlases do not hold its grid (one put together by hand) draws
    /// nothing.
    pub fn picture(&self, d: Vec3, pixels: u32) -> Vec<[u8; 4]> {
        let side = self.frames as u64 * self.cell as u64;
        let holds = |a: &Image| {
            a.width as u64 >= side
                && a.height as u64 >= side
                && a.pixels.len() as u64 >= a.width as u64 * a.height as u64 * 4
        };
        if self.frames == 0 || self.cell == 0 || !holds(&self.albedo) || !holds(&self.normal) {
            return vec![[0u8; 4]; pixels as usize * pixels as usize];
        }
        let (up, centre, r) = (Vec3::from(self.up), Vec3::from(self.centre), self.radius);
        let view = view_from(d, centre, r, up);
        let cells: Vec<(u32, u32, f32, View, u32)> = self
            .frames_around(d)
            .iter()
            .filter(|&&(_, w)| w > 0.0)
            .map(|&((i, j), w)| {
                let dk = self.frame_direction(i, j);
                (
                    i,
                    j,
                    w,
                    view_from(dk, centre, r, up),
                    self.march_steps(d, dk),
                )
            })
            .collect();
        let mut out = vec![[0u8; 4]; (pixels * pixels) as usize];
        for y in 0..pixels {
            for x in 0..pixels {
                let (cx, cy) = (
                    (x as f32 + 0.5) / pixels as f32 * 2.0 - 1.0,
                    1.0 - (y as f32 + 0.5) / pixels as f32 * 2.0,
                );
                // The pixel's point on the plane through the centre facing d.
                let at = (view.right * cx + view.up * cy) * r;
                // Colour weighted by coverage too (an empty texel has no colour).
                let (mut rgb, mut alpha) = ([0.0f32; 3], 0.0f32);
                for &(i, j, w, ref v, steps) in &cells {
                    let Some(t) = self.march(i, j, v, steps, at, d) else {
                        continue;
                    };
                    let a = w * t[3] as f32;
                    for (sum, &c) in rgb.iter_mut().zip(&t) {
                        *sum += a * c as f32;
                    }
                    alpha += a;
                }
                let c = |s: f32| (s / alpha.max(1e-6)).round().clamp(0.0, 255.0) as u8;
                out[(y * pixels + x) as usize] = [
                    c(rgb[0]),
                    c(rgb[1]),
                    c(rgb[2]),
                    alpha.round().clamp(0.0, 255.0) as u8,
                ];
            }
        }
        out
    }

    /// Steps a ray seen from `d` is followed across a cell drawn from `dk`: one per
    /// two thirds of a texel it moves across the cell, at least 4.
    fn march_steps(&self, d: Vec3, dk: Vec3) -> u32 {
        let sin = (d - dk * d.dot(dk)).length();
        ((1.5 * self.cell as f32 * sin).ceil() as u32).clamp(4, (4 * self.cell).max(4))
    }

    /// The albedo of cell (`i`, `j`) (filtered), drawn by `view`, where the ray through `at`
    /// (from the centre, on the plane facing `d`) along `-d` first meets the surface the
    /// cell saw: the first of `steps` points from the near side of the bounding sphere to
    /// its far side over a covered texel whose depth is at most [`SHELL_STEPS`] steps
    /// nearer than the point.
    fn march(&self, i: u32, j: u32, view: &View, steps: u32, at: Vec3, d: Vec3) -> Option<[u8; 4]> {
        let r = self.radius;
        let cell = self.cell as f32;
        let step = 2.0 * r / steps as f32;
        for s in 0..=steps {
            let p = at + d * (r - s as f32 * step);
            let (u, v) = (
                0.5 + p.dot(view.right) / (2.0 * r),
                0.5 - p.dot(view.up) / (2.0 * r),
            );
            if !(0.0..1.0).contains(&u) || !(0.0..1.0).contains(&v) {
                continue;
            }
            let tx = i * self.cell + ((u * cell) as u32).min(self.cell - 1);
            let ty = j * self.cell + ((v * cell) as u32).min(self.cell - 1);
            let texel = self.albedo.pixel(tx, ty);
            if texel[3] == 0 {
                continue;
            }
            let surface = (self.normal.pixel(tx, ty)[3] as f32 / 255.0 * 2.0 - 1.0) * r;
            let depth = p.dot(view.forward);
            if depth >= surface - DEPTH_SLACK * r && depth <= surface + SHELL_STEPS * step {
                return Some(self.filtered(i, j, u, v));
            }
        }
        None
    }

    /// The albedo of cell (`i`, `j`) at `(u, v)` in [0, 1)² as a host's sampler filters it:
    /// bilinear between the four nearest texel centres, kept within the cell.
    fn filtered(&self, i: u32, j: u32, u: f32, v: f32) -> [u8; 4] {
        let cell = self.cell as f32;
        let fx = (u * cell - 0.5).clamp(0.0, cell - 1.0);
        let fy = (v * cell - 0.5).clamp(0.0, cell - 1.0);
        let (x0, y0) = (fx as u32, fy as u32);
        let (x1, y1) = ((x0 + 1).min(self.cell - 1), (y0 + 1).min(self.cell - 1));
        let (wx, wy) = (fx - x0 as f32, fy - y0 as f32);
        let at = |x: u32, y: u32| self.albedo.pixel(i * self.cell + x, j * self.cell + y);
        let (a, b, c, d) = (at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1));
        std::array::from_fn(|k| {
            let top = a[k] as f32 * (1.0 - wx) + b[k] as f32 * wx;
            let bottom = c[k] as f32 * (1.0 - wx) + d[k] as f32 * wx;
            (top * (1.0 - wy) + bottom * wy).round() as u8
        })
    }
}

/// How far behind the surface a cell saw, in march steps, a ray still meets it (the
/// surface is taken as a shell this thick: thin enough that a ray passing behind a twig
/// does not meet it, thick enough that a step does not jump over it).
pub const SHELL_STEPS: f32 = 3.0;

/// How far in front of the surface a cell saw, as a share of the radius, a ray meets it
/// (the depth is stored in 8 bits across the sphere's diameter).
pub const DEPTH_SLACK: f32 = 0.01;

/// The direction cell (`i`, `j`) of a `frames`-square grid is drawn from.
fn cell_direction(i: u32, j: u32, frames: u32, sphere: Sphere, up: Vec3) -> Vec3 {
    let q = [
        2.0 * (i as f32 + 0.5) / frames as f32 - 1.0,
        2.0 * (j as f32 + 0.5) / frames as f32 - 1.0,
    ];
    grid_direction(q, sphere, up)
}

/// A billboard: `planes` crossed vertical quads through the tree's centre, each sampling
/// its cell of the atlases (a row of `planes` cells).
#[derive(Clone, Debug, PartialEq)]
pub struct Billboard {
    /// Quads, 2..=4.
    pub planes: u32,
    /// Pixels a side of one cell.
    pub cell: u32,
    /// The bounding sphere's centre.
    pub centre: [f32; 3],
    /// The bounding sphere's radius: each quad is twice this a side.
    pub radius: f32,
    /// The up axis.
    pub up: [f32; 3],
    /// Colour and coverage.
    pub albedo: Image,
    /// Normal and depth.
    pub normal: Image,
}

/// The direction billboard plane `k` of `planes` faces, level, turned `k / planes` of a
/// half turn about `up`.
fn plane_direction(k: u32, planes: u32, up: Vec3) -> Vec3 {
    let (up, a, b) = axes(up);
    let t = std::f32::consts::PI * k as f32 / planes as f32;
    let _ = up;
    (b * t.cos() + a * t.sin()).normalize()
}

/// Bakes a billboard of `surfaces` (as [`octahedral`]): `planes` (2..=4) level views,
/// each of `cell` pixels.
pub fn billboard(surfaces: &[Surface<'_>], up: Vec3, planes: u32, cell: u32) -> Result<Billboard> {
    if !(2..=4).contains(&planes) {
        return Err(Error::invalid(
            "planes",
            format!("{planes}; expected 2..=4"),
        ));
    }
    check(planes, cell, 4)?;
    let (centre, radius) = crate::raster::bounds(surfaces)
        .ok_or_else(|| Error::invalid("surfaces", "no vertices; expected a tree"))?;
    let up = up.normalize_or(Vec3::Y);
    let cells = draw_cells(planes as usize, cell, cores(), |k, a, n| {
        let d = plane_direction(k as u32, planes, up);
        draw_cell(surfaces, &view_from(d, centre, radius, up), cell, a, n);
    });
    let (albedo, normal) = atlas(&cells, planes, 1, cell);
    Ok(Billboard {
        planes,
        cell,
        centre: centre.to_array(),
        radius,
        up: up.to_array(),
        albedo,
        normal,
    })
}

impl Billboard {
    /// The crossed quads (a triangle list, drawn from both sides, normals facing each
    /// plane's view), uv into the atlases' cells; counter-clockwise seen from the view
    /// unless `clockwise`.
    pub fn mesh(&self, clockwise: bool) -> Mesh {
        let up = Vec3::from(self.up);
        let centre = Vec3::from(self.centre);
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        for k in 0..self.planes {
            let d = plane_direction(k, self.planes, up);
            let view = view_from(d, centre, self.radius, up);
            let base = vertices.len() as u32;
            for (u, v) in [(0.0f32, 1.0f32), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)] {
                let p = centre
                    + view.right * ((2.0 * u - 1.0) * self.radius)
                    + view.up * ((1.0 - 2.0 * v) * self.radius);
                vertices.push(Vertex {
                    position: p.to_array(),
                    normal: d.to_array(),
                    uv: [(k as f32 + u) / self.planes as f32, v],
                });
            }
            for mut t in [[base, base + 1, base + 2], [base, base + 2, base + 3]] {
                if clockwise {
                    t.swap(1, 2);
                }
                indices.extend(t);
            }
        }
        Mesh {
            vertices,
            indices,
            topology: Topology::TriangleList,
            ranges: Vec::new(),
        }
    }
}

impl Billboard {
    /// [`mesh`](Self::mesh) with each quad also wound the other way (its own vertices,
    /// normals turned round): for hosts whose alpha-tested material culls back faces.
    pub fn two_sided_mesh(&self, clockwise: bool) -> Mesh {
        let mut m = self.mesh(clockwise);
        let n = m.vertices.len() as u32;
        let back: Vec<Vertex> = m
            .vertices
            .iter()
            .map(|v| Vertex {
                normal: v.normal.map(|c| -c),
                ..*v
            })
            .collect();
        m.vertices.extend(back);
        let reversed: Vec<u32> = m
            .indices
            .chunks_exact(3)
            .flat_map(|t| [t[0] + n, t[2] + n, t[1] + n])
            .collect();
        m.indices.extend(reversed);
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_directions_and_coordinates_are_inverse() {
        for sphere in [Sphere::Hemi, Sphere::Full] {
            for up in [Vec3::Y, Vec3::Z] {
                for i in 0..9 {
                    for j in 0..9 {
                        let q = [i as f32 / 4.0 - 1.0, j as f32 / 4.0 - 1.0];
                        let d = grid_direction(q, sphere, up);
                        assert!((d.length() - 1.0).abs() < 1e-5);
                        if sphere == Sphere::Hemi {
                            assert!(d.dot(up) >= -1e-6, "{d}");
                        }
                        let back = grid_direction(grid_coordinates(d, sphere, up), sphere, up);
                        assert!((back - d).length() < 1e-4, "{sphere:?} {q:?}: {d} {back}");
                    }
                }
            }
        }
        // The grid's centre looks straight down from above.
        assert!((grid_direction([0.0, 0.0], Sphere::Hemi, Vec3::Y) - Vec3::Y).length() < 1e-6);
    }
}
