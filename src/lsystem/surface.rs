//! cpfg's predefined surfaces: the `.s` files the view file names (`surface: x file.s
//! [scale [s t]]`), drawn at every `~x(scale)` module.
//!
//! A `.s` file is a bounding box line, optional `PRECISION S: s T: t`, the surface's
//! `CONTACT POINT`, `END POINT`, `HEADING`, `UP` and `SIZE`, then bicubic Bézier patches
//! (a name, a colour line, three neighbour lines, then 4 rows of 4 control points). arbor
//! tessellates each patch once, at load, into an s × t grid (the view file's divisions,
//! else the file's precision, else 4 × 4, at most 32 each) in the surface's own frame:
//! coordinates relative to the contact point, divided by SIZE, on the surface's heading,
//! up and left axes. At a `~x(k)` site the triangles are placed in the turtle's frame
//! (heading, up, left) scaled by the view file's scale × k, and recorded as polygons of
//! three points, so every mesh and export path draws them.

use glam::DVec3;

/// One tessellated surface: triangles in its own frame (x along its heading, y along
/// its up, z along its left).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Surface {
    /// The character after `~`.
    pub(crate) name: char,
    /// The view file's scale.
    pub(crate) scale: f64,
    pub(crate) triangles: Vec<[DVec3; 3]>,
    /// The largest distance of a triangle's corner from the surface's origin (unscaled):
    /// a placed copy lies within it, times the scale, of the turtle's position.
    pub(crate) radius: f64,
    /// The file's END POINT as cpfg keeps it: the turtle moves by its x along its left,
    /// y along its heading and z along its up (times the scale) after drawing the surface
    /// (zero when the file names no END POINT).
    pub(crate) end: DVec3,
}

/// Most triangles one surface may have.
const MAX_TRIANGLES: usize = 1 << 16;

fn vec_after(line: &str) -> Option<DVec3> {
    let mut v = [0.0; 3];
    for (k, key) in ["X:", "Y:", "Z:"].iter().enumerate() {
        let rest = &line[line.find(key)? + 2..];
        v[k] = rest.split_whitespace().next()?.parse().ok()?;
    }
    Some(DVec3::from_array(v))
}

fn bernstein(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

/// Reads and tessellates a `.s` file; `divisions` from the view file (0: the file's).
pub(crate) fn parse(
    text: &str,
    name: char,
    scale: f64,
    divisions: (usize, usize),
) -> Result<Surface, String> {
    let mut contact = DVec3::ZERO;
    let mut end_point = None;
    let mut heading = DVec3::Y;
    let mut up = DVec3::NEG_Z;
    let mut size = 1.0f64;
    let mut precision = (4usize, 4usize);
    let mut patches: Vec<[[DVec3; 4]; 4]> = Vec::new();
    let mut lines = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .peekable();
    lines.next(); // the bounding box
    while let Some(line) = lines.next() {
        let upper = line.to_ascii_uppercase();
        if upper.starts_with("PRECISION") {
            let n: Vec<usize> = line
                .split_whitespace()
                .filter_map(|w| w.parse().ok())
                .collect();
            if n.len() >= 2 {
                precision = (n[0], n[1]);
            }
        } else if upper.starts_with("CONTACT POINT") {
            contact = vec_after(line).ok_or("a CONTACT POINT X: Y: Z:")?;
        } else if upper.starts_with("END POINT") {
            end_point = Some(vec_after(line).ok_or("an END POINT X: Y: Z:")?);
        } else if upper.starts_with("HEADING") {
            heading = vec_after(line).ok_or("a HEADING X: Y: Z:")?;
        } else if upper.starts_with("UP") {
            up = vec_after(line).ok_or("an UP X: Y: Z:")?;
        } else if upper.starts_with("SIZE") {
            size = line
                .split(':')
                .nth(1)
                .and_then(|v| v.trim().parse().ok())
                .filter(|s: &f64| s.is_finite() && *s > 0.0)
                .ok_or("a SIZE > 0")?;
        } else {
            // A patch: its name, a colour line, three neighbour lines, 4 rows of points.
            let p = read_patch(&mut lines)?;
            patches.push(p);
        }
    }
    if patches.is_empty() {
        return Err("no patch in the surface file".into());
    }
    let h = heading
        .try_normalize()
        .ok_or("a HEADING that is not zero")?;
    let u = (up - h * up.dot(h))
        .try_normalize()
        .ok_or("an UP that is not along the HEADING")?;
    let l = h.cross(u);
    let (s, t) = match divisions {
        (0, _) | (_, 0) => precision,
        d => d,
    };
    let (s, t) = (s.clamp(1, 32), t.clamp(1, 32));
    if patches.len() * s * t * 2 > MAX_TRIANGLES {
        return Err(format!(
            "{} patches of {s} x {t} make more than {MAX_TRIANGLES} triangles",
            patches.len()
        ));
    }
    let local = |p: DVec3| {
        let d = (p - contact) / size;
        DVec3::new(d.dot(h), d.dot(u), d.dot(l))
    };
    let triangles = tessellate(&patches, (s, t), local);
    // cpfg's end point (patches.c): the offset from the contact point over SIZE, rotated
    // by the matrix whose columns are the file's left (heading x up), heading and up;
    // the turtle then moves by its x along its left, y along its heading, z along its up.
    let up_n = up.try_normalize().unwrap_or(DVec3::Z);
    let d = (end_point.unwrap_or(contact) - contact) / size;
    let end = h.cross(up_n) * d.x + h * d.y + up_n * d.z;
    let radius = triangles
        .iter()
        .flatten()
        .map(|p| p.length())
        .fold(0.0, f64::max);
    Ok(Surface {
        name,
        scale,
        triangles,
        radius,
        end,
    })
}

/// One patch's 4 rows of 4 points, after its name, colour and neighbour lines.
fn read_patch<'a>(lines: &mut impl Iterator<Item = &'a str>) -> Result<[[DVec3; 4]; 4], String> {
    for _ in 0..4 {
        lines.next().ok_or("a patch cut short")?;
    }
    let mut p = [[DVec3::ZERO; 4]; 4];
    for row in &mut p {
        let l = lines
            .next()
            .ok_or("a patch with fewer than 4 rows of points")?;
        let v = super::function_files::numbers(l, "a row of points")?;
        if v.len() != 12 {
            return Err(format!("`{l}` is not 4 points (12 numbers)"));
        }
        for (k, c) in row.iter_mut().enumerate() {
            *c = DVec3::new(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
        }
    }
    Ok(p)
}

/// Every bicubic patch cut into `s` x `t` quads of two triangles each, its points taken
/// into the surface's frame by `local`; the triangles a degenerate patch edge collapses
/// are skipped.
fn tessellate(
    patches: &[[[DVec3; 4]; 4]],
    (s, t): (usize, usize),
    local: impl Fn(DVec3) -> DVec3,
) -> Vec<[DVec3; 3]> {
    let wu: Vec<[f64; 4]> = (0..=s).map(|i| bernstein(i as f64 / s as f64)).collect();
    let wv: Vec<[f64; 4]> = (0..=t).map(|j| bernstein(j as f64 / t as f64)).collect();
    let mut triangles = Vec::with_capacity(patches.len() * s * t * 2);
    let mut grid = vec![DVec3::ZERO; (s + 1) * (t + 1)];
    for p in patches {
        for (i, bu) in wu.iter().enumerate() {
            for (j, bv) in wv.iter().enumerate() {
                let mut q = DVec3::ZERO;
                for (a, row) in p.iter().enumerate() {
                    for (b, c) in row.iter().enumerate() {
                        q += *c * (bu[a] * bv[b]);
                    }
                }
                grid[i * (t + 1) + j] = local(q);
            }
        }
        for i in 0..s {
            for j in 0..t {
                let g = |a: usize, b: usize| grid[a * (t + 1) + b];
                let (p00, p01, p10, p11) = (g(i, j), g(i, j + 1), g(i + 1, j), g(i + 1, j + 1));
                for tri in [[p00, p10, p11], [p00, p11, p01]] {
                    if (tri[1] - tri[0]).cross(tri[2] - tri[0]).length_squared() > 1e-24 {
                        triangles.push(tri);
                    }
                }
            }
        }
    }
    triangles
}

#[cfg(test)]
mod tests {
    use super::*;

    const FLAT: &str = "0 1 0 1 0 0\nCONTACT POINT  X: 0.0 Y: 0.0 Z: 0.0\nEND POINT X: 0 Y: 1 Z: 0\n\
        HEADING  X: 0.00 Y: 1.00 Z: 0.00\nUP  X: 0.00 Y: 0.00 Z: -1.00\nSIZE: 2.00\npatch\n\
        TOP COLOR: 0 DIFFUSE: 0.00 BOTTOM COLOR: 0 DIFFUSE: 0.00\nAL: ~ A: ~ AR: ~\nL: ~ R: ~\nBL: ~ B: ~ BR: ~\n\
        0 0 0  1 0 0  2 0 0  3 0 0\n0 1 0  1 1 0  2 1 0  3 1 0\n0 2 0  1 2 0  2 2 0  3 2 0\n0 3 0  1 3 0  2 3 0  3 3 0\n";

    #[test]
    fn a_flat_patch_tessellates_in_its_own_frame() {
        let s = parse(FLAT, 'l', 5.0, (2, 3)).unwrap();
        assert_eq!((s.name, s.scale, s.triangles.len()), ('l', 5.0, 12));
        // Heading is +Y: x along the heading spans 0..3 / SIZE; the plane z = 0 lies in
        // the heading-left plane, so every point has up coordinate 0.
        for t in &s.triangles {
            for p in t {
                assert!(p.y.abs() < 1e-12);
                assert!((-1e-12..=1.5 + 1e-12).contains(&p.x));
            }
        }
        let area: f64 = s
            .triangles
            .iter()
            .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length())
            .sum();
        assert!((area - 2.25).abs() < 1e-9, "{area}");
        assert!(parse("0 0 0 0 0 0\nSIZE: 1\n", 'x', 1.0, (0, 0)).is_err());
        assert!(parse(&FLAT.replace("3 3 0\n", "3 3\n"), 'x', 1.0, (0, 0)).is_err());
    }
}
