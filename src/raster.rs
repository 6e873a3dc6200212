//! A software rasterizer for arbor's own pictures of its meshes: orthographic views of
//! bark and alpha-tested leaves into colour, normal and depth, on the CPU, the same bytes
//! on every machine. It bakes impostors ([`crate::impostor`]) and measures silhouettes
//! ([`iou`]) for the levels of detail; it is not a renderer for display (no lighting, no
//! filtering beyond a texel's nearest).
//!
//! Written here rather than taken from a crate: what arbor needs is narrow (orthographic
//! views of triangle meshes that are mostly smaller than a pixel, an alpha test against
//! the leaf atlas, colour, normal and depth written together, and many small views on
//! every core), and the general crates draw one target at a time in perspective.

use crate::mesh::Mesh;
use crate::texture::Image;
use glam::Vec3;

/// An orthographic view: the square of side `2 * half` around `centre`, seen along
/// `forward` (from the viewer into the scene) with `up` at the top of the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// The point at the centre of the image.
    pub centre: Vec3,
    /// The direction the view looks along (unit).
    pub forward: Vec3,
    /// The image's right (unit, across `forward`).
    pub right: Vec3,
    /// The image's up (unit, across `forward` and `right`).
    pub up: Vec3,
    /// Half the side of the square seen, in model units.
    pub half: f32,
}

impl View {
    /// The view along `forward` with `up_hint` as near the image's up as it can be (any
    /// other direction when they are parallel).
    pub fn looking(centre: Vec3, forward: Vec3, up_hint: Vec3, half: f32) -> View {
        let forward = forward.normalize_or(Vec3::NEG_Z);
        let mut right = forward.cross(up_hint);
        if right.length_squared() < 1e-8 {
            right = forward.any_orthonormal_vector();
        }
        let right = right.normalize();
        View {
            centre,
            forward,
            right,
            up: right.cross(forward),
            half,
        }
    }
}

/// What one mesh looks like to the rasterizer.
#[derive(Clone, Copy, Debug)]
pub struct Surface<'a> {
    /// The triangles (any topology).
    pub mesh: &'a Mesh,
    /// Sampled at each pixel's uv (nearest texel, repeated): its colour, and its alpha
    /// against `alpha_cutoff`; none: `color` everywhere.
    pub texture: Option<&'a Image>,
    /// The colour where there is no texture (sRGB bytes).
    pub color: [u8; 3],
    /// Pixels whose texel alpha is below this (0..=255) are not drawn; 0: none cut.
    pub alpha_cutoff: u8,
    /// Drawn from both sides (leaves); else only the side its winding faces.
    pub double_sided: bool,
    /// Front faces wind clockwise in the view (a mesh written with a reversed winding).
    pub clockwise: bool,
}

/// Where a view is drawn: colour (sRGB, alpha 255 where anything was drawn), normal
/// (a unit vector in model space as `n * 127.5 + 127.5`, alpha 255 where drawn) and
/// depth (model units along the view's `forward` from its centre; `f32::INFINITY` where
/// nothing was drawn). Rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Target {
    /// Pixels a row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// RGBA8 per pixel.
    pub color: Vec<[u8; 4]>,
    /// RGBA8 per pixel.
    pub normal: Vec<[u8; 4]>,
    /// Per pixel.
    pub depth: Vec<f32>,
    /// Only coverage is drawn: `color`, `normal` and `depth` stay empty, and a pixel once
    /// covered is not visited again (a bit a pixel, 64 skipped at a time). For silhouettes.
    pub coverage_only: bool,
    /// The coverage bits of a [`coverage_only`](Self::coverage_only) target, `words` a row.
    bits: Vec<u64>,
    words: usize,
}

impl Target {
    /// An empty target (nothing drawn).
    pub fn new(width: u32, height: u32) -> Target {
        let n = width as usize * height as usize;
        Target {
            width,
            height,
            color: vec![[0; 4]; n],
            normal: vec![[0; 4]; n],
            depth: vec![f32::INFINITY; n],
            coverage_only: false,
            bits: Vec::new(),
            words: 0,
        }
    }

    /// A target that draws only coverage (see [`coverage_only`](Self::coverage_only)): its
    /// `color`, `normal` and `depth` are empty; [`mask`](Self::mask) says what it covers.
    pub fn coverage_only(width: u32, height: u32) -> Target {
        let words = (width as usize).div_ceil(64);
        Target {
            width,
            height,
            color: Vec::new(),
            normal: Vec::new(),
            depth: Vec::new(),
            coverage_only: true,
            bits: vec![0; words * height as usize],
            words,
        }
    }

    /// Which pixels something was drawn on.
    pub fn mask(&self) -> Vec<bool> {
        if self.coverage_only {
            let w = self.width as usize;
            let mut out = Vec::with_capacity(w * self.height as usize);
            for row in self.bits.chunks_exact(self.words.max(1)) {
                out.extend((0..w).map(|x| row[x / 64] >> (x % 64) & 1 == 1));
            }
            return out;
        }
        self.depth.iter().map(|d| d.is_finite()).collect()
    }

    /// Draws `surfaces` as `view` sees them, nearest in front.
    pub fn draw(&mut self, view: &View, surfaces: &[Surface<'_>]) {
        let mut screen = Vec::new();
        for s in surfaces {
            self.draw_one(view, s, &mut screen);
        }
    }

    /// Every pixel of the box `x0..=x1` × `y0..=y1` (inside the target) is covered.
    fn covered(&self, (x0, x1): (usize, usize), (y0, y1): (usize, usize)) -> bool {
        (y0..=y1).all(|y| {
            let row = &self.bits[y * self.words..][..self.words];
            (x0 / 64..=x1 / 64).all(|wi| {
                let want = span_bits(wi, x0, x1);
                row[wi] & want == want
            })
        })
    }

    fn draw_one(&mut self, view: &View, s: &Surface<'_>, screen: &mut Vec<[f32; 3]>) {
        let (w, h) = (self.width as f32, self.height as f32);
        let (sx, sy) = (0.5 * w / view.half, 0.5 * h / view.half);
        screen.clear();
        screen.extend(s.mesh.vertices.iter().map(|v| {
            let d = Vec3::from(v.position) - view.centre;
            [
                0.5 * w + d.dot(view.right) * sx,
                0.5 * h - d.dot(view.up) * sy,
                d.dot(view.forward),
            ]
        }));
        let tex = s.texture.filter(|t| t.width > 0 && t.height > 0);
        for t in s.mesh.triangles() {
            let [i0, i1, i2] = t.map(|i| i as usize);
            let (Some(a), Some(b), Some(c)) = (screen.get(i0), screen.get(i1), screen.get(i2))
            else {
                continue;
            };
            // Twice the signed area; the image's y runs down, so a counter-clockwise
            // triangle (seen from the viewer) has a negative one here.
            let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            if area == 0.0 || !area.is_finite() {
                continue;
            }
            let front = (area < 0.0) != s.clockwise;
            if !front && !s.double_sided {
                continue;
            }
            let lo_x = a[0].min(b[0]).min(c[0]).max(0.0);
            let hi_x = a[0].max(b[0]).max(c[0]).min(w);
            let lo_y = a[1].min(b[1]).min(c[1]).max(0.0);
            let hi_y = a[1].max(b[1]).max(c[1]).min(h);
            // Pixel centres inside the box.
            let (x0, x1) = (ceil_i(lo_x - 0.5), floor_i(hi_x - 0.5));
            let (y0, y1) = (ceil_i(lo_y - 0.5), floor_i(hi_y - 0.5));
            if x0 > x1 || y0 > y1 {
                continue;
            }
            // A silhouette's triangle over pixels all covered already adds nothing (the
            // inside of a crown, once its outer leaves are drawn).
            let (bx, by) = ((x0 as usize, x1 as usize), (y0 as usize, y1 as usize));
            if self.coverage_only && self.covered(bx, by) {
                continue;
            }
            // A triangle taller than wide (a twig's side along the image's up) is walked a
            // column at a time: a span a column, then a bit or a pixel a row, where a
            // span a row would be worked out for a pixel or none. (Not a silhouette's
            // textured one: its rows find the pixels not yet covered a word at a time.)
            let tall = y1 - y0 > x1 - x0 && !(self.coverage_only && tex.is_some());
            // The barycentric weights as planes over the image: l = ax * px + ay * py + k
            // at the pixel centre (px, py); the third is 1 - l0 - l1.
            let inv = 1.0 / area;
            let e0 = Edge::new(
                (b[1] - c[1]) * inv,
                (c[0] - b[0]) * inv,
                (b[0] * c[1] - b[1] * c[0]) * inv,
                tall,
            );
            let e1 = Edge::new(
                (c[1] - a[1]) * inv,
                (a[0] - c[0]) * inv,
                (c[0] * a[1] - c[1] * a[0]) * inv,
                tall,
            );
            let e2 = Edge::new(-e0.ax - e1.ax, -e0.ay - e1.ay, 1.0 - e0.k - e1.k, tall);
            if self.coverage_only && tall {
                self.columns([&e0, &e1, &e2], bx, by);
                continue;
            }
            let vs = &s.mesh.vertices;
            let tri = Tri {
                z: [a[2], b[2], c[2]],
                v: [&vs[i0], &vs[i1], &vs[i2]],
                tex,
                surface: s,
                forward: view.forward,
            };
            // A full target's tall triangle, a column at a time: the weights at a pixel
            // are those its row would give.
            if tall {
                let w = self.width as usize;
                for x in bx.0..=bx.1 {
                    let Some((ys, ye)) = column_span([&e0, &e1, &e2], x, by) else {
                        continue;
                    };
                    let px = x as f32 + 0.5;
                    for y in ys..=ye {
                        let py = y as f32 + 0.5;
                        let l0 = e0.ax * px + e0.row(py);
                        let l1 = e1.ax * px + e1.row(py);
                        self.shade(y * w + x, (l0, l1, 1.0 - l0 - l1), &tri);
                    }
                }
                continue;
            }
            for y in y0..=y1 {
                let py = y as f32 + 0.5;
                // The span of pixel centres where all three weights are non-negative.
                let (mut lo, mut hi) = (x0 as f32 + 0.5, x1 as f32 + 0.5);
                let (k0, k1) = (e0.row(py), e1.row(py));
                let mut empty = false;
                // Without a branch: an edge rising along the row bounds the span from the
                // left, a falling one from the right, a flat one empties the row where
                // its weight is negative.
                for (e, k) in [(&e0, k0), (&e1, k1), (&e2, e2.row(py))] {
                    let t = -k * e.inv;
                    lo = lo.max(if e.ax > 0.0 { t } else { f32::NEG_INFINITY });
                    hi = hi.min(if e.ax < 0.0 { t } else { f32::INFINITY });
                    empty |= e.flat & (k < 0.0);
                }
                if empty || lo.is_nan() || hi.is_nan() || lo > hi {
                    continue;
                }
                let xs = ceil_i(lo - 0.5).max(x0);
                let xe = floor_i(hi - 0.5).min(x1);
                if xs > xe {
                    continue;
                }
                let weights = |x: i64| {
                    let px = x as f32 + 0.5;
                    let l0 = e0.ax * px + k0;
                    let l1 = e1.ax * px + k1;
                    (l0, l1, 1.0 - l0 - l1)
                };
                if self.coverage_only {
                    let row = &mut self.bits[y as usize * self.words..][..self.words];
                    if tex.is_none() {
                        set_span(row, xs as usize, xe as usize);
                        continue;
                    }
                    // Only the pixels not yet covered, found a word at a time.
                    let (first, last) = (xs as usize / 64, xe as usize / 64);
                    for (wi, word) in row.iter_mut().enumerate().take(last + 1).skip(first) {
                        let mut open = !*word & span_bits(wi, xs as usize, xe as usize);
                        while open != 0 {
                            let bit = open.trailing_zeros() as usize;
                            open &= open - 1;
                            let (l0, l1, l2) = weights((wi * 64 + bit) as i64);
                            if l0 >= 0.0
                                && l1 >= 0.0
                                && l2 >= 0.0
                                && tri.opaque(l0, l1, l2).is_some()
                            {
                                *word |= 1 << bit;
                            }
                        }
                    }
                    continue;
                }
                let row = y as usize * self.width as usize;
                for x in xs..=xe {
                    self.shade(row + x as usize, weights(x), &tri);
                }
            }
        }
    }
}

impl Target {
    /// Covers the pixel centres of columns `x0..=x1` and rows `y0..=y1` where all three
    /// weights `e` are non-negative, a column at a time (a coverage-only target).
    fn columns(&mut self, e: [&Edge; 3], (x0, x1): (usize, usize), (y0, y1): (usize, usize)) {
        for x in x0..=x1 {
            let Some((ys, ye)) = column_span(e, x, (y0, y1)) else {
                continue;
            };
            let (word, bit) = (x / 64, 1u64 << (x % 64));
            for y in ys..=ye {
                self.bits[y * self.words + word] |= bit;
            }
        }
    }

    /// Draws pixel `k` at weights `l` of `tri` where it is nearer than what is there and
    /// its texel passes the alpha test (a full target).
    #[inline(always)]
    fn shade(&mut self, k: usize, (l0, l1, l2): (f32, f32, f32), tri: &Tri<'_>) {
        if l0 < 0.0 || l1 < 0.0 || l2 < 0.0 {
            return;
        }
        let z = tri.z[0] * l0 + tri.z[1] * l1 + tri.z[2] * l2;
        if z >= self.depth[k] {
            return;
        }
        let Some(color) = tri.opaque(l0, l1, l2) else {
            return;
        };
        let [va, vb, vc] = tri.v;
        self.depth[k] = z;
        let n =
            Vec3::from(va.normal) * l0 + Vec3::from(vb.normal) * l1 + Vec3::from(vc.normal) * l2;
        let n = n.normalize_or(-tri.forward);
        // The side facing the viewer (a leaf seen from behind).
        let n = if n.dot(tri.forward) > 0.0 && tri.surface.double_sided {
            -n
        } else {
            n
        };
        self.color[k] = color;
        self.normal[k] = [
            (n.x * 127.5 + 127.5) as u8,
            (n.y * 127.5 + 127.5) as u8,
            (n.z * 127.5 + 127.5) as u8,
            255,
        ];
    }
}

/// The rows `ys..=ye` (within `y0..=y1`) of column `x` whose pixel centres all three
/// weights `e` cover: a row's span (see `Target::draw_one`) with x and y swapped.
#[inline(always)]
fn column_span(e: [&Edge; 3], x: usize, (y0, y1): (usize, usize)) -> Option<(usize, usize)> {
    let px = x as f32 + 0.5;
    let (mut lo, mut hi) = (y0 as f32 + 0.5, y1 as f32 + 0.5);
    let mut empty = false;
    for e in e {
        let k = e.ax * px + e.k;
        let t = -k * e.inv;
        lo = lo.max(if e.ay > 0.0 { t } else { f32::NEG_INFINITY });
        hi = hi.min(if e.ay < 0.0 { t } else { f32::INFINITY });
        empty |= e.flat & (k < 0.0);
    }
    if empty || lo.is_nan() || hi.is_nan() || lo > hi {
        return None;
    }
    let ys = ceil_i(lo - 0.5).max(y0 as i64);
    let ye = floor_i(hi - 0.5).min(y1 as i64);
    (ys <= ye).then_some((ys as usize, ye as usize))
}

/// A triangle as a pixel is drawn from it: its vertices' depths and vertices, its
/// surface's texture, and the view's direction.
struct Tri<'a> {
    z: [f32; 3],
    v: [&'a crate::mesh::Vertex; 3],
    tex: Option<&'a Image>,
    surface: &'a Surface<'a>,
    forward: Vec3,
}

impl Tri<'_> {
    /// The colour at weights `l` where the texel there passes the alpha test.
    #[inline(always)]
    fn opaque(&self, l0: f32, l1: f32, l2: f32) -> Option<[u8; 4]> {
        let s = self.surface;
        match self.tex {
            Some(t) => {
                let [va, vb, vc] = self.v;
                let u = va.uv[0] * l0 + vb.uv[0] * l1 + vc.uv[0] * l2;
                let v = va.uv[1] * l0 + vb.uv[1] * l1 + vc.uv[1] * l2;
                let p = t.pixel(wrap(u, t.width), wrap(v, t.height));
                (p[3] >= s.alpha_cutoff).then_some([p[0], p[1], p[2], 255])
            }
            None => Some([s.color[0], s.color[1], s.color[2], 255]),
        }
    }
}

/// One barycentric weight as a plane over the image (`ax * px + ay * py + k`), with the
/// reciprocal of its slope along the way the triangle is walked (a row; a column for a
/// tall one), 0 where it is flat, and whether it is flat (neither rising nor falling that
/// way: zero or not a number).
struct Edge {
    ax: f32,
    ay: f32,
    k: f32,
    inv: f32,
    flat: bool,
}

impl Edge {
    fn new(ax: f32, ay: f32, k: f32, columns: bool) -> Edge {
        let slope = if columns { ay } else { ax };
        Edge {
            ax,
            ay,
            k,
            inv: if slope != 0.0 { 1.0 / slope } else { 0.0 },
            flat: matches!(
                slope.partial_cmp(&0.0),
                Some(std::cmp::Ordering::Equal) | None
            ),
        }
    }

    /// The weight's constant along the row whose centres are at `py`.
    fn row(&self, py: f32) -> f32 {
        self.ay * py + self.k
    }
}

/// The bits of word `wi` (pixels `64 * wi ..`) inside the span `xs..=xe`.
fn span_bits(wi: usize, xs: usize, xe: usize) -> u64 {
    let (first, last) = (wi * 64, wi * 64 + 63);
    let lo = xs.max(first) - first;
    let hi = xe.min(last) - first;
    (u64::MAX >> (63 - hi)) & (u64::MAX << lo)
}

/// Sets the bits of pixels `xs..=xe` of a row of coverage words.
fn set_span(row: &mut [u64], xs: usize, xe: usize) {
    for (wi, word) in row.iter_mut().enumerate().take(xe / 64 + 1).skip(xs / 64) {
        *word |= span_bits(wi, xs, xe);
    }
}

/// The largest integer at most `x` (saturating; 0 for NaN), without a call to `floor`.
fn floor_i(x: f32) -> i64 {
    let t = x as i64;
    t - i64::from((t as f32) > x)
}

/// The smallest integer at least `x` (saturating; 0 for NaN), without a call to `ceil`.
fn ceil_i(x: f32) -> i64 {
    let t = x as i64;
    t + i64::from((t as f32) < x)
}

/// The texel of coordinate `x` on an axis of `n` texels, repeated: by a truncating
/// conversion and a mask (a power of two) or a remainder.
fn wrap(x: f32, n: u32) -> u32 {
    let k = floor_i((x * n as f32).clamp(-1e9, 1e9));
    if n.is_power_of_two() {
        (k as u32) & (n - 1)
    } else {
        k.rem_euclid(n as i64) as u32
    }
}

/// Intersection over union of two masks of the same size (1 when both are empty).
pub fn iou(a: &[bool], b: &[bool]) -> f32 {
    let (mut both, mut either) = (0usize, 0usize);
    for (&x, &y) in a.iter().zip(b) {
        both += usize::from(x && y);
        either += usize::from(x || y);
    }
    if either == 0 {
        1.0
    } else {
        both as f32 / either as f32
    }
}

/// The bounding sphere's centre and radius of the surfaces' vertices (the middle of their
/// box and the farthest vertex from it); none without vertices.
pub fn bounds(surfaces: &[Surface<'_>]) -> Option<(Vec3, f32)> {
    let mut lo = Vec3::splat(f32::MAX);
    let mut hi = Vec3::splat(f32::MIN);
    for s in surfaces {
        for v in &s.mesh.vertices {
            lo = lo.min(Vec3::from(v.position));
            hi = hi.max(Vec3::from(v.position));
        }
    }
    if lo.x > hi.x {
        return None;
    }
    let c = 0.5 * (lo + hi);
    let r = surfaces
        .iter()
        .flat_map(|s| &s.mesh.vertices)
        .map(|v| (Vec3::from(v.position) - c).length_squared())
        .fold(0.0f32, f32::max)
        .sqrt();
    Some((c, r))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Topology, Vertex};

    fn quad(z: f32, half: f32) -> Mesh {
        let v = |x: f32, y: f32, u: f32, w: f32| Vertex {
            position: [x, y, z],
            normal: [0.0, 0.0, 1.0],
            uv: [u, w],
        };
        Mesh {
            vertices: vec![
                v(-half, -half, 0.0, 0.0),
                v(half, -half, 1.0, 0.0),
                v(half, half, 1.0, 1.0),
                v(-half, half, 0.0, 1.0),
            ],
            indices: vec![0, 1, 2, 0, 2, 3],
            topology: Topology::TriangleList,
            ranges: Vec::new(),
        }
    }

    fn surface(mesh: &Mesh, color: [u8; 3]) -> Surface<'_> {
        Surface {
            mesh,
            texture: None,
            color,
            alpha_cutoff: 0,
            double_sided: false,
            clockwise: false,
        }
    }

    /// Thin triangles, tall (walked a column at a time), wide and slanted (a row at a
    /// time), cover exactly the pixel centres inside them, in a coverage target and a full
    /// one: checked against the centres' barycentric weights worked out in f64.
    #[test]
    fn thin_triangles_cover_the_pixel_centres_inside_them() {
        let tris: [[[f32; 2]; 3]; 4] = [
            [[-0.031, -0.93], [0.012, -0.91], [0.043, 0.87]],
            [[-0.95, 0.021], [0.91, 0.063], [0.88, -0.017]],
            [[-0.71, -0.83], [-0.66, -0.86], [0.79, 0.74]],
            [[0.203, 0.911], [0.227, -0.889], [0.161, -0.902]],
        ];
        let (w, h) = (101u32, 89u32);
        let view = View::looking(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 1.0);
        for t in tris {
            let mesh = Mesh {
                vertices: t
                    .iter()
                    .map(|&[x, y]| Vertex {
                        position: [x, y, 0.0],
                        normal: [0.0, 0.0, 1.0],
                        uv: [0.0, 0.0],
                    })
                    .collect(),
                indices: vec![0, 1, 2],
                topology: Topology::TriangleList,
                ranges: Vec::new(),
            };
            let mut s = surface(&mesh, [1, 2, 3]);
            s.double_sided = true;
            // The pixel centres inside, in f64; those within a thousandth of a pixel of
            // an edge are left out (f32 may round either way there).
            let screen: Vec<[f64; 2]> = t
                .iter()
                .map(|&[x, y]| {
                    [
                        0.5 * w as f64 + x as f64 * 0.5 * w as f64,
                        0.5 * h as f64 - y as f64 * 0.5 * h as f64,
                    ]
                })
                .collect();
            let edge = |a: [f64; 2], b: [f64; 2], p: [f64; 2]| {
                (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
            };
            let mut inside = Vec::new();
            for y in 0..h {
                for x in 0..w {
                    let p = [x as f64 + 0.5, y as f64 + 0.5];
                    let e = [
                        edge(screen[0], screen[1], p),
                        edge(screen[1], screen[2], p),
                        edge(screen[2], screen[0], p),
                    ];
                    let lengths = [(0, 1), (1, 2), (2, 0)].map(|(i, j)| {
                        (screen[j][0] - screen[i][0]).hypot(screen[j][1] - screen[i][1])
                    });
                    let near = e.iter().zip(lengths).any(|(v, l)| v.abs() / l < 1e-3);
                    inside.push(
                        (!near).then(|| e.iter().all(|&v| v > 0.0) || e.iter().all(|&v| v < 0.0)),
                    );
                }
            }
            let count = inside.iter().filter(|&&i| i == Some(true)).count();
            assert!(count > 20, "{count} centres inside");
            let mut full = Target::new(w, h);
            full.draw(&view, &[s]);
            let mut cover = Target::coverage_only(w, h);
            cover.draw(&view, &[s]);
            for mask in [full.mask(), cover.mask()] {
                for (k, (&m, &i)) in mask.iter().zip(&inside).enumerate() {
                    if let Some(i) = i {
                        assert_eq!(m, i, "{t:?}: pixel {k}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_square_covers_its_pixels_and_the_nearer_wins() {
        // Seen from +Z (looking along -Z): the quad at z 1 is nearer than the one at z 0.
        let (far, near) = (quad(0.0, 1.0), quad(1.0, 0.5));
        let view = View::looking(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 2.0);
        let mut t = Target::new(40, 40);
        t.draw(
            &view,
            &[surface(&far, [255, 0, 0]), surface(&near, [0, 255, 0])],
        );
        let drawn = t.mask().iter().filter(|&&m| m).count();
        // The far quad is half the view's side: 20 by 20 pixels.
        assert_eq!(drawn, 400);
        let green = t.color.iter().filter(|c| c[1] == 255).count();
        assert_eq!(green, 100);
        assert_eq!(t.color[20 * 40 + 20], [0, 255, 0, 255]);
        assert!((t.depth[20 * 40 + 20] + 1.0).abs() < 1e-5);
        // The normal +Z, toward the viewer.
        assert_eq!(t.normal[20 * 40 + 20][2], 255);
        // Seen from behind, a one-sided quad is not drawn; a two-sided one is.
        let back = View::looking(Vec3::ZERO, Vec3::Z, Vec3::Y, 2.0);
        let mut t = Target::new(40, 40);
        t.draw(&back, &[surface(&far, [255, 0, 0])]);
        assert!(t.mask().iter().all(|&m| !m));
        let mut two = surface(&far, [255, 0, 0]);
        two.double_sided = true;
        t.draw(&back, &[two]);
        assert_eq!(t.mask().iter().filter(|&&m| m).count(), 400);
        // Its normal turned to the viewer.
        assert_eq!(t.normal[20 * 40 + 20][2], 0);
    }

    #[test]
    fn a_coverage_target_covers_what_a_full_target_draws() {
        // Quads at angles across the 64-pixel words of a 150-pixel row, some textured
        // (a checker of holes) and two-sided, overlapping: the coverage bits are the
        // full target's drawn pixels, pixel for pixel.
        let mut pixels = Vec::new();
        for y in 0..8 {
            for x in 0..8 {
                pixels.extend([40, 160, 60, if (x + y) % 3 == 0 { 0 } else { 255 }]);
            }
        }
        let image = Image {
            width: 8,
            height: 8,
            pixels,
        };
        let meshes: Vec<Mesh> = (0..7)
            .map(|k| {
                let mut m = quad(k as f32 * 0.1, 0.3 + 0.15 * k as f32);
                let (sin, cos) = (0.37 * k as f32).sin_cos();
                for v in &mut m.vertices {
                    let [x, y, z] = v.position;
                    v.position = [
                        x * cos - y * sin + 0.2 * k as f32 - 0.6,
                        x * sin + y * cos,
                        z,
                    ];
                }
                m
            })
            .collect();
        let surfaces: Vec<Surface<'_>> = meshes
            .iter()
            .enumerate()
            .map(|(k, m)| {
                let mut s = surface(m, [200, 100, 50]);
                if k % 2 == 1 {
                    s.texture = Some(&image);
                    s.alpha_cutoff = 128;
                    s.double_sided = true;
                }
                s
            })
            .collect();
        for forward in [Vec3::NEG_Z, Vec3::new(0.3, -0.2, -1.0)] {
            let view = View::looking(Vec3::ZERO, forward, Vec3::Y, 1.6);
            let mut full = Target::new(150, 97);
            full.draw(&view, &surfaces);
            let mut cover = Target::coverage_only(150, 97);
            cover.draw(&view, &surfaces);
            let (a, b) = (full.mask(), cover.mask());
            let drawn = a.iter().filter(|&&m| m).count();
            assert!(drawn > 3000 && drawn < 150 * 97, "{drawn} drawn");
            assert_eq!(a, b);
        }
    }

    #[test]
    fn the_alpha_test_cuts_what_the_texture_cuts() {
        let q = quad(0.0, 1.0);
        // Left half transparent.
        let mut pixels = Vec::new();
        for _y in 0..4 {
            for x in 0..4 {
                pixels.extend([10, 200, 30, if x < 2 { 0 } else { 255 }]);
            }
        }
        let image = Image {
            width: 4,
            height: 4,
            pixels,
        };
        let mut s = surface(&q, [0; 3]);
        s.texture = Some(&image);
        s.alpha_cutoff = 128;
        let view = View::looking(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 1.0);
        let mut t = Target::new(16, 16);
        t.draw(&view, &[s]);
        let mask = t.mask();
        assert_eq!(mask.iter().filter(|&&m| m).count(), 128);
        assert!(mask[8 * 16 + 12] && !mask[8 * 16 + 3]);
        assert_eq!(t.color[8 * 16 + 12], [10, 200, 30, 255]);
        assert!((iou(&mask, &vec![true; 256]) - 0.5).abs() < 1e-6);
    }
}
