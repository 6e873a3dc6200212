//! The C preprocessor pass cpfg runs over every `.l` and `.v` file before reading it.
//!
//! A real pass over text, in the order of C's translation phases: backslash-newline
//! splicing, comments (`/* */` and `//`, string literals respected) replaced by a space,
//! then directives line by line (`#define` object- and function-like, `#undef`,
//! `#include "file"` relative to the including file, `#if/#ifdef/#ifndef/#elif/#else/
//! #endif`, `#error`; `#pragma` and `#line` ignored) and macro expansion of the other
//! lines with C's rescanning rules, `#` stringizing and `##` pasting. Every output line
//! records the file and line it came from, so errors point into the original text.
//!
//! Where arbor differs from a C compiler's preprocessor, on purpose:
//! - a macro whose expansion reaches itself (directly, or through other macros) is an
//!   error naming the chain: in a grammar that is always a mistake, where C would
//!   silently leave the name as a module;
//! - a `#` line whose word is not a directive (`#ignore:`, `#consider:`, or a module `#`
//!   at the start of a continued successor) is kept as text, as cpfg's preprocessor does;
//! - work is bounded: output size, tokens produced by expansion, include depth and
//!   conditional nesting all have limits whose errors say which was passed.

mod condition;
mod expand;
#[cfg(test)]
mod tests;
mod text;

use crate::error::{Error, Result};
use crate::files::Source;
use expand::{err_unterminated, macro_name, skip_space};
use rustc_hash::FxHashMap;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use text::{Logical, file_place, join, logical_lines, tokenize};

/// Most bytes the preprocessed text of one grammar may reach (all includes together).
pub(crate) const MAX_OUTPUT_BYTES: usize = 16 << 20;
/// Most tokens macro expansion may produce for one grammar (a bound on time).
pub(crate) const MAX_EXPANDED_TOKENS: usize = 4 << 20;
/// Deepest `#include` nesting.
pub(crate) const MAX_INCLUDE_DEPTH: usize = 32;
/// Deepest `#if` nesting.
pub(crate) const MAX_CONDITIONAL_DEPTH: usize = 4096;
/// Longest line (bytes) whose macros are expanded.
const MAX_EXPANDED_LINE: usize = 1 << 20;
/// Most lines one function-like macro call may span.
const MAX_CALL_LINES: usize = 256;

/// Where an output line came from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Origin {
    /// Index into [`Preprocessed::files`].
    pub(crate) file: u32,
    /// 1-based line in that file.
    pub(crate) line: u32,
}

/// Preprocessed text with the origin of each of its lines.
#[derive(Clone, Debug, Default)]
pub(crate) struct Preprocessed {
    pub(crate) text: String,
    /// One per line of `text`.
    pub(crate) origins: Vec<Origin>,
    /// Names of the files read (the main one first), as written or as found.
    pub(crate) files: Vec<String>,
    /// The original text of the output lines macro expansion changed (0-based output
    /// line), so error columns are told in the file's own text.
    pub(crate) changed: FxHashMap<u32, String>,
    /// Where the characters of an output line's original text stand in its file (see
    /// [`Logical::places`]), for the lines a splice or a comment joined or shifted
    /// (0-based output line): an error is told at its file's own line and column.
    pub(crate) places: FxHashMap<u32, Vec<[u32; 3]>>,
}

/// Column `column` (1-based, in characters) of `expanded`, as a column of `original`,
/// the line it was expanded from: the same where the two agree (before the first and
/// after the last character expansion changed), else where the changed part starts (the
/// macro's name) in the original.
fn original_column(original: &str, expanded: &str, column: u32) -> u32 {
    let (o, e): (Vec<char>, Vec<char>) = (original.chars().collect(), expanded.chars().collect());
    let prefix = o.iter().zip(&e).take_while(|(a, b)| a == b).count();
    let room = o.len().min(e.len()) - prefix;
    let suffix = o
        .iter()
        .rev()
        .zip(e.iter().rev())
        .take(room)
        .take_while(|(a, b)| a == b)
        .count();
    let c = column.saturating_sub(1) as usize;
    let mapped = if c < prefix {
        c
    } else if c >= e.len() - suffix {
        (o.len() - (e.len() - c).min(o.len())).min(o.len())
    } else {
        prefix
    };
    mapped as u32 + 1
}

impl Preprocessed {
    /// The file name (`None` for the main text) and line of output line `line` (1-based).
    pub(crate) fn origin(&self, line: u32) -> (Option<&str>, u32) {
        match self.origins.get((line as usize).saturating_sub(1)) {
            Some(o) if o.file == 0 => (None, o.line),
            Some(o) => (Some(self.files[o.file as usize].as_str()), o.line),
            None => (None, line),
        }
    }

    /// Maps an error whose line is a line of `text` back to the original file and line.
    pub(crate) fn map_error(&self, e: Error) -> Error {
        match e {
            Error::Parse {
                line,
                column,
                message,
            } => {
                let out = line.saturating_sub(1);
                let column = match self.changed.get(&out) {
                    Some(original) => {
                        let expanded = self.text.lines().nth(out as usize).unwrap_or("");
                        original_column(original, expanded, column)
                    }
                    None => column,
                };
                let (file, first) = self.origin(line);
                let (line, column) = match self.places.get(&out) {
                    Some(places) => file_place(places, first, column),
                    None => (first, column),
                };
                Error::Parse {
                    line,
                    column,
                    message: match file {
                        Some(f) => format!("in `{f}`: {message}"),
                        None => message,
                    },
                }
            }
            other => other,
        }
    }
}

/// Where `#include` looks for files.
#[derive(Clone)]
pub(crate) enum Includes<'l> {
    /// Text in memory: `#include` is refused with an error that says so.
    None,
    /// The folder of the main file, and the load's reads (policy, budget, progress).
    Dir(PathBuf, &'l dyn Source),
}

#[derive(Clone, Debug, PartialEq)]
enum Kind {
    Ident,
    Number,
    Str,
    Punct,
    Space,
}

#[derive(Clone, Debug)]
struct Tok {
    kind: Kind,
    text: String,
    /// Macros this token came out of (C's "hide set"): an index into [`HideSets`].
    hide: u32,
}

impl Tok {
    fn is(&self, s: &str) -> bool {
        self.kind == Kind::Punct && self.text == s
    }
}

#[derive(Clone, Debug)]
struct Macro {
    id: u32,
    params: Option<Vec<String>>,
    body: Vec<Tok>,
}

struct Frame {
    /// Whether lines are kept at this level.
    active: bool,
    /// Whether some branch of this `#if` has been taken.
    taken: bool,
    /// Whether `#else` was seen.
    else_seen: bool,
    line: u32,
}

/// Interned hide sets (sorted macro ids); set 0 is empty. Tokens carry an index, so a
/// copy is cheap and a union is computed once per pair.
#[derive(Default)]
struct HideSets {
    sets: Vec<Vec<u32>>,
    index: FxHashMap<Vec<u32>, u32>,
    unions: FxHashMap<(u32, u32), u32>,
}

impl HideSets {
    fn new() -> Self {
        let mut h = HideSets::default();
        h.intern(Vec::new());
        h
    }

    fn intern(&mut self, set: Vec<u32>) -> u32 {
        if let Some(&i) = self.index.get(&set) {
            return i;
        }
        let i = self.sets.len() as u32;
        self.sets.push(set.clone());
        self.index.insert(set, i);
        i
    }

    fn contains(&self, set: u32, id: u32) -> bool {
        self.sets[set as usize].binary_search(&id).is_ok()
    }

    fn union(&mut self, a: u32, b: u32) -> u32 {
        if a == b || b == 0 {
            return a;
        }
        if a == 0 {
            return b;
        }
        if let Some(&u) = self.unions.get(&(a, b)) {
            return u;
        }
        let mut v = self.sets[a as usize].clone();
        v.extend_from_slice(&self.sets[b as usize]);
        v.sort_unstable();
        v.dedup();
        let u = self.intern(v);
        self.unions.insert((a, b), u);
        u
    }

    fn with(&mut self, a: u32, id: u32) -> u32 {
        let single = self.intern(vec![id]);
        self.union(a, single)
    }
}

struct Pre<'l> {
    hides: HideSets,
    macros: HashMap<String, std::rc::Rc<Macro>>,
    next_id: u32,
    names: Vec<String>,
    out: Preprocessed,
    tokens: usize,
    includes: Includes<'l>,
    stack: Vec<PathBuf>,
    /// Lines preprocessed, for progress every [`crate::progress::EVERY`].
    lines_done: usize,
}

/// "line 3 of `a.h`", or "line 3" in the main text.
fn place(file: &str, line: u32) -> String {
    if file.is_empty() {
        format!("line {line}")
    } else {
        format!("line {line} of `{file}`")
    }
}

fn perr(file: &str, line: u32, message: String) -> Error {
    Error::Parse {
        line,
        column: 1,
        message: if file.is_empty() {
            message
        } else {
            format!("in `{file}`: {message}")
        },
    }
}

/// Preprocesses `text` (the main grammar or view file, named `name` in messages; empty
/// for text in memory).
pub(crate) fn preprocess(text: &str, name: &str, includes: Includes<'_>) -> Result<Preprocessed> {
    let mut p = Pre {
        hides: HideSets::new(),
        macros: HashMap::new(),
        next_id: 0,
        names: Vec::new(),
        out: Preprocessed {
            files: vec![name.to_string()],
            ..Default::default()
        },
        tokens: 0,
        includes,
        stack: Vec::new(),
        lines_done: 0,
    };
    p.file(text, 0, "")?;
    Ok(p.out)
}

impl Pre<'_> {
    fn file(&mut self, text: &str, file_idx: u32, file: &str) -> Result<()> {
        let lines = logical_lines(text, file)?;
        let mut frames: Vec<Frame> = Vec::new();
        let mut i = 0;
        while i < lines.len() {
            self.lines_done += 1;
            if self.lines_done % crate::progress::EVERY == 0 {
                if let Includes::Dir(_, source) = &self.includes {
                    source.tick()?;
                }
            }
            let (line_no, line) = (lines[i].line, &lines[i].text);
            let active = frames.last().is_none_or(|f| f.active);
            if let Some(rest) = line.trim_start().strip_prefix('#') {
                let rest = rest.trim_start();
                let word_len = rest
                    .find(|c: char| !c.is_ascii_alphabetic())
                    .unwrap_or(rest.len());
                let (word, args) = rest.split_at(word_len);
                let at = (file, line_no);
                if self.directive(&mut frames, word, args.trim(), at, active)? {
                    self.push_line("", file_idx, line_no)?;
                    i += 1;
                    continue;
                }
            }
            if !active {
                self.push_line("", file_idx, line_no)?;
                i += 1;
                continue;
            }
            let (text, expanded, used) = self.expand_call(&lines, i, file)?;
            let at = self.out.origins.len() as u32;
            let call = &lines[i..i + used];
            if used > 1 || !call[0].plain() {
                // The places of the lines a macro call spans, one after another (each
                // joined to the one before by a space).
                let mut places = Vec::new();
                let mut offset = 0;
                for l in call {
                    places.extend(l.places.iter().map(|&[k, ln, c]| [k + offset, ln, c]));
                    offset += l.chars + 1;
                }
                self.out.places.insert(at, places);
            }
            if expanded != text {
                self.out.changed.insert(at, text);
            }
            self.push_line(&expanded, file_idx, line_no)?;
            for k in 1..used {
                self.push_line("", file_idx, lines[i + k].line)?;
            }
            i += used;
        }
        if let Some(f) = frames.last() {
            return Err(perr(
                file,
                f.line,
                "this `#if` is never closed by an `#endif`".into(),
            ));
        }
        Ok(())
    }

    /// Runs the directive `#word args` at `(file, line)`; `false` when `word` is not a
    /// directive (the line is then text). `active`: whether lines are kept here.
    fn directive(
        &mut self,
        frames: &mut Vec<Frame>,
        word: &str,
        args: &str,
        (file, line_no): (&str, u32),
        active: bool,
    ) -> Result<bool> {
        let err = |m: String| perr(file, line_no, m);
        Ok(match word {
            "if" | "ifdef" | "ifndef" => {
                if frames.len() >= MAX_CONDITIONAL_DEPTH {
                    return Err(err(format!(
                        "conditionals nested deeper than {MAX_CONDITIONAL_DEPTH} levels"
                    )));
                }
                let cond = if !active {
                    false
                } else if word == "if" {
                    self.condition(args, file, line_no)?
                } else {
                    let name = macro_name(args)
                        .ok_or_else(|| err(format!("a macro name after `#{word}`")))?;
                    self.macros.contains_key(name) == (word == "ifdef")
                };
                frames.push(Frame {
                    active: active && cond,
                    taken: cond || !active,
                    else_seen: false,
                    line: line_no,
                });
                true
            }
            "elif" | "else" => {
                let parent = frames.len() < 2 || frames[frames.len() - 2].active;
                let Some(f) = frames.last_mut() else {
                    return Err(err(format!("`#{word}` without an `#if`")));
                };
                if f.else_seen {
                    return Err(err(format!("`#{word}` after `#else`")));
                }
                let taken = f.taken;
                let cond = if taken || !parent {
                    false
                } else if word == "elif" {
                    self.condition(args, file, line_no)?
                } else {
                    true
                };
                let f = frames.last_mut().expect("checked above");
                f.else_seen = word == "else";
                f.active = cond;
                f.taken |= cond;
                true
            }
            "endif" => {
                if frames.pop().is_none() {
                    return Err(err("`#endif` without an `#if`".into()));
                }
                true
            }
            _ if !active => matches!(
                word,
                "define" | "undef" | "include" | "error" | "pragma" | "line" | "warning"
            ),
            "define" => {
                self.define(args, file, line_no)?;
                true
            }
            "undef" => {
                let name =
                    macro_name(args).ok_or_else(|| err("a macro name after `#undef`".into()))?;
                self.macros.remove(name);
                true
            }
            "include" => {
                self.include(args, file, line_no)?;
                true
            }
            "error" => return Err(err(format!("#error {args}"))),
            "pragma" | "line" | "warning" => true,
            _ => false,
        })
    }

    /// The line at `lines[i]` expanded, with the text it was and how many lines it took: a
    /// function-like macro call may continue on the following lines.
    fn expand_call(
        &mut self,
        lines: &[Logical],
        i: usize,
        file: &str,
    ) -> Result<(String, String, usize)> {
        let line_no = lines[i].line;
        let mut text = lines[i].text.clone();
        let mut used = 1;
        loop {
            if let Some(e) = self.expand_line(&text, file, line_no)? {
                return Ok((text, e, used));
            }
            match lines.get(i + used).map(|l| l.text.trim_start()) {
                Some(n) if !n.starts_with('#') && used < MAX_CALL_LINES => {
                    text.push(' ');
                    text.push_str(&lines[i + used].text);
                    used += 1;
                }
                _ => return Err(err_unterminated(file, line_no)),
            }
        }
    }

    fn push_line(&mut self, text: &str, file: u32, line: u32) -> Result<()> {
        if self.out.text.len() + text.len() + 1 > MAX_OUTPUT_BYTES {
            return Err(perr(
                &self.out.files[file as usize].clone(),
                line,
                format!("the preprocessed grammar passes {MAX_OUTPUT_BYTES} bytes"),
            ));
        }
        if !self.out.origins.is_empty() {
            self.out.text.push('\n');
        }
        self.out.text.push_str(text);
        self.out.origins.push(Origin { file, line });
        Ok(())
    }

    fn define(&mut self, args: &str, file: &str, line: u32) -> Result<()> {
        let err = |m: &str| perr(file, line, m.to_string());
        let name_len = args
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(args.len());
        let name = &args[..name_len];
        if name.is_empty() || name.as_bytes()[0].is_ascii_digit() {
            return Err(err("a macro name after `#define`"));
        }
        let mut rest = &args[name_len..];
        let mut params = None;
        if let Some(r) = rest.strip_prefix('(') {
            let Some(close) = r.find(')') else {
                return Err(err(
                    "`)` closing the parameters of a function-like macro (unterminated #define)",
                ));
            };
            let list: Vec<String> = r[..close]
                .split(',')
                .map(|s| s.trim().to_string())
                .filter(|s| !s.is_empty())
                .collect();
            for p in &list {
                if p != "..."
                    && (!p.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                        || p.as_bytes()[0].is_ascii_digit())
                {
                    return Err(err(&format!(
                        "a parameter name in the #define of `{name}`, not `{p}`"
                    )));
                }
            }
            params = Some(list);
            rest = &r[close + 1..];
        }
        let mut body = tokenize(rest.trim());
        while body.last().is_some_and(|t| t.kind == Kind::Space) {
            body.pop();
        }
        let id = self.next_id;
        self.next_id += 1;
        self.names.push(name.to_string());
        self.macros.insert(
            name.to_string(),
            std::rc::Rc::new(Macro { id, params, body }),
        );
        Ok(())
    }

    fn include(&mut self, args: &str, file: &str, line: u32) -> Result<()> {
        let err = |m: String| perr(file, line, m);
        let args = args.trim();
        let target = if let Some(r) = args.strip_prefix('"') {
            r.split('"').next().filter(|_| r.contains('"'))
        } else if let Some(r) = args.strip_prefix('<') {
            r.split('>').next().filter(|_| r.contains('>'))
        } else {
            None
        };
        let Some(target) = target else {
            return Err(err(format!(
                "a file name after #include (`\"file\"` or `<file>`), not `{args}`"
            )));
        };
        let (dir, source) = match &self.includes {
            Includes::None => {
                return Err(err(format!(
                    "#include \"{target}\" needs the grammar's folder: read it from a file \
                     (arbor_tree_from_lsystem_file / LSystem::from_file)"
                )));
            }
            Includes::Dir(d, source) => (
                self.stack
                    .last()
                    .and_then(|p| p.parent().map(Path::to_path_buf))
                    .unwrap_or_else(|| d.clone()),
                *source,
            ),
        };
        if self.stack.len() >= MAX_INCLUDE_DEPTH {
            return Err(err(format!(
                "#include \"{target}\" nests deeper than {MAX_INCLUDE_DEPTH} files"
            )));
        }
        let loaded = source
            .read(&dir, target, "#include")
            .map_err(|e| match e {
                Error::FileAccess { path, reason } => Error::FileAccess {
                    path,
                    reason: format!("{reason} (`#include` at {})", place(file, line)),
                },
                other => other,
            })?
            // A missing file is an error of the text, at its line.
            .ok_or_else(|| {
                err(format!(
                    "#include \"{target}\": cannot open `{}` (no such file)",
                    dir.join(target).display()
                ))
            })?;
        let canonical = loaded.key;
        if self.stack.contains(&canonical) {
            let chain: Vec<String> = self
                .stack
                .iter()
                .chain(std::iter::once(&canonical))
                .map(|p| {
                    p.file_name()
                        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
                })
                .collect();
            return Err(err(format!(
                "#include cycle: {} includes itself again",
                chain.join(" → ")
            )));
        }
        if loaded.bytes.len() > MAX_OUTPUT_BYTES {
            return Err(err(format!(
                "#include \"{target}\" is {} bytes; at most {MAX_OUTPUT_BYTES} are accepted",
                loaded.bytes.len()
            )));
        }
        let text = String::from_utf8(loaded.bytes)
            .map_err(|_| err(format!("#include \"{target}\" is not UTF-8 text")))?;
        let idx = self.out.files.len() as u32;
        self.out.files.push(target.to_string());
        self.stack.push(canonical);
        let r = self.file(&text, idx, target);
        self.stack.pop();
        r
    }
}
