//! What a derivation step needs besides the strings: the grammar, the random stream and
//! globals, the limits and the budget, and the evaluation of successors into a string.

use super::expr::Env;
use super::grammar::ModuleList;
use super::random::{Choice, Random};
use super::stmt::{self, Effects, Stmt};
use super::{LSystem, LsystemOptions, ModuleString};
use crate::error::{Error, Result};
use crate::rng::Drand48;

/// The least work a derivation step spends against `max_work`, however short its string:
/// so `max_work` bounds the number of steps too (2^28 / 64 = 4,194,304 by default).
pub(crate) const STEP_WORK: usize = 64;

/// The birth a module made in `step` records: the step, or 65,535 for every step past it.
#[inline]
pub(crate) fn birth(step: u32) -> u16 {
    step.min(u16::MAX as u32) as u16
}

/// Everything a step needs besides the strings.
pub(crate) struct Ctx<'a> {
    pub(crate) ls: &'a LSystem,
    /// The random stream and the global variables.
    pub(crate) env: Env,
    /// The work budget, the statements' log and `stop()`, and the caller's progress
    /// callback (`fx.progress`).
    pub(crate) fx: Effects<'a>,
    /// The line of the production whose statements are running (for messages).
    pub(super) line: u32,
    /// Steps of the derivation (for the fraction reported).
    pub(super) steps: u32,
    pub(crate) max_modules: usize,
    pub(crate) max_params: usize,
    /// The work budget all steps together may spend (`LsystemOptions::max_work`).
    pub(crate) max_work: u64,
    pub(crate) step: u32,
    /// Bound parameter values of the production being tried.
    pub(super) args: Vec<f64>,
    /// Stochastic candidates: (production index, offset of its args in `cand_args`,
    /// weight).
    pub(super) cands: Vec<(u32, usize, f64)>,
    pub(super) cand_args: Vec<f64>,
    /// How the productions (not the interpretation or decomposition rules) are chosen.
    pub(super) choice: Choice,
    /// cpfg's drand48 stream of stochastic productions (seed48 of `seed:`).
    pub(super) draws: Drand48,
    /// Per symbol, the modules cpfg's string holds for it, one a character (`@Gt(1)` is
    /// `@`, `G`, `t(1)`): cpfg draws once for each. Empty unless the choice is weighted.
    pub(super) chars: Vec<u32>,
}

impl<'a> Ctx<'a> {
    /// cpfg's draws for the characters of `sym` that come before its last one (the last
    /// draws when its production is chosen).
    #[inline]
    pub(super) fn draw_prefix(&mut self, sym: u16) {
        for _ in 1..self.chars[sym as usize] {
            self.draws.next_f64();
        }
    }

    pub(crate) fn new(ls: &'a LSystem, options: &LsystemOptions) -> Self {
        // cpfg's streams unless the host asks for a seed of its own (see
        // docs/grammars.md, "Random streams").
        let cpfg = options.variation_seed == 0 && (ls.seed.is_some() || options.seed == 0);
        let (random, choice) = match (cpfg, ls.seed) {
            (false, _) => (
                Random::Arbor(crate::rng::Rng::new(ls.effective_seed(options))),
                Choice::Arbor,
            ),
            (true, Some(_)) => (Random::cpfg(), Choice::Weighted),
            (true, None) => (Random::cpfg(), Choice::First),
        };
        // cpfg: `if (seed != 0) seed48({seed, 0, 155})`, the seed taken as a 16-bit word.
        let draws = match ls.seed {
            Some(s) if s != 0 => Drand48::from_words([s as u16, 0, 155]),
            _ => Drand48::initial(),
        };
        let mut env = Env::new(random, &ls.globals, ls.functions.clone());
        env.curves = ls.curves.clone();
        Ctx {
            ls,
            env,
            fx: Effects::with_budget(options.max_work as u64),
            line: 0,
            steps: 0,
            max_modules: options.max_modules,
            max_params: options.max_params.min(u32::MAX as usize),
            max_work: options.max_work as u64,
            step: 0,
            args: Vec::new(),
            cands: Vec::new(),
            cand_args: Vec::new(),
            chars: if choice == Choice::Weighted {
                ls.symbols
                    .names
                    .iter()
                    .map(|n| n.chars().count() as u32)
                    .collect()
            } else {
                Vec::new()
            },
            choice,
            draws,
        }
    }

    /// Spends `units` of work against `max_work` (a step's modules, before it runs).
    pub(crate) fn spend(&mut self, units: usize) -> Result<()> {
        if self.fx.spend(&mut self.env, units as u64) {
            return Ok(());
        }
        self.fault_error("the derivation")
    }

    /// Runs a block of statements without parameters (`Start:` and the like).
    pub(crate) fn run_block(&mut self, stmts: &[Stmt], what: &str) -> Result<()> {
        if stmts.is_empty() {
            return Ok(());
        }
        stmt::exec(stmts, &mut [], &mut self.env, &mut self.fx);
        self.check(what)
    }

    /// Turns a fault the statements or expressions noted into an error.
    #[inline]
    pub(crate) fn check(&mut self, what: &str) -> Result<()> {
        if self.env.fault.is_none() {
            return Ok(());
        }
        self.fault_error(what)
    }

    #[cold]
    #[inline(never)]
    fn fault_error(&mut self, what: &str) -> Result<()> {
        let Some(fault) = self.env.fault.take() else {
            return Ok(());
        };
        if fault == stmt::OVER_BUDGET {
            return Err(Error::LimitExceeded {
                limit_name: "max_work",
                what: "work units (rewriting, decomposition, interpretation rules, \
                       statements and queries together)",
                limit: self.max_work,
                requested: self.max_work.saturating_add(1),
                // The interpretation's context counts modules' births, not steps.
                step: (self.fx.stage == crate::progress::Stage::Derivation).then_some(self.step),
            });
        }
        if fault == stmt::CANCELLED {
            return Err(Error::Cancelled {
                stage: self.fx.stage.name(),
            });
        }
        let place = if self.line > 0 {
            format!("the production at line {}", self.line)
        } else {
            what.to_string()
        };
        Err(Error::Eval {
            step: self.step,
            message: format!("in {place}: {fault}"),
        })
    }

    pub(super) fn limit(
        &self,
        name: &'static str,
        what: &'static str,
        limit: usize,
        need: usize,
    ) -> Error {
        Error::LimitExceeded {
            limit_name: name,
            what,
            limit: limit as u64,
            requested: need as u64,
            step: Some(self.step),
        }
    }

    /// Checks that `out` can take `modules` more modules and `params` more values, within
    /// the limits and the memory there is (it grows `out` fallibly where it must).
    #[inline]
    pub(crate) fn room(&self, out: &mut ModuleString, modules: usize, params: usize) -> Result<()> {
        if out.len() + modules > self.max_modules {
            return Err(self.limit(
                "max_modules",
                "modules",
                self.max_modules,
                out.len() + modules,
            ));
        }
        if out.params.len() + params > self.max_params {
            return Err(self.limit(
                "max_params",
                "parameter values",
                self.max_params,
                out.params.len() + params,
            ));
        }
        out.try_room(modules, params)
    }
}

/// Evaluates `list` with bound `args` and appends it to `out` with birth `birth`: the
/// symbols, births and offsets in bulk, then the parameter values in text order.
#[inline]
pub(super) fn emit(
    ctx: &mut Ctx<'_>,
    list: &ModuleList,
    args: &[f64],
    birth: u16,
    out: &mut ModuleString,
) -> Result<()> {
    let n = list.syms.len();
    ctx.room(out, n, list.exprs.len())?;
    let base = out.params.len() as u32;
    if n <= 8 {
        // Most successors are a few modules: element by element (the room is there)
        // costs less than a library copy per array.
        for (&sym, &end) in list.syms.iter().zip(&list.param_ends) {
            out.syms.push(sym);
            out.births.push(birth);
            out.offsets.push(base + end);
        }
    } else {
        out.syms.extend_from_slice(&list.syms);
        out.births.extend(std::iter::repeat_n(birth, n));
        out.offsets
            .extend(list.param_ends.iter().map(|&e| base + e));
    }
    let mut bad = None;
    for (k, e) in list.exprs.iter().enumerate() {
        let v = e.eval(args, &mut ctx.env);
        let stored = v as f32;
        if !stored.is_finite() && bad.is_none() {
            bad = Some((k, v));
        }
        out.params.push(stored);
    }
    if let Some((k, v)) = bad {
        let m = list
            .modules
            .iter()
            .find(|m| (m.first + m.count) as usize > k)
            .expect("every parameter belongs to a module");
        return Err(non_finite(ctx, m.sym, v, list.line));
    }
    Ok(())
}

pub(super) fn non_finite(ctx: &Ctx<'_>, sym: u16, v: f64, line: u32) -> Error {
    let place = if line > 0 {
        format!(" (written at line {line} of the grammar)")
    } else {
        String::new()
    };
    Error::Eval {
        step: ctx.step,
        message: format!(
            "a parameter of module `{}` evaluated to {v}{place}; expected a finite number \
             within the f32 range (look for a division by zero, log or sqrt of a negative \
             number, or overflow)",
            ctx.ls.symbol_name(sym)
        ),
    }
}
