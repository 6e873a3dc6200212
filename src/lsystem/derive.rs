//! A derivation: the steps of parallel rewriting over flat module strings,
//! double-buffered, with cpfg's blocks, cuts and query answers between the steps.

use super::ctx::{Ctx, STEP_WORK, birth as birth_of, emit};
use super::links::Links;
use super::query;
use super::rewrite::{Expander, copy_run, rewrite, select_multi, successor_of};
use super::{LSystem, LsystemOptions, ModuleString};
use crate::error::Result;
use crate::progress::Stage;

pub(crate) fn derive<'a>(
    ls: &'a LSystem,
    options: &LsystemOptions,
    progress: crate::progress::Run<'a>,
) -> Result<ModuleString> {
    let mut string = derive_string(ls, options, progress)?;
    string.grammar = ls.id;
    Ok(string)
}

fn derive_string<'a>(
    ls: &'a LSystem,
    options: &LsystemOptions,
    progress: crate::progress::Run<'a>,
) -> Result<ModuleString> {
    let steps = options.steps.unwrap_or(ls.derivation_length);
    let mut ctx = Ctx::new(ls, options);
    ctx.fx.progress = progress;
    ctx.steps = steps;
    if let Some(d0l) = &ls.d0l {
        let mut s = d0l.derive(&mut ctx, steps)?;
        ctx.fx.progress.report(Stage::Derivation, 1.0)?;
        s.work_left = Some(ctx.fx.budget);
        return Ok(s);
    }
    let mut cur = ModuleString::new();
    let mut next = ModuleString::new();
    // cpfg's order: Start, the axiom, then per step StartEach, the step, EndEach; End.
    ctx.run_block(&ls.blocks.start, "the Start: block")?;
    emit(&mut ctx, &ls.axiom, &[], 0, &mut cur)?;
    ctx.check("the axiom")?;
    // The axiom is decomposed during step 1, as cpfg decomposes what each step makes or
    // copies, not before it.
    // Query modules (`?P` ...) learn where the turtle is before every step's rewriting,
    // as cpfg answers them: those the last step makes stay as it made them.
    let queries = query::has_queries(ls);
    let mut links = Links::default();
    // Growth of the last step (modules, parameters), to size the next buffer once instead
    // of letting it double (and copy) its way up.
    let mut growth = (1.0f64, 1.0f64);
    for step in 1..=steps {
        if ctx.fx.stop {
            break;
        }
        ctx.step = step;
        ctx.fx.fraction = (step - 1) as f64 / steps as f64;
        ctx.fx.progress.report(Stage::Derivation, ctx.fx.fraction)?;
        ctx.spend((cur.len() + cur.params.len()).max(STEP_WORK))?;
        // A `%` cuts its branch in the next step, as the rewriting reaches it (see
        // `rewrite`): one made by the last step stays in the string and the turtle draws
        // past it, and until then context still sees what it will cut, as in cpfg.
        if queries {
            // The turtle's walk to answer them: a unit a module, and its rules' work.
            ctx.spend(cur.len())?;
            super::interpret::answer_queries(ls, &mut cur, options, &mut ctx.fx, step)?;
            ctx.fx.stage = Stage::Derivation;
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
        ctx.run_block(&ls.blocks.end_each, "the EndEach: block")?;
    }
    ctx.run_block(&ls.blocks.end, "the End: block")?;
    ctx.fx.progress.report(Stage::Derivation, 1.0)?;
    cur.globals = std::mem::take(&mut ctx.env.vars);
    cur.log = std::mem::take(&mut ctx.fx.log);
    cur.work_left = Some(ctx.fx.budget);
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
            if !table.has_rules[cur.syms[i] as usize] {
                // A run of modules without decomposition rules is copied at once.
                let j = cur.syms[i + 1..]
                    .iter()
                    .position(|&s| table.has_rules[s as usize])
                    .map_or(cur.len(), |k| i + 1 + k);
                copy_run(ctx, cur, i, j, spare)?;
                i = j;
                continue;
            }
            let birth = cur.births[i];
            let mut sink = |ctx: &mut Ctx<'_>, sym: u16, params: &[f32], new: bool| {
                ctx.room(spare, 1, params.len())?;
                spare.push(sym, if new { birth_of(ctx.step) } else { birth }, params);
                Ok(())
            };
            if let Some(p) = select_multi(ctx, table, cur, i) {
                successor_of(ctx, table, p, birth_of(ctx.step), &mut produced)?;
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

#[cfg(test)]
mod tests {
    use super::super::grammar::{POP, PUSH, branch_end};
    use super::*;
    use crate::error::Error;
    use crate::rng::Rng;

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
    /// strings, balanced or not: each bracket's partner (as a forward scan pairs them),
    /// the closing `]` of every position's branch, and the next module not skipped.
    #[test]
    fn links_equal_the_scans_they_replace() {
        // A right context with `=` asks for the branches' ends.
        let ls = LSystem::parse("ignore: B\nAxiom: A\nA > = B --> A\n").unwrap();
        let id = |name: &str| ls.symbols.names.iter().position(|n| n == name).unwrap() as u16;
        let (a, b) = (id("A"), id("B"));
        let mut rng = Rng::new(11);
        // One table for every string, as a derivation keeps it: a string after one that
        // needed the next-kept table makes it while its brackets are paired.
        let mut links = Links::default();
        let mut made_in_build = 0;
        for _ in 0..500 {
            // Long runs of B too, past the short scan.
            let n = (rng.next_u64() % 80) as usize;
            let bs = rng.next_u64() % 4 == 0;
            let syms: Vec<u16> = (0..n)
                .map(|_| match rng.next_u64() % if bs { 40 } else { 4 } {
                    0 => PUSH,
                    1 => POP,
                    2 => a,
                    _ => b,
                })
                .collect();
            let s = ModuleString {
                births: vec![0; n],
                syms: syms.clone(),
                ..Default::default()
            };
            links.build(&ls, &s);
            made_in_build += usize::from(links.table_ready());
            let mut forward = Vec::new();
            super::super::links::brackets(&s, &mut forward);
            assert_eq!(links.partner, forward, "{syms:?}");
            for j in 0..=n {
                let scan = branch_end(&syms, j).map_or(u32::MAX, |k| k as u32);
                assert_eq!(links.close[j], scan, "{syms:?} at {j}");
                let next = (j..n).find(|&k| syms[k] != b).unwrap_or(n);
                assert_eq!(links.next_kept(&ls, &s, j), next, "{syms:?} at {j}");
            }
        }
        assert!(
            made_in_build > 50,
            "the table was made in build {made_in_build} times"
        );
    }

    #[test]
    fn the_end_of_a_branch_skips_nested_branches() {
        let ls = LSystem::parse("Axiom: A[B[C]D]E").unwrap();
        let s = ls.derive(&options(0)).unwrap();
        // A [ B [ C ] D ] E: from B (index 2) the branch closes at 7; from C at 5.
        assert_eq!(branch_end(&s.syms, 2), Some(7));
        assert_eq!(branch_end(&s.syms, 4), Some(5));
        assert_eq!(branch_end(&s.syms, 8), None);
        // Right context `=]E` (cpfg's answers): `=` skips the rest of the branch, nested
        // ones too; `]E` alone needs the `]` next, so neither B nor C matches it.
        let ls = LSystem::parse("Axiom: A[B[C]D]E\nB > =]E --> X\nC > ]E --> Y\n").unwrap();
        assert_eq!(ls.format(&ls.derive(&options(1)).unwrap()), "A[X[C]D]E");
        let ls = LSystem::parse("Axiom: A[B[C]D]E\nB > ]E --> X\n").unwrap();
        assert_eq!(ls.format(&ls.derive(&options(1)).unwrap()), "A[B[C]D]E");
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

    #[test]
    fn a_symbols_only_production_needs_its_arity_and_the_stochastic_draw() {
        let grow = |text: &str| {
            let ls = LSystem::parse(text).unwrap();
            let s = derive(&ls, &options(1), Default::default()).unwrap();
            ls.format(&s)
        };
        // `A(x)` is A's one production: it rewrites A(1), not A(1,2) or A.
        assert_eq!(grow("Axiom: A(1)A(1,2)A\nA(x) --> B(x+1)\n"), "B(2)A(1,2)A");
        // Under cpfg's random stream the one production still takes its draw: the
        // stochastic choice after it sees the same stream as a derivation without it.
        let coins = "C --> D : 1\nC --> E : 1\n";
        assert_eq!(
            grow(&format!(
                "seed: 5\nAxiom: A(1)CCCCCCCCCCCC\nA(x) --> B(x)\n{coins}"
            )),
            grow(&format!(
                "seed: 5\nAxiom: A(1)CCCCCCCCCCCC\nA(x) : 1 --> B(x)\n{coins}"
            ))
        );
        // A module no production takes (its arity matches none) draws as a module of a
        // symbol without productions does.
        assert_eq!(
            grow(&format!("seed: 5\nAxiom: A(1,2)CCCCCCCCCCCC\n{coins}")),
            grow(&format!(
                "seed: 5\nAxiom: A(1,2)CCCCCCCCCCCC\nA(x) --> B(x)\n{coins}"
            ))
        );
    }
}
