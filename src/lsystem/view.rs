//! cpfg's view file (`.v`): the turtle's angle, line widths and tropism, read after the
//! same preprocessor pass as the grammar.
//!
//! Read: `angle factor: N` (the angle is 360/N degrees), `angle increment: D`, `initial
//! line width: W [pixels|polygons]`, `line width increment: W`, `tropism direction: x,y,z`
//! with `initial elasticity: e` and `elasticity increment: d`, and `tropism: T: x,y,z
//! ... E: e` (the first tropism of cpfg's newer syntax). Every other line (colours,
//! lights, viewpoint, projection, render modes, surfaces, contours, textures, ...) has
//! no meaning for a mesh and is accepted without effect; a line that is not `key: value`
//! is also skipped, as cpfg does.

use super::function_files::Function;
use super::grammar::{OldTropism, ViewSettings};
use super::preprocess::{Includes, Preprocessed, preprocess};
use crate::error::{Error, Result};
use crate::files::MAX_COMPANIONS;
use glam::DVec3;

/// What a view file brings besides settings: the functions it lists (`function:` and
/// `function set:` files, numbered from 1 in order) and its surfaces (`surface:`), read
/// from the view file's folder.
#[derive(Debug, Default)]
pub(crate) struct Extras {
    pub(crate) functions: Vec<Function>,
    pub(crate) surfaces: Vec<super::surface::Surface>,
    /// What was skipped, for the grammar's warnings.
    pub(crate) warnings: Vec<String>,
    /// The curves (`curve:` files), numbered from 1 in order.
    pub(crate) curves: Vec<super::function_files::Curve>,
}

/// Reads a companion file the view file names, from `inc`'s folder, under the load's
/// file policy and budget; `None` when there is no such file.
fn companion(inc: &Includes<'_>, file: &str, what: &'static str) -> Result<Option<String>> {
    let Includes::Dir(dir, source) = inc else {
        return Err(Error::FileAccess {
            path: file.to_string(),
            reason: format!(
                "the {what} needs the view file's folder: read the grammar with \
                 LSystem::from_file / arbor_tree_from_lsystem_file"
            ),
        });
    };
    let Some(loaded) = source.read(dir, file, what)? else {
        return Ok(None);
    };
    if loaded.bytes.len() > 4 << 20 {
        return Err(Error::FileAccess {
            path: file.to_string(),
            reason: format!("the {what} is larger than 4 MiB"),
        });
    }
    Ok(Some(String::from_utf8(loaded.bytes).unwrap_or_else(|e| {
        e.into_bytes().iter().map(|&b| b as char).collect()
    })))
}

/// Refuses a view file's `count + 1`-th function, curve or surface (`what`, plural).
fn bounded(count: usize, what: &'static str) -> Result<()> {
    if count >= MAX_COMPANIONS {
        return Err(Error::LimitExceeded {
            limit_name: "MAX_COMPANIONS",
            what,
            limit: MAX_COMPANIONS as u64,
            requested: count as u64 + 1,
            step: None,
        });
    }
    Ok(())
}

/// A companion's refusal with the view file's line it was named on.
fn with_line(e: Error, line: u32) -> Error {
    match e {
        Error::FileAccess { path, reason } => Error::FileAccess {
            path,
            reason: format!("{reason} (view file line {line})"),
        },
        other => other,
    }
}

/// Applies view-file text to `view`; `name` names the file in messages.
pub(crate) fn apply(
    view: &mut ViewSettings,
    text: &str,
    name: &str,
    inc: Includes<'_>,
) -> Result<Extras> {
    super::syntax::check_size(text)?;
    let pre = preprocess(text, name, inc.clone())?;
    let mut reader = Reader {
        pre: &pre,
        name,
        inc: &inc,
        extras: Extras::default(),
        direction: None,
        elasticity: 0.0,
        increment: 0.0,
        bad: std::cell::Cell::new(false),
    };
    for (k, line) in pre.text.lines().enumerate() {
        let Some((key, value)) = line.split_once(':') else {
            continue;
        };
        let key: String = key
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
            .to_ascii_lowercase();
        let at = Line {
            k,
            key: &key,
            value: value.trim(),
            text: line,
        };
        // A value cpfg cannot read leaves the setting as it was, with a warning (cpfg's
        // fscanf fails and it goes on).
        reader.bad.set(false);
        if let Err(e) = reader.line(view, &at) {
            if !reader.bad.get() {
                return Err(e);
            }
            reader
                .extras
                .warnings
                .push(format!("{e}; the setting keeps its value"));
        }
    }
    if let Some(d) = reader.direction {
        if d.length_squared() > 0.0 {
            view.old_tropism = Some(OldTropism {
                direction: d.normalize(),
                elasticity: reader.elasticity,
                increment: reader.increment,
            });
        }
    }
    Ok(reader.extras)
}

/// One `key: value` line of a view file (`k` counts from 0; `key` in lower case with
/// single spaces).
struct Line<'t> {
    k: usize,
    key: &'t str,
    value: &'t str,
    text: &'t str,
}

impl Line<'_> {
    /// The count after a companion's file name (`curve: file.con 100`), if there is one.
    fn samples(&self) -> Option<usize> {
        self.value.split_whitespace().nth(1)?.parse().ok()
    }
}

/// A view file being read: what it brings besides settings, and the older tropism's parts.
struct Reader<'a, 'l> {
    pre: &'a Preprocessed,
    name: &'a str,
    inc: &'a Includes<'l>,
    extras: Extras,
    direction: Option<DVec3>,
    elasticity: f64,
    increment: f64,
    /// Whether the last error was a value cpfg would pass over (see `bad_value`).
    bad: std::cell::Cell<bool>,
}

/// The numbers of a value (separated by commas or blanks); `None` for one that is not a
/// finite number.
fn numbers(value: &str) -> Vec<Option<f64>> {
    value
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect()
}

impl Reader<'_, '_> {
    /// The error of line `at`: `key:` needs `what`.
    fn fail(&self, at: &Line<'_>, what: &str) -> Error {
        let (file, line) = self.pre.origin(at.k as u32 + 1);
        let place = file.map_or_else(
            || {
                if self.name.is_empty() {
                    "the view file".to_string()
                } else {
                    format!("`{}`", self.name)
                }
            },
            |f| format!("`{f}`"),
        );
        Error::Parse {
            line,
            column: 1,
            message: format!(
                "in {place}: `{}:` needs {what}, found `{}`",
                at.key, at.value
            ),
        }
    }

    /// [`fail`](Self::fail) for a setting's value: cpfg passes over such a line, so the
    /// caller turns it into a warning.
    fn bad_value(&self, at: &Line<'_>, what: &str) -> Error {
        self.bad.set(true);
        self.fail(at, what)
    }

    /// The view file's line number of line `at`.
    fn line_no(&self, at: &Line<'_>) -> u32 {
        self.pre.origin(at.k as u32 + 1).1
    }

    fn line(&mut self, view: &mut ViewSettings, at: &Line<'_>) -> Result<()> {
        let first = || numbers(at.value).first().copied().flatten();
        let width = || first().filter(|&w| w >= 0.0);
        let color = || first().filter(|&c| (0.0..=65535.0).contains(&c));
        match at.key {
            "angle factor" => {
                let n = first()
                    .filter(|&n| n > 0.0)
                    .ok_or_else(|| self.bad_value(at, "a number > 0"))?;
                view.angle_increment = 360.0 / n;
            }
            "angle increment" => {
                view.angle_increment =
                    first().ok_or_else(|| self.bad_value(at, "a number of degrees"))?;
            }
            "initial line width" => {
                view.initial_width = width().ok_or_else(|| self.bad_value(at, "a width >= 0"))?;
            }
            "line width increment" => {
                view.width_increment = width().ok_or_else(|| self.bad_value(at, "a width >= 0"))?;
            }
            "tropism direction" => match numbers(at.value).as_slice() {
                [Some(x), Some(y), Some(z), ..] => self.direction = Some(DVec3::new(*x, *y, *z)),
                _ => return Err(self.bad_value(at, "three numbers x, y, z")),
            },
            "initial color" | "initial colour" => {
                let c =
                    color().ok_or_else(|| self.bad_value(at, "a colour index from 0 to 65535"))?;
                view.initial_color = c as u32;
            }
            "color increment" | "colour increment" => {
                let c =
                    color().ok_or_else(|| self.bad_value(at, "a colour step from 0 to 65535"))?;
                view.color_increment = c as u32;
            }
            "interpretation past %" => {
                view.interpretation_past_cut = !at.value.to_ascii_lowercase().starts_with("off");
            }
            "initial elasticity" => {
                self.elasticity = first().ok_or_else(|| self.bad_value(at, "a number"))?;
            }
            "elasticity increment" => {
                self.increment = first().ok_or_else(|| self.bad_value(at, "a number"))?;
            }
            "surface" => self.surface(at)?,
            "curve" => self.curve(at)?,
            "function" | "function set" | "functions" => self.function(at)?,
            "tropism" => {
                // `tropism: T: x,y,z, A: angle, I: intensity, E: elasticity, S: step`
                if let Some((t, e)) = new_style_tropism(at.text) {
                    view.tropism = Some((t, e));
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// `surface: x file.s [scale [s t]]`. A surface file that cannot be read leaves its
    /// `~x` a plain leaf site (cpfg reports it and draws on): a warning, not an error.
    fn surface(&mut self, at: &Line<'_>) -> Result<()> {
        let w: Vec<&str> = at.value.split_whitespace().collect();
        let (Some(id), Some(file)) = (w.first(), w.get(1)) else {
            return Err(self.fail(at, "a surface letter and its .s file"));
        };
        let mut chars = id.chars();
        let (Some(letter), None) = (chars.next(), chars.next()) else {
            return Err(self.fail(at, "a one-character surface name"));
        };
        let num = |k: usize| w.get(k).and_then(|v| v.parse::<f64>().ok());
        let scale = num(2).unwrap_or(1.0);
        let div = |k: usize| num(k).map_or(0, |v| v.clamp(0.0, 32.0) as usize);
        let surfaces = &self.extras.surfaces;
        if !surfaces.iter().any(|x| x.name == letter) {
            bounded(surfaces.len(), "surfaces of a view file")?;
        }
        let text = match companion(self.inc, file, "surface file") {
            Ok(Some(t)) => t,
            Ok(None) => {
                let line = self.line_no(at);
                self.extras.warnings.push(format!(
                    "view file line {line}: surface `{letter}` not loaded: `{file}`: no such file"
                ));
                return Ok(());
            }
            Err(
                e
                @ (Error::Cancelled { .. } | Error::FileBudget { .. } | Error::OutOfMemory { .. }),
            ) => return Err(e),
            Err(e) => {
                let line = self.line_no(at);
                self.extras.warnings.push(format!(
                    "view file line {line}: surface `{letter}` not loaded: {e}"
                ));
                return Ok(());
            }
        };
        let s = super::surface::parse(&text, letter, scale, (div(3), div(4)))
            .map_err(|e| self.fail(at, &format!("a surface file cpfg can read (`{file}`: {e})")))?;
        self.extras.surfaces.retain(|x| x.name != letter);
        self.extras.surfaces.push(s);
        Ok(())
    }

    /// The text of the companion file `line` names, read from the view file's folder.
    fn companion_text(&self, at: &Line<'_>, what: &'static str) -> Result<(String, String)> {
        let file = at.value.split_whitespace().next().unwrap_or("").to_string();
        let text = companion(self.inc, &file, what)
            .map_err(|e| with_line(e, self.line_no(at)))?
            .ok_or_else(|| self.fail(at, &format!("a readable {what} (`{file}`: no such file)")))?;
        Ok((file, text))
    }

    /// `curve: file.con`.
    fn curve(&mut self, at: &Line<'_>) -> Result<()> {
        bounded(self.extras.curves.len(), "curves of a view file")?;
        let (file, text) = self.companion_text(at, "curve file")?;
        // `curve: file.con [samples]`: cpfg's arc table has 100 samples by default.
        let samples = at.samples().unwrap_or(100);
        let curve = super::function_files::parse_curve(&text, samples)
            .map_err(|e| self.fail(at, &format!("a curve file cpfg can read (`{file}`: {e})")))?;
        self.extras.curves.push(curve);
        Ok(())
    }

    /// `function: file.func [samples]` or `function set: file.fset`.
    fn function(&mut self, at: &Line<'_>) -> Result<()> {
        let functions = &self.extras.functions;
        bounded(functions.len(), "functions of a view file")?;
        let (file, text) = self.companion_text(at, "function file")?;
        // `function: f.func 100`: the samples the older form of the file uses.
        let samples = at.samples().unwrap_or(0);
        let room = MAX_COMPANIONS - functions.len();
        let read = super::function_files::parse(&text, &file, room, samples).map_err(|e| {
            self.fail(
                at,
                &format!("a function file cpfg can read (`{file}`: {e})"),
            )
        })?;
        self.extras.functions.extend(read);
        Ok(())
    }
}

/// The T and E of a new-style `tropism:` line, when both are there.
fn new_style_tropism(line: &str) -> Option<(DVec3, f64)> {
    let rest = line.split_once(':')?.1;
    let mut t = None;
    let mut e = None;
    let mut parts = rest.split(':').peekable();
    let mut key = parts.next()?.trim().to_string();
    while let Some(part) = parts.next() {
        // `part` holds this key's value, then the next key's letter at its end.
        let (value, next_key) = match parts.peek() {
            Some(_) => {
                let cut = part
                    .trim_end()
                    .rfind(|c: char| c == ',' || c.is_whitespace());
                match cut {
                    Some(i) => (&part[..i], part[i + 1..].trim().to_string()),
                    None => (part, String::new()),
                }
            }
            None => (part, String::new()),
        };
        let nums: Vec<f64> = value
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter_map(|s| s.parse().ok())
            .collect();
        match key.as_str() {
            "T" | "t" if nums.len() >= 3 => t = Some(DVec3::new(nums[0], nums[1], nums[2])),
            "E" | "e" if !nums.is_empty() => e = Some(nums[0]),
            _ => {}
        }
        key = next_key;
    }
    Some((t?, e?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_widths_and_tropism() {
        let mut v = ViewSettings::default();
        apply(
            &mut v,
            "#define N 40\nangle factor: N\ninitial line width: 2 pixels\nline width increment: .1\n\
             viewpoint: -1,0,30\ntropism direction: 0.0,1.0,0.0\ninitial elasticity: 0.02\n\
             surface: l leaf.s 800 3 5\nnonsense line\n",
            "plant.v",
            Includes::None,
        )
        .unwrap();
        assert_eq!(v.angle_increment, 9.0);
        assert_eq!(v.initial_width, 2.0);
        assert_eq!(v.width_increment, 0.1);
        let t = v.old_tropism.unwrap();
        assert_eq!(t.direction, DVec3::Y);
        assert_eq!(t.elasticity, 0.02);
        let mut v = ViewSettings::default();
        apply(
            &mut v,
            "angle increment: 22.5\ntropism: T: 0,-1,0, A: 0, E: 0.3\n",
            "",
            Includes::None,
        )
        .unwrap();
        assert_eq!(v.angle_increment, 22.5);
        assert_eq!(v.tropism, Some((DVec3::NEG_Y, 0.3)));
    }

    #[test]
    fn bad_values_name_the_key_and_line() {
        let mut v = ViewSettings::default();
        let extras = apply(&mut v, "\nangle factor: zero\n", "plant.v", Includes::None).unwrap();
        assert_eq!(v.angle_increment, 45.0, "cpfg keeps the setting's value");
        let text = extras.warnings.join("\n");
        assert!(
            text.contains("line 2") && text.contains("angle factor") && text.contains("plant.v"),
            "{text}"
        );
    }
}
