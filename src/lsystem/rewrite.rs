//! One parallel rewriting step: production selection (conditions, contexts, chance),
//! successors emitted into the next string, and decomposition and homomorphism expansion.

use super::ctx::{Ctx, emit, non_finite};
use super::grammar::{CUT, POP, PUSH, Pattern, Production, ProductionTable, REST, arity_bit};
use super::links::Links;
use super::random::Choice;
use super::stmt;
use super::{LSystem, ModuleString};
use crate::error::Result;
use crate::progress::Stage;

pub(super) fn rewrite(
    ctx: &mut Ctx<'_>,
    cur: &ModuleString,
    links: &Links,
    next: &mut ModuleString,
) -> Result<()> {
    let table = &ctx.ls.productions;
    let birth = super::ctx::birth(ctx.step);
    let n = cur.len();
    let has_rules = &table.has_rules[..];
    // Modules `copy..i` go to `next` unchanged: they are copied in one run when a
    // successor (or a cut, or the end) comes, however they came to be copied.
    let mut copy = 0;
    let mut i = 0;
    let mut report_at = crate::progress::EVERY;
    while i < n {
        if i >= report_at && ctx.fx.progress.active() {
            report_at = i + crate::progress::EVERY;
            let done = (ctx.step - 1) as f64 + i as f64 / n as f64;
            // The work's own reports (statements, rules) go on from here.
            ctx.fx.fraction = done / ctx.steps.max(1) as f64;
            ctx.fx.progress.report(Stage::Derivation, ctx.fx.fraction)?;
        }
        let sym = cur.syms[i];
        if sym == CUT && ctx.ls.has_cut && !has_rules[CUT as usize] {
            // cpfg's cut: the `%` and the rest of its branch are left out as the rewriting
            // reaches it (the `]` stays); cpfg draws for the `%`, not for what it cuts.
            copy_run(ctx, cur, copy, i, next)?;
            if ctx.choice == Choice::Weighted {
                ctx.draws.next_f64();
            }
            i = super::grammar::branch_end(&cur.syms, i + 1).unwrap_or(n);
            copy = i;
            continue;
        }
        if !has_rules[sym as usize] {
            // The whole run of modules without productions at once (a cut ends it).
            let cuts = ctx.ls.has_cut;
            let j = cur.syms[i + 1..]
                .iter()
                .position(|&s| has_rules[s as usize] || (cuts && s == CUT))
                .map_or(n, |k| i + 1 + k);
            if ctx.choice == Choice::Weighted {
                // cpfg draws for every module of its string, rules or none: one a
                // character of arbor's modules.
                for k in i..j {
                    let sym = cur.syms[k];
                    ctx.draw_prefix(sym);
                    ctx.draws.next_f64();
                }
            }
            i = j;
            continue;
        }
        if table.arities[sym as usize] & arity_bit(cur.params(i).len()) == 0 {
            // No production of the symbol takes this many parameters: the module is
            // copied as one without rules is.
            if ctx.choice == Choice::Weighted {
                ctx.draw_prefix(sym);
                ctx.draws.next_f64();
            }
            i += 1;
            continue;
        }
        let only = table.only[sym as usize];
        if only != u32::MAX && ctx.choice != Choice::Weighted {
            // The symbol's one production, which applies whenever the arity matches.
            let params = cur.params(i);
            let prod = &table.productions[only as usize];
            if prod.pred.arity as usize == params.len() {
                copy_run(ctx, cur, copy, i, next)?;
                bind_all(&mut ctx.args, prod, params);
                emit_production(ctx, table, only, birth, next, "a production")?;
                i += 1;
                copy = i;
                continue;
            }
        }
        if ctx.choice == Choice::Weighted {
            ctx.draw_prefix(sym);
        }
        let chosen = select(ctx, table, cur, links, i);
        if ctx.env.fault.is_some() {
            return ctx.check("a production");
        }
        if let Some(p) = chosen {
            copy_run(ctx, cur, copy, i, next)?;
            let prod = emit_production(ctx, table, p, birth, next, "a production")?;
            i += 1 + prod.pred_rest.len();
            copy = i;
        } else {
            i += 1;
        }
    }
    copy_run(ctx, cur, copy, n, next)
}

/// Runs (modules, parameter values) short enough to copy element by element.
const SHORT_RUN: usize = 8;

/// Appends modules `i..j` of `cur` to `next` unchanged.
pub(super) fn copy_run(
    ctx: &Ctx<'_>,
    cur: &ModuleString,
    i: usize,
    j: usize,
    next: &mut ModuleString,
) -> Result<()> {
    if i == j {
        return Ok(());
    }
    let (p0, p1) = (cur.offsets[i] as usize, cur.offsets[j] as usize);
    ctx.room(next, j - i, p1 - p0)?;
    let base = next.params.len() as u32;
    let shift = base.wrapping_sub(p0 as u32);
    if j - i <= SHORT_RUN && p1 - p0 <= SHORT_RUN {
        // Most runs between rewritten modules are a module or three: element by element
        // (the room is there) costs less than a library copy per array.
        for k in i..j {
            next.syms.push(cur.syms[k]);
            next.births.push(cur.births[k]);
            next.offsets.push(cur.offsets[k + 1].wrapping_add(shift));
        }
        for &v in &cur.params[p0..p1] {
            next.params.push(v);
        }
        return Ok(());
    }
    next.syms.extend_from_slice(&cur.syms[i..j]);
    next.births.extend_from_slice(&cur.births[i..j]);
    next.params.extend_from_slice(&cur.params[p0..p1]);
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
    bind_all(args, p, params);
    true
}

/// `args` as production `p` binds them: the predecessor's `params` in its slots, every
/// other slot zero until its context binds it.
#[inline]
fn bind_all(args: &mut Vec<f64>, p: &Production, params: &[f32]) {
    args.clear();
    if p.slots == params.len() {
        // The predecessor's parameters are all there is (no context): no zeroing.
        args.extend(params.iter().map(|&v| v as f64));
        return;
    }
    args.resize(p.slots, 0.0);
    bind(args, p.pred.slot, params);
}

/// The production that applies to module `i` of `s`, with its bound parameters left in
/// `ctx.args`; `None` when none applies.
pub(crate) fn select(
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
    if !ctx.fx.spend(&mut ctx.env, table.costs[p as usize].1) {
        ctx.check(what)?;
    }
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
/// hold, as the derivation's [`Choice`] says: arbor's (the first that holds decides; one
/// with a probability is drawn by weight among the applicable ones with a probability),
/// cpfg's deterministic (the first that holds) or cpfg's stochastic (every applicable one
/// by weight, one drand48 draw whether any applies or not). Interpretation and
/// decomposition rules are chosen deterministically under cpfg's streams.
fn select_with(
    ctx: &mut Ctx<'_>,
    table: &ProductionTable,
    sym: u16,
    params: &[f32],
    mut context: impl FnMut(&Production, &mut [f64]) -> bool,
) -> Option<u32> {
    let choice = match ctx.choice {
        Choice::Arbor => Choice::Arbor,
        c if std::ptr::eq(table, &ctx.ls.productions) => c,
        _ => Choice::First,
    };
    ctx.cands.clear();
    ctx.cand_args.clear();
    let mut total = 0.0;
    for &pi in table.candidates(sym) {
        let p = &table.productions[pi as usize];
        if !ctx.fx.spend(&mut ctx.env, table.costs[pi as usize].0) {
            return None;
        }
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
            let weight = match (choice, &p.probability) {
                (Choice::First, _) => {
                    ctx.args = args;
                    return Some(pi);
                }
                (Choice::Arbor, None) if ctx.cands.is_empty() => {
                    ctx.args = args;
                    return Some(pi);
                }
                (Choice::Arbor, None) => None,
                (Choice::Arbor, Some(w)) => {
                    Some(w.eval(&args, &mut ctx.env)).filter(|w| w.is_finite() && *w > 0.0)
                }
                // cpfg sums the weights in f32.
                (Choice::Weighted, w) => {
                    Some(w.as_ref().map_or(1.0, |w| w.eval(&args, &mut ctx.env)) as f32 as f64)
                }
            };
            if let Some(w) = weight {
                ctx.cands.push((pi, ctx.cand_args.len(), w));
                ctx.cand_args.extend_from_slice(&args);
                total = if choice == Choice::Weighted {
                    (total as f32 + w as f32) as f64
                } else {
                    total + w
                };
            }
        }
        ctx.args = args;
    }
    let chosen = if choice == Choice::Weighted {
        // cpfg's SelectProd: scaled = total * drand48(), less each weight in turn until
        // it is <= 0, in f32.
        let mut scaled = (total * ctx.draws.next_f64()) as f32;
        ctx.cands.iter().copied().find(|c| {
            scaled -= c.2 as f32;
            scaled <= 0.0
        })?
    } else {
        if ctx.cands.is_empty() {
            return None;
        }
        let mut r = ctx.env.rng.uniform() * total;
        let mut chosen = ctx.cands[ctx.cands.len() - 1];
        for &c in &ctx.cands {
            if r < c.2 {
                chosen = c;
                break;
            }
            r -= c.2;
        }
        chosen
    };
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
pub(crate) fn match_left(
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

/// Bracket-aware right context, as cpfg's: a branch in the string is skipped unless the
/// context itself has a `[` there; a `]` in the context must meet the `]` that ends the
/// branch (`=` before it skips the rest of the branch).
pub(crate) fn match_right(
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
            j = links.next_kept(ls, s, j);
            if j >= n || s.syms[j] != PUSH {
                return false;
            }
            j += 1;
            continue;
        }
        if pat.sym == REST {
            // `=`: the rest of the current branch, up to its `]` (the string's end at the
            // top level).
            let close = links.close[j.min(n)];
            j = if close == u32::MAX { n } else { close as usize };
            continue;
        }
        // The next module that is not ignored, past whole branches: an ignored bracket
        // (not listed by `consider:`, or listed by `ignore:`) is passed over like any
        // ignored module, as cpfg asks that first.
        loop {
            j = links.next_kept(ls, s, j);
            if j >= n {
                // A ring L-system's string closes on itself: after the last is the first.
                if wrapped || n == 0 {
                    return false;
                }
                wrapped = true;
                j = links.next_kept(ls, s, 0);
                if j >= n {
                    return false;
                }
            }
            let sym = s.syms[j];
            if ls.skip[sym as usize] {
                j += 1;
                continue;
            }
            if sym == PUSH {
                let close = links.partner[j];
                if close == u32::MAX {
                    return false;
                }
                j = close as usize + 1;
                continue;
            }
            break;
        }
        // A `]` in the context must meet the `]` that ends the branch; any other module
        // of the context fails at a `]`.
        if pat.sym == POP {
            if s.syms[j] != POP {
                return false;
            }
            j += 1;
            continue;
        }
        if s.syms[j] == POP {
            return false;
        }
        if !bind_module(s, j, pat, args) {
            return false;
        }
        j += 1;
    }
    true
}

/// Whether the rest of `p`'s predecessor matches the modules after the one just taken
/// from an expander's `stack` (its parameters end at `base` of `arena`): the next modules
/// of the same successor (`depth`), in order, binding their parameters into `args`.
/// Context is checked by the caller.
fn following_match(
    stack: &[(u16, u32, u32)],
    arena: &[f32],
    base: usize,
    depth: u32,
    p: &Production,
    args: &mut [f64],
) -> bool {
    let mut end = base;
    let mut next = stack.iter().rev();
    for pat in &p.pred_rest {
        let Some(&(sym, d, n)) = next.next() else {
            return false;
        };
        if d != depth || sym != pat.sym || n != pat.arity as u32 {
            return false;
        }
        let params = &arena[end - n as usize..end];
        bind(args, pat.slot, params);
        end -= n as usize;
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
        self.run(
            ctx,
            table,
            |p, _| p.left.is_empty() && p.right.is_empty(),
            sink,
        )
    }

    /// Expands the modules of `modules`, a successor a rule made at depth `depth - 1`,
    /// together (a rule whose predecessor is several of them takes them all), and hands
    /// every resulting module to `sink` in order. `context` checks a rule's left and right
    /// context (cpfg's interpretation rules see the context of the module the first rule
    /// rewrote, at every depth), binding their parameters.
    pub(crate) fn expand_successor<F>(
        &mut self,
        ctx: &mut Ctx<'_>,
        table: &ProductionTable,
        modules: &ModuleString,
        depth: u32,
        context: impl Fn(&Production, &mut [f64]) -> bool,
        sink: F,
    ) -> Result<()>
    where
        F: FnMut(&mut Ctx<'_>, u16, &[f32], bool) -> Result<()>,
    {
        self.stack.clear();
        self.arena.clear();
        for k in (0..modules.len()).rev() {
            self.stack
                .push((modules.symbol(k), depth, modules.params(k).len() as u32));
        }
        // The arena holds the parameters of the stack's entries in the stack's order.
        for k in (0..modules.len()).rev() {
            self.arena.extend_from_slice(modules.params(k));
        }
        self.run(ctx, table, context, sink)
    }

    /// Applies the rules to the modules on the stack until none is left.
    fn run<F>(
        &mut self,
        ctx: &mut Ctx<'_>,
        table: &ProductionTable,
        context: impl Fn(&Production, &mut [f64]) -> bool,
        mut sink: F,
    ) -> Result<()>
    where
        F: FnMut(&mut Ctx<'_>, u16, &[f32], bool) -> Result<()>,
    {
        while let Some((sym, depth, n)) = self.stack.pop() {
            if !ctx.fx.spend(&mut ctx.env, 1) {
                return ctx.check("an interpretation or decomposition rule");
            }
            let base = self.arena.len() - n as usize;
            let chosen = if depth < table.max_depth && !table.candidates(sym).is_empty() {
                let (stack, arena) = (&self.stack, &self.arena);
                select_with(ctx, table, sym, &arena[base..], |p, args| {
                    following_match(stack, arena, base, depth, p, args) && context(p, args)
                })
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
            // A predecessor of several modules takes the modules after this one too.
            let mut base = base;
            for _ in 0..table.productions[pi as usize].pred_rest.len() {
                let (_, _, m) = self.stack.pop().expect("matched by following_match");
                base -= m as usize;
            }
            self.arena.truncate(base);
            if !ctx.fx.spend(&mut ctx.env, table.costs[pi as usize].1) {
                return ctx.check("an interpretation or decomposition rule");
            }
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
