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

use crate::error::{Error, Result};
use crate::files::Source;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

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
    pub(crate) changed: HashMap<u32, String>,
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
                let column = match self.changed.get(&line.saturating_sub(1)) {
                    Some(original) => {
                        let expanded = self.text.lines().nth(line as usize - 1).unwrap_or("");
                        original_column(original, expanded, column)
                    }
                    None => column,
                };
                let (file, line) = self.origin(line);
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
    index: HashMap<Vec<u32>, u32>,
    unions: HashMap<(u32, u32), u32>,
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

/// Splices `\`-newline and replaces comments by a space; returns logical lines with the
/// physical line each starts on. Newlines inside a block comment end the logical line,
/// so line numbers stay those of the file.
fn logical_lines(text: &str, file: &str) -> Result<Vec<(u32, String)>> {
    let mut lines = Vec::new();
    let mut cur = String::new();
    let mut start_line = 1u32;
    let mut line = 1u32;
    let mut chars = text.chars().peekable();
    let mut in_block: Option<(u32, u32)> = None;
    let mut quote: Option<char> = None;
    // 1-based column (in characters) of the next character, for a comment left open.
    let mut col = 1u32;
    while let Some(c) = chars.next() {
        let here = col;
        col = if c == '\n' { 1 } else { col + 1 };
        // A line ending in backslashes continues (cpfg's models also write `\\`).
        while c == '\\' && chars.peek() == Some(&'\\') && in_block.is_none() && quote.is_none() {
            let mut ahead = chars.clone();
            while ahead.peek() == Some(&'\\') {
                ahead.next();
            }
            if !matches!(ahead.peek(), Some('\n') | Some('\r')) {
                break;
            }
            chars.next();
        }
        if c == '\\' && matches!(chars.peek(), Some('\n') | Some('\r')) {
            if chars.next() == Some('\r') && chars.peek() == Some(&'\n') {
                chars.next();
            }
            line += 1;
            continue;
        }
        if c == '\n' {
            line += 1;
            // An unterminated literal ends at the line's end, as in cpp.
            quote = None;
            lines.push((start_line, std::mem::take(&mut cur)));
            start_line = line;
            continue;
        }
        if in_block.is_some() {
            if c == '*' && chars.peek() == Some(&'/') {
                chars.next();
                in_block = None;
                cur.push(' ');
            }
            continue;
        }
        if let Some(q) = quote {
            cur.push(c);
            if c == '\\' {
                if let Some(&n) = chars.peek() {
                    if n != '\n' {
                        cur.push(n);
                        chars.next();
                    }
                }
            } else if c == q {
                quote = None;
            }
            continue;
        }
        match c {
            '"' => {
                quote = Some(c);
                cur.push(c);
            }
            '/' if chars.peek() == Some(&'*') => {
                chars.next();
                col += 1;
                in_block = Some((line, here));
            }
            '/' if chars.peek() == Some(&'/') => {
                while let Some(&n) = chars.peek() {
                    if n == '\n' {
                        break;
                    }
                    chars.next();
                }
                cur.push(' ');
            }
            '\r' if chars.peek() == Some(&'\n') => {}
            _ => cur.push(c),
        }
    }
    if let Some((at, column)) = in_block {
        let mut e = perr(
            file,
            at,
            "unterminated comment: `/*` has no closing `*/`".into(),
        );
        if let Error::Parse { column: c, .. } = &mut e {
            *c = column;
        }
        return Err(e);
    }
    lines.push((start_line, cur));
    Ok(lines)
}

fn tokenize(s: &str) -> Vec<Tok> {
    let mut out = Vec::new();
    let b = s.as_bytes();
    let mut i = 0;
    let tok = |kind, text: &str| Tok {
        kind,
        text: text.to_string(),
        hide: 0,
    };
    while i < b.len() {
        let c = b[i];
        let start = i;
        if c == b' ' || c == b'\t' || c == b'\x0c' || c == b'\x0b' || c == b'\r' {
            while i < b.len() && matches!(b[i], b' ' | b'\t' | b'\x0c' | b'\x0b' | b'\r') {
                i += 1;
            }
            // Kept as written: a leading TAB continues a production in cpfg.
            out.push(tok(Kind::Space, &s[start..i]));
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            out.push(tok(Kind::Ident, &s[start..i]));
        } else if c.is_ascii_digit() || (c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            // A preprocessing number: digits, letters, `.`, and a sign after an exponent.
            i += 1;
            while i < b.len() {
                let d = b[i];
                let sign = (d == b'+' || d == b'-') && matches!(b[i - 1], b'e' | b'E');
                if sign || d.is_ascii_alphanumeric() || d == b'.' || d == b'_' {
                    i += 1;
                } else {
                    break;
                }
            }
            out.push(tok(Kind::Number, &s[start..i]));
        } else if c == b'"' || c == b'\'' {
            i += 1;
            while i < b.len() && b[i] != c {
                if b[i] == b'\\' {
                    i += 1;
                }
                i += 1;
            }
            i = (i + 1).min(b.len());
            out.push(tok(Kind::Str, &s[start..i]));
        } else {
            let two = s.get(i..i + 2);
            if matches!(two, Some("##")) {
                i += 2;
            } else {
                i += s[i..].chars().next().map_or(1, char::len_utf8);
            }
            out.push(tok(Kind::Punct, &s[start..i]));
        }
    }
    out
}

fn join(tokens: &[Tok]) -> String {
    tokens.iter().map(|t| t.text.as_str()).collect()
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
            let (line_no, line) = (&lines[i].0, &lines[i].1);
            let line_no = *line_no;
            let active = frames.last().is_none_or(|f| f.active);
            let trimmed = line.trim_start();
            if let Some(rest) = trimmed.strip_prefix('#') {
                let rest = rest.trim_start();
                let word_len = rest
                    .find(|c: char| !c.is_ascii_alphabetic())
                    .unwrap_or(rest.len());
                let (word, args) = rest.split_at(word_len);
                let args = args.trim();
                let err = |m: String| perr(file, line_no, m);
                let handled = match word {
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
                        let name = macro_name(args)
                            .ok_or_else(|| err("a macro name after `#undef`".into()))?;
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
                };
                if handled {
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
            // A function-like macro call may continue on the following lines.
            let mut text = line.clone();
            let mut used = 1;
            let expanded = loop {
                match self.expand_line(&text, file, line_no)? {
                    Some(e) => break e,
                    None => {
                        let next = lines.get(i + used).map(|l| l.1.trim_start());
                        match next {
                            Some(n) if !n.starts_with('#') && used < MAX_CALL_LINES => {
                                text.push(' ');
                                text.push_str(&lines[i + used].1);
                                used += 1;
                            }
                            _ => {
                                return Err(err_unterminated(file, line_no));
                            }
                        }
                    }
                }
            };
            if expanded != text {
                let at = self.out.origins.len() as u32;
                self.out.changed.insert(at, text);
            }
            self.push_line(&expanded, file_idx, line_no)?;
            for k in 1..used {
                self.push_line("", file_idx, lines[i + k].0)?;
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

    /// Expands a line; `None` when a function-like macro call is not closed on it.
    fn expand_line(&mut self, line: &str, file: &str, line_no: u32) -> Result<Option<String>> {
        if !line.bytes().any(|b| b.is_ascii_alphabetic() || b == b'_') || self.macros.is_empty() {
            return Ok(Some(line.to_string()));
        }
        // Tokens cost tens of bytes each: a line whose macros need expanding is at most
        // 1 MiB (cpfg's lines are short; text without macros is not tokenized at all).
        if line.len() > MAX_EXPANDED_LINE {
            return Err(perr(
                file,
                line_no,
                format!(
                    "a line of {} bytes with macros to expand; at most {MAX_EXPANDED_LINE} bytes",
                    line.len()
                ),
            ));
        }
        let toks = tokenize(line);
        match self.expand(toks, file, line_no)? {
            Some(t) => Ok(Some(join(&t))),
            None => Ok(None),
        }
    }

    fn count(&mut self, n: usize, file: &str, line: u32) -> Result<()> {
        self.tokens += n;
        if self.tokens > MAX_EXPANDED_TOKENS {
            return Err(perr(
                file,
                line,
                format!(
                    "macro expansion produces more than {MAX_EXPANDED_TOKENS} tokens \
                     (macros that multiply each other?)"
                ),
            ));
        }
        Ok(())
    }

    /// C's expansion with hide sets; `None` when a call's `)` is missing.
    fn expand(&mut self, input: Vec<Tok>, file: &str, line: u32) -> Result<Option<Vec<Tok>>> {
        let mut out = Vec::with_capacity(input.len());
        let mut rest: std::collections::VecDeque<Tok> = input.into();
        while let Some(t) = rest.pop_front() {
            if t.kind != Kind::Ident {
                out.push(t);
                continue;
            }
            let Some(m) = self.macros.get(&t.text) else {
                out.push(t);
                continue;
            };
            // A function-like macro name not followed by `(` is an ordinary name.
            let call_open = rest.iter().position(|t| t.kind != Kind::Space);
            if m.params.is_some() && !call_open.is_some_and(|k| rest[k].is("(")) {
                out.push(t);
                continue;
            }
            if self.hides.contains(t.hide, m.id) {
                let chain: Vec<&str> = self.hides.sets[t.hide as usize]
                    .iter()
                    .map(|&i| self.names[i as usize].as_str())
                    .collect();
                return Err(perr(
                    file,
                    line,
                    format!(
                        "the macro `{}` expands to itself (recursive #define: {} → {})",
                        t.text,
                        chain.join(" → "),
                        t.text
                    ),
                ));
            }
            let m = m.clone();
            let hide = self.hides.with(t.hide, m.id);
            let body = match &m.params {
                None => self.substitute(&m, &[], hide, file, line)?,
                Some(_) => {
                    let k = call_open.expect("checked above");
                    let Some((args, close)) = collect_args(&rest, k) else {
                        return Ok(None);
                    };
                    let nparams = m.params.as_ref().map_or(0, Vec::len);
                    let variadic = m
                        .params
                        .as_ref()
                        .is_some_and(|p| p.last().is_some_and(|s| s == "..."));
                    let ok = args.len() == nparams
                        || (nparams == 0 && args.len() == 1 && args[0].is_empty())
                        || (variadic && args.len() >= nparams - 1);
                    if !ok {
                        return Err(perr(
                            file,
                            line,
                            format!(
                                "the macro `{}` takes {nparams} argument(s), not {}",
                                t.text,
                                args.len()
                            ),
                        ));
                    }
                    let args = if variadic && args.len() >= nparams {
                        let mut a = args[..nparams - 1].to_vec();
                        let mut tail = Vec::new();
                        for (i, arg) in args[nparams - 1..].iter().enumerate() {
                            if i > 0 {
                                tail.push(Tok {
                                    kind: Kind::Punct,
                                    text: ",".into(),
                                    hide: 0,
                                });
                            }
                            tail.extend(arg.iter().cloned());
                        }
                        a.push(tail);
                        a
                    } else {
                        args
                    };
                    rest.drain(..=close);
                    self.substitute(&m, &args, hide, file, line)?
                }
            };
            self.count(body.len(), file, line)?;
            for tok in body.into_iter().rev() {
                rest.push_front(tok);
            }
        }
        Ok(Some(out))
    }

    fn substitute(
        &mut self,
        m: &Macro,
        args: &[Vec<Tok>],
        hide: u32,
        file: &str,
        line: u32,
    ) -> Result<Vec<Tok>> {
        let params = m.params.as_deref().unwrap_or(&[]);
        let index = |t: &Tok| {
            (t.kind == Kind::Ident)
                .then(|| {
                    params
                        .iter()
                        .position(|p| *p == t.text || (p == "..." && t.text == "__VA_ARGS__"))
                })
                .flatten()
        };
        let mut out: Vec<Tok> = Vec::new();
        let body = &m.body;
        let mut i = 0;
        while i < body.len() {
            let t = &body[i];
            // `#param`: the argument as a string literal.
            if t.is("#") && !params.is_empty() {
                let j = skip_space(body, i + 1);
                if let Some(k) = body.get(j).and_then(index) {
                    let text = join(&args[k])
                        .trim()
                        .replace('\\', "\\\\")
                        .replace('"', "\\\"");
                    out.push(Tok {
                        kind: Kind::Str,
                        text: format!("\"{text}\""),
                        hide: 0,
                    });
                    i = j + 1;
                    continue;
                }
            }
            // `a ## b`: paste the neighbours (arguments unexpanded).
            if t.is("##") {
                while out.last().is_some_and(|t| t.kind == Kind::Space) {
                    out.pop();
                }
                let j = skip_space(body, i + 1);
                let right: Vec<Tok> = match body.get(j) {
                    Some(r) => match index(r) {
                        Some(k) => args[k].clone(),
                        None => vec![r.clone()],
                    },
                    None => Vec::new(),
                };
                let left = out.pop();
                let mut text = left.map(|l| l.text).unwrap_or_default();
                let mut right = right.into_iter();
                if let Some(r) = right.next() {
                    text.push_str(&r.text);
                }
                out.extend(tokenize(&text));
                out.extend(right);
                i = j + 1;
                continue;
            }
            match index(t) {
                Some(k) => {
                    let next = skip_space(body, i + 1);
                    if body.get(next).is_some_and(|n| n.is("##")) {
                        out.extend(args[k].iter().cloned());
                    } else {
                        self.count(args[k].len(), file, line)?;
                        match self.expand(args[k].clone(), file, line)? {
                            Some(e) => out.extend(e),
                            None => {
                                return Err(err_unterminated(file, line));
                            }
                        }
                    }
                }
                None => out.push(t.clone()),
            }
            i += 1;
        }
        for t in &mut out {
            t.hide = self.hides.union(t.hide, hide);
        }
        Ok(out)
    }

    /// Evaluates an `#if` / `#elif` expression.
    fn condition(&mut self, args: &str, file: &str, line: u32) -> Result<bool> {
        // `defined X` and `defined(X)` first, before expansion.
        let toks = tokenize(args);
        let mut pre = Vec::new();
        let mut i = 0;
        while i < toks.len() {
            if toks[i].kind == Kind::Ident && toks[i].text == "defined" {
                let mut j = skip_space(&toks, i + 1);
                let paren = toks.get(j).is_some_and(|t| t.is("("));
                if paren {
                    j = skip_space(&toks, j + 1);
                }
                let Some(name) = toks.get(j).filter(|t| t.kind == Kind::Ident) else {
                    return Err(perr(file, line, "a macro name after `defined`".into()));
                };
                let v = self.macros.contains_key(&name.text);
                if paren {
                    j = skip_space(&toks, j + 1);
                    if !toks.get(j).is_some_and(|t| t.is(")")) {
                        return Err(perr(file, line, "`)` after `defined(NAME`".into()));
                    }
                }
                pre.push(Tok {
                    kind: Kind::Number,
                    text: if v { "1".into() } else { "0".into() },
                    hide: 0,
                });
                i = j + 1;
                continue;
            }
            pre.push(toks[i].clone());
            i += 1;
        }
        let Some(expanded) = self.expand(pre, file, line)? else {
            return Err(err_unterminated(file, line));
        };
        let toks: Vec<Tok> = expanded
            .into_iter()
            .filter(|t| t.kind != Kind::Space)
            .collect();
        let mut e = CondEval {
            toks: &toks,
            pos: 0,
            depth: 0,
        };
        let v = e
            .ternary()
            .map_err(|m| perr(file, line, format!("in `#if {}`: {m}", args.trim())))?;
        if e.pos < toks.len() {
            return Err(perr(
                file,
                line,
                format!(
                    "in `#if {}`: unexpected `{}` after the condition",
                    args.trim(),
                    toks[e.pos].text
                ),
            ));
        }
        Ok(v != 0)
    }
}

fn err_unterminated(file: &str, line: u32) -> Error {
    perr(
        file,
        line,
        "unterminated macro call: its `(` is never closed".into(),
    )
}

fn macro_name(args: &str) -> Option<&str> {
    let len = args
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(args.len());
    let name = &args[..len];
    (!name.is_empty() && !name.as_bytes()[0].is_ascii_digit()).then_some(name)
}

fn skip_space(toks: &[Tok], mut i: usize) -> usize {
    while toks.get(i).is_some_and(|t| t.kind == Kind::Space) {
        i += 1;
    }
    i
}

/// The arguments of a call whose `(` is at `open`, and the index of its `)`.
fn collect_args(
    toks: &std::collections::VecDeque<Tok>,
    open: usize,
) -> Option<(Vec<Vec<Tok>>, usize)> {
    let mut args = vec![Vec::new()];
    let mut depth = 0usize;
    for (i, t) in toks.iter().enumerate().skip(open + 1) {
        if t.is("(") {
            depth += 1;
        } else if t.is(")") {
            if depth == 0 {
                for a in &mut args {
                    while a.first().is_some_and(|t: &Tok| t.kind == Kind::Space) {
                        a.remove(0);
                    }
                    while a.last().is_some_and(|t| t.kind == Kind::Space) {
                        a.pop();
                    }
                }
                return Some((args, i));
            }
            depth -= 1;
        } else if t.is(",") && depth == 0 {
            args.push(Vec::new());
            continue;
        }
        args.last_mut().expect("never empty").push(t.clone());
    }
    None
}

/// Integer expressions of `#if` (names left after expansion are 0, as in C).
struct CondEval<'a> {
    toks: &'a [Tok],
    pos: usize,
    depth: usize,
}

type CResult = std::result::Result<i64, String>;

impl CondEval<'_> {
    fn peek(&self) -> Option<&str> {
        self.toks.get(self.pos).map(|t| t.text.as_str())
    }

    /// Eats a punctuator sequence such as `&&` or `<=` (tokens are single characters).
    fn eat(&mut self, op: &str) -> bool {
        let n = op.chars().count();
        if self.pos + n > self.toks.len() {
            return false;
        }
        let text: String = self.toks[self.pos..self.pos + n]
            .iter()
            .map(|t| t.text.as_str())
            .collect();
        let all_punct = self.toks[self.pos..self.pos + n]
            .iter()
            .all(|t| t.kind == Kind::Punct);
        if all_punct && text == op {
            // `<` must not be the start of `<=` or `<<` unless asked.
            self.pos += n;
            true
        } else {
            false
        }
    }

    fn ternary(&mut self) -> CResult {
        self.depth += 1;
        if self.depth > 200 {
            return Err("the condition nests too deeply".into());
        }
        let c = self.binary(0)?;
        let v = if self.eat("?") {
            let a = self.ternary()?;
            if !self.eat(":") {
                return Err("`:` of `?:`".into());
            }
            let b = self.ternary()?;
            if c != 0 { a } else { b }
        } else {
            c
        };
        self.depth -= 1;
        Ok(v)
    }

    fn binary(&mut self, level: usize) -> CResult {
        const LEVELS: &[&[&str]] = &[
            &["||"],
            &["&&"],
            &["|"],
            &["^"],
            &["&"],
            &["==", "!="],
            &["<=", ">=", "<<", ">>", "<", ">"],
            &["+", "-"],
            &["*", "/", "%"],
        ];
        if level == LEVELS.len() {
            return self.unary();
        }
        let mut v = self.binary(level + 1)?;
        'outer: loop {
            for &op in LEVELS[level] {
                // `&` and `|` must not eat `&&` / `||`.
                if (op == "&" && self.peek_two("&&")) || (op == "|" && self.peek_two("||")) {
                    continue;
                }
                if (op == "<" || op == ">") && (self.peek_two("<=") || self.peek_two(">=")) {
                    continue;
                }
                if self.eat(op) {
                    let r = self.binary(level + 1)?;
                    v = match op {
                        "||" => ((v != 0) || (r != 0)) as i64,
                        "&&" => ((v != 0) && (r != 0)) as i64,
                        "|" => v | r,
                        "^" => v ^ r,
                        "&" => v & r,
                        "==" => (v == r) as i64,
                        "!=" => (v != r) as i64,
                        "<=" => (v <= r) as i64,
                        ">=" => (v >= r) as i64,
                        "<<" => v.wrapping_shl(r as u32),
                        ">>" => v.wrapping_shr(r as u32),
                        "<" => (v < r) as i64,
                        ">" => (v > r) as i64,
                        "+" => v.wrapping_add(r),
                        "-" => v.wrapping_sub(r),
                        "*" => v.wrapping_mul(r),
                        "/" | "%" if r == 0 => return Err("division by zero".into()),
                        "/" => v.wrapping_div(r),
                        _ => v.wrapping_rem(r),
                    };
                    continue 'outer;
                }
            }
            return Ok(v);
        }
    }

    fn peek_two(&self, s: &str) -> bool {
        let a = self.toks.get(self.pos).map(|t| t.text.as_str());
        let b = self.toks.get(self.pos + 1).map(|t| t.text.as_str());
        matches!((a, b), (Some(x), Some(y)) if format!("{x}{y}") == s)
    }

    fn unary(&mut self) -> CResult {
        let mut ops = Vec::new();
        loop {
            if self.eat("-") {
                ops.push('-');
            } else if self.eat("+") {
            } else if self.peek() == Some("!") && !self.peek_two("!=") {
                self.pos += 1;
                ops.push('!');
            } else if self.eat("~") {
                ops.push('~');
            } else {
                break;
            }
            if ops.len() > 10_000 {
                return Err("too many unary operators".into());
            }
        }
        let mut v = self.primary()?;
        for op in ops.into_iter().rev() {
            v = match op {
                '-' => v.wrapping_neg(),
                '!' => (v == 0) as i64,
                _ => !v,
            };
        }
        Ok(v)
    }

    fn primary(&mut self) -> CResult {
        let Some(t) = self.toks.get(self.pos) else {
            return Err("an expression, found the end of the line".into());
        };
        self.pos += 1;
        match t.kind {
            Kind::Number => {
                let s = t.text.trim_end_matches(['u', 'U', 'l', 'L']);
                let v = if let Some(h) = s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
                    i64::from_str_radix(h, 16).ok()
                } else if s.len() > 1 && s.starts_with('0') {
                    i64::from_str_radix(&s[1..], 8).ok()
                } else {
                    s.parse::<i64>().ok()
                };
                v.ok_or_else(|| format!("an integer, not `{}`", t.text))
            }
            Kind::Ident => Ok(0),
            Kind::Str => Err(format!("an integer, not the string {}", t.text)),
            _ if t.text == "(" => {
                let v = self.ternary()?;
                if !self.eat(")") {
                    return Err("`)`".into());
                }
                Ok(v)
            }
            _ => Err(format!("an expression, not `{}`", t.text)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pp(text: &str) -> String {
        preprocess(text, "", Includes::None).unwrap().text
    }

    fn pp_err(text: &str) -> String {
        match preprocess(text, "", Includes::None) {
            Err(Error::Parse { line, message, .. }) => format!("{line}: {message}"),
            other => panic!("expected an error, got {other:?}"),
        }
    }

    #[test]
    fn object_and_function_like_macros() {
        let out = pp("#define N 3\n#define SQ(x) ((x)*(x))\nA(N) SQ(N+1)\n");
        assert_eq!(out.lines().nth(2).unwrap(), "A(3) ((3+1)*(3+1))");
        // Macros that expand to parameter lists and to several statements.
        let out = pp("#define P 1,2\n#define S a=1; b=2;\nF(P) { S }\n");
        assert_eq!(out.lines().nth(2).unwrap(), "F(1,2) { a=1; b=2; }");
        // A function-like name without `(` is left alone; `#` and `##`.
        let out = pp(
            "#define f(x) g(x)\n#define STR(x) #x\n#define CAT(a,b) a##b\nf + STR(a b) CAT(x,1)\n",
        );
        assert_eq!(out.lines().nth(3).unwrap(), "f + \"a b\" x1");
        // Rescanning: a macro's result is expanded again.
        let out = pp("#define A B\n#define B 7\nA\n");
        assert_eq!(out.lines().nth(2).unwrap(), "7");
    }

    #[test]
    fn undef_conditionals_continuations_and_comments() {
        let src = "#define X 1\n#ifdef X\nyes\n#else\nno\n#endif\n#undef X\n#ifndef X\nundone\n#endif\n\
                   #if defined(X) || 2 > 1 && !0\nif\n#elif 1\nelif\n#endif\n\
                   F(1,\\\n2) // two rolls? no: a comment\nG /* inline */ H\n";
        let out = pp(src);
        let lines: Vec<&str> = out.lines().collect();
        assert!(lines.contains(&"yes"));
        assert!(!lines.contains(&"no"));
        assert!(lines.contains(&"undone"));
        assert!(lines.contains(&"if"));
        assert!(!lines.contains(&"elif"));
        assert!(lines.iter().any(|l| l.trim_end() == "F(1,2)"));
        assert!(lines.iter().any(|l| l.trim_end() == "G   H"));
        // `//` in a string is not a comment.
        assert!(pp("printf(\"a//b\");").contains("a//b"));
    }

    #[test]
    fn lines_map_back_to_the_file() {
        let p = preprocess(
            "#define A 1\n/* a\n comment */\nB\n#if 0\nx\n#endif\nC\n",
            "",
            Includes::None,
        )
        .unwrap();
        let lines: Vec<&str> = p.text.lines().collect();
        let b = lines.iter().position(|l| l.trim() == "B").unwrap();
        let c = lines.iter().position(|l| l.trim() == "C").unwrap();
        assert_eq!(p.origin(b as u32 + 1), (None, 4));
        assert_eq!(p.origin(c as u32 + 1), (None, 8));
    }

    #[test]
    fn a_call_may_span_lines() {
        let p = preprocess("#define M(a,b) a+b\nX M(1,\n2) Y\nZ\n", "", Includes::None).unwrap();
        let lines: Vec<&str> = p.text.lines().collect();
        assert_eq!(lines[1], "X 1+2 Y");
        assert_eq!(lines[3], "Z");
        assert_eq!(p.origin(4), (None, 4));
    }

    #[test]
    fn malformed_input_gets_clear_errors() {
        assert!(pp_err("#define M(a) a\nM(1\n").contains("unterminated macro call"));
        assert!(pp_err("#define M(a, b\n").contains("unterminated #define"));
        assert!(pp_err("#define A B\n#define B A\nA\n").contains("recursive"));
        assert!(pp_err("#define A A\nA\n").contains("recursive"));
        assert!(pp_err("#if 1\nx\n").starts_with("1: "));
        assert!(pp_err("#endif\n").contains("without an `#if`"));
        assert!(pp_err("#include \"x.h\"\n").contains("needs the grammar's folder"));
        assert!(pp_err("/* open\n").contains("unterminated comment"));
        assert!(pp_err("#define M(a) a\nM(1,2)\n").contains("1 argument"));
        assert!(pp_err("#if 1 +\n#endif\n").contains("#if"));
        // Exponential macros stop at the token bound.
        let mut src = String::from("#define A0 x\n");
        for i in 1..40 {
            src.push_str(&format!("#define A{i} A{} A{}\n", i - 1, i - 1));
        }
        src.push_str("A39\n");
        assert!(pp_err(&src).contains("more than"));
        // Deep conditionals: bounded, with an error past the limit.
        let deep = "#if 1\n".repeat(100_000);
        assert!(pp_err(&deep).contains("nested deeper"));
        let fine = format!("{}x\n{}", "#if 1\n".repeat(4000), "#endif\n".repeat(4000));
        assert!(pp(&fine).lines().any(|l| l == "x"));
    }
}
