//! Parallel rewriting over flat module strings, double-buffered.

use super::expr::Env;
use super::grammar::{CUT, ModuleList, POP, PUSH, Pattern, Production, ProductionTable};
use super::stmt::{self, Effects, Stmt};
use super::{LSystem, LsystemOptions, ModuleString};
use crate::error::{Error, Result};
use crate::progress::Stage;
#[cfg(test)]
use crate::rng::Rng;

/// Everything a step needs besides the strings.
pub(crate) struct Ctx<'a> {
    pub(crate) ls: &'a LSystem,
    /// The random stream and the global variables.
    pub(crate) env: Env,
    /// The statements' budget, log and `stop()`.
    pub(crate) fx: Effects,
    /// The line of the production whose statements are running (for messages).
    line: u32,
    /// The caller's progress callback.
    pub(crate) progress: crate::progress::Progress<'a>,
    /// Steps of the derivation (for the fraction reported).
    steps: u32,
    pub(crate) max_modules: usize,
    pub(crate) max_params: usize,
    /// Most modules all steps together may rewrite (`LsystemOptions::max_work`).
    pub(crate) max_work: u64,
    /// Modules rewritten so far.
    pub(crate) work: u64,
    pub(crate) step: u32,
    /// Bound parameter values of the production being tried.
    args: Vec<f64>,
    /// Stochastic candidates: (production index, offset of its args in `cand_args`,
    /// weight).
    cands: Vec<(u32, usize, f64)>,
    cand_args: Vec<f64>,
}

impl<'a> Ctx<'a> {
    pub(crate) fn new(ls: &'a LSystem, options: &LsystemOptions) -> Self {
        let mut env = Env::new(
            ls.effective_seed(options),
            &ls.globals,
            ls.functions.clone(),
        );
        env.curves = ls.curves.clone();
        Ctx {
            ls,
            env,
            fx: Effects {
                budget: options.max_work as u64,
                ..Default::default()
            },
            line: 0,
            progress: Default::default(),
            steps: 0,
            max_modules: options.max_modules,
            max_params: options.max_params.min(u32::MAX as usize),
            max_work: options.max_work as u64,
            work: 0,
            step: 0,
            args: Vec::new(),
            cands: Vec::new(),
            cand_args: Vec::new(),
        }
    }

    /// Counts a step that rewrites `modules` modules against `max_work`, before it runs.
    pub(crate) fn spend(&mut self, modules: usize) -> Result<()> {
        self.work = self.work.saturating_add(modules as u64);
        if self.work > self.max_work {
            return Err(Error::LimitExceeded {
                limit_name: "max_work",
                what: "modules rewritten by all steps together",
                limit: self.max_work,
                requested: self.work,
                step: Some(self.step),
            });
        }
        Ok(())
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
    pub(crate) fn check(&mut self, what: &str) -> Result<()> {
        let Some(fault) = self.env.fault.take() else {
            return Ok(());
        };
        if fault.contains("max_work") {
            return Err(Error::LimitExceeded {
                limit_name: "max_work",
                what: "statements executed (max_work)",
                limit: self.max_work,
                requested: self.max_work.saturating_add(1),
                step: Some(self.step),
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

    fn limit(&self, name: &'static str, what: &'static str, limit: usize, need: usize) -> Error {
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
fn emit(
    ctx: &mut Ctx<'_>,
    list: &ModuleList,
    args: &[f64],
    birth: u16,
    out: &mut ModuleString,
) -> Result<()> {
    let n = list.syms.len();
    ctx.room(out, n, list.exprs.len())?;
    out.syms.extend_from_slice(&list.syms);
    out.births.extend(std::iter::repeat_n(birth, n));
    let base = out.params.len();
    out.offsets
        .extend(list.param_ends.iter().map(|&e| base as u32 + e));
    out.params.resize(base + list.exprs.len(), 0.0);
    let mut bad = None;
    for (k, (slot, e)) in out.params[base..].iter_mut().zip(&list.exprs).enumerate() {
        let v = e.eval(args, &mut ctx.env);
        let stored = v as f32;
        if !stored.is_finite() && bad.is_none() {
            bad = Some((k, v));
        }
        *slot = stored;
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

fn non_finite(ctx: &Ctx<'_>, sym: u16, v: f64, line: u32) -> Error {
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

/// The productions of a grammar without parameters, contexts, conditions,
/// probabilities, cuts or decomposition (a D0L-system, like ABOP's Fig. 1.24): each
/// symbol has at most one successor, so a step is a lookup per module and the length of
/// the next string is known before it is written.
#[derive(Clone, Debug)]
pub(crate) struct D0l {
    /// Per symbol: whether it is rewritten.
    rewrites: Vec<bool>,
    /// Per symbol: the modules it becomes (1 for a symbol that is not rewritten).
    lens: Vec<u32>,
    /// Per symbol: where its successor starts in `succ`.
    starts: Vec<u32>,
    succ: Vec<u16>,
}

impl D0l {
    /// The table, or `None` when the grammar needs the general rewriter.
    pub(crate) fn new(
        axiom: &ModuleList,
        table: &ProductionTable,
        decomposition: &ProductionTable,
        has_cut: bool,
        symbols: usize,
    ) -> Option<D0l> {
        let plain = |p: &Production| {
            p.left.is_empty()
                && p.right.is_empty()
                && p.condition.is_none()
                && p.probability.is_none()
                && p.pred.arity == 0
                && p.successor.exprs.is_empty()
        };
        if has_cut
            || !decomposition.is_empty()
            || !axiom.exprs.is_empty()
            || !table.productions.iter().all(plain)
        {
            return None;
        }
        let mut d = D0l {
            rewrites: vec![false; symbols],
            lens: vec![1; symbols],
            starts: vec![0; symbols],
            succ: Vec::new(),
        };
        // Every production is unconditional and deterministic: the first of a symbol is
        // the one the general rewriter would choose.
        for p in &table.productions {
            let s = p.pred.sym as usize;
            if !d.rewrites[s] {
                d.rewrites[s] = true;
                d.lens[s] = p.successor.syms.len() as u32;
                d.starts[s] = d.succ.len() as u32;
                d.succ.extend_from_slice(&p.successor.syms);
            }
        }
        Some(d)
    }

    fn derive(&self, ctx: &mut Ctx<'_>, steps: u32) -> Result<ModuleString> {
        let axiom = &ctx.ls.axiom.syms;
        ctx.step = 0;
        if axiom.len() > ctx.max_modules {
            return Err(ctx.limit("max_modules", "modules", ctx.max_modules, axiom.len()));
        }
        let mut cur = ModuleString {
            syms: axiom.clone(),
            births: vec![0; axiom.len()],
            ..Default::default()
        };
        let mut next = ModuleString::default();
        for step in 1..=steps {
            ctx.step = step;
            ctx.progress
                .report(Stage::Derivation, (step - 1) as f64 / steps as f64)?;
            ctx.spend(cur.syms.len())?;
            let len: usize = cur
                .syms
                .iter()
                .map(|&s| self.lens[s as usize] as usize)
                .sum();
            if len > ctx.max_modules {
                return Err(ctx.limit("max_modules", "modules", ctx.max_modules, len));
            }
            next.syms.clear();
            next.births.clear();
            next.try_exact(len)?;
            let birth = step as u16;
            let n = cur.syms.len();
            let chunk = if ctx.progress.active() {
                crate::progress::EVERY
            } else {
                n.max(1)
            };
            for (k, (syms, births)) in cur
                .syms
                .chunks(chunk)
                .zip(cur.births.chunks(chunk))
                .enumerate()
            {
                if k > 0 {
                    let done = (step - 1) as f64 + (k * chunk) as f64 / n as f64;
                    ctx.progress
                        .report(Stage::Derivation, done / steps as f64)?;
                }
                for (&s, &b) in syms.iter().zip(births) {
                    if self.rewrites[s as usize] {
                        let start = self.starts[s as usize] as usize;
                        let succ = &self.succ[start..start + self.lens[s as usize] as usize];
                        next.syms.extend_from_slice(succ);
                        next.births.extend(std::iter::repeat_n(birth, succ.len()));
                    } else {
                        next.syms.push(s);
                        next.births.push(b);
                    }
                }
            }
            std::mem::swap(&mut cur, &mut next);
        }
        Ok(cur)
    }
}

pub(crate) fn derive<'a>(
    ls: &'a LSystem,
    options: &LsystemOptions,
    progress: crate::progress::Progress<'a>,
) -> Result<ModuleString> {
    let mut string = derive_string(ls, options, progress)?;
    string.grammar = ls.id;
    Ok(string)
}

fn derive_string<'a>(
    ls: &'a LSystem,
    options: &LsystemOptions,
    progress: crate::progress::Progress<'a>,
) -> Result<ModuleString> {
    let steps = options.steps.unwrap_or(ls.derivation_length);
    if steps > u16::MAX as u32 {
        return Err(Error::invalid(
            "steps",
            format!("{steps}; expected at most {}", u16::MAX),
        ));
    }
    let mut ctx = Ctx::new(ls, options);
    ctx.progress = progress;
    ctx.steps = steps;
    if let Some(d0l) = &ls.d0l {
        let s = d0l.derive(&mut ctx, steps)?;
        ctx.progress.report(Stage::Derivation, 1.0)?;
        return Ok(s);
    }
    let mut cur = ModuleString::new();
    let mut next = ModuleString::new();
    // cpfg's order: Start, the axiom, then per step StartEach, the step, EndEach; End.
    ctx.run_block(&ls.blocks.start, "the Start: block")?;
    emit(&mut ctx, &ls.axiom, &[], 0, &mut cur)?;
    ctx.check("the axiom")?;
    post_process(&mut ctx, &mut cur, &mut next)?;
    // Query modules (`?P` ...) learn where the turtle is after every step.
    let queries = super::interpret::has_queries(ls);
    if queries {
        super::interpret::answer_queries(ls, &mut cur, options)?;
    }
    let mut links = Links::default();
    // Growth of the last step (modules, parameters), to size the next buffer once instead
    // of letting it double (and copy) its way up.
    let mut growth = (1.0f64, 1.0f64);
    for step in 1..=steps {
        if ctx.fx.stop {
            break;
        }
        ctx.step = step;
        ctx.progress
            .report(Stage::Derivation, (step - 1) as f64 / steps as f64)?;
        ctx.spend(cur.len())?;
        // A `%` cuts its branch as the next step begins (cpfg's order): one made by the
        // last step stays in the string, and the turtle draws past it.
        if ls.has_cut {
            next.clear();
            cut(&cur, &mut next);
            std::mem::swap(&mut cur, &mut next);
        }
        ctx.run_block(&ls.blocks.start_each, "the StartEach: block")?;
        next.clear();
        let want = |len: usize, g: f64, limit: usize| ((len as f64 * g * 1.02) as usize).min(limit);
        next.reserve(
            want(cur.len(), growth.0, ctx.max_modules),
            want(cur.params.len(), growth.1, ctx.max_params),
        )?;
        let before = (cur.len().max(1) as f64, cur.params.len().max(1) as f64);
        if ls.has_context {
            links.build(ls, &cur);
        }
        rewrite(&mut ctx, &cur, &links, &mut next)?;
        growth = (
            next.len() as f64 / before.0,
            next.params.len() as f64 / before.1,
        );
        std::mem::swap(&mut cur, &mut next);
        post_process(&mut ctx, &mut cur, &mut next)?;
        if queries {
            super::interpret::answer_queries(ls, &mut cur, options)?;
        }
        ctx.run_block(&ls.blocks.end_each, "the EndEach: block")?;
    }
    ctx.run_block(&ls.blocks.end, "the End: block")?;
    ctx.progress.report(Stage::Derivation, 1.0)?;
    cur.globals = std::mem::take(&mut ctx.env.vars);
    cur.log = std::mem::take(&mut ctx.fx.log);
    Ok(cur)
}

/// Decomposition after a step (or after the axiom).
fn post_process(ctx: &mut Ctx<'_>, cur: &mut ModuleString, spare: &mut ModuleString) -> Result<()> {
    if !ctx.ls.decomposition.is_empty() {
        spare.clear();
        let table = &ctx.ls.decomposition;
        let mut expander = Expander::default();
        let mut produced = ModuleString::new();
        let mut i = 0;
        while i < cur.len() {
            let birth = cur.births[i];
            let mut sink = |ctx: &mut Ctx<'_>, sym: u16, params: &[f32], new: bool| {
                ctx.room(spare, 1, params.len())?;
                spare.push(sym, if new { ctx.step as u16 } else { birth }, params);
                Ok(())
            };
            if let Some(p) = select_multi(ctx, table, cur, i) {
                successor_of(ctx, table, p, ctx.step as u16, &mut produced)?;
                for k in 0..produced.len() {
                    expander.expand(
                        ctx,
                        table,
                        produced.symbol(k),
                        produced.params(k),
                        |ctx, sym, params, _| sink(ctx, sym, params, true),
                    )?;
                }
                i += 1 + table.productions[p as usize].pred_rest.len();
                continue;
            }
            ctx.check("a decomposition rule")?;
            expander.expand(ctx, table, cur.symbol(i), cur.params(i), &mut sink)?;
            i += 1;
        }
        std::mem::swap(cur, spare);
    }
    Ok(())
}

/// Removes every `%` and the rest of its branch (up to, not including, the `]` that
/// closes it).
fn cut(src: &ModuleString, dst: &mut ModuleString) {
    let mut i = 0;
    while i < src.len() {
        if src.syms[i] == CUT {
            i = branch_end(&src.syms, i + 1).unwrap_or(src.len());
            continue;
        }
        dst.push(src.syms[i], src.births[i], src.params(i));
        i += 1;
    }
}

/// The index of the `]` that closes the branch `syms[from..]` starts inside (nested
/// branches skipped whole); `None` when it is never closed.
fn branch_end(syms: &[u16], from: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (k, &sym) in syms.iter().enumerate().skip(from) {
        match sym {
            PUSH => depth += 1,
            POP if depth == 0 => return Some(k),
            POP => depth -= 1,
            _ => {}
        }
    }
    None
}

/// What context matching needs of a string, computed once per step so that matching a
/// context costs time proportional to the context, not to the string: each bracket's
/// partner, the next module not skipped by `ignore:`/`consider:`, and the `]` that closes
/// the branch each module is in (`u32::MAX` for none).
#[derive(Default)]
pub(crate) struct Links {
    pub(crate) partner: Vec<u32>,
    next: Vec<u32>,
    close: Vec<u32>,
}

impl Links {
    pub(crate) fn build(&mut self, ls: &LSystem, s: &ModuleString) {
        brackets(s, &mut self.partner);
        let n = s.len();
        self.next.clear();
        self.next.resize(n + 1, n as u32);
        for j in (0..n).rev() {
            let sym = s.syms[j];
            // Brackets are never skipped: they are the string's structure.
            self.next[j] = if sym != PUSH && sym != POP && ls.skip[sym as usize] {
                self.next[j + 1]
            } else {
                j as u32
            };
        }
        // close[j]: the first `]` at or after j that closes the branch j is in (j itself
        // at a `]`), as scanning forward with a depth count finds it; from the right with a
        // stack of the `]`s not yet matched.
        self.close.clear();
        self.close.resize(n + 1, u32::MAX);
        let mut unmatched: Vec<u32> = Vec::new();
        for j in (0..n).rev() {
            match s.syms[j] {
                POP => unmatched.push(j as u32),
                PUSH => {
                    unmatched.pop();
                }
                _ => {}
            }
            self.close[j] = unmatched.last().copied().unwrap_or(u32::MAX);
        }
    }
}

/// For each bracket, the index of its partner (`u32::MAX` for none).
pub(crate) fn brackets(s: &ModuleString, partner: &mut Vec<u32>) {
    partner.clear();
    partner.resize(s.len(), u32::MAX);
    let mut stack: Vec<u32> = Vec::new();
    for (i, &sym) in s.syms.iter().enumerate() {
        if sym == PUSH {
            stack.push(i as u32);
        } else if sym == POP {
            if let Some(open) = stack.pop() {
                partner[open as usize] = i as u32;
                partner[i] = open;
            }
        }
    }
}

fn rewrite(
    ctx: &mut Ctx<'_>,
    cur: &ModuleString,
    links: &Links,
    next: &mut ModuleString,
) -> Result<()> {
    let table = &ctx.ls.productions;
    let birth = ctx.step as u16;
    let n = cur.len();
    let has_rules = &table.has_rules[..];
    let mut i = 0;
    let mut report_at = crate::progress::EVERY;
    while i < n {
        if i >= report_at && ctx.progress.active() {
            report_at = i + crate::progress::EVERY;
            let done = (ctx.step - 1) as f64 + i as f64 / n as f64;
            ctx.progress
                .report(Stage::Derivation, done / ctx.steps.max(1) as f64)?;
        }
        let sym = cur.syms[i];
        if !has_rules[sym as usize] {
            // Copy the whole run of modules without productions at once.
            let j = cur.syms[i + 1..]
                .iter()
                .position(|&s| has_rules[s as usize])
                .map_or(n, |k| i + 1 + k);
            copy_run(ctx, cur, i, j, next)?;
            i = j;
            continue;
        }
        let chosen = select(ctx, table, cur, links, i);
        if ctx.env.fault.is_some() {
            return ctx.check("a production");
        }
        match chosen {
            Some(p) => {
                let prod = emit_production(ctx, table, p, birth, next, "a production")?;
                i += prod.pred_rest.len();
            }
            None => copy_run(ctx, cur, i, i + 1, next)?,
        }
        i += 1;
    }
    Ok(())
}

/// Appends modules `i..j` of `cur` to `next` unchanged.
fn copy_run(
    ctx: &Ctx<'_>,
    cur: &ModuleString,
    i: usize,
    j: usize,
    next: &mut ModuleString,
) -> Result<()> {
    let (p0, p1) = (cur.offsets[i] as usize, cur.offsets[j] as usize);
    ctx.room(next, j - i, p1 - p0)?;
    next.syms.extend_from_slice(&cur.syms[i..j]);
    next.births.extend_from_slice(&cur.births[i..j]);
    let base = next.params.len() as u32;
    next.params.extend_from_slice(&cur.params[p0..p1]);
    let shift = base.wrapping_sub(p0 as u32);
    next.offsets.extend(
        cur.offsets[i + 1..=j]
            .iter()
            .map(|&o| o.wrapping_add(shift)),
    );
    Ok(())
}

/// Binds the predecessor's parameters; `false` when the arity differs.
#[inline]
fn bind_pred(args: &mut Vec<f64>, p: &Production, params: &[f32]) -> bool {
    if p.pred.arity as usize != params.len() {
        return false;
    }
    args.clear();
    args.resize(p.slots, 0.0);
    bind(args, p.pred.slot, params);
    true
}

/// The production that applies to module `i` of `s`, with its bound parameters left in
/// `ctx.args`; `None` when none applies.
fn select(
    ctx: &mut Ctx<'_>,
    table: &ProductionTable,
    s: &ModuleString,
    links: &Links,
    i: usize,
) -> Option<u32> {
    let ls = ctx.ls;
    select_with(ctx, table, s.syms[i], s.params(i), |p, args| {
        (p.pred_rest.is_empty() || match_rest(s, i, p, args))
            && (p.left.is_empty() || match_left(ls, s, links, i, p, args))
            && (p.right.is_empty() || match_right(ls, s, links, i + p.pred_rest.len(), p, args))
    })
}

/// In a table of context-free rules (interpretation, decomposition): the production with
/// a predecessor of several modules that matches at module `i` of `s`, its bound
/// parameters left in `ctx.args`. Such productions are tried before those of one module.
pub(crate) fn select_multi(
    ctx: &mut Ctx<'_>,
    table: &ProductionTable,
    s: &ModuleString,
    i: usize,
) -> Option<u32> {
    if !table.multi[s.syms[i] as usize] {
        return None;
    }
    select_with(ctx, table, s.syms[i], s.params(i), |p, args| {
        !p.pred_rest.is_empty() && match_rest(s, i, p, args)
    })
}

/// The successor of production `p` of `table` (its arguments in `ctx.args`) as modules
/// in `out` (cleared first).
pub(crate) fn successor_of(
    ctx: &mut Ctx<'_>,
    table: &ProductionTable,
    p: u32,
    birth: u16,
    out: &mut ModuleString,
) -> Result<()> {
    out.clear();
    emit_production(ctx, table, p, birth, out, "a rule").map(|_| ())
}

/// Appends the successor of production `p` (its predecessor's arguments in `ctx.args`)
/// to `out`, then reports a fault of its statements as an error about `what`.
fn emit_production<'t>(
    ctx: &mut Ctx<'_>,
    table: &'t ProductionTable,
    p: u32,
    birth: u16,
    out: &mut ModuleString,
    what: &str,
) -> Result<&'t Production> {
    let prod = &table.productions[p as usize];
    let args = std::mem::take(&mut ctx.args);
    let r = emit(ctx, &prod.successor, &args, birth, out);
    ctx.args = args;
    r?;
    ctx.line = prod.line;
    ctx.check(what)?;
    Ok(prod)
}

/// The modules after the first of a predecessor of several, one after another.
fn match_rest(s: &ModuleString, i: usize, p: &Production, args: &mut [f64]) -> bool {
    if i + p.pred_rest.len() >= s.len() {
        return false;
    }
    p.pred_rest
        .iter()
        .enumerate()
        .all(|(k, pat)| bind_module(s, i + 1 + k, pat, args))
}

/// Chooses among the productions of `sym` whose arity, context (`context`) and condition
/// hold. The first that holds decides: a deterministic one applies at once; if it has a
/// probability, one of all the applicable stochastic productions is drawn by weight.
fn select_with(
    ctx: &mut Ctx<'_>,
    table: &ProductionTable,
    sym: u16,
    params: &[f32],
    mut context: impl FnMut(&Production, &mut [f64]) -> bool,
) -> Option<u32> {
    ctx.cands.clear();
    ctx.cand_args.clear();
    let mut total = 0.0;
    for &pi in table.candidates(sym) {
        let p = &table.productions[pi as usize];
        let mut args = std::mem::take(&mut ctx.args);
        let mut ok = bind_pred(&mut args, p, params) && context(p, &mut args);
        if ok && !p.pre.is_empty() {
            ctx.line = p.line;
            ok = stmt::exec(&p.pre, &mut args, &mut ctx.env, &mut ctx.fx);
        }
        ok = ok
            && p.condition
                .as_ref()
                .is_none_or(|c| c.eval(&args, &mut ctx.env) != 0.0);
        if ok && !p.post.is_empty() {
            ctx.line = p.line;
            ok = stmt::exec(&p.post, &mut args, &mut ctx.env, &mut ctx.fx);
        }
        if ctx.env.fault.is_some() {
            ctx.args = args;
            return None;
        }
        if ok {
            match &p.probability {
                None if ctx.cands.is_empty() => {
                    ctx.args = args;
                    return Some(pi);
                }
                None => {}
                Some(w) => {
                    let w = w.eval(&args, &mut ctx.env);
                    if w.is_finite() && w > 0.0 {
                        ctx.cands.push((pi, ctx.cand_args.len(), w));
                        ctx.cand_args.extend_from_slice(&args);
                        total += w;
                    }
                }
            }
        }
        ctx.args = args;
    }
    if ctx.cands.is_empty() {
        return None;
    }
    let mut r = ctx.env.rng.next_f64() * total;
    let mut chosen = ctx.cands[ctx.cands.len() - 1];
    for &c in &ctx.cands {
        if r < c.2 {
            chosen = c;
            break;
        }
        r -= c.2;
    }
    let slots = table.productions[chosen.0 as usize].slots;
    ctx.args.clear();
    ctx.args
        .extend_from_slice(&ctx.cand_args[chosen.1..chosen.1 + slots]);
    Some(chosen.0)
}

#[inline]
fn bind(args: &mut [f64], slot: u16, params: &[f32]) {
    let s = slot as usize;
    for (a, &v) in args[s..s + params.len()].iter_mut().zip(params) {
        *a = v as f64;
    }
}

/// Whether module `j` of `s` is `pat` (symbol and arity); if so its parameters are bound.
#[inline]
fn bind_module(s: &ModuleString, j: usize, pat: &Pattern, args: &mut [f64]) -> bool {
    let params = s.params(j);
    if s.syms[j] != pat.sym || params.len() != pat.arity as usize {
        return false;
    }
    bind(args, pat.slot, params);
    true
}

/// Bracket-aware left context: walking back, a completed branch `[...]` is skipped whole
/// and a `[` leads to the module the branch grows from.
fn match_left(
    ls: &LSystem,
    s: &ModuleString,
    links: &Links,
    i: usize,
    p: &Production,
    args: &mut [f64],
) -> bool {
    let mut j = i;
    // A ring L-system's string closes on itself: before the first module is the last.
    let mut wrapped = !ls.ring;
    for pat in p.left.iter().rev() {
        loop {
            if j == 0 {
                if wrapped || s.is_empty() {
                    return false;
                }
                wrapped = true;
                j = s.len();
            }
            j -= 1;
            let sym = s.syms[j];
            if sym == POP {
                let open = links.partner[j];
                if open == u32::MAX {
                    return false;
                }
                j = open as usize;
                continue;
            }
            if sym == PUSH || ls.skip[sym as usize] {
                continue;
            }
            break;
        }
        if !bind_module(s, j, pat, args) {
            return false;
        }
    }
    true
}

/// Bracket-aware right context: a branch in the string is skipped unless the context
/// itself has a `[` there; a `]` in the context skips to the end of the current branch.
fn match_right(
    ls: &LSystem,
    s: &ModuleString,
    links: &Links,
    i: usize,
    p: &Production,
    args: &mut [f64],
) -> bool {
    let n = s.len();
    let mut j = i + 1;
    let mut wrapped = !ls.ring;
    for pat in &p.right {
        if pat.sym == PUSH {
            j = links.next[j.min(n)] as usize;
            if j >= n || s.syms[j] != PUSH {
                return false;
            }
            j += 1;
            continue;
        }
        if pat.sym == POP {
            // The `]` that closes the branch j is in (or, at a `]`, that one).
            let close = links.close[j.min(n)];
            if close == u32::MAX {
                return false;
            }
            j = close as usize + 1;
            continue;
        }
        loop {
            j = links.next[j.min(n)] as usize;
            if j >= n {
                // A ring L-system's string closes on itself: after the last is the first.
                if wrapped || n == 0 {
                    return false;
                }
                wrapped = true;
                j = links.next[0] as usize;
                if j >= n {
                    return false;
                }
            }
            let sym = s.syms[j];
            if sym == PUSH {
                let close = links.partner[j];
                if close == u32::MAX {
                    return false;
                }
                j = close as usize + 1;
                continue;
            }
            if sym == POP {
                return false;
            }
            break;
        }
        if !bind_module(s, j, pat, args) {
            return false;
        }
        j += 1;
    }
    true
}

/// Recursive application of context-free rules (interpretation and decomposition) with
/// an explicit stack, at most `max_depth` levels deep.
#[derive(Default)]
pub(crate) struct Expander {
    /// Pending modules: (symbol, depth, number of parameters on `arena`).
    stack: Vec<(u16, u32, u32)>,
    arena: Vec<f32>,
    produced: Vec<(u16, u32, u32)>,
    produced_params: Vec<f32>,
}

impl Expander {
    /// Expands one module and hands every resulting module to `sink` in order.
    pub(crate) fn expand<F>(
        &mut self,
        ctx: &mut Ctx<'_>,
        table: &ProductionTable,
        sym: u16,
        params: &[f32],
        mut sink: F,
    ) -> Result<()>
    where
        F: FnMut(&mut Ctx<'_>, u16, &[f32], bool) -> Result<()>,
    {
        if table.candidates(sym).is_empty() {
            return sink(ctx, sym, params, false);
        }
        self.stack.clear();
        self.arena.clear();
        self.stack.push((sym, 0, params.len() as u32));
        self.arena.extend_from_slice(params);
        while let Some((sym, depth, n)) = self.stack.pop() {
            let base = self.arena.len() - n as usize;
            let chosen = if depth < table.max_depth && !table.candidates(sym).is_empty() {
                select_with(ctx, table, sym, &self.arena[base..], |_, _| true)
            } else {
                None
            };
            if ctx.env.fault.is_some() {
                return ctx.check("an interpretation or decomposition rule");
            }
            let Some(pi) = chosen else {
                sink(ctx, sym, &self.arena[base..], depth > 0)?;
                self.arena.truncate(base);
                continue;
            };
            self.arena.truncate(base);
            let succ = &table.productions[pi as usize].successor;
            self.produced.clear();
            self.produced_params.clear();
            let args = std::mem::take(&mut ctx.args);
            for m in &succ.modules {
                let first = self.produced_params.len() as u32;
                for e in succ.params(m) {
                    let v = e.eval(&args, &mut ctx.env);
                    if !(v as f32).is_finite() {
                        ctx.args = args;
                        return Err(non_finite(ctx, m.sym, v, succ.line));
                    }
                    self.produced_params.push(v as f32);
                }
                self.produced.push((m.sym, first, m.count));
            }
            ctx.args = args;
            if self.stack.len() + self.produced.len() > ctx.max_modules {
                return Err(ctx.limit(
                    "max_modules",
                    "pending modules of interpretation or decomposition rules",
                    ctx.max_modules,
                    self.stack.len() + self.produced.len(),
                ));
            }
            for &(s, first, count) in self.produced.iter().rev() {
                let f = first as usize;
                self.arena
                    .extend_from_slice(&self.produced_params[f..f + count as usize]);
                self.stack.push((s, depth + 1, count));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;

    /// Derives with the lookup table and with the general rewriter.
    fn both(text: &str, options: &LsystemOptions) -> (Result<ModuleString>, Result<ModuleString>) {
        let ls = LSystem::parse(text).unwrap();
        assert!(ls.d0l.is_some(), "{text}: expected the lookup table");
        let mut general = ls.clone();
        general.d0l = None;
        (
            derive(&ls, options, Default::default()),
            derive(&general, options, Default::default()),
        )
    }

    fn options(steps: u32) -> LsystemOptions {
        LsystemOptions {
            steps: Some(steps),
            ..Default::default()
        }
    }

    #[test]
    fn lookup_table_equals_the_general_rewriter_on_the_shipped_grammars() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/grammars");
        let mut tabled = 0;
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let text = std::fs::read_to_string(&path).unwrap();
            let ls = LSystem::parse(&text).unwrap();
            if ls.d0l.is_none() {
                continue;
            }
            tabled += 1;
            let steps = ls.derivation_length().min(5);
            let (fast, slow) = both(&text, &options(steps));
            let (fast, slow) = (fast.unwrap(), slow.unwrap());
            assert!(fast.len() > 1, "{}", path.display());
            assert_eq!(fast, slow, "{}", path.display());
            assert!(fast.offsets.is_empty(), "no offsets without parameters");
        }
        // ABOP 1.24a–f, the Koch snowflake, the X/F fern.
        assert!(tabled >= 7, "only {tabled} grammars took the lookup table");
    }

    #[test]
    fn lookup_table_equals_the_general_rewriter_on_random_grammars() {
        let alphabet = ["F", "G", "X", "Y", "+", "-", "f", "[F]", "[+X]", "[-G[Y]]"];
        let mut rng = Rng::new(7);
        let mut pick = |n: usize| (rng.next_u64() % n as u64) as usize;
        let (mut grown, mut stopped) = (0, 0);
        for case in 0..1000 {
            let mut text = String::from("Axiom: ");
            for _ in 0..1 + pick(4) {
                text.push_str(alphabet[pick(alphabet.len())]);
            }
            text.push('\n');
            // Several productions per symbol (the first applies), empty successors and
            // symbols without any.
            for _ in 0..pick(5) {
                let pred = alphabet[pick(4)];
                let succ: String = (0..pick(7))
                    .map(|_| alphabet[pick(alphabet.len())])
                    .collect();
                let succ = if succ.is_empty() {
                    "*".to_string()
                } else {
                    succ
                };
                text.push_str(&format!("{pred} --> {succ}\n"));
            }
            let o = LsystemOptions {
                steps: Some(pick(9) as u32),
                max_modules: 1 + pick(3000),
                ..Default::default()
            };
            match both(&text, &o) {
                (Ok(a), Ok(b)) => {
                    assert_eq!(a, b, "case {case}:\n{text}");
                    grown += usize::from(a.len() > 20);
                }
                (
                    Err(Error::LimitExceeded {
                        limit_name: n1,
                        step: s1,
                        ..
                    }),
                    Err(Error::LimitExceeded {
                        limit_name: n2,
                        step: s2,
                        ..
                    }),
                ) => {
                    assert_eq!((n1, s1), (n2, s2), "case {case}:\n{text}");
                    stopped += 1;
                }
                (a, b) => panic!("case {case}:\n{text}\n{a:?}\n{b:?}"),
            }
        }
        assert!(
            grown > 150 && stopped > 30,
            "{grown} grown, {stopped} stopped"
        );
    }

    #[test]
    fn grammars_with_parameters_context_or_chance_take_the_general_rewriter() {
        for text in [
            "Axiom: A(1)\nA(x) --> A(x+1)\n",
            "Axiom: AB\nA < B --> BB\n",
            "Axiom: A\nA : 1 --> AB\n",
            "Axiom: A\nA --> AB : 0.5\nA --> B : 0.5\n",
            "Axiom: A\nA --> A[%B]\n",
            "Axiom: A\nA --> AB\ndecomposition\nB --> CC\n",
            "Axiom: A\nA --> F(2)\n",
        ] {
            assert!(LSystem::parse(text).unwrap().d0l.is_none(), "{text}");
        }
    }

    /// The per-step links give what the scans they replace gave, on random bracket
    /// strings, balanced or not: the closing `]` of every position's branch, and the next
    /// module not skipped.
    #[test]
    fn links_equal_the_scans_they_replace() {
        let ls = LSystem::parse("ignore: B\nAxiom: A\n").unwrap();
        let id = |name: &str| ls.symbols.names.iter().position(|n| n == name).unwrap() as u16;
        let (a, b) = (id("A"), id("B"));
        let mut rng = Rng::new(11);
        for _ in 0..500 {
            let n = (rng.next_u64() % 40) as usize;
            let syms: Vec<u16> = (0..n)
                .map(|_| [PUSH, POP, a, b][(rng.next_u64() % 4) as usize])
                .collect();
            let s = ModuleString {
                births: vec![0; n],
                syms: syms.clone(),
                ..Default::default()
            };
            let mut links = Links::default();
            links.build(&ls, &s);
            for j in 0..=n {
                let scan = branch_end(&syms, j).map_or(u32::MAX, |k| k as u32);
                assert_eq!(links.close[j], scan, "{syms:?} at {j}");
                let next = (j..n).find(|&k| syms[k] != b).unwrap_or(n) as u32;
                assert_eq!(links.next[j], next, "{syms:?} at {j}");
            }
        }
    }

    #[test]
    fn the_end_of_a_branch_skips_nested_branches() {
        let ls = LSystem::parse("Axiom: A[B[C]D]E").unwrap();
        let s = ls.derive(&options(0)).unwrap();
        // A [ B [ C ] D ] E: from B (index 2) the branch closes at 7; from C at 5.
        assert_eq!(branch_end(&s.syms, 2), Some(7));
        assert_eq!(branch_end(&s.syms, 4), Some(5));
        assert_eq!(branch_end(&s.syms, 8), None);
        // Right context `]E`: the rest of the branch is skipped whole, nested ones too.
        let ls = LSystem::parse("Axiom: A[B[C]D]E\nB > ]E --> X\nC > ]E --> Y\n").unwrap();
        assert_eq!(ls.format(&ls.derive(&options(1)).unwrap()), "A[X[C]D]E");
        // A cut removes the rest of its branch with the branches nested in it (as the
        // step after the one that made it begins).
        let ls = LSystem::parse("Axiom: F[A[G]F]F\nA --> %\n").unwrap();
        assert_eq!(ls.format(&ls.derive(&options(2)).unwrap()), "F[]F");
    }

    #[test]
    fn the_lookup_table_checks_the_limit_before_writing() {
        let text = "Axiom: F\nF --> F[+F]F[-F]F\n";
        let o = LsystemOptions {
            steps: Some(10),
            max_modules: 1000,
            ..Default::default()
        };
        match both(text, &o).0 {
            Err(Error::LimitExceeded {
                limit_name: "max_modules",
                step: Some(4),
                requested,
                ..
            }) => assert_eq!(requested, 5u64.pow(4) + 6 * (1 + 5 + 25 + 125)),
            other => panic!("{other:?}"),
        }
    }
}
