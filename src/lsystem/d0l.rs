//! The lookup-table rewriter of grammars without parameters, contexts, conditions,
//! probabilities, cuts or decomposition.

use super::ModuleString;
use super::ctx::Ctx;
use super::grammar::{ModuleList, Production, ProductionTable};
use crate::error::Result;
use crate::progress::Stage;

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

    pub(super) fn derive(&self, ctx: &mut Ctx<'_>, steps: u32) -> Result<ModuleString> {
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
            ctx.fx.fraction = (step - 1) as f64 / steps as f64;
            ctx.fx.progress.report(Stage::Derivation, ctx.fx.fraction)?;
            ctx.spend(cur.syms.len().max(super::ctx::STEP_WORK))?;
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
            let birth = super::ctx::birth(step);
            let n = cur.syms.len();
            let chunk = if ctx.fx.progress.active() {
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
                    ctx.fx.fraction = done / steps as f64;
                    ctx.fx.progress.report(Stage::Derivation, ctx.fx.fraction)?;
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
