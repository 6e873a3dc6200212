//! Reading grammar text in the cpfg language into an [`LSystem`].

mod header;
mod productions;
mod scan;

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
use scan::Depth;
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
    let folder = !matches!(includes, Includes::None);
    let pre = preprocess(source, name, includes)?;
    let ls = parse_text(&pre.text, names).map_err(|e| pre.map_error(e))?;
    // Text without a folder has no data files to look for.
    if let (false, Some((file, at))) = (folder, ls.globals.reads.first()) {
        let (line, column) = line_col(&pre.text, *at);
        return Err(pre.map_error(Error::Parse {
            line,
            column,
            message: format!(
                "fopen(\"{file}\", \"r\"): the grammar reads a data file, and text has no \
                 folder to read it from; read the model from its file"
            ),
        }));
    }
    Ok(ls)
}

/// The data files a grammar read from `dir` opens (`fopen(name, "r")`): a missing one is
/// what cpfg goes on without (its `fscanf` reads nothing), so it is a warning; one that is
/// there is refused, since arbor does not read data files' values yet.
fn data_files(
    ls: &mut LSystem,
    dir: &std::path::Path,
    exists: &dyn Fn(&std::path::Path) -> bool,
) -> Result<()> {
    for (file, _) in ls.globals.reads.clone() {
        if exists(&dir.join(&file)) {
            return Err(Error::invalid(
                "path",
                format!(
                    "fopen(\"{file}\", \"r\"): the grammar reads its values from `{file}`, a \
                     data file, which arbor does not read"
                ),
            ));
        }
        ls.warnings.push(format!(
            "fopen(\"{file}\", \"r\"): `{file}` is not there; as in cpfg, fscanf from it \
             reads nothing and the model runs with its variables as they are"
        ));
    }
    Ok(())
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
        mut symbols,
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
    prefixed_productions(&mut symbols, &mut productions);
    prefixed_productions(&mut symbols, &mut decomposition);
    let n = symbols.len();
    productions.index(n);
    homomorphism.index(n);
    decomposition.index(n);
    // Context matching skips ignored symbols: those listed by `ignore:`, or all but those
    // listed by `consider:`. A bracket's flag matters only to a right context, which (as
    // cpfg's) asks whether a module is ignored before whether it is a bracket.
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

/// cpfg keeps `~l(s)` and `@o(r)` as two modules (`~` then `l(s)`), so productions for
/// `l` and `o` rewrite what follows a `~` or `@`. For each symbol `~X` or `@X` of the
/// grammar whose X has productions of one module: copies of them for it, the prefix kept
/// in front of the successor's first module (`~l(s) --> l(2s)` gives `~l(2s)`; a first
/// module of several characters, or none, gets the prefix as a module of its own).
fn prefixed_productions(symbols: &mut Symbols, table: &mut ProductionTable) {
    let mut added = Vec::new();
    for id in 0..symbols.len() {
        let mut chars = symbols.names[id].chars();
        let (Some(prefix @ ('~' | '@')), Some(x), None) =
            (chars.next(), chars.next(), chars.next())
        else {
            continue;
        };
        let Some(target) = symbols.get(x.encode_utf8(&mut [0; 4])) else {
            continue;
        };
        let own: Vec<Production> = table
            .productions
            .iter()
            .filter(|p| p.pred.sym == target && p.pred_rest.is_empty())
            .cloned()
            .collect();
        for mut p in own {
            p.pred.sym = id as u16;
            let first = p.successor.modules.first().map(|m| m.sym);
            let merged = first.and_then(|s| {
                let name = &symbols.names[s as usize];
                (name.chars().count() == 1).then(|| format!("{prefix}{name}"))
            });
            match merged.and_then(|name| symbols.intern(&name)) {
                Some(sym) => p.successor.modules[0].sym = sym,
                None => {
                    let Some(sym) = symbols.intern(prefix.encode_utf8(&mut [0; 4])) else {
                        continue;
                    };
                    p.successor.modules.insert(
                        0,
                        SuccModule {
                            sym,
                            first: 0,
                            count: 0,
                        },
                    );
                }
            }
            p.successor.finish();
            added.push(p);
        }
    }
    table.productions.extend(added);
}

/// The grammar and view file of a vlab object at `folder` (a folder, or under the host's
/// reader a path without an extension): those its `specifications` passes to `cpfg` in
/// its `model:` command (`cpfg -M plant.mat plant.l plant.v plant.a`), else the first
/// `.l` and `.v` it lists. `None` when `folder` is a file.
fn vlab_object(
    folder: &std::path::Path,
    read: &dyn Fn(&std::path::Path) -> Result<String>,
) -> Result<Option<(std::path::PathBuf, Option<std::path::PathBuf>)>> {
    if !(folder.is_dir() || (folder.extension().is_none() && !folder.exists())) {
        return Ok(None);
    }
    let specs = folder.join("specifications");
    let text = match read(&specs) {
        Ok(text) => text,
        Err(_) if !folder.is_dir() => return Ok(None),
        Err(e) => return Err(e),
    };
    let words =
        |line: &str| -> Vec<String> { line.split_whitespace().map(str::to_string).collect() };
    // The files the cpfg command passes, else the files listed at the top.
    let command = text
        .lines()
        .map(words)
        .find(|w| w.first().is_some_and(|c| c == "cpfg"));
    let listed: Vec<String> = text
        .lines()
        .take_while(|l| !l.trim_end().ends_with(':'))
        .flat_map(words)
        .collect();
    let names = command.unwrap_or(listed);
    let pick = |ext: &str| {
        names
            .iter()
            .find(|w| w.ends_with(ext))
            .map(|w| folder.join(w))
    };
    let Some(grammar) = pick(".l") else {
        return Err(Error::invalid(
            "path",
            format!(
                "`{}` is a folder whose `specifications` names no `.l` file (a vlab object \
                 lists its grammar there)",
                folder.display()
            ),
        ));
    };
    Ok(Some((grammar, pick(".v"))))
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
    // A vlab object: its folder, whose `specifications` names the grammar and view file.
    let object = vlab_object(path, &|p| read(p, "vlab object's specifications"))?;
    let (path, view) = match &object {
        Some((l, v)) => (l.as_path(), view.or(v.as_deref())),
        None => (path, view),
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
    let mut ls = parse_named(&text, &name, Includes::Dir(dir.clone(), &loader), &names)?;
    data_files(&mut ls, &dir, &|p| loader.exists(p))?;
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
    pub(super) fn run(&mut self) -> PResult<()> {
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

    pub(super) fn err(&self, pos: usize, expected: &str) -> PErr {
        Cursor::range(self.text, pos, self.text.len()).error_at(pos, expected)
    }

    pub(super) fn msg(&self, pos: usize, message: &str) -> PErr {
        Cursor::new(self.text).message_at(pos, message)
    }

    /// `{ statements }` filling the rest of the line (a `Start:` block and the like).
    pub(super) fn block(&mut self, pos: usize, end: usize) -> PResult<Vec<Stmt>> {
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
}
