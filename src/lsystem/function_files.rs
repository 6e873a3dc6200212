//! cpfg's function files: the curves `func(id, x)` reads, listed in the view file
//! (`function: name.func [samples]` one by one, or `function set: name.fset` for a
//! gallery of several), numbered from 1 in the order they are listed.
//!
//! A function is a curve through control points (x, y[, multiplicity]) as cpfg's
//! function editor makes them: a clamped uniform cubic B-spline (it passes through the
//! first and last points; a point of multiplicity k counts k times). `func(id, x)` is
//! the curve's y where it reaches x, found on 512 samples of the curve and interpolated
//! linearly; x outside the curve's range reads the end value.

/// One function, sampled.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Function {
    pub(crate) name: String,
    xs: Vec<f64>,
    ys: Vec<f64>,
}

const SAMPLES: usize = 512;
/// Most control points read for one function.
const MAX_POINTS: usize = 10_000;

impl Function {
    /// The curve's y at `x`.
    pub(crate) fn eval(&self, x: f64) -> f64 {
        let (xs, ys) = (&self.xs, &self.ys);
        if x.is_nan() || xs.is_empty() {
            return f64::NAN;
        }
        if x <= xs[0] {
            return ys[0];
        }
        let last = xs.len() - 1;
        if x >= xs[last] {
            return ys[last];
        }
        // The first sample past x (the curve's x does not decrease along it).
        let k = xs.partition_point(|&v| v <= x).clamp(1, last);
        let (x0, x1) = (xs[k - 1], xs[k]);
        if x1 <= x0 {
            return ys[k];
        }
        ys[k - 1] + (ys[k] - ys[k - 1]) * (x - x0) / (x1 - x0)
    }

    fn from_points(name: String, points: &[(f64, f64)]) -> Function {
        let (mut xs, mut ys) = (
            Vec::with_capacity(SAMPLES + 1),
            Vec::with_capacity(SAMPLES + 1),
        );
        let n = points.len();
        if n < 4 {
            for &(x, y) in points {
                xs.push(x);
                ys.push(y);
            }
        } else {
            // Clamped uniform knots: 0,0,0,0,1,...,m-1,m,m,m,m with m = n - 3.
            let m = (n - 3) as f64;
            let mut knots = vec![0.0; 4];
            knots.extend((1..n - 3).map(|i| i as f64));
            knots.extend([m; 4]);
            for s in 0..=SAMPLES {
                let t = m * s as f64 / SAMPLES as f64;
                let (x, y) = de_boor(points, &knots, t);
                xs.push(x);
                ys.push(y);
            }
        }
        // Keep x from going backwards (a curve that doubles back reads its first pass).
        for i in 1..xs.len() {
            if xs[i] < xs[i - 1] {
                xs[i] = xs[i - 1];
            }
        }
        Function { name, xs, ys }
    }
}

fn de_boor(p: &[(f64, f64)], knots: &[f64], t: f64) -> (f64, f64) {
    let n = p.len();
    // The span k with knots[k] <= t < knots[k+1], within 3..n-1.
    let mut k = 3;
    while k + 1 < n && knots[k + 1] <= t {
        k += 1;
    }
    let mut d: [(f64, f64); 4] = std::array::from_fn(|j| p[j + k - 3]);
    for r in 1..4 {
        for j in (r..4).rev() {
            let i = j + k - 3;
            let den = knots[i + 4 - r] - knots[i];
            let a = if den > 0.0 { (t - knots[i]) / den } else { 0.0 };
            d[j] = (
                (1.0 - a) * d[j - 1].0 + a * d[j].0,
                (1.0 - a) * d[j - 1].1 + a * d[j].1,
            );
        }
    }
    d[3]
}

/// Reads the control points of one function from `lines` (after its header lines).
fn points<'a>(
    lines: &mut impl Iterator<Item = &'a str>,
    count: usize,
) -> Result<Vec<(f64, f64)>, String> {
    if count > MAX_POINTS {
        return Err(format!("{count} points; at most {MAX_POINTS}"));
    }
    let mut out = Vec::new();
    for _ in 0..count {
        let line = lines.next().ok_or("fewer points than `points:` says")?;
        let v = numbers(line, "a point")?;
        if v.len() < 2 {
            return Err(format!("`{line}` is not a point (x y [multiplicity])"));
        }
        let mult = v.get(2).map_or(1, |&m| (m.round() as usize).clamp(1, 3));
        for _ in 0..mult {
            out.push((v[0], v[1]));
        }
    }
    if out.is_empty() {
        return Err("a function without points".into());
    }
    Ok(out)
}

fn value<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    line.trim().strip_prefix(key).map(str::trim)
}

/// Reads functions: one `.func` file (`fver` or the older `range:` form) or a `.fset`
/// gallery (`funcgalleryver`, `items: n`, then n functions).
/// At most `max` functions are read (each takes 8 KiB of samples): one more is an error.
pub(crate) fn parse(text: &str, name: &str, max: usize) -> Result<Vec<Function>, String> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty()).peekable();
    let mut out = Vec::new();
    let mut default_name = name.trim_end_matches(".func").to_string();
    while let Some(&line) = lines.peek() {
        let t = line.trim();
        if t.starts_with("funcgalleryver") || value(t, "items:").is_some() {
            lines.next();
            continue;
        }
        if t.starts_with("fver") {
            lines.next();
            continue;
        }
        if let Some(n) = value(t, "name:") {
            default_name = n.to_string();
            lines.next();
            continue;
        }
        if value(t, "samples:").is_some()
            || value(t, "flip:").is_some()
            || value(t, "range:").is_some()
        {
            lines.next();
            continue;
        }
        if let Some(n) = value(t, "points:") {
            lines.next();
            let count: usize = n
                .parse()
                .map_err(|_| format!("`points: {n}` is not a count"))?;
            if out.len() >= max {
                return Err(format!(
                    "more functions than the {max} a view file may bring \
                     (arbor::files::MAX_COMPANIONS, less those listed before)"
                ));
            }
            let p = points(&mut lines, count)?;
            out.push(Function::from_points(std::mem::take(&mut default_name), &p));
            continue;
        }
        return Err(format!("unexpected line `{t}`"));
    }
    if out.is_empty() {
        return Err("no function in the file".into());
    }
    Ok(out)
}

/// A curve of the view file's `curve:` list (a `.con` contour): `curveX/Y/Z(id, t)` read
/// the point at fraction t of its arc length, `curveGAL(id)` its arc length.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Curve {
    points: Vec<[f64; 3]>,
    /// Arc length up to each point.
    along: Vec<f64>,
}

impl Curve {
    /// The arc length.
    pub(crate) fn length(&self) -> f64 {
        self.along.last().copied().unwrap_or(0.0)
    }

    /// Coordinate `axis` of the point at fraction `t` of the arc length.
    pub(crate) fn at(&self, t: f64, axis: usize) -> f64 {
        if t.is_nan() || self.points.is_empty() {
            return f64::NAN;
        }
        let s = t.clamp(0.0, 1.0) * self.length();
        let k = self
            .along
            .partition_point(|&a| a < s)
            .clamp(1, self.points.len() - 1);
        let (a0, a1) = (self.along[k - 1], self.along[k]);
        let f = if a1 > a0 { (s - a0) / (a1 - a0) } else { 0.0 };
        let (p, q) = (self.points[k - 1][axis], self.points[k][axis]);
        p + (q - p) * f
    }
}

/// Reads a `.con` contour: `key: value` lines, then `points: n` and, after the header,
/// n lines `x y z [multiplicity]` of a B-spline's control points.
pub(crate) fn parse_curve(text: &str) -> Result<Curve, String> {
    let mut lines = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .peekable();
    let mut count = None;
    let mut control: Vec<[f64; 3]> = Vec::new();
    while let Some(line) = lines.next() {
        if let Some(n) = value(line, "points:") {
            count = Some(
                n.parse::<usize>()
                    .map_err(|_| format!("`points: {n}` is not a count"))?,
            );
            continue;
        }
        if line.contains(':') {
            continue;
        }
        let n = count.ok_or("points before `points:`")?;
        if n > MAX_POINTS {
            return Err(format!("{n} points; at most {MAX_POINTS}"));
        }
        let mut rows = vec![line];
        for _ in 1..n {
            rows.push(lines.next().ok_or("fewer points than `points:` says")?);
        }
        for l in rows {
            let v = numbers(l, "a point")?;
            if v.len() < 3 {
                return Err(format!("`{l}` is not a point (x y z [multiplicity])"));
            }
            let mult = v.get(3).map_or(1, |&m| (m.round() as usize).clamp(1, 3));
            for _ in 0..mult {
                control.push([v[0], v[1], v[2]]);
            }
        }
        break;
    }
    if control.len() < 2 {
        return Err("a curve needs at least two points".into());
    }
    // Sampled as a clamped cubic B-spline in the plane of each pair of axes.
    let xy: Vec<(f64, f64)> = control.iter().map(|p| (p[0], p[1])).collect();
    let xz: Vec<(f64, f64)> = control.iter().map(|p| (p[0], p[2])).collect();
    let sample = |pts: &[(f64, f64)]| -> Vec<(f64, f64)> {
        let n = pts.len();
        if n < 4 {
            return pts.to_vec();
        }
        let m = (n - 3) as f64;
        let mut knots = vec![0.0; 4];
        knots.extend((1..n - 3).map(|i| i as f64));
        knots.extend([m; 4]);
        (0..=SAMPLES)
            .map(|s| de_boor(pts, &knots, m * s as f64 / SAMPLES as f64))
            .collect()
    };
    let (a, b) = (sample(&xy), sample(&xz));
    let points: Vec<[f64; 3]> = a.iter().zip(&b).map(|(p, q)| [p.0, p.1, q.1]).collect();
    let mut along = vec![0.0];
    for w in points.windows(2) {
        let d = ((w[1][0] - w[0][0]).powi(2)
            + (w[1][1] - w[0][1]).powi(2)
            + (w[1][2] - w[0][2]).powi(2))
        .sqrt();
        along.push(along.last().copied().unwrap_or(0.0) + d);
    }
    Ok(Curve { points, along })
}

/// The finite numbers of a line of a curve, function or surface file, or an error saying
/// the line is not `what`.
pub(crate) fn numbers(line: &str, what: &str) -> Result<Vec<f64>, String> {
    line.split_whitespace()
        .map(|w| {
            w.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("`{line}` is not {what}"))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_function_passes_through_its_ends_and_interpolates() {
        let f = parse(
            "fver 1 1\nname: ramp\nsamples: 10\nflip: off\npoints: 4\n0 0 1\n0.333 0.333 1\n0.667 0.667 1\n1 1 1\n",
            "ramp.func",
            16,
        )
        .unwrap();
        assert_eq!(f.len(), 1);
        let f = &f[0];
        assert_eq!(f.name, "ramp");
        assert!((f.eval(0.0)).abs() < 1e-12);
        assert!((f.eval(1.0) - 1.0).abs() < 1e-12);
        // Collinear control points: the spline is the line.
        assert!((f.eval(0.5) - 0.5).abs() < 1e-3, "{}", f.eval(0.5));
        assert_eq!(f.eval(-1.0), 0.0);
        assert_eq!(f.eval(2.0), 1.0);
        // The older form, and a gallery of two.
        let old = parse("range: 0.0 1.0\npoints: 2\n0 1\n1 3\n", "old.func", 16).unwrap();
        assert!((old[0].eval(0.5) - 2.0).abs() < 1e-12);
        let set = parse(
            "funcgalleryver 1 1\nitems: 2\nfver 1 1\nname: A\nsamples: 5\nflip: off\npoints: 2\n0 0\n1 1\nfver 1 1\nname: B\nsamples: 5\nflip: off\npoints: 2\n0 2\n1 2\n",
            "set.fset",
            16,
        )
        .unwrap();
        assert_eq!(set.len(), 2);
        assert_eq!(set[1].eval(0.3), 2.0);
        assert!(parse("points: 3\n0 0\n", "bad.func", 16).is_err());
        // A straight contour: arc length and points by fraction of it.
        let c = parse_curve("version: 1.4\npoints: 2\ntype: bspline\n0 0 0 1\n3 4 0 1\n").unwrap();
        assert!((c.length() - 5.0).abs() < 1e-12);
        assert!((c.at(0.5, 0) - 1.5).abs() < 1e-12 && (c.at(0.5, 1) - 2.0).abs() < 1e-12);
        assert!(parse_curve("points: 1\n0 0 0\n").is_err());
        assert!(parse("hello\n", "bad.func", 16).is_err());
        // A set with more functions than allowed stops at the bound, naming it.
        let two = "funcgalleryver 1 1\nitems: 2\nfver 1 1\nname: A\npoints: 2\n0 0\n1 1\n\
                   fver 1 1\nname: B\npoints: 2\n0 0\n1 1\n";
        assert_eq!(parse(two, "two.fset", 2).unwrap().len(), 2);
        assert!(
            parse(two, "two.fset", 1)
                .unwrap_err()
                .contains("more functions than the 1")
        );
    }
}
