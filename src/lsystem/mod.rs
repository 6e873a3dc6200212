//! Parametric L-systems in the language of cpfg: parse → derive → interpret.
//!
//! ```
//! use arbor::lsystem::{LSystem, LsystemOptions};
//!
//! let grammar = LSystem::parse(
//!     "Lsystem: 1\n derivation length: 3\n Axiom: F\n F --> F[+F]F[-F]F\n endlsystem",
//! )?;
//! let options = LsystemOptions::default();
//! let string = grammar.derive(&options)?;
//! // 5^3 = 125 F's and 6 other modules for each F rewritten: 6 · (1 + 5 + 25) = 186.
//! assert_eq!(string.len(), 125 + 186);
//! let skeleton = grammar.interpret(&string, &options)?;
//! assert_eq!(skeleton.len(), 125); // 5^3 F's
//! # Ok::<(), arbor::Error>(())
//! ```

mod builtins;
mod ctx;
mod d0l;
pub(crate) mod derive;
mod expr;
mod function_files;
pub(crate) mod grammar;
mod interpret;
mod links;
mod parse;
pub(crate) mod preprocess;
mod query;
mod random;
mod rewrite;
mod stmt;
pub(crate) mod surface;
mod syntax;
mod view;

pub use grammar::{OldTropism, ViewSettings};
pub use syntax::MAX_SOURCE_BYTES;

use crate::error::{Error, Result};
use crate::progress::Run;
use crate::skeleton::Skeleton;
use grammar::{ModuleList, ProductionTable, Symbols};

pub use crate::limits::DEFAULT_MAX_MODULES;
pub use crate::limits::DEFAULT_MAX_PARAMS;

crate::options::options! {
/// Options of [`LSystem::derive`] and [`LSystem::interpret`]. `Default` gives the
/// documented defaults; the settings given here override the grammar's directives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LsystemOptions {
    /// Rewriting steps; `None`: the grammar's `derivation length:` (0 if it has none).
    pub steps: Option<u32> = None,
    /// Seed of stochastic productions, `ran` and `nran`, used when the grammar has no
    /// `seed:`. Default 0.
    pub seed: u64 = 0,
    /// Derivation stops with `LimitExceeded` before a string would pass this many modules;
    /// the same limit bounds the modules the turtle reads after interpretation rules.
    /// Default [`DEFAULT_MAX_MODULES`].
    pub max_modules: usize = DEFAULT_MAX_MODULES,
    /// Derivation stops with `LimitExceeded` before a string would hold more parameter
    /// values than this (at most 2^32 − 1). Default [`DEFAULT_MAX_PARAMS`].
    pub max_params: usize = DEFAULT_MAX_PARAMS,
    /// Interpretation stops with `LimitExceeded` past this many branches. Default
    /// [`crate::limits::DEFAULT_MAX_BRANCHES`].
    pub max_branches: usize = crate::limits::DEFAULT_MAX_BRANCHES,
    /// Overrides `angle increment:` (degrees).
    pub angle_increment: Option<f64> = None,
    /// Overrides `initial line width:`.
    pub initial_width: Option<f64> = None,
    /// Overrides `line width increment:`.
    pub width_increment: Option<f64> = None,
    /// Each turn of `+ - & ^ / \` is off by a random amount up to ± this many degrees,
    /// the way hand-made stochastic tree grammars vary their plants (seeded by the
    /// grammar's `seed:` or `seed`). Default 0.
    pub turn_jitter: f64 = 0.0, checked AtLeast(0.0), "a finite angle >= 0",
    /// 0 (default): the plant's seed is the grammar's `seed:` (else `seed`), as written.
    /// Otherwise this value is mixed into that seed, so every value grows a distinct plant
    /// even from a grammar that fixes its own `seed:` (what a forest of one stochastic
    /// grammar needs): see [`LSystem::effective_seed`].
    pub variation_seed: u64 = 0,
    /// One work budget, in units, for everything a derivation and its interpretation do
    /// (a bound on time, where `max_modules` bounds memory): each step's modules and
    /// parameters, each production tried (its predecessor, context, condition and
    /// probability expressions) and each successor made, decomposition and
    /// interpretation rules, statements and their loops, query answers, and the turtle's
    /// reading of what interpretation rules make. Past it the work stops with
    /// `LimitExceeded` naming `max_work`; a progress callback hears the work every 2^20
    /// units. Default [`DEFAULT_MAX_WORK`](crate::limits::DEFAULT_MAX_WORK).
    pub max_work: usize = crate::limits::DEFAULT_MAX_WORK,
}
}

impl LsystemOptions {
    /// Refuses options the turtle cannot use, naming the first (a jitter or an angle,
    /// width or width increment that is not finite, or is negative where it must not be).
    pub fn validate(&self) -> Result<()> {
        let options = self;
        options.check_fields()?;
        for (field, v) in [
            ("angle_increment", options.angle_increment),
            ("initial_width", options.initial_width),
            ("width_increment", options.width_increment),
        ] {
            if let Some(v) = v {
                if !v.is_finite() || (field != "angle_increment" && v < 0.0) {
                    return Err(Error::invalid(
                        field,
                        format!("{v}; expected a finite number >= 0"),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// A parsed and compiled grammar.
#[derive(Clone, Debug)]
pub struct LSystem {
    pub(crate) symbols: Symbols,
    pub(crate) axiom: ModuleList,
    pub(crate) derivation_length: u32,
    pub(crate) seed: Option<u64>,
    pub(crate) productions: ProductionTable,
    pub(crate) homomorphism: ProductionTable,
    pub(crate) decomposition: ProductionTable,
    /// Per symbol: skipped when matching context (`ignore:` / `consider:`).
    pub(crate) skip: Vec<bool>,
    pub(crate) view: ViewSettings,
    pub(crate) has_context: bool,
    pub(crate) has_cut: bool,
    /// The lookup table of a grammar without parameters, contexts, conditions,
    /// probabilities, cuts or decomposition.
    pub(crate) d0l: Option<d0l::D0l>,
    /// Which grammar this is (unique per parse; clones keep it): the strings it derives
    /// carry it, so one is never read with another grammar's symbol table.
    pub(crate) id: u64,
    /// Global variables and arrays.
    pub(crate) globals: expr::Globals,
    pub(crate) blocks: grammar::Blocks,
    /// The view file's functions (`func(id, x)`).
    pub(crate) functions: std::sync::Arc<[function_files::Function]>,
    /// The view file's surfaces (`~x`).
    pub(crate) surfaces: std::sync::Arc<[surface::Surface]>,
    /// What reading the files skipped (a surface file that is missing, ...).
    pub(crate) warnings: Vec<String>,
    /// `ring lsystem`: context wraps from the string's end to its start.
    pub(crate) ring: bool,
    /// The view file's curves (`curveX(id, t)` and the like).
    pub(crate) curves: std::sync::Arc<[function_files::Curve]>,
}

/// Ids of parsed grammars (0 is no grammar).
static NEXT_GRAMMAR_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

impl LSystem {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        symbols: Symbols,
        axiom: ModuleList,
        derivation_length: u32,
        seed: Option<u64>,
        productions: ProductionTable,
        homomorphism: ProductionTable,
        decomposition: ProductionTable,
        skip: Vec<bool>,
        view: ViewSettings,
        globals: expr::Globals,
        blocks: grammar::Blocks,
    ) -> Self {
        let has_context = productions
            .productions
            .iter()
            .any(|p| !p.left.is_empty() || !p.right.is_empty());
        let has_statements = !blocks.is_empty()
            || [&productions, &homomorphism, &decomposition]
                .iter()
                .any(|t| {
                    t.productions
                        .iter()
                        .any(|p| !p.pre.is_empty() || !p.post.is_empty() || !p.pred_rest.is_empty())
                });
        let cut = grammar::CUT;
        let has_cut = axiom.modules.iter().any(|m| m.sym == cut)
            || [&productions, &decomposition].iter().any(|t| {
                t.productions
                    .iter()
                    .any(|p| p.successor.modules.iter().any(|m| m.sym == cut))
            });
        // Under `seed:` cpfg draws among all applicable productions of a symbol, so one
        // with two or more plain productions needs the general rewriter.
        let drawn = seed.is_some() && {
            let mut seen = vec![false; symbols.len()];
            productions
                .productions
                .iter()
                .any(|p| std::mem::replace(&mut seen[p.pred.sym as usize], true))
        };
        let d0l = if has_statements || drawn || !globals.init.is_empty() {
            None
        } else {
            d0l::D0l::new(&axiom, &productions, &decomposition, has_cut, symbols.len())
        };
        LSystem {
            d0l,
            id: NEXT_GRAMMAR_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            symbols,
            axiom,
            derivation_length,
            seed,
            productions,
            homomorphism,
            decomposition,
            skip,
            view,
            has_context,
            has_cut,
            globals,
            blocks,
            functions: Vec::new().into(),
            surfaces: Vec::new().into(),
            warnings: Vec::new(),
            ring: false,
            curves: Vec::new().into(),
        }
    }

    /// What reading the grammar and its view file skipped without failing (a surface
    /// file that is missing leaves its `~x` a plain leaf site).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Parses grammar text in the cpfg language (see `GRAMMAR.md`). Errors are
    /// [`crate::error::Error::Parse`] with line, column and what was expected.
    pub fn parse(source: &str) -> Result<Self> {
        parse::parse(source)
    }

    /// Reads an L-system file as cpfg does: preprocessed (`#include` relative to its
    /// folder), with its view file: `view` if given, else the `.v` file beside it with the
    /// same stem, else none. Errors name the file and line.
    ///
    /// The model may read the files of its own folder, at most
    /// [`DEFAULT_MAX_FILE_BYTES`](crate::files::DEFAULT_MAX_FILE_BYTES) in all
    /// ([`FileAccess::Bundle`](crate::files::FileAccess::Bundle)); see
    /// [`from_file_with`](Self::from_file_with) for other policies.
    pub fn from_file(
        path: impl AsRef<std::path::Path>,
        view: Option<&std::path::Path>,
    ) -> Result<Self> {
        parse::parse_file(
            path.as_ref(),
            view,
            &crate::files::FileOptions::default(),
            None,
        )
    }

    /// [`from_file`](Self::from_file) under a file policy and byte budget (see
    /// [`crate::files`]), in `run`: it hears [`Stage::Load`](crate::progress::Stage::Load)
    /// while the files are read and preprocessed (the callback may cancel). The host names `path` and
    /// `view`, so they are read under every policy (through the host's reader under
    /// [`FileAccess::Host`](crate::files::FileAccess::Host)); what they name
    /// (`#include`, `function:`, `curve:`, `surface:`, the `.v` file beside the grammar)
    /// is read only as the policy allows.
    pub fn from_file_with(
        path: impl AsRef<std::path::Path>,
        view: Option<&std::path::Path>,
        files: &crate::files::FileOptions,
        run: &mut Run<'_>,
    ) -> Result<Self> {
        parse::parse_file(path.as_ref(), view, files, run.callback())
    }

    /// Parses grammar text with the text of its view file (`.v`): the view file's
    /// settings (angle factor or increment, line widths, tropism) apply as cpfg applies
    /// them. `#include` is refused in text without a folder.
    pub fn parse_with_view(source: &str, view: &str) -> Result<Self> {
        let mut settings = ViewSettings::default();
        let extras = view::apply(&mut settings, view, "", preprocess::Includes::None)?;
        let mut ls = parse::parse(source)?;
        parse::merge_view(&mut ls.view, &settings);
        ls.functions = extras.functions.into();
        ls.surfaces = extras.surfaces.into();
        ls.warnings.extend(extras.warnings);
        ls.curves = extras.curves.into();
        Ok(ls)
    }

    /// The grammar's `derivation length:` (0 when it has none).
    pub fn derivation_length(&self) -> u32 {
        self.derivation_length
    }

    /// The seed a derivation with `options` uses: the grammar's `seed:` (else
    /// `options.seed`), with `options.variation_seed` mixed in when it is not 0.
    pub fn effective_seed(&self, options: &LsystemOptions) -> u64 {
        let base = self.seed.unwrap_or(options.seed);
        match options.variation_seed {
            0 => base,
            v => crate::rng::Rng::new(base ^ v.rotate_left(32)).next_u64(),
        }
    }

    /// The grammar's `seed:`, if it has one.
    pub fn seed(&self) -> Option<u64> {
        self.seed
    }

    /// The turtle settings the grammar's directives gave.
    pub fn view(&self) -> &ViewSettings {
        &self.view
    }

    /// The name of symbol `id` of a [`ModuleString`] derived from this grammar.
    pub fn symbol_name(&self, id: u16) -> &str {
        &self.symbols.names[id as usize]
    }

    /// Rewrites the axiom `steps` times in parallel. The same grammar, seed and options
    /// give the same string on every run.
    pub fn derive(&self, options: &LsystemOptions) -> Result<ModuleString> {
        derive::derive(self, options, Run::default())
    }

    /// [`derive`](Self::derive) in `run`, reporting
    /// [`Stage::Derivation`](crate::progress::Stage) at every step and every 65,536 modules
    /// within one; `false` stops with [`Error::Cancelled`].
    pub fn derive_in(&self, options: &LsystemOptions, run: &mut Run<'_>) -> Result<ModuleString> {
        derive::derive(self, options, Run::new(run.callback()))
    }

    /// [`interpret`](Self::interpret) in `run`, reporting
    /// [`Stage::Interpretation`](crate::progress::Stage) every 65,536 modules.
    pub fn interpret_in(
        &self,
        string: &ModuleString,
        options: &LsystemOptions,
        run: &mut Run<'_>,
    ) -> Result<Skeleton> {
        self.check_string(string)?;
        interpret::interpret_with(self, string, options, Run::new(run.callback()))
    }

    /// [`skeleton`](Self::skeleton) in `run`: one callback hears both stages.
    pub fn skeleton_in(&self, options: &LsystemOptions, run: &mut Run<'_>) -> Result<Skeleton> {
        let string = self.derive_in(options, run)?;
        self.interpret_in(&string, options, run)
    }

    /// A string of another grammar is refused: its symbols are numbers in that grammar's
    /// table.
    fn check_string(&self, string: &ModuleString) -> Result<()> {
        if string.grammar != self.id {
            return Err(crate::error::Error::invalid(
                "string",
                "derived from another grammar; interpret a string with the grammar that derived it",
            ));
        }
        Ok(())
    }

    /// Reads `string` with the 3-D turtle (applying interpretation rules) into a skeleton.
    ///
    /// `string` must come from [`derive`](Self::derive) of this grammar (or a clone of
    /// it): its symbols are numbers in this grammar's table, so a string of another
    /// grammar is refused with [`Error::InvalidArgument`].
    pub fn interpret(&self, string: &ModuleString, options: &LsystemOptions) -> Result<Skeleton> {
        self.interpret_in(string, options, &mut Run::default())
    }

    /// [`derive`](Self::derive), then [`interpret`](Self::interpret).
    pub fn skeleton(&self, options: &LsystemOptions) -> Result<Skeleton> {
        let string = self.derive(options)?;
        self.interpret(&string, options)
    }

    /// `string` as text, e.g. `F(1)[+(25)A(0.5,2)]`: numbers printed shortest, modules
    /// without separators.
    pub fn format(&self, string: &ModuleString) -> String {
        let mut out = String::new();
        for i in 0..string.len() {
            out.push_str(self.symbol_name(string.symbol(i)));
            let params = string.params(i);
            if !params.is_empty() {
                out.push('(');
                for (k, v) in params.iter().enumerate() {
                    if k > 0 {
                        out.push(',');
                    }
                    out.push_str(&v.to_string());
                }
                out.push(')');
            }
        }
        out
    }
}

/// A derived string: flat arrays of symbols, birth steps and parameters.
///
/// Parameters are stored as `f32`, as cpfg stores them; expressions evaluate in `f64`.
/// A string whose grammar has no parameters at all keeps 4 bytes per module (symbol and
/// birth step) and no offsets.
#[derive(Clone, Debug, Default)]
pub struct ModuleString {
    pub(crate) syms: Vec<u16>,
    pub(crate) births: Vec<u16>,
    /// `offsets[i]..offsets[i + 1]` are module i's parameters; `offsets[0] = 0`. Empty
    /// when no module has parameters (a string without parameters skips them).
    pub(crate) offsets: Vec<u32>,
    pub(crate) params: Vec<f32>,
    /// The id of the grammar that derived it (0: none).
    pub(crate) grammar: u64,
    /// The global variables after the derivation (read by interpretation rules).
    pub(crate) globals: Vec<f64>,
    /// What the grammar's `printf` statements wrote (at most 64 KiB).
    pub(crate) log: String,
    /// The work budget its derivation left (`max_work` less what it spent): the
    /// interpretation rules that read it spend from the rest.
    pub(crate) work_left: Option<u64>,
}

impl PartialEq for ModuleString {
    /// Equal modules (symbols, births, parameters), whether or not offsets are kept.
    fn eq(&self, other: &Self) -> bool {
        self.syms == other.syms
            && self.births == other.births
            && self.params == other.params
            && (self.params.is_empty() || self.offsets == other.offsets)
    }
}

impl ModuleString {
    /// What the grammar's `printf` statements wrote while deriving it (at most 64 KiB).
    pub fn log(&self) -> &str {
        &self.log
    }

    pub(crate) fn new() -> Self {
        ModuleString {
            offsets: vec![0],
            ..Default::default()
        }
    }

    /// Makes room for `modules` modules and `params` values in total (a guess of the next
    /// step's size), or `OutOfMemory`.
    pub(crate) fn reserve(&mut self, modules: usize, params: usize) -> crate::error::Result<()> {
        self.try_room(
            modules.saturating_sub(self.len()),
            params.saturating_sub(self.params.len()),
        )
    }

    /// Makes room for `modules` more modules and `params` more values (growing as `push`
    /// would, amortized), or `OutOfMemory` naming the string's size, instead of aborting.
    #[inline]
    pub(crate) fn try_room(&mut self, modules: usize, params: usize) -> crate::error::Result<()> {
        // The common case, inline: there is room already.
        let spare = |cap: usize, len: usize| cap - len;
        if spare(self.syms.capacity(), self.syms.len()) >= modules
            && spare(self.births.capacity(), self.births.len()) >= modules
            && spare(self.offsets.capacity(), self.offsets.len()) >= modules
            && spare(self.params.capacity(), self.params.len()) >= params
        {
            return Ok(());
        }
        self.grow(modules, params)
    }

    #[cold]
    #[inline(never)]
    fn grow(&mut self, modules: usize, params: usize) -> crate::error::Result<()> {
        use crate::limits::Room;
        let ok = self.syms.room(modules, false)
            && self.births.room(modules, false)
            && self.offsets.room(modules, false)
            && self.params.room(params, false);
        if ok {
            Ok(())
        } else {
            Err(self.out_of_memory(modules, params))
        }
    }

    /// Room for exactly `modules` more modules without parameters (bracketed strings), or
    /// `OutOfMemory`.
    pub(crate) fn try_exact(&mut self, modules: usize) -> crate::error::Result<()> {
        let (len, params) = (self.len(), self.params.len());
        crate::limits::try_room(
            &mut [&mut self.syms, &mut self.births],
            modules,
            true,
            || Self::describe(len + modules, params),
        )
    }

    #[cold]
    fn out_of_memory(&self, modules: usize, params: usize) -> crate::error::Error {
        crate::error::Error::OutOfMemory {
            what: Self::describe(
                self.len().saturating_add(modules),
                self.params.len().saturating_add(params),
            ),
        }
    }

    fn describe(modules: usize, params: usize) -> String {
        format!("the module string ({modules} modules, {params} parameter values)")
    }

    pub(crate) fn clear(&mut self) {
        self.syms.clear();
        self.births.clear();
        self.offsets.clear();
        self.offsets.push(0);
        self.params.clear();
    }

    /// Number of modules.
    #[inline]
    pub fn len(&self) -> usize {
        self.syms.len()
    }

    /// Whether there are no modules.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.syms.is_empty()
    }

    /// Symbol id of module `i` (see [`LSystem::symbol_name`]).
    #[inline]
    pub fn symbol(&self, i: usize) -> u16 {
        self.syms[i]
    }

    /// Parameters of module `i`.
    #[inline]
    pub fn params(&self, i: usize) -> &[f32] {
        if self.offsets.is_empty() {
            assert!(i < self.syms.len(), "module {i} of {}", self.syms.len());
            return &[];
        }
        &self.params[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// The rewriting step that produced module `i` (axiom modules: 0).
    #[inline]
    pub fn birth(&self, i: usize) -> u32 {
        self.births[i] as u32
    }

    /// Total number of parameter values.
    pub fn param_count(&self) -> usize {
        self.params.len()
    }

    #[inline]
    pub(crate) fn push(&mut self, sym: u16, birth: u16, params: &[f32]) {
        self.syms.push(sym);
        self.births.push(birth);
        self.params.extend_from_slice(params);
        self.offsets.push(self.params.len() as u32);
    }
}
