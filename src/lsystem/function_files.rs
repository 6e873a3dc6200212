//! cpfg's function files: the curves `func(id, x)` reads, listed in the view file
//! (`function: name.func [samples]` one by one, or `function set: name.fset` for a
//! gallery of several), numbered from 1 in the order they are listed.
//!
//! A function is a curve through control points (x, y[, multiplicity]) as cpfg's
//! function editor makes them: a clamped uniform cubic B-spline (it passes through the
//! first and last points; a point of multiplicity k counts k times). `func(id, x)` reads
//! it as cpfg does: x is clamped to [0, 1]; the curve's parameter where its x comes within
//! 0.001 of x is found by bisection and the y there is the value; a function with
//! `samples:` (or, in the older `range:` form, the view file's sample count) above 2 has
//! that many values found so at x = i / (samples - 1) and interpolates them linearly.

/// One function, as cpfg evaluates it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Function {
    pub(crate) name: String,
    /// The control points, each repeated by its multiplicity (read as `f32`, as cpfg
    /// reads them).
    points: Vec<(f64, f64)>,
    /// The precomputed values at i / (len - 1), or none (every call bisects).
    vals: Vec<f64>,
}

/// Most control points read for one function.
const MAX_POINTS: usize = 10_000;
/// Most precomputed samples of one function.
const MAX_SAMPLES: usize = 1 << 16;
/// How close the bisection brings the curve's x to the one asked for (cpfg's MaxError).
const MAX_ERROR: f64 = 0.001;

impl Function {
    /// The curve's y at `x`.
    pub(crate) fn eval(&self, x: f64) -> f64 {
        if x.is_nan() {
            return f64::NAN;
        }
        let v = x.clamp(0.0, 1.0);
        let s = self.vals.len();
        if s > 2 {
            let index = v * (s - 1) as f64;
            let i = index.floor() as usize;
            if i >= s - 1 {
                return self.vals[s - 1];
            }
            let (w1, w2) = (1.0 - index + i as f64, index - i as f64);
            return w1 * self.vals[i] + w2 * self.vals[i + 1];
        }
        self.bisect(v)
    }

    /// The y where the curve's x comes within [`MAX_ERROR`] of `x`, by bisection on the
    /// curve's parameter (at most 64 halvings: a curve that never reaches x ends there).
    fn bisect(&self, x: f64) -> f64 {
        if self.points.len() < 4 {
            return self.polyline(x);
        }
        let (mut low, mut high) = (0.0f64, 1.0f64);
        let mut at = (0.0, 0.0);
        for _ in 0..64 {
            let check = (low + high) / 2.0;
            at = self.point(check);
            if at.0 > x {
                high = check;
            } else {
                low = check;
            }
            if (at.0 - x).abs() <= MAX_ERROR {
                break;
            }
        }
        at.1
    }

    /// Fewer than four points make no cubic: the polyline through them.
    fn polyline(&self, x: f64) -> f64 {
        let p = &self.points;
        let k = p.partition_point(|q| q.0 <= x).clamp(1, p.len().max(2) - 1);
        match p.len() {
            0 => 0.0,
            1 => p[0].1,
            _ if x <= p[0].0 => p[0].1,
            _ if p[k].0 <= p[k - 1].0 => p[k].1,
            _ => {
                let t = ((x - p[k - 1].0) / (p[k].0 - p[k - 1].0)).clamp(0.0, 1.0);
                p[k - 1].1 + (p[k].1 - p[k - 1].1) * t
            }
        }
    }

    /// The curve's point at parameter `d` in [0, 1]: cpfg's uniform clamped B-spline of
    /// order 4 with integer knots (its basis is 0 at d = 1, as cpfg's is).
    fn point(&self, d: f64) -> (f64, f64) {
        let n = self.points.len() as i64 - 1;
        let u = d * (n - 2) as f64;
        let mut sum = (0.0, 0.0);
        for (k, &(x, y)) in self.points.iter().enumerate() {
            let b = basis(k as i64, 4, u, n);
            sum.0 += x * b;
            sum.1 += y * b;
        }
        sum
    }

    /// A function of `points` with `samples` precomputed values (none for 2 or fewer).
    fn new(name: String, points: Vec<(f64, f64)>, samples: usize) -> Function {
        let mut f = Function {
            name,
            points,
            vals: Vec::new(),
        };
        if samples > 2 {
            let vals = (0..samples)
                .map(|i| f.bisect(i as f64 / (samples - 1) as f64))
                .collect();
            f.vals = vals;
        }
        f
    }
}

/// The knot `j` of a clamped uniform B-spline of order 4 over `n + 1` points.
fn knot(j: i64, n: i64) -> i64 {
    if j < 4 {
        0
    } else if j > n {
        n - 2
    } else {
        j - 3
    }
}

/// The B-spline basis N(k, t) at `u` (Cox-de Boor, half-open spans).
fn basis(k: i64, t: i64, u: f64, n: i64) -> f64 {
    if t == 1 {
        return if knot(k, n) as f64 <= u && u < knot(k + 1, n) as f64 {
            1.0
        } else {
            0.0
        };
    }
    let mut sum = 0.0;
    let div = knot(k + t - 1, n) - knot(k, n);
    if div != 0 {
        sum = (u - knot(k, n) as f64) / div as f64 * basis(k, t - 1, u, n);
    }
    let div = knot(k + t, n) - knot(k + 1, n);
    if div != 0 {
        sum += (knot(k + t, n) as f64 - u) / div as f64 * basis(k + 1, t - 1, u, n);
    }
    sum
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
            out.push((v[0] as f32 as f64, v[1] as f32 as f64));
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
/// At most `max` functions are read: one more is an error.
/// `view_samples` is the view file's count after the file name (`function: f.func 100`),
/// which the older `range:` form uses; the `fver` form says its own (`samples:`).
pub(crate) fn parse(
    text: &str,
    name: &str,
    max: usize,
    view_samples: usize,
) -> Result<Vec<Function>, String> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty()).peekable();
    let mut out = Vec::new();
    let mut default_name = name.trim_end_matches(".func").to_string();
    // A larger count would only cost time: at most MAX_SAMPLES are precomputed.
    let view_samples = view_samples.min(MAX_SAMPLES);
    let mut samples = view_samples;
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
        if let Some(n) = value(t, "samples:") {
            samples = n
                .parse()
                .ok()
                .filter(|&n| n <= MAX_SAMPLES)
                .ok_or_else(|| format!("`samples: {n}` is not a count up to {MAX_SAMPLES}"))?;
            lines.next();
            continue;
        }
        if value(t, "flip:").is_some() || value(t, "range:").is_some() {
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
            out.push(Function::new(std::mem::take(&mut default_name), p, samples));
            samples = view_samples;
            continue;
        }
        return Err(format!("unexpected line `{t}`"));
    }
    if out.is_empty() {
        return Err("no function in the file".into());
    }
    Ok(out)
}

/// A curve of the view file's `curve:` list (a `.con` contour), as cpfg samples it:
/// `curveX/Y/Z(id, t)` read the curve where fraction t of its arc length falls on a table
/// of `samples` points (the view file's count, 100 by default), the curve evaluated at
/// the parameter interpolated there; `curveGAL(id)` is the length of that table's
/// polyline.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Curve {
    /// The control points, each repeated by its multiplicity, with the type's extra
    /// points (closed: the first three again; phantom: one mirrored at each end).
    points: Vec<[f64; 3]>,
    /// The `bspline-endpoint` type: a clamped spline; the others are uniform.
    clamped: bool,
    /// Arc length at each sample, over the whole length (0 to 1).
    along: Vec<f64>,
    length: f64,
}

/// The uniform cubic B-spline basis B(i, 4) at `t` (knots at the integers), as cpfg
/// computes it: order 1 on half-open spans, then three recursive steps.
fn uniform(i: f64, order: u32, t: f64) -> f64 {
    if order == 1 {
        return if i <= t && t < i + 1.0 { 1.0 } else { 0.0 };
    }
    let k = (order - 1) as f64;
    (t - i) / k * uniform(i, order - 1, t)
        + (i + order as f64 - t) / k * uniform(i + 1.0, order - 1, t)
}

impl Curve {
    /// The arc length.
    pub(crate) fn length(&self) -> f64 {
        self.length
    }

    /// The curve's point at parameter `t` in [0, 1] (cpfg's calcPValue).
    fn point(&self, t: f64) -> [f64; 3] {
        let p = &self.points;
        let n = p.len();
        let mut out = [0.0; 3];
        if n <= 3 {
            return out;
        }
        if self.clamped {
            let u = t * (n as f64 - 3.000001);
            for (k, q) in p.iter().enumerate() {
                let b = basis(k as i64, 4, u, n as i64 - 1);
                for a in 0..3 {
                    out[a] += q[a] * b;
                }
            }
            return out;
        }
        let i = 3 + (t * (n as f64 - 3.000001)) as usize;
        let u = 3.0 + t * (n as f64 - 3.000001);
        for (j, q) in p.iter().enumerate().take(i.min(n - 1) + 1).skip(i - 3) {
            let b = uniform(j as f64, 4, u);
            for a in 0..3 {
                out[a] += q[a] * b;
            }
        }
        out
    }

    /// Coordinate `axis` of the point at fraction `t` of the arc length (cpfg's
    /// calcAValue: t clamped to [0, 1]).
    pub(crate) fn at(&self, t: f64, axis: usize) -> f64 {
        if t.is_nan() || self.along.len() < 2 {
            return f64::NAN;
        }
        let t = t.clamp(0.0, 1.0);
        let l = &self.along;
        let (mut min, mut max) = (0usize, l.len() - 1);
        while max - min > 1 {
            let med = (min + max) / 2;
            if l[med] > t {
                max = med;
            } else {
                min = med;
            }
        }
        let span = l[max] - l[min];
        let f = if span > 0.0 { (t - l[min]) / span } else { 0.0 };
        let u = (min as f64 + f) / (l.len() - 1) as f64;
        self.point(u)[axis]
    }
}

/// Reads a `.con` contour: `key: value` lines (`type:` bspline, bspline-closed,
/// bspline-phantom or bspline-endpoint; the Bézier types are read as bspline), then
/// `points: n` and n lines `x y z [multiplicity]`; `samples` from the view file.
pub(crate) fn parse_curve(text: &str, samples: usize) -> Result<Curve, String> {
    let mut lines = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .peekable();
    let mut count = None;
    let mut kind = "bspline".to_string();
    let mut control: Vec<[f64; 3]> = Vec::new();
    while let Some(line) = lines.next() {
        if let Some(n) = value(line, "points:") {
            count = Some(
                n.parse::<usize>()
                    .map_err(|_| format!("`points: {n}` is not a count"))?,
            );
            continue;
        }
        if let Some(t) = value(line, "type:") {
            kind = t.to_string();
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
            let mult = v.get(3).map_or(1, |&m| (m.round() as usize).clamp(1, 16));
            for _ in 0..mult {
                control.push([v[0], v[1], v[2]].map(|c| c as f32 as f64));
            }
        }
        break;
    }
    if control.len() < 2 {
        return Err("a curve needs at least two points".into());
    }
    match kind.as_str() {
        "bspline-closed" => {
            let first: Vec<[f64; 3]> = control.iter().take(3).copied().collect();
            control.extend(first);
        }
        "bspline-phantom" if control.len() >= 2 => {
            let n = control.len();
            let mirror = |a: [f64; 3], b: [f64; 3]| [0, 1, 2].map(|k| 2.0 * a[k] - b[k]);
            let (head, tail) = (
                mirror(control[0], control[1]),
                mirror(control[n - 1], control[n - 2]),
            );
            control.insert(0, head);
            control.push(tail);
        }
        _ => {}
    }
    let samples = samples.clamp(2, MAX_SAMPLES);
    let mut curve = Curve {
        points: control,
        clamped: kind == "bspline-endpoint",
        along: Vec::with_capacity(samples),
        length: 0.0,
    };
    let mut last = curve.point(0.0);
    let mut length = 0.0;
    for i in 0..samples {
        let p = curve.point(i as f64 / (samples - 1) as f64);
        if i > 0 {
            length +=
                ((p[0] - last[0]).powi(2) + (p[1] - last[1]).powi(2) + (p[2] - last[2]).powi(2))
                    .sqrt();
        }
        curve.along.push(length);
        last = p;
    }
    if length > 0.0 {
        curve.along.iter_mut().for_each(|l| *l /= length);
    }
    curve.length = length;
    Ok(curve)
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
            0,
        )
        .unwrap();
        assert_eq!(f.len(), 1);
        let f = &f[0];
        assert_eq!(f.name, "ramp");
        // Collinear control points: the spline is the line; cpfg finds each value where
        // the curve's x is within 0.001 of x.
        for x in [0.0, 0.25, 0.5, 0.9, 1.0] {
            assert!((f.eval(x) - x).abs() <= 1e-3, "{x}: {}", f.eval(x));
        }
        assert_eq!(f.eval(-1.0), f.eval(0.0));
        assert_eq!(f.eval(2.0), f.eval(1.0));
        // Without samples every call bisects; with them, values between samples are
        // interpolated linearly.
        let bent = "fver 1 1\nname: b\nsamples: 3\nflip: off\npoints: 4\n0 0\n0.1 1\n0.9 1\n1 0\n";
        let three = &parse(bent, "b.func", 16, 0).unwrap()[0];
        let direct = &parse(&bent.replace("samples: 3", "samples: 0"), "b.func", 16, 0).unwrap()[0];
        let mid = 0.5 * (three.eval(0.0) + three.eval(0.5));
        assert!((three.eval(0.25) - mid).abs() < 1e-12);
        assert!(
            (direct.eval(0.25) - mid).abs() > 0.1,
            "{}",
            direct.eval(0.25)
        );
        // The older form, and a gallery of two.
        let old = parse("range: 0.0 1.0\npoints: 2\n0 1\n1 3\n", "old.func", 16, 0).unwrap();
        assert!((old[0].eval(0.5) - 2.0).abs() < 1e-12);
        let set = parse(
            "funcgalleryver 1 1\nitems: 2\nfver 1 1\nname: A\nsamples: 5\nflip: off\npoints: 2\n0 0\n1 1\nfver 1 1\nname: B\nsamples: 5\nflip: off\npoints: 2\n0 2\n1 2\n",
            "set.fset",
            16,
            0,
        )
        .unwrap();
        assert_eq!(set.len(), 2);
        assert_eq!(set[1].eval(0.3), 2.0);
        assert!(parse("points: 3\n0 0\n", "bad.func", 16, 0).is_err());
        // A straight contour (its ends of multiplicity 3, so the uniform spline reaches
        // them): arc length and points by fraction of it.
        let c = parse_curve(
            "version: 1.4\npoints: 2\ntype: bspline\n0 0 0 3\n3 4 0 3\n",
            100,
        )
        .unwrap();
        assert!((c.length() - 5.0).abs() < 1e-5, "{}", c.length());
        assert!((c.at(0.5, 0) - 1.5).abs() < 1e-4 && (c.at(0.5, 1) - 2.0).abs() < 1e-4);
        assert!(c.at(0.0, 0).abs() < 1e-12 && (c.at(1.0, 1) - 4.0).abs() < 1e-4);
        // cpfg's uniform spline needs four control points: fewer draw nothing.
        let short = parse_curve("points: 2\ntype: bspline\n0 0 0 1\n3 4 0 1\n", 100).unwrap();
        assert_eq!((short.length(), short.at(0.5, 0)), (0.0, 0.0));
        assert!(parse_curve("points: 1\n0 0 0\n", 100).is_err());
        assert!(parse("hello\n", "bad.func", 16, 0).is_err());
        // A set with more functions than allowed stops at the bound, naming it.
        let two = "funcgalleryver 1 1\nitems: 2\nfver 1 1\nname: A\npoints: 2\n0 0\n1 1\n\
                   fver 1 1\nname: B\npoints: 2\n0 0\n1 1\n";
        assert_eq!(parse(two, "two.fset", 2, 0).unwrap().len(), 2);
        assert!(
            parse(two, "two.fset", 1, 0)
                .unwrap_err()
                .contains("more functions than the 1")
        );
    }
}
