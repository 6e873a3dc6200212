//! The turtle's walk through the grammar's interpretation rules (`homomorphism`), as
//! cpfg's InterpretHomomorphism applies them, spending from the derivation's work budget.

use super::{Frame, Turtle};
use crate::error::{Error, Result};
use crate::lsystem::ctx::Ctx;
use crate::lsystem::links::Links;
use crate::lsystem::rewrite::{Expander, match_left, match_right, select, successor_of};
use crate::lsystem::{LSystem, LsystemOptions, ModuleString};
use crate::progress::{Run, Stage};

/// Work units the turtle spends reading one module an interpretation rule made.
const TURTLE_WORK: u64 = 8;

/// The turtle walks `string` through the grammar's interpretation rules (`homomorphism`):
/// each module is expanded, and the turtle reads what the rules produce.
///
/// The rules spend from `work.budget` (what is left of `max_work`), and `work.progress`
/// hears the walk and the work.
pub(super) fn walk_with_rules<'p>(
    t: &mut Turtle,
    ls: &'p LSystem,
    string: &ModuleString,
    options: &LsystemOptions,
    work: Work<'_, 'p>,
    ask: &mut dyn FnMut(usize, &Frame),
) -> Result<()> {
    let mut ctx = Ctx::new(ls, options);
    ctx.fx.reset_budget(*work.budget);
    (ctx.fx.stage, ctx.fx.fraction) = match work.derivation {
        Some(d) => {
            ctx.step = d.step;
            (Stage::Derivation, d.fraction)
        }
        None => (Stage::Interpretation, 0.0),
    };
    ctx.fx.progress = std::mem::take(work.progress);
    let r = walk_rules(t, ls, string, &mut ctx, ask);
    *work.progress = std::mem::take(&mut ctx.fx.progress);
    *work.budget = ctx.fx.budget;
    r
}

/// What interpretation rules spend from and report to: the progress callback, the work
/// budget left, and, when they answer a derivation's queries, where the derivation stands
/// (they then report and fail as the derivation).
pub(super) struct Work<'r, 'p> {
    pub(super) progress: &'r mut Run<'p>,
    pub(super) budget: &'r mut u64,
    pub(super) derivation: Option<Derivation>,
}

impl<'p> Work<'_, 'p> {
    /// The same work, borrowed again for a call.
    pub(super) fn reborrow(&mut self) -> Work<'_, 'p> {
        Work {
            progress: self.progress,
            budget: self.budget,
            derivation: self.derivation,
        }
    }
}

/// A derivation step whose query modules a walk answers.
#[derive(Clone, Copy)]
pub(super) struct Derivation {
    pub(super) step: u32,
    /// The fraction of the derivation done.
    pub(super) fraction: f64,
}

fn walk_rules(
    t: &mut Turtle,
    ls: &LSystem,
    string: &ModuleString,
    ctx: &mut Ctx<'_>,
    ask: &mut dyn FnMut(usize, &Frame),
) -> Result<()> {
    let n = string.len().max(1) as f64;
    let table = &ls.homomorphism;
    if string.globals.len() == ctx.env.vars.len() {
        // Interpretation rules read the variables as the derivation left them.
        ctx.env.vars.clone_from(&string.globals);
    }
    let mut expander = Expander::default();
    let mut links = Links::default();
    if table.has_context {
        links.build(ls, string);
    }
    let links = &links;
    let mut read = 0usize;
    let mut produced = ModuleString::new();
    let mut i = 0;
    let mut report_at = 0;
    while i < string.len() {
        if i >= report_at && ctx.fx.stage == Stage::Interpretation {
            report_at = i + crate::progress::EVERY;
            ctx.fx.fraction = i as f64 / n;
            ctx.fx
                .progress
                .report(Stage::Interpretation, ctx.fx.fraction)?;
        }
        let birth = string.birth(i);
        if ctx.fx.stage == Stage::Interpretation {
            // Messages name the step that made the module being read.
            ctx.step = birth;
        }
        ask(i, &t.state.frame);
        let mut sink = |ctx: &mut Ctx<'_>, sym: u16, params: &[f32], _: bool| {
            // The turtle's reading of a module the rules made: a few units (it costs
            // several times a rule's try).
            if !ctx.fx.spend(&mut ctx.env, TURTLE_WORK) {
                ctx.check("an interpretation rule")?;
            }
            read += 1;
            if read > ctx.max_modules {
                return Err(Error::LimitExceeded {
                    limit_name: "max_modules",
                    what: "modules read by the turtle after interpretation rules",
                    limit: ctx.max_modules as u64,
                    requested: read as u64,
                    step: None,
                });
            }
            // Interpretation rules draw an unknown number of branches: room is made
            // here, fallibly (without them, the arrays were sized exactly above).
            if t.branches.len() == t.branches.capacity() {
                t.grow_branches()?;
            }
            t.module(sym, params, birth, birth)
        };
        // cpfg's InterpretHomomorphism: the first rule in file order whose predecessor
        // (of one module or several), context and condition match at module `i` rewrites
        // it at depth 0; its successor's modules are rewritten at depth 1, and so on, and
        // modules at `maximum depth:` are read as they are. Context is always read around
        // module `i` of the string, at every depth.
        let chosen = select(ctx, table, string, links, i);
        let Some(p) = chosen else {
            ctx.check("an interpretation rule")?;
            sink(ctx, string.symbol(i), string.params(i), false)?;
            i += 1;
            continue;
        };
        let rest = table.productions[p as usize].pred_rest.len();
        if table.max_depth == 0 {
            // cpfg finds the rule (running its condition and statements) before it looks
            // at the depth: at a maximum depth of 0 the module is then read as it is.
            sink(ctx, string.symbol(i), string.params(i), false)?;
            i += 1;
            continue;
        }
        successor_of(ctx, table, p, birth as u16, &mut produced)?;
        let ls = ctx.ls;
        let context = |p: &crate::lsystem::grammar::Production, args: &mut [f64]| {
            (p.left.is_empty() || match_left(ls, string, links, i, p, args))
                && (p.right.is_empty() || match_right(ls, string, links, i + rest, p, args))
        };
        expander.expand_successor(ctx, table, &produced, 1, context, &mut sink)?;
        i += 1 + rest;
    }
    Ok(())
}
