//! Every grammar shipped in `examples/grammars/` parses, derives and draws, and has a test
//! on a property of its result that follows from the grammar.

use arbor::lsystem::{LSystem, LsystemOptions, ModuleString};
use arbor::skeleton::Skeleton;
use glam::Vec3;

fn source(name: &str) -> String {
    let path = format!("{}/examples/grammars/{name}.l", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn grammar(name: &str) -> LSystem {
    LSystem::parse(&source(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn grow(name: &str) -> Skeleton {
    grammar(name)
        .skeleton(&LsystemOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn max_abs_z(s: &Skeleton) -> f32 {
    s.branches()
        .iter()
        .flat_map(|b| [b.start[2], b.end[2]])
        .fold(0.0f32, |m, z| m.max(z.abs()))
}

fn count(ls: &LSystem, s: &ModuleString, name: &str) -> usize {
    (0..s.len())
        .filter(|&i| ls.symbol_name(s.symbol(i)) == name)
        .count()
}

#[test]
fn every_shipped_grammar_parses_derives_and_draws() {
    let dir = format!("{}/examples/grammars", env!("CARGO_MANIFEST_DIR"));
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "l") {
            continue;
        }
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        let s = grow(&name);
        assert!(!s.is_empty(), "{name} draws nothing");
        for b in s.branches() {
            assert!(
                b.start.iter().chain(&b.end).all(|v| v.is_finite()),
                "{name}"
            );
        }
        n += 1;
    }
    assert!(n >= 30, "only {n} grammars shipped");
}

/// F counts of `X → a F + b X`-style grammars: `(F, X)` after `steps`, where one step maps
/// F to `ff` F's and X to `fx` F's and `xx` X's.
fn linear_counts(
    steps: u32,
    ff: usize,
    fx: usize,
    xx: usize,
    f0: usize,
    x0: usize,
) -> (usize, usize) {
    let (mut f, mut x) = (f0, x0);
    for _ in 0..steps {
        (f, x) = (ff * f + fx * x, xx * x);
    }
    (f, x)
}

#[test]
fn abop_figure_1_24_counts_follow_from_the_productions() {
    // (name, steps, F→ how many F, X→ how many F, X→ how many X, axiom F, axiom X)
    let cases = [
        ("abop_1_24a", 5, 5, 0, 0, 1, 0),
        ("abop_1_24b", 5, 5, 0, 0, 1, 0),
        ("abop_1_24c", 4, 8, 0, 0, 1, 0),
        ("abop_1_24d", 7, 2, 2, 3, 0, 1),
        ("abop_1_24e", 7, 2, 2, 3, 0, 1),
        ("abop_1_24f", 5, 2, 3, 4, 0, 1),
    ];
    for (name, steps, ff, fx, xx, f0, x0) in cases {
        let ls = grammar(name);
        assert_eq!(ls.derivation_length(), steps, "{name}");
        let s = ls.derive(&LsystemOptions::default()).unwrap();
        let (f, x) = linear_counts(steps, ff, fx, xx, f0, x0);
        assert_eq!(count(&ls, &s, "F"), f, "{name}");
        assert_eq!(count(&ls, &s, "X"), x, "{name}");
        let sk = ls.interpret(&s, &LsystemOptions::default()).unwrap();
        assert_eq!(sk.len(), f, "{name}: one branch per F");
        assert!(max_abs_z(&sk) < 1e-3, "{name} is planar");
        // Every internode has unit length.
        for b in sk.branches() {
            assert!((b.length() - 1.0).abs() < 1e-3, "{name}");
        }
    }
    // 1.24a in full: 5^5 F's and 6 other modules for each F rewritten.
    let ls = grammar("abop_1_24a");
    let s = ls.derive(&LsystemOptions::default()).unwrap();
    assert_eq!(s.len(), 3125 + 6 * (1 + 5 + 25 + 125 + 625));
}

#[test]
fn koch_snowflake_is_a_closed_planar_curve() {
    let s = grow("koch_snowflake");
    assert_eq!(s.len(), 3 * 4usize.pow(4));
    let last = s.branches().last().unwrap();
    assert!(
        last.end().length() < 1e-3,
        "the curve closes: {:?}",
        last.end
    );
    assert!(max_abs_z(&s) < 1e-4);
    // Consecutive segments connect.
    for w in s.branches().windows(2) {
        assert!((w[0].end() - w[1].start()).length() < 1e-4);
    }
}

#[test]
fn binary_tree_counts_and_mirror_symmetry() {
    let ls = grammar("binary_tree");
    let s = ls.derive(&LsystemOptions::default()).unwrap();
    let (mut a, mut b) = (1usize, 0usize);
    for _ in 0..6 {
        (a, b) = (2 * a, a + 2 * b);
    }
    assert_eq!(count(&ls, &s, "a"), a);
    assert_eq!(count(&ls, &s, "b"), b);
    let sk = ls.interpret(&s, &LsystemOptions::default()).unwrap();
    assert_eq!(sk.len(), a + b, "a and b are both drawn as F");
    let (lo, hi) = sk.bounds().unwrap();
    assert!((lo.x + hi.x).abs() < 1e-3, "symmetric: {lo} {hi}");
    assert!(hi.x > 1.0, "the interpretation rules turn the branches");
}

#[test]
fn fern_two_formulations_agree_and_mirror_figure_1_24f() {
    let a = grow("fern");
    let b = grow("fern_xf");
    let mirror = grow("abop_1_24f");
    assert_eq!(a.len(), b.len());
    assert_eq!(a.len(), mirror.len());
    for ((x, y), m) in a.branches().iter().zip(b.branches()).zip(mirror.branches()) {
        assert!((x.end() - y.end()).length() < 1e-4);
        assert_eq!((x.parent, x.birth, x.order), (y.parent, y.birth, y.order));
        let mirrored = Vec3::new(-m.end[0], m.end[1], m.end[2]);
        assert!((x.end() - mirrored).length() < 1e-3);
    }
}

#[test]
fn parametric_examples() {
    let s = grow("parametric_double");
    assert_eq!(s.len(), 1);
    assert!((s.branches()[0].length() - 64.0).abs() < 1e-4);

    let s = grow("parametric_rolls");
    // X → 3 F + 5 X per step: 3 (5^5 − 1) / 4 F's.
    assert_eq!(s.len(), 3 * (5usize.pow(5) - 1) / 4);
    assert!(
        s.branches()
            .iter()
            .all(|b| (b.length() - 10.0).abs() < 1e-3)
    );
    assert!(max_abs_z(&s) > 1.0, "rolls take it out of the plane");

    // ABOP 2.8a: the A's triple each step and each makes 4 F's, plus the trunk.
    let with = grow("parametric_tropism");
    assert_eq!(with.len(), 1 + 4 * (3usize.pow(6) - 1) / 2);
    let straight = LSystem::parse(&source("parametric_tropism").replace("E: 0.22", "E: 0"))
        .unwrap()
        .skeleton(&LsystemOptions::default())
        .unwrap();
    assert_eq!(straight.len(), with.len());
    let mean_y = |s: &Skeleton| s.branches().iter().map(|b| b.end[1]).sum::<f32>() / s.len() as f32;
    assert!(
        mean_y(&with) < mean_y(&straight) - 10.0,
        "tropism bends the branches down: {} vs {}",
        mean_y(&with),
        mean_y(&straight)
    );
    // Widths grow by vr per step from the base: the trunk is the widest.
    let trunk = with.branches()[0].start_radius;
    assert!(with.branches().iter().all(|b| b.start_radius <= trunk));
    assert!((trunk - 0.5 * 1.732f32.powi(6)).abs() < 1e-2, "{trunk}");
}

#[test]
fn signals_propagate_as_the_book_prints() {
    let strings_by_step = |name: &str, expected: &[&str]| {
        let ls = grammar(name);
        for (n, want) in expected.iter().enumerate() {
            let o = LsystemOptions::default().steps(Some(n as u32));
            assert_eq!(ls.format(&ls.derive(&o).unwrap()), *want, "{name} step {n}");
        }
    };
    strings_by_step(
        "signal_acropetal",
        &[
            "Fb[+Fa]Fa[-Fa]Fa[+Fa]Fa",
            "Fb[+Fb]Fb[-Fa]Fa[+Fa]Fa",
            "Fb[+Fb]Fb[-Fb]Fb[+Fa]Fa",
            "Fb[+Fb]Fb[-Fb]Fb[+Fb]Fb",
        ],
    );
    strings_by_step(
        "signal_basipetal",
        &[
            "Fa[+Fa]Fa[-Fa]Fa[+Fa]Fb",
            "Fa[+Fa]Fa[-Fa]Fb[+Fa]Fb",
            "Fa[+Fa]Fb[-Fa]Fb[+Fa]Fb",
            "Fb[+Fa]Fb[-Fa]Fb[+Fa]Fb",
        ],
    );
    // The one-dimensional signal of ABOP 1.8: b moves right one place per step.
    let ls = LSystem::parse("Axiom: baaaaaaa\nb < a --> b\nb --> a").unwrap();
    for n in 0..8 {
        let o = LsystemOptions::default().steps(Some(n));
        let mut want = vec!['a'; 8];
        want[n as usize] = 'b';
        let want: String = want.into_iter().collect();
        assert_eq!(ls.format(&ls.derive(&o).unwrap()), want, "step {n}");
    }
}

/// A naive string-rewriting reference for non-parametric bracketed grammars with
/// single-symbol contexts and an ignore list: used to check the engine on ABOP 1.31a.
fn reference(
    axiom: &str,
    rules: &[(char, char, char, &str)],
    ignore: &str,
    steps: usize,
) -> Vec<String> {
    let mut s: Vec<char> = axiom.chars().collect();
    let mut out = vec![s.iter().collect()];
    for _ in 0..steps {
        let mut next = Vec::new();
        for i in 0..s.len() {
            let left = {
                let mut j = i;
                let mut found = None;
                while j > 0 {
                    j -= 1;
                    match s[j] {
                        ']' => {
                            let mut depth = 1;
                            while depth > 0 {
                                j -= 1;
                                match s[j] {
                                    ']' => depth += 1,
                                    '[' => depth -= 1,
                                    _ => {}
                                }
                            }
                        }
                        '[' => {}
                        c if ignore.contains(c) => {}
                        c => {
                            found = Some(c);
                            break;
                        }
                    }
                }
                found
            };
            let right = {
                let mut j = i + 1;
                let mut found = None;
                while j < s.len() {
                    match s[j] {
                        '[' => {
                            let mut depth = 1;
                            while depth > 0 {
                                j += 1;
                                match s[j] {
                                    '[' => depth += 1,
                                    ']' => depth -= 1,
                                    _ => {}
                                }
                            }
                            j += 1;
                        }
                        ']' => break,
                        c if ignore.contains(c) => j += 1,
                        c => {
                            found = Some(c);
                            break;
                        }
                    }
                }
                found
            };
            let rule = rules.iter().find(|&&(l, p, r, _)| {
                p == s[i] && (l == '*' || Some(l) == left) && (r == '*' || Some(r) == right)
            });
            match rule {
                Some(&(_, _, _, succ)) => next.extend(succ.chars()),
                None => next.push(s[i]),
            }
        }
        s = next;
        out.push(s.iter().collect());
    }
    out
}

#[test]
fn abop_1_31a_matches_a_naive_reference_at_every_step() {
    let rules = [
        ('0', '0', '0', "0"),
        ('0', '0', '1', "1[+F1F1]"),
        ('0', '1', '0', "1"),
        ('0', '1', '1', "1"),
        ('1', '0', '0', "0"),
        ('1', '0', '1', "1F1"),
        ('1', '1', '0', "0"),
        ('1', '1', '1', "0"),
        ('*', '+', '*', "-"),
        ('*', '-', '*', "+"),
    ];
    let want = reference("F1F1F1", &rules, "+-F", 30);
    let ls = grammar("context_1_31a");
    for (n, w) in want.iter().enumerate() {
        let o = LsystemOptions::default().steps(Some(n as u32));
        assert_eq!(&ls.format(&ls.derive(&o).unwrap()), w, "step {n}");
    }
    let s = grow("context_1_31a");
    assert_eq!(s.len(), want[30].matches('F').count());
    assert!(s.len() > 100, "it grows: {}", s.len());
    assert!(max_abs_z(&s) < 1e-3);
}

fn f_count(text: &str, seed: Option<u64>) -> (usize, String) {
    let text = match seed {
        Some(seed) => text
            .lines()
            .map(|l| {
                if l.starts_with("seed:") {
                    format!("seed: {seed}")
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n"),
        None => text.to_string(),
    };
    let ls = LSystem::parse(&text).unwrap();
    let s = ls.derive(&LsystemOptions::default()).unwrap();
    (count(&ls, &s, "F"), ls.format(&s))
}

#[test]
fn stochastic_grammars_are_seeded() {
    for k in 1..=6 {
        let text = source(&format!("stochastic_{k}"));
        let (n1, s1) = f_count(&text, None);
        let (n2, s2) = f_count(&text, None);
        assert_eq!(
            (n1, &s1),
            (n2, &s2),
            "stochastic_{k}: same seed, same string"
        );
        let distinct: std::collections::HashSet<String> =
            (0..8).map(|seed| f_count(&text, Some(seed)).1).collect();
        assert!(
            distinct.len() >= 4,
            "stochastic_{k}: seeds give only {} strings",
            distinct.len()
        );
        // Drawing agrees with the string and stays finite.
        let sk = LSystem::parse(&text)
            .unwrap()
            .skeleton(&LsystemOptions::default())
            .unwrap();
        assert_eq!(sk.len(), n1, "stochastic_{k}");
    }
    // The grammar's seed wins over the caller's; without one, the caller's is used.
    let text = source("stochastic_2");
    let ls = LSystem::parse(&text).unwrap();
    let with = |seed| ls.format(&ls.derive(&LsystemOptions::default().seed(seed)).unwrap());
    assert_eq!(with(10), with(11));
    let no_seed: String = text
        .lines()
        .filter(|l| !l.starts_with("seed:"))
        .collect::<Vec<_>>()
        .join("\n");
    let ls = LSystem::parse(&no_seed).unwrap();
    let with = |seed| ls.format(&ls.derive(&LsystemOptions::default().seed(seed)).unwrap());
    assert_eq!(with(10), with(10));
    assert_ne!(with(10), with(11));
}

#[test]
fn stochastic_frequencies_match_the_weights() {
    // 4096 modules A choose among weights 1 : 3 : 4 at the last step.
    let text = "derivation length: 14\nAxiom: X(12)\n\
                X(n) : n > 0 --> X(n-1)X(n-1)\nX(n) : n == 0 --> A\n\
                A --> B : 1\nA --> C : 3\nA --> D : 4\n";
    // arbor's stream (the host's seeds), then cpfg's (the grammar's `seed:` lines).
    let ls = LSystem::parse(text).unwrap();
    let runs: Vec<(LSystem, LsystemOptions)> = (1..=5)
        .map(|seed| (ls.clone(), LsystemOptions::default().seed(seed)))
        .chain((1..=5).map(|seed| {
            let with_seed = format!("seed: {seed}\n{text}");
            (
                LSystem::parse(&with_seed).unwrap(),
                LsystemOptions::default(),
            )
        }))
        .collect();
    for half in runs.chunks(5) {
        let (mut b, mut c, mut d) = (0usize, 0usize, 0usize);
        for (ls, options) in half {
            let s = ls.derive(options).unwrap();
            b += count(ls, &s, "B");
            c += count(ls, &s, "C");
            d += count(ls, &s, "D");
        }
        let total = (b + c + d) as f64;
        assert_eq!(total, 5.0 * 4096.0);
        // Binomial standard deviations are below 0.004 here; allow 0.015 (about 4 sigma).
        for (got, want) in [(b, 0.125), (c, 0.375), (d, 0.5)] {
            let f = got as f64 / total;
            assert!(
                (f - want).abs() < 0.015,
                "frequency {f}, weight share {want}"
            );
        }
    }
    // Without `seed:` and without a seed from the host, cpfg's L-system is deterministic:
    // the first applicable production, whatever its probability.
    let s = ls.derive(&LsystemOptions::default()).unwrap();
    assert_eq!(count(&ls, &s, "B"), 4096);
}

#[test]
fn decomposition_cut_polygons_and_leaves() {
    // Decomposition rewrites right after each step; its modules count as produced then.
    let ls = LSystem::parse(
        "derivation length: 2\nAxiom: A\nA --> AB\ndecomposition\nmaximum depth: 2\nB --> CC\nC --> F",
    )
    .unwrap();
    let s = ls.derive(&LsystemOptions::default()).unwrap();
    assert_eq!(ls.format(&s), "AFFFF");
    assert_eq!((s.birth(0), s.birth(1), s.birth(4)), (2, 2, 1));
    // Cut: % removes the rest of its branch as the next step begins, as in cpfg; one
    // the last step made is drawn past (`interpretation past %:` on), unless the view
    // file turns that off.
    let text = "derivation length: 1\nAxiom: F[FA F]F\nA --> %\nF --> F";
    let ls = LSystem::parse(text).unwrap();
    let last = ls.derive(&LsystemOptions::default()).unwrap();
    assert_eq!(ls.format(&last), "F[F%F]F");
    assert_eq!(ls.interpret(&last, &Default::default()).unwrap().len(), 4);
    let two = LsystemOptions::default().steps(Some(2));
    assert_eq!(ls.format(&ls.derive(&two).unwrap()), "F[F]F");
    let strict = LSystem::parse_with_view(text, "interpretation past %: off\n").unwrap();
    assert_eq!(strict.skeleton(&Default::default()).unwrap().len(), 3);
    // Polygons and leaf sites are recorded, not drawn as branches.
    // `~l` is a surface site (cpfg's predefined surface `l`).
    let ls = LSystem::parse("Axiom: F[{.+f.+f.+f.}]~lF").unwrap();
    let sk = ls.skeleton(&LsystemOptions::default()).unwrap();
    assert_eq!(sk.len(), 2);
    assert_eq!(sk.polygons().len(), 1);
    assert_eq!(sk.polygon(&sk.polygons()[0]).len(), 4);
    assert_eq!(sk.leaves().len(), 1);
    assert_eq!(sk.leaves()[0].branch, 0);
    assert_eq!(sk.leaves()[0].position, [0.0, 1.0, 0.0]);
    assert_eq!(
        sk.branches()[1].parent,
        0,
        "F after [ ] continues from the first F"
    );
}

#[test]
fn turtle_symbols_follow_cpfg() {
    let run = |axiom: &str| {
        let ls = LSystem::parse(&format!("angle increment: 90\nAxiom: {axiom}")).unwrap();
        ls.skeleton(&LsystemOptions::default()).unwrap()
    };
    let end = |s: &Skeleton| s.branches().last().unwrap().end();
    assert!(
        end(&run("+F")).abs_diff_eq(Vec3::new(-1.0, 0.0, 0.0), 1e-6),
        "+ turns toward -X"
    );
    assert!(end(&run("-F")).abs_diff_eq(Vec3::new(1.0, 0.0, 0.0), 1e-6));
    assert!(
        end(&run("&F")).abs_diff_eq(Vec3::new(0.0, 0.0, -1.0), 1e-6),
        "& pitches toward U = -Z"
    );
    assert!(end(&run("^F")).abs_diff_eq(Vec3::new(0.0, 0.0, 1.0), 1e-6));
    assert!(
        end(&run("/+F")).abs_diff_eq(Vec3::new(0.0, 0.0, -1.0), 1e-6),
        "/ rolls L toward U"
    );
    assert!(end(&run("\\+F")).abs_diff_eq(Vec3::new(0.0, 0.0, 1.0), 1e-6));
    assert!(end(&run("|F")).abs_diff_eq(Vec3::new(0.0, -1.0, 0.0), 1e-6));
    assert!(end(&run("F(2)f(3)F")).abs_diff_eq(Vec3::new(0.0, 6.0, 0.0), 1e-6));
    assert_eq!(
        run("F(2)f(3)F").branches()[1].parent,
        u32::MAX,
        "a move starts a new root"
    );
    assert!(end(&run("@M(1,2,3)F")).abs_diff_eq(Vec3::new(1.0, 3.0, 3.0), 1e-6));
    assert!(end(&run("@R(1,0,0)F")).abs_diff_eq(Vec3::new(1.0, 0.0, 0.0), 1e-6));
    assert!(end(&run("+(30)F(2)")).abs_diff_eq(Vec3::new(-1.0, 3f32.sqrt(), 0.0), 1e-5));
    // $ rolls L back to horizontal after a roll and a pitch.
    let s = run("/(30)&(30)$+F");
    let e = end(&s);
    assert!(
        e.y.abs() < 1e-5,
        "after $ a + turn stays horizontal-ish: {e}"
    );
    // Widths: !(w) sets, # and ! step by the increment; radius is half the width.
    let ls = LSystem::parse("line width increment: 0.5\nAxiom: !(4)F#F!!F").unwrap();
    let s = ls.skeleton(&LsystemOptions::default()).unwrap();
    let radii: Vec<f32> = s.branches().iter().map(|b| b.start_radius).collect();
    assert_eq!(radii, vec![2.0, 2.25, 1.75]);
    // Consecutive F's stay separate internodes linked as parent and child on one axis.
    let s = run("FF[+F]F");
    let b = s.branches();
    assert_eq!((b[1].parent, b[2].parent, b[3].parent), (0, 1, 1));
    assert_eq!((b[1].order, b[2].order, b[3].order), (0, 1, 0));
    assert_eq!(
        b.iter().map(|x| x.birth).max(),
        Some(0),
        "axiom modules have depth 0"
    );
}

#[test]
fn derivation_limits_stop_before_the_memory_is_spent() {
    let ls = LSystem::parse("Axiom: F\nF --> FF").unwrap();
    let o = LsystemOptions::default()
        .steps(Some(60))
        .max_modules(1 << 20);
    match ls.derive(&o) {
        Err(arbor::Error::LimitExceeded {
            limit_name, step, ..
        }) => {
            assert_eq!(limit_name, "max_modules");
            assert_eq!(step, Some(21), "2^21 modules first pass 2^20 at step 21");
        }
        other => panic!("{other:?}"),
    }
    let ls = LSystem::parse("Axiom: A(1)\nA(x) --> A(x)A(x)B(x,x,x,x)").unwrap();
    let o = LsystemOptions::default().steps(Some(40)).max_params(1000);
    let e = ls.derive(&o).unwrap_err();
    assert!(e.to_string().contains("max_params"), "{e}");
    // An interpretation rule that expands without end is bounded by its maximum depth.
    let ls = LSystem::parse("Axiom: X\nhomomorphism\nmaximum depth: 12\nX --> F[+X][-X]").unwrap();
    let s = ls.skeleton(&LsystemOptions::default()).unwrap();
    assert_eq!(s.len(), (1 << 12) - 1);
    let o = LsystemOptions::default().max_branches(100);
    assert!(matches!(
        ls.skeleton(&o),
        Err(arbor::Error::LimitExceeded { .. })
    ));
}

#[test]
fn same_grammar_same_options_same_string() {
    for name in ["stochastic_4", "parametric_tropism", "context_1_31a"] {
        let ls = grammar(name);
        let a = ls.derive(&LsystemOptions::default()).unwrap();
        let b = ls.derive(&LsystemOptions::default()).unwrap();
        assert_eq!(a, b, "{name}");
    }
}

#[test]
fn non_finite_values_are_an_error_with_the_module() {
    let ls = LSystem::parse("derivation length: 1\nAxiom: A(0)\nA(x) --> F(log(x))").unwrap();
    let e = ls.derive(&LsystemOptions::default()).unwrap_err();
    assert!(matches!(e, arbor::Error::Eval { step: 1, .. }), "{e}");
    assert!(e.to_string().contains("`F`"), "{e}");
}

#[test]
fn turn_jitter_varies_turns_within_its_bound() {
    let ls = LSystem::parse("angle increment: 30\nAxiom: F+F+F+F-F&F^F").unwrap();
    let run = |seed, turn_jitter| {
        ls.skeleton(
            &LsystemOptions::default()
                .seed(seed)
                .turn_jitter(turn_jitter),
        )
        .unwrap()
    };
    assert_eq!(
        run(1, 0.0),
        run(2, 0.0),
        "no jitter: the seed does not matter"
    );
    assert_eq!(run(1, 5.0), run(1, 5.0), "same seed, same plant");
    assert_ne!(run(1, 5.0), run(2, 5.0), "another seed, another plant");
    let s = run(3, 5.0);
    let b = s.branches();
    let mut moved = false;
    for w in b.windows(2) {
        let a = (w[0].end() - w[0].start())
            .normalize()
            .angle_between((w[1].end() - w[1].start()).normalize())
            .to_degrees();
        assert!(
            (25.0 - 1e-3..=35.0 + 1e-3).contains(&a),
            "turn of {a} degrees"
        );
        moved |= (a - 30.0).abs() > 0.01;
    }
    assert!(moved, "the turns really vary");
    let bad = LsystemOptions::default().turn_jitter(-1.0);
    assert!(ls.skeleton(&bad).is_err());
}

/// A string remembers the grammar that derived it: reading it with another grammar (whose
/// symbol table differs) is an error naming the string, not a panic or a wrong tree.
#[test]
fn a_string_is_read_only_by_its_own_grammar() {
    let big = LSystem::parse("derivation length: 2\nAxiom: A\nA --> F[+B][-C]D E A").unwrap();
    let small = LSystem::parse("derivation length: 1\nAxiom: F\nF --> FF").unwrap();
    let options = LsystemOptions::default();
    let s = big.derive(&options).unwrap();
    let err = small.interpret(&s, &options).unwrap_err();
    assert!(
        matches!(
            err,
            arbor::Error::InvalidArgument {
                field: "string",
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("another grammar"), "{err}");
    // The same grammar, or a clone of it, reads it.
    assert!(big.interpret(&s, &options).is_ok());
    assert!(big.clone().interpret(&s, &options).is_ok());
}
