//! Reading grammar text in the cpfg language into an [`LSystem`].

use super::LSystem;
use super::expr::{self, Globals, Scope};
use super::grammar::{
    Blocks, ModuleList, POP, PUSH, Pattern, Production, ProductionTable, SuccModule, Symbols,
    ViewSettings,
};
use super::preprocess::{Includes, preprocess};
use super::stmt::{self, Stmt};
use super::syntax::{Cursor, MAX_SOURCE_BYTES, PErr, PResult, check_size, line_col};
use crate::error::{Error, Result};
use glam::DVec3;
use std::cell::RefCell;
use std::collections::HashMap;

/// Replaces comments by spaces (newlines kept) so that byte offsets stay those of the
/// source.
fn strip_comments(src: &str) -> PResult<String> {
    let bytes = src.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    let blank = |out: &mut Vec<u8>, b: u8| out.push(if b == b'\n' { b'\n' } else { b' ' });
    while i < bytes.len() {
        if bytes[i] == b'/' && bytes.get(i + 1) == Some(&b'*') {
            let start = i;
            let Some(len) = src[i + 2..].find("*/") else {
                return Err(PErr {
                    pos: start,
                    found: String::new(),
                    expected: "unterminated comment: `/*` has no closing `*/`".into(),
                });
            };
            let stop = i + 2 + len + 2;
            for &b in &bytes[i..stop] {
                blank(&mut out, b);
            }
            i = stop;
        } else if bytes[i] == b'/' && bytes.get(i + 1) == Some(&b'/') {
            while i < bytes.len() && bytes[i] != b'\n' {
                blank(&mut out, bytes[i]);
                i += 1;
            }
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    // Whole characters were replaced (a comment starts and ends on ASCII), so it stays
    // UTF-8.
    Ok(String::from_utf8(out).expect("comments are replaced whole"))
}

#[derive(Clone, Copy, PartialEq)]
enum Section {
    Productions,
    Homomorphism,
    Decomposition,
}

struct Parser<'a> {
    text: &'a str,
    symbols: Symbols,
    defines: HashMap<String, f64>,
    axiom: Option<ModuleList>,
    derivation_length: u32,
    seed: Option<u64>,
    productions: ProductionTable,
    homomorphism: ProductionTable,
    decomposition: ProductionTable,
    ignore: Option<Vec<u16>>,
    consider: Option<Vec<u16>>,
    view: ViewSettings,
    section: Section,
    lsystem_seen: bool,
    ended: bool,
    globals: RefCell<Globals>,
    blocks: Blocks,
    ring: bool,
}

/// Parses grammar text in memory (preprocessed first; `#include` is refused); errors
/// carry line, column, what was found and what was expected.
pub fn parse(source: &str) -> Result<LSystem> {
    parse_with(source, "", Includes::None)
}

/// Preprocesses `source` (named `name` in messages, its includes found by `includes`),
/// then parses it; errors point into the original files.
pub(crate) fn parse_with(source: &str, name: &str, includes: Includes<'_>) -> Result<LSystem> {
    parse_named(source, name, includes, &[])
}

/// [`parse_with`], with `names` (the view file's function names) standing for numbers.
fn parse_named(
    source: &str,
    name: &str,
    includes: Includes<'_>,
    names: &[(String, f64)],
) -> Result<LSystem> {
    check_size(source)?;
    let pre = preprocess(source, name, includes)?;
    parse_text(&pre.text, names).map_err(|e| pre.map_error(e))
}

/// Parses preprocessed text.
fn parse_text(source: &str, names: &[(String, f64)]) -> Result<LSystem> {
    check_size(source)?;
    let to_error = |e: PErr| {
        let (line, column) = line_col(source, e.pos);
        let message = if e.found.is_empty() {
            e.expected
        } else {
            format!("found {}, expected {}", e.found, e.expected)
        };
        Error::Parse {
            line,
            column,
            message,
        }
    };
    let clean = strip_comments(source).map_err(to_error)?;
    let mut p = Parser {
        text: &clean,
        symbols: Symbols::new(),
        defines: names.iter().cloned().collect(),
        axiom: None,
        derivation_length: 0,
        seed: None,
        productions: ProductionTable::default(),
        homomorphism: ProductionTable {
            max_depth: 1,
            ..Default::default()
        },
        decomposition: ProductionTable {
            max_depth: 1,
            ..Default::default()
        },
        ignore: None,
        consider: None,
        view: ViewSettings::default(),
        section: Section::Productions,
        lsystem_seen: false,
        ended: false,
        globals: RefCell::new(Globals::default()),
        blocks: Blocks::default(),
        ring: false,
    };
    p.run().map_err(to_error)?;
    let Parser {
        symbols,
        axiom,
        derivation_length,
        seed,
        mut productions,
        mut homomorphism,
        mut decomposition,
        ignore,
        consider,
        view,
        globals,
        blocks,
        ring,
        ..
    } = p;
    let Some(axiom) = axiom else {
        let (line, column) = line_col(source, source.len());
        return Err(Error::Parse {
            line,
            column,
            message: "found end of text, expected an `Axiom:` line".into(),
        });
    };
    let n = symbols.len();
    productions.index(n);
    homomorphism.index(n);
    decomposition.index(n);
    // Context matching skips ignored symbols: those listed by `ignore:`, or all but those
    // listed by `consider:`. Brackets are never skipped.
    let mut skip = vec![false; n];
    if let Some(list) = &ignore {
        for &s in list {
            skip[s as usize] = true;
        }
    }
    if let Some(list) = &consider {
        skip.iter_mut().for_each(|s| *s = true);
        for &s in list {
            skip[s as usize] = false;
        }
    }
    skip[PUSH as usize] = false;
    skip[POP as usize] = false;
    Ok(LSystem::new(
        symbols,
        axiom,
        derivation_length,
        seed,
        productions,
        homomorphism,
        decomposition,
        skip,
        view,
        globals.into_inner(),
        blocks,
    ))
    .map(|mut ls| {
        ls.ring = ring;
        if ls.symbols.names.iter().any(|n| n == "?E") {
            ls.warnings.push(
                "the grammar queries an environment program (`?E`); arbor has none, so every \
                 `?E` keeps the parameters its productions give it"
                    .into(),
            );
        }
        ls
    })
}

/// Settings of a view file over those a grammar's directives gave: a directive that
/// left its default takes the view file's value.
pub(crate) fn merge_view(grammar: &mut ViewSettings, view: &ViewSettings) {
    let d = ViewSettings::default();
    if grammar.angle_increment == d.angle_increment {
        grammar.angle_increment = view.angle_increment;
    }
    if grammar.initial_width == d.initial_width {
        grammar.initial_width = view.initial_width;
    }
    if grammar.width_increment == d.width_increment {
        grammar.width_increment = view.width_increment;
    }
    if grammar.tropism.is_none() {
        grammar.tropism = view.tropism;
    }
    if grammar.old_tropism.is_none() {
        grammar.old_tropism = view.old_tropism;
    }
    grammar.initial_color = view.initial_color;
    grammar.interpretation_past_cut = view.interpretation_past_cut;
    grammar.color_increment = view.color_increment;
}

/// Reads a grammar file with its view file (see [`LSystem::from_file_with`]).
pub(crate) fn parse_file(
    path: &std::path::Path,
    view: Option<&std::path::Path>,
    files: &crate::files::FileOptions,
    progress: Option<crate::progress::ProgressFn<'_>>,
) -> Result<LSystem> {
    let loader = crate::files::Loader::new(files, progress);
    let read = |p: &std::path::Path, what: &'static str| -> Result<String> {
        // The host names these two files: what goes wrong is a bad argument, as before.
        let loaded = loader.read_named(p, what).map_err(|e| match e {
            Error::FileAccess { path, reason } => {
                Error::invalid("path", format!("`{path}`: {reason}"))
            }
            other => other,
        })?;
        if loaded.bytes.len() > MAX_SOURCE_BYTES {
            return Err(Error::Parse {
                line: 1,
                column: 1,
                message: format!(
                    "the {what} `{}` is {} bytes; at most {MAX_SOURCE_BYTES} are accepted",
                    p.display(),
                    loaded.bytes.len()
                ),
            });
        }
        // cpfg reads bytes: a file that is not UTF-8 (Latin-1 comments in older models)
        // is read as Latin-1.
        Ok(String::from_utf8(loaded.bytes)
            .unwrap_or_else(|e| e.into_bytes().iter().map(|&b| b as char).collect()))
    };
    let text = read(path, "grammar file")?;
    // The view file first: the names of its functions are numbers in the grammar
    // (`func(LEAF_GROWTH, t)`), as cpfg defines them.
    let view_path = match view {
        Some(v) => Some(v.to_path_buf()),
        None => {
            let beside = path.with_extension("v");
            loader.exists(&beside).then_some(beside)
        }
    };
    let mut settings = ViewSettings::default();
    let mut extras = super::view::Extras::default();
    let dir = path
        .parent()
        .map(std::path::Path::to_path_buf)
        .unwrap_or_default();
    let dir = if dir.as_os_str().is_empty() {
        std::path::PathBuf::from(".")
    } else {
        dir
    };
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let mut view_seen = false;
    if let Some(v) = view_path {
        let text = read(&v, "view file")?;
        let vname = v
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let vdir = v
            .parent()
            .map(std::path::Path::to_path_buf)
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or_else(|| dir.clone());
        extras = super::view::apply(&mut settings, &text, &vname, Includes::Dir(vdir, &loader))?;
        view_seen = true;
    }
    let names: Vec<(String, f64)> = extras
        .functions
        .iter()
        .enumerate()
        .filter(|(_, f)| !f.name.is_empty())
        .map(|(i, f)| (format!("{}{}", expr::FUNCTION_NAME, f.name), (i + 1) as f64))
        .collect();
    let mut ls = parse_named(&text, &name, Includes::Dir(dir, &loader), &names)?;
    loader.finish()?;
    if view_seen {
        // The grammar's own directives stand; the view file's settings fill in what it
        // leaves at the defaults (cpfg reads the angle and widths only from the view).
        merge_view(&mut ls.view, &settings);
    }
    ls.functions = extras.functions.into();
    ls.surfaces = extras.surfaces.into();
    ls.warnings.extend(extras.warnings);
    ls.curves = extras.curves.into();
    Ok(ls)
}

fn keyword<'t>(line: &'t str, key: &str) -> Option<&'t str> {
    let head = line.get(..key.len())?;
    head.eq_ignore_ascii_case(key).then(|| &line[key.len()..])
}

impl<'a> Parser<'a> {
    fn run(&mut self) -> PResult<()> {
        let text = self.text;
        let mut start = 0;
        while start < text.len() {
            let mut end = text[start..].find('\n').map_or(text.len(), |i| start + i);
            // A line continues on the next while its parentheses are open, while the
            // braces of statements are open (braces after a production's arrow are the
            // turtle's polygon modules), and whenever the next line starts with a TAB
            // (cpfg reads newline-TAB as a blank); the state is carried from line to
            // line (time linear in the text).
            let mut depth = Depth::default();
            depth.scan(&text[start..end]);
            while end < text.len()
                && (depth.parens > 0
                    || depth.braces > 0
                    || text.as_bytes().get(end + 1) == Some(&b'\t'))
            {
                let next = text[end + 1..]
                    .find('\n')
                    .map_or(text.len(), |i| end + 1 + i);
                depth.scan(&text[end..next]);
                end = next;
            }
            self.line(start, end)?;
            start = end + 1;
        }
        Ok(())
    }

    fn err(&self, pos: usize, expected: &str) -> PErr {
        Cursor::range(self.text, pos, self.text.len()).error_at(pos, expected)
    }

    fn msg(&self, pos: usize, message: &str) -> PErr {
        Cursor::new(self.text).message_at(pos, message)
    }

    fn line(&mut self, start: usize, end: usize) -> PResult<()> {
        let raw = &self.text[start..end];
        let lead = raw.len() - raw.trim_start().len();
        let line = raw.trim();
        let at = start + lead;
        if line.is_empty() {
            return Ok(());
        }
        // Where the text after a keyword starts, past its leading blanks.
        let rest_at = |rest: &str| at + (line.len() - rest.trim_start().len());
        if self.ended {
            if keyword(line, "lsystem:").is_some() {
                return Err(self.msg(at, "sub-L-systems (a second `Lsystem:`) are not supported"));
            }
            return Err(self.err(at, "nothing after `endlsystem`"));
        }
        for (key, which) in [
            ("starteach:", 2),
            ("start each:", 2),
            ("endeach:", 3),
            ("end each:", 3),
            ("start:", 0),
            ("end:", 1),
        ] {
            if let Some(rest) = keyword(line, key) {
                let stmts = self.block(rest_at(rest), end)?;
                let b = &mut self.blocks;
                let slot = [&mut b.start, &mut b.end, &mut b.start_each, &mut b.end_each];
                slot.into_iter()
                    .nth(which)
                    .expect("four blocks")
                    .extend(stmts);
                return Ok(());
            }
        }
        if let Some(rest) = keyword(line, "define:") {
            return self.arrays(rest_at(rest), end);
        }
        if keyword(line, "ring lsystem").is_some() || keyword(line, "ring l-system").is_some() {
            self.ring = true;
            return Ok(());
        }
        if let Some(rest) = keyword(line, "lsystem:") {
            if self.lsystem_seen {
                return Err(self.msg(at, "sub-L-systems (a second `Lsystem:`) are not supported"));
            }
            self.lsystem_seen = true;
            let _ = rest;
            return Ok(());
        }
        if keyword(line, "endlsystem").is_some() {
            self.ended = true;
            return Ok(());
        }
        if let Some(rest) =
            keyword(line, "derivation length:").or_else(|| keyword(line, "derivationlength:"))
        {
            let v = self.const_expr(rest_at(rest), end, "a derivation length")?;
            if !(v.is_finite() && v >= 0.0 && v <= u16::MAX as f64 && v.fract() == 0.0) {
                return Err(self.err(rest_at(rest), "a whole number of steps from 0 to 65535"));
            }
            self.derivation_length = v as u32;
            return Ok(());
        }
        if let Some(rest) = keyword(line, "seed:") {
            let v = self.const_expr(rest_at(rest), end, "a seed")?;
            if !(v.is_finite() && v >= 0.0 && v.fract() == 0.0) {
                return Err(self.err(rest_at(rest), "a whole, non-negative seed"));
            }
            self.seed = Some(v as u64);
            return Ok(());
        }
        if let Some(rest) = keyword(line, "axiom:") {
            if self.axiom.is_some() {
                return Err(self.err(at, "one `Axiom:` line only"));
            }
            let mut cur = Cursor::range(self.text, rest_at(rest), end);
            let axiom_at = cur.pos();
            let mut list = self.module_list(&mut cur, &[], false, true)?;
            list.line = super::syntax::line_col(self.text, axiom_at).0;
            cur.skip_ws();
            if !cur.at_end() {
                return Err(cur.error("a module"));
            }
            self.axiom = Some(list);
            return Ok(());
        }
        for (key, is_ignore) in [
            ("ignore:", true),
            ("#ignore:", true),
            ("consider:", false),
            ("#consider:", false),
        ] {
            if let Some(rest) = keyword(line, key) {
                if self.ignore.is_some() || self.consider.is_some() {
                    return Err(self.err(at, "one `ignore:` or `consider:` line, not both"));
                }
                let mut cur = Cursor::range(self.text, rest_at(rest), end);
                let mut list = Vec::new();
                loop {
                    cur.skip_ws();
                    if cur.at_end() {
                        break;
                    }
                    let sym = self.symbol(&mut cur)?;
                    list.push(sym);
                }
                if is_ignore {
                    self.ignore = Some(list);
                } else {
                    self.consider = Some(list);
                }
                return Ok(());
            }
        }
        // `homomorphism`, `homomorphism:`, `homomorphism: warnings` / `no warnings`, and
        // what follows on the line when a TAB continued it.
        for (key, section) in [
            ("homomorphism", Section::Homomorphism),
            ("interpretation:", Section::Homomorphism),
            ("decomposition", Section::Decomposition),
        ] {
            if let Some(rest) = keyword(line, key) {
                self.section = section;
                let mut rest = rest.trim_start();
                rest = rest.strip_prefix(':').unwrap_or(rest).trim_start();
                for w in ["no warnings", "warnings"] {
                    if let Some(r) = keyword(rest, w) {
                        rest = r.trim_start();
                    }
                }
                if rest.is_empty() {
                    return Ok(());
                }
                let at = rest_at(rest);
                return self.line(at, end);
            }
        }
        if let Some(rest) = keyword(line, "maximum depth:") {
            let v = self.const_expr(rest_at(rest), end, "a maximum depth")?;
            if !(v.is_finite() && (0.0..=1_000_000.0).contains(&v) && v.fract() == 0.0) {
                return Err(self.err(rest_at(rest), "a whole maximum depth from 0 to 1000000"));
            }
            match self.section {
                Section::Homomorphism => self.homomorphism.max_depth = v as u32,
                Section::Decomposition => self.decomposition.max_depth = v as u32,
                Section::Productions => {
                    return Err(self.err(
                        at,
                        "`maximum depth:` after `homomorphism` or `decomposition`",
                    ));
                }
            }
            return Ok(());
        }
        for (key, field) in [
            ("angle increment:", 0),
            ("initial line width:", 1),
            ("line width increment:", 2),
            ("step size:", 3),
        ] {
            if let Some(rest) = keyword(line, key) {
                let v = self.const_expr(rest_at(rest), end, "a number")?;
                if !v.is_finite() || (field != 0 && v < 0.0) {
                    return Err(self.err(rest_at(rest), "a finite, non-negative number"));
                }
                match field {
                    0 => self.view.angle_increment = v,
                    1 => self.view.initial_width = v,
                    2 => self.view.width_increment = v,
                    _ => self.view.step_size = v,
                }
                return Ok(());
            }
        }
        if let Some(rest) = keyword(line, "tropism:") {
            return self.tropism(rest_at(rest), end);
        }
        self.production(at, end)
    }

    /// `{ statements }` filling the rest of the line (a `Start:` block and the like).
    fn block(&mut self, pos: usize, end: usize) -> PResult<Vec<Stmt>> {
        let mut cur = Cursor::range(self.text, pos, end);
        let scope = Scope {
            params: &[],
            defines: &self.defines,
            globals: Some(&self.globals),
        };
        let stmts = stmt::block(&mut cur, &scope)?;
        cur.skip_ws();
        if !cur.at_end() {
            return Err(cur.error("the end of the line after the block"));
        }
        Ok(stmts)
    }

    /// `define: { array a[n] = { v, ... }, b[n][m]; ... }`.
    fn arrays(&mut self, pos: usize, end: usize) -> PResult<()> {
        let mut cur = Cursor::range(self.text, pos, end);
        cur.skip_ws();
        if !cur.eat("{") {
            return Err(cur.error("`{` opening the `define:` block"));
        }
        loop {
            cur.skip_ws();
            if cur.eat("}") {
                break;
            }
            if cur.eat(";") {
                continue;
            }
            if cur.identifier() != Some("array") {
                return Err(cur.error("`array name[size];` in the `define:` block"));
            }
            loop {
                cur.skip_ws();
                let name_at = cur.pos();
                let Some(name) = cur.identifier() else {
                    return Err(cur.error("an array name"));
                };
                let name = name.to_string();
                let mut dims = Vec::new();
                let mut total = 1usize;
                loop {
                    cur.skip_ws();
                    if !cur.eat("[") {
                        break;
                    }
                    let at = cur.pos();
                    let e = {
                        let scope = Scope {
                            params: &[],
                            defines: &self.defines,
                            globals: None,
                        };
                        expr::compile(&mut cur, &scope)?
                    };
                    let n = e.as_const().unwrap_or(f64::NAN);
                    if !(n >= 1.0 && n <= expr::MAX_GLOBAL_VALUES as f64) {
                        return Err(self.err(at, "a constant array size from 1 to 4194304"));
                    }
                    cur.skip_ws();
                    if !cur.eat("]") {
                        return Err(cur.error("`]` after the array size"));
                    }
                    dims.push(n as u32);
                    total = total.saturating_mul(n as usize);
                }
                if dims.is_empty() {
                    return Err(cur.error("`[size]` after the array name"));
                }
                let mut g = self.globals.borrow_mut();
                if g.array(&name).is_some() || g.var(&name).is_some() {
                    return Err(self.msg(name_at, &format!("`{name}` is declared twice")));
                }
                if g.init.len() + total > expr::MAX_GLOBAL_VALUES {
                    return Err(self.msg(name_at, "arrays of at most 4194304 values in all"));
                }
                let offset = g.init.len() as u32;
                let len = g.init.len() + total;
                g.init.resize(len, 0.0);
                g.arrays.push(expr::ArrayDecl { name, dims, offset });
                drop(g);
                cur.skip_ws();
                if cur.eat("=") {
                    // Initial values, flat or nested in braces, in row-major order.
                    let mut values = Vec::new();
                    let mut depth = 0usize;
                    loop {
                        cur.skip_ws();
                        if cur.eat("{") {
                            depth += 1;
                            if depth > 16 {
                                return Err(cur.error("initial values nested at most 16 deep"));
                            }
                            continue;
                        }
                        if cur.eat("}") {
                            if depth == 0 {
                                return Err(cur.error("a value"));
                            }
                            depth -= 1;
                            if depth == 0 {
                                break;
                            }
                            continue;
                        }
                        if cur.eat(",") {
                            continue;
                        }
                        let at = cur.pos();
                        let scope = Scope {
                            params: &[],
                            defines: &self.defines,
                            globals: None,
                        };
                        let v = expr::compile(&mut cur, &scope)?
                            .as_const()
                            .ok_or_else(|| self.err(at, "a constant initial value"))?;
                        values.push(v);
                        if depth == 0 {
                            break;
                        }
                    }
                    if values.len() > total {
                        return Err(self.err(
                            name_at,
                            &format!("at most {total} initial values for this array"),
                        ));
                    }
                    let mut g = self.globals.borrow_mut();
                    let o = offset as usize;
                    g.init[o..o + values.len()].copy_from_slice(&values);
                }
                cur.skip_ws();
                if cur.eat(",") {
                    continue;
                }
                break;
            }
            cur.skip_ws();
            if !cur.eat(";") && !cur.peek_str("}") {
                return Err(cur.error("`;` after the array declaration"));
            }
        }
        cur.skip_ws();
        if !cur.at_end() {
            return Err(cur.error("the end of the line after the `define:` block"));
        }
        Ok(())
    }

    fn const_expr(&self, pos: usize, end: usize, what: &str) -> PResult<f64> {
        let mut cur = Cursor::range(self.text, pos, end);
        cur.skip_ws();
        if cur.at_end() {
            return Err(cur.error(what));
        }
        let scope = Scope {
            params: &[],
            defines: &self.defines,
            globals: None,
        };
        let e = expr::compile(&mut cur, &scope)?;
        cur.skip_ws();
        if !cur.at_end() {
            return Err(cur.error("the end of the line after the value"));
        }
        e.as_const()
            .ok_or_else(|| self.err(pos, &format!("{what} that is constant (no ran/nran)")))
    }

    fn tropism(&mut self, pos: usize, end: usize) -> PResult<()> {
        let mut cur = Cursor::range(self.text, pos, end);
        // Components are separated by spaces or commas, so each is a signed number or a
        // #define name, not a full expression (`0 -1 0` is three numbers).
        let defines = &self.defines;
        let number = |cur: &mut Cursor<'_>| -> PResult<f64> {
            cur.skip_ws();
            cur.eat(",");
            cur.skip_ws();
            let at = cur.pos();
            let sign = if cur.eat("-") {
                -1.0
            } else {
                cur.eat("+");
                1.0
            };
            let v = match cur.number()? {
                Some(v) => v,
                None => match cur.identifier().and_then(|n| defines.get(n)) {
                    Some(&v) => v,
                    None => return Err(cur.error_at(at, "a number or a #define name")),
                },
            };
            Ok(sign * v)
        };
        cur.skip_ws();
        if !(cur.eat("T:") || cur.eat("t:")) {
            return Err(cur.error("`T:` and the tropism vector (tropism: T: x y z E: e)"));
        }
        let t = DVec3::new(number(&mut cur)?, number(&mut cur)?, number(&mut cur)?);
        cur.skip_ws();
        cur.eat(",");
        cur.skip_ws();
        if !(cur.eat("E:") || cur.eat("e:")) {
            return Err(cur.error("`E:` and the elasticity (tropism: T: x y z E: e)"));
        }
        let e = number(&mut cur)?;
        cur.skip_ws();
        if !cur.at_end() {
            return Err(cur.error("the end of the tropism line"));
        }
        self.view.tropism = Some((t, e));
        Ok(())
    }

    /// A symbol: one character, or `@` and a letter (`@M`, `@R`, `@v`, ...).
    fn symbol(&mut self, cur: &mut Cursor<'_>) -> PResult<u16> {
        let at = cur.pos();
        let Some(c) = cur.bump() else {
            return Err(cur.error("a module"));
        };
        let name_end;
        match c {
            '(' | ')' | ':' => {
                return Err(cur.error_at(at, "a module (a letter or a turtle symbol)"));
            }
            '@' => match cur.peek() {
                // `@;` `@!` and the like: cpfg's variants of the one-character modules.
                Some(p) if p.is_ascii_punctuation() && !matches!(p, '(' | ')' | '[' | ']') => {
                    cur.bump();
                    name_end = cur.pos();
                }
                Some(l) if l.is_ascii_alphabetic() => {
                    cur.bump();
                    // `@Tx`-style texture switches are three characters.
                    if l == 'T' && cur.peek().is_some_and(|c| c.is_ascii_lowercase()) {
                        cur.bump();
                    }
                    // cpfg's generalized cylinders are two letters after `@`: @Gs (start),
                    // @Gc (control point), @Ge (end), @Gt and @Gr (tangent, radius).
                    if l == 'G' && matches!(cur.peek(), Some('s' | 'c' | 'e' | 't' | 'r')) {
                        cur.bump();
                    }
                    name_end = cur.pos();
                }
                _ => return Err(cur.error("a letter after `@` (such as @M, @R or @v)")),
            },
            c if c.is_whitespace() || c.is_control() => {
                return Err(cur.error_at(at, "a module (a letter or a turtle symbol)"));
            }
            // Query modules (`?P`, `?H`, `?U`, `?L`, `?E`) and surfaces (`~l`) are two
            // characters, as cpfg reads them.
            '?' | '~' if cur.peek().is_some_and(|l| l.is_ascii_alphanumeric()) => {
                cur.bump();
                name_end = cur.pos();
            }
            _ => name_end = cur.pos(),
        }
        let name = &self.text[at..name_end];
        self.symbols
            .intern(name)
            .ok_or_else(|| self.msg(at, "too many distinct symbols (at most 65536)"))
    }

    /// A successor or axiom: modules with parameter expressions, until the end of the
    /// range or a top-level `:`. Brackets must balance.
    fn module_list(
        &mut self,
        cur: &mut Cursor<'_>,
        params: &[(String, u16)],
        stop_at_colon: bool,
        balanced: bool,
    ) -> PResult<ModuleList> {
        let mut list = ModuleList::default();
        let mut open: Vec<usize> = Vec::new();
        cur.skip_ws();
        if cur.rest().trim() == "*" {
            cur.eat("*");
            list.finish();
            return Ok(list);
        }
        loop {
            cur.skip_ws();
            if cur.at_end() || (stop_at_colon && cur.peek_str(":")) {
                break;
            }
            let at = cur.pos();
            let sym = self.symbol(cur)?;
            if sym == PUSH {
                open.push(at);
            } else if sym == POP && open.pop().is_none() && balanced {
                return Err(self.msg(at, "unbalanced brackets: this `]` closes no `[`"));
            }
            let first = list.exprs.len() as u32;
            cur.skip_ws();
            if cur.eat("(") {
                let scope = Scope {
                    params,
                    defines: &self.defines,
                    globals: Some(&self.globals),
                };
                loop {
                    cur.skip_ws();
                    if cur.peek_str("\"") {
                        // A text parameter (`@L("label")`): labels have no geometry, so
                        // the text is read and the value is 0.
                        skip_string(cur)?;
                        list.exprs.push(expr::Expr::Const(0.0));
                        cur.skip_ws();
                        if cur.eat(",") {
                            continue;
                        }
                        if cur.eat(")") {
                            break;
                        }
                        return Err(cur.error("`,` or `)` after a module parameter"));
                    }
                    list.exprs.push(expr::compile(cur, &scope)?);
                    cur.skip_ws();
                    if cur.eat(",") {
                        continue;
                    }
                    if cur.eat(")") {
                        break;
                    }
                    return Err(cur.error("`,` or `)` after a module parameter"));
                }
                if list.exprs.len() - first as usize > u16::MAX as usize {
                    return Err(self.err(at, "at most 65535 parameters on a module"));
                }
            }
            list.modules.push(SuccModule {
                sym,
                first,
                count: list.exprs.len() as u32 - first,
            });
        }
        if let (Some(&at), true) = (open.last(), balanced) {
            return Err(self.msg(at, "unbalanced brackets: this `[` is never closed"));
        }
        list.finish();
        Ok(list)
    }

    /// Modules with formal parameter names (a predecessor or a context).
    fn patterns(
        &mut self,
        cur: &mut Cursor<'_>,
        names: &mut Vec<(String, u16)>,
        allow_brackets: bool,
    ) -> PResult<Vec<Pattern>> {
        let mut out = Vec::new();
        cur.skip_ws();
        if cur.rest().trim() == "*" {
            cur.eat("*");
            return Ok(out);
        }
        loop {
            cur.skip_ws();
            if cur.at_end() {
                return Ok(out);
            }
            let at = cur.pos();
            let sym = self.symbol(cur)?;
            if (sym == PUSH || sym == POP) && !allow_brackets {
                return Err(self.msg(at, "brackets are supported in a right context only"));
            }
            let slot = names.len() as u16;
            let mut arity = 0u16;
            cur.skip_ws();
            if cur.eat("(") {
                loop {
                    cur.skip_ws();
                    let name_at = cur.pos();
                    let Some(name) = cur.identifier() else {
                        return Err(cur.error("a parameter name"));
                    };
                    if names.iter().any(|(n, _)| n == name) {
                        return Err(self.err(
                            name_at,
                            "a parameter name not used before in this production",
                        ));
                    }
                    if names.len() >= 1024 {
                        return Err(self.err(name_at, "at most 1024 parameters in a production"));
                    }
                    names.push((name.to_string(), names.len() as u16));
                    arity += 1;
                    cur.skip_ws();
                    if cur.eat(",") {
                        continue;
                    }
                    if cur.eat(")") {
                        break;
                    }
                    return Err(cur.error("`,` or `)` after a parameter name"));
                }
            }
            out.push(Pattern { sym, arity, slot });
        }
    }

    fn production(&mut self, start: usize, end: usize) -> PResult<()> {
        let text = &self.text[start..end];
        let Some((arrow, arrow_len)) = find_arrow(text) else {
            return Err(self.err(
                start,
                "a production with `-->` or a directive such as `Axiom:` or `derivation length:`",
            ));
        };
        let (arrow, after) = (start + arrow, start + arrow + arrow_len);
        // Left side: [lc <] pred [> rc] [: [{pre}] [condition] [{post}]]
        let left = &self.text[start..arrow];
        let colon = top_level(left, b':').map(|i| start + i);
        let pred_end = colon.unwrap_or(arrow);
        let pred_text = &self.text[start..pred_end];
        let lt = top_level(pred_text, b'<').map(|i| start + i);
        let gt = top_level_last(pred_text, b'>').map(|i| start + i);
        let (lc_range, pred_range, rc_range) = match (lt, gt) {
            (Some(l), Some(g)) if g > l => ((start, l), (l + 1, g), (g + 1, pred_end)),
            (Some(l), None) => ((start, l), (l + 1, pred_end), (pred_end, pred_end)),
            (None, Some(g)) => ((start, start), (start, g), (g + 1, pred_end)),
            (None, None) => ((start, start), (start, pred_end), (pred_end, pred_end)),
            (Some(_), Some(g)) => return Err(self.err(g, "`<` before `>` in the context")),
        };
        let mut names = Vec::new();
        let left_ctx = self.patterns(
            &mut Cursor::range(self.text, lc_range.0, lc_range.1),
            &mut names,
            false,
        )?;
        let pred = self.patterns(
            &mut Cursor::range(self.text, pred_range.0, pred_range.1),
            &mut names,
            true,
        )?;
        let right_ctx = self.patterns(
            &mut Cursor::range(self.text, rc_range.0, rc_range.1),
            &mut names,
            true,
        )?;
        let (pred, pred_rest) = match pred.split_first() {
            Some((p, rest)) => (*p, rest.to_vec()),
            None => return Err(self.err(pred_range.0, "a predecessor module before `-->`")),
        };
        if pred_rest.is_empty()
            && (pred.sym == PUSH || pred.sym == POP)
            && self.section != Section::Homomorphism
        {
            return Err(self.msg(
                pred_range.0,
                "a bracket alone as a predecessor is rewritten only by interpretation rules",
            ));
        }
        let mut scope_names = names.clone();
        let (mut pre, mut post, mut condition) = (Vec::new(), Vec::new(), None);
        if let Some(c) = colon {
            let mut cur = Cursor::range(self.text, c + 1, arrow);
            cur.skip_ws();
            if cur.peek_str("{") {
                pre = self.statements(&mut cur, &scope_names)?;
                cur.skip_ws();
            }
            let star = cur.peek_str("*") && {
                let mut probe = cur.clone();
                probe.eat("*");
                probe.skip_ws();
                probe.at_end() || probe.peek_str("{")
            };
            if star {
                cur.eat("*");
            } else if !cur.at_end() && !cur.peek_str("{") {
                let scope = Scope {
                    params: &scope_names,
                    defines: &self.defines,
                    globals: Some(&self.globals),
                };
                condition = Some(expr::compile(&mut cur, &scope)?);
            }
            cur.skip_ws();
            if cur.peek_str("{") {
                post = self.statements(&mut cur, &scope_names)?;
                cur.skip_ws();
            }
            if !cur.at_end() {
                return Err(cur.error("`-->` after the condition"));
            }
        }
        scope_names.truncate(names.len());
        let mut cur = Cursor::range(self.text, after, end);
        // Interpretation rules feed only the turtle, so they may open or close a branch
        // (`[ --> [+`); strings that are derived further must stay balanced.
        let interpretation = self.section == Section::Homomorphism;
        let successor_at = cur.pos();
        let mut successor = self.module_list(&mut cur, &scope_names, true, !interpretation)?;
        let line = super::syntax::line_col(self.text, start).0;
        successor.line = super::syntax::line_col(self.text, successor_at).0;
        let probability = if cur.eat(":") {
            let scope = Scope {
                params: &scope_names,
                defines: &self.defines,
                globals: Some(&self.globals),
            };
            cur.skip_ws();
            let at = cur.pos();
            let e = expr::compile(&mut cur, &scope)?;
            cur.skip_ws();
            if !cur.at_end() {
                return Err(cur.error("the end of the production after its probability"));
            }
            if let Some(v) = e.as_const() {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(self.err(at, "a finite probability >= 0"));
                }
            }
            Some(e)
        } else {
            None
        };
        if self.section != Section::Productions && (!left_ctx.is_empty() || !right_ctx.is_empty()) {
            return Err(self.msg(
                start,
                "context in homomorphism or decomposition rules is not supported",
            ));
        }
        let production = Production {
            pred,
            pred_rest,
            pre,
            post,
            left: left_ctx,
            right: right_ctx,
            condition,
            successor,
            probability,
            slots: names.len(),
            line,
        };
        match self.section {
            Section::Productions => self.productions.productions.push(production),
            Section::Homomorphism => self.homomorphism.productions.push(production),
            Section::Decomposition => self.decomposition.productions.push(production),
        }
        Ok(())
    }

    fn statements(&self, cur: &mut Cursor<'_>, names: &[(String, u16)]) -> PResult<Vec<Stmt>> {
        let scope = Scope {
            params: names,
            defines: &self.defines,
            globals: Some(&self.globals),
        };
        stmt::block(cur, &scope)
    }
}

/// Open parentheses and statement braces of a production or directive being read.
#[derive(Default)]
struct Depth {
    parens: i64,
    braces: i64,
    arrow: bool,
    quoted: bool,
}

impl Depth {
    fn scan(&mut self, s: &str) {
        let b = s.as_bytes();
        for (i, &c) in b.iter().enumerate() {
            match c {
                b'"' => self.quoted = !self.quoted,
                _ if self.quoted => {}
                b'(' => self.parens += 1,
                b')' => self.parens -= 1,
                b'{' if !self.arrow => self.braces += 1,
                b'}' if !self.arrow => self.braces -= 1,
                b'-' if self.parens <= 0 && self.braces <= 0 && b[i..].starts_with(b"->") => {
                    self.arrow = true
                }
                b'-' if self.parens <= 0 && self.braces <= 0 && b[i..].starts_with(b"-->") => {
                    self.arrow = true
                }
                _ => {}
            }
        }
    }
}

/// Depth of parentheses and braces before each byte of `s`, strings skipped: calls
/// `visit(i, byte)` for every byte outside both and outside string literals.
fn scan_top(s: &str, mut visit: impl FnMut(usize, u8) -> bool) {
    let b = s.as_bytes();
    let (mut depth, mut quoted) = (0i64, false);
    for (i, &c) in b.iter().enumerate() {
        match c {
            b'"' => quoted = !quoted,
            _ if quoted => {}
            b'(' | b'{' => depth += 1,
            b')' | b'}' => depth -= 1,
            _ if depth == 0 && !visit(i, c) => return,
            _ => {}
        }
    }
}

/// The first `-->` or `->` outside parentheses, braces and strings: (offset, length).
fn find_arrow(s: &str) -> Option<(usize, usize)> {
    let b = s.as_bytes();
    let mut found = None;
    scan_top(s, |i, c| {
        if c == b'-' {
            if b[i..].starts_with(b"-->") {
                found = Some((i, 3));
                return false;
            }
            if b[i..].starts_with(b"->") {
                found = Some((i, 2));
                return false;
            }
        }
        true
    });
    found
}

fn top_level(s: &str, target: u8) -> Option<usize> {
    let mut found = None;
    scan_top(s, |i, c| {
        if c == target {
            found = Some(i);
            return false;
        }
        true
    });
    found
}

fn top_level_last(s: &str, target: u8) -> Option<usize> {
    let mut found = None;
    scan_top(s, |i, c| {
        if c == target {
            found = Some(i);
        }
        true
    });
    found
}

fn skip_string(cur: &mut Cursor<'_>) -> PResult<()> {
    cur.eat("\"");
    loop {
        match cur.bump() {
            Some('"') => return Ok(()),
            Some('\\') => {
                cur.bump();
            }
            Some(_) => {}
            None => return Err(cur.error("`\"` closing the text")),
        }
    }
}
