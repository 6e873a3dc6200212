//! Grammar semantics as cpfg has them, each on a minimal grammar of arbor's own. The
//! expected strings are what the real cpfg (built headless from the vlab sources, see
//! `../shared/cpfg-oracle`) derives for the same constructs; the comment on each test says
//! which rule of cpfg's it pins down.

use arbor::lsystem::{LSystem, LsystemOptions};

/// The string `text` derives, formatted as arbor prints it (`F(1)A(2,3)`).
fn derived(text: &str) -> String {
    let ls = LSystem::parse(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let s = ls.derive(&LsystemOptions::default()).unwrap();
    ls.format(&s)
}

/// QLS: cpfg answers query modules before each step's rewriting, so a `?P` the last step
/// makes keeps the values it was made with, and one that was there before the last step
/// holds the turtle's position then.
#[test]
fn queries_are_answered_before_each_step() {
    let made_last = "derivation length: 2\nAxiom: A\nA --> F B\nB --> F ?P(0,0,0)\n";
    assert_eq!(derived(made_last), "FF?P(0,0,0)");
    let kept = "derivation length: 2\nAxiom: F ?P(7,7,7) A\nA --> F\n";
    assert_eq!(derived(kept), "F?P(0,1,0)F");
    // A step that copies an answered query carries the answer on.
    let copied = "derivation length: 3\nAxiom: F F ?P(9,9,9)\n?P(x,y,z) --> ?P(x+1,y,z)\n";
    assert_eq!(derived(copied), "FF?P(1,2,0)");
}

/// EQ: `=` in a right context stands for the rest of the current branch, so a context can
/// name a branch's first module and ignore what follows it.
#[test]
fn eq_in_a_right_context_skips_the_rest_of_the_branch() {
    let text = "derivation length: 1\nconsider: N[]\n\
                Axiom: N(1) [ N(10) F N(100) ] [ N(1000) ] N(10000)\n\
                N(w) > [N(a)=][N(b)=]N(c) --> N(w+a+b+c)\n";
    assert_eq!(derived(text), "N(11011)[N(10)FN(100)][N(1000)]N(10000)");
    // The branch's first considered module must still match.
    let other = text
        .replace("consider: N[]", "consider: NK[]")
        .replace("[ N(10) F", "[ K N(10) F");
    assert_eq!(derived(&other), "N(1)[KN(10)FN(100)][N(1000)]N(10000)");
}

/// CON: under `consider:`, a bracket the list does not name is ignored like any other
/// module, so a right context leaves its branch and finds what follows the branch.
#[test]
fn an_unconsidered_bracket_is_ignored_in_a_right_context() {
    let text = "derivation length: 1\nconsider: MK\nAxiom: F [ + F M ] K\nM > K --> X\n";
    assert_eq!(derived(text), "F[+FX]K");
    // Listed, the `]` ends the branch and the context fails.
    let listed = text.replace("consider: MK", "consider: MK[]");
    assert_eq!(derived(&listed), "F[+FM]K");
}

/// DAX: the axiom is decomposed during step 1, as every step decomposes what it makes or
/// copies, not before the first step.
#[test]
fn the_axiom_is_decomposed_during_step_one() {
    let text =
        |n: u32| format!("derivation length: {n}\nAxiom: Y\nC --> D\ndecomposition\nY --> C\n");
    assert_eq!(derived(&text(0)), "Y");
    assert_eq!(derived(&text(1)), "C");
    assert_eq!(derived(&text(2)), "D");
    // A ring L-system whose axiom decomposes into context for its first step.
    let ring = "ring lsystem\nderivation length: 1\nAxiom: Y(3)\nP < Q --> P\nP --> Q\n\
                decomposition\nmaximum depth: 10\nY(n) : n>1 --> Y(n-1)Q\nY(n) : n==1 --> P\n";
    assert_eq!(derived(ring), "PQQ");
}

/// LEN: cpfg takes any derivation length; a model that ends itself with `stop()` after a
/// few steps runs with a length past 65,535.
#[test]
fn a_long_derivation_length_ends_at_stop() {
    let text = "derivation length: 2000000\nStart: {k = 0;}\n\
                EndEach: {k = k + 1; if (k >= 4) {stop(1);}}\nAxiom: B\nB --> F B\n";
    assert_eq!(derived(text), "FFFFB");
    // The birth of a module made past step 65,535 reads 65,535.
    let ls = LSystem::parse("derivation length: 70000\nAxiom: B\nB --> C\nC --> B\n").unwrap();
    let s = ls.derive(&LsystemOptions::default()).unwrap();
    assert_eq!((ls.format(&s), s.birth(0)), ("B".to_string(), 65_535));
}

/// The branches `text` draws: (count, total length).
fn drawn(text: &str) -> (usize, f32) {
    let ls = LSystem::parse(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let s = ls.skeleton(&LsystemOptions::default()).unwrap();
    let length = s
        .branches()
        .iter()
        .map(|b| (glam::Vec3::from(b.end) - glam::Vec3::from(b.start)).length())
        .sum();
    (s.len(), length)
}

/// HMM: an interpretation rule whose predecessor is several modules also applies to what
/// another interpretation rule made, matched against that rule's successor as a whole;
/// a rule of several modules never applies to one module alone.
#[test]
fn multi_module_interpretation_rules_match_rule_output() {
    let text = |second: &str| {
        format!(
            "derivation length: 0\nAxiom: W\nhomomorphism\nmaximum depth: 2\n\
             W --> {second}\nQa --> F(1)\nQb --> F(2)\n"
        )
    };
    assert_eq!(drawn(&text("Qb Zb")), (1, 2.0));
    assert_eq!(drawn(&text("Qa Zb")), (1, 1.0));
    // Q alone (no a or b after it) is drawn by no rule.
    assert_eq!(drawn(&text("Q Zb")), (0, 0.0));
}

/// HCTX: interpretation rules may have context (cpfg is built with it), read from the
/// L-system string; a module a rule made reads the context of the string's module whose
/// rewriting made it (cpfg passes that module's context down every depth).
#[test]
fn interpretation_rules_read_context_from_the_string() {
    let text = "derivation length: 1\nAxiom: K J K\nJ --> J\nhomomorphism\n\
                K > J --> F(3)\nK --> F(1)\n";
    assert_eq!(drawn(text), (2, 4.0));
    let left = "derivation length: 0\nAxiom: K J K\nhomomorphism\nJ < K --> F(5)\nK --> F(1)\n";
    assert_eq!(drawn(left), (2, 6.0));
    // A K made by a rule from M reads M's context in the string: J on its right (cpfg
    // draws F(3)).
    let made = "derivation length: 0\nAxiom: M J\nhomomorphism\nmaximum depth: 2\n\
                M --> K\nK > J --> F(3)\nK --> F(1)\n";
    assert_eq!(drawn(made), (1, 3.0));
    // Decomposition rules still may not have context.
    let e = LSystem::parse("Axiom: K\ndecomposition\nK > J --> F\n").unwrap_err();
    assert!(
        e.to_string().contains("context in decomposition rules"),
        "{e}"
    );
}

/// A model of files held in memory (`m/NAME`), read as a host's files; its skeleton.
fn grown_from_files(files: &[(&str, &str)]) -> arbor::skeleton::Skeleton {
    use arbor::files::{FileAccess, FileOptions};
    let map = files
        .iter()
        .map(|(k, v)| (format!("m/{k}"), v.as_bytes().to_vec()))
        .collect();
    let options = FileOptions::default().access(FileAccess::from_map(map));
    let run = &mut arbor::progress::Run::default();
    let ls = LSystem::from_file_with("m/plant.l", None, &options, run).unwrap();
    ls.skeleton(&LsystemOptions::default()).unwrap()
}

fn ends(s: &arbor::skeleton::Skeleton) -> Vec<[f32; 3]> {
    s.branches().iter().map(|b| b.end).collect()
}

fn close(got: &[[f32; 3]], want: &[[f32; 3]]) -> bool {
    got.len() == want.len()
        && got
            .iter()
            .zip(want)
            .all(|(a, b)| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-3))
}

/// FBEND: the view file's older tropism (`tropism direction:`) bends the heading after
/// `f` and `g` as it does after `F` and `G`.
#[test]
fn the_older_tropism_bends_after_moves_too() {
    let s = grown_from_files(&[
        ("plant.l", "derivation length: 0\nAxiom: g(1) F(1)\n"),
        (
            "plant.v",
            "tropism direction: 1,0,0\ninitial elasticity: 0.5\n",
        ),
    ]);
    // After g(1) the heading leans 30 degrees toward +x.
    assert!(close(&ends(&s), &[[0.5, 1.866, 0.0]]), "{:?}", ends(&s));
}

/// TROP0: without `tropism direction:`, cpfg's tropism vector is (0, 1, 0), so `_(e)`
/// alone bends toward +Y.
#[test]
fn elasticity_bends_toward_cpfgs_default_direction() {
    let s = grown_from_files(&[(
        "plant.l",
        "derivation length: 0\nAxiom: +(90) _(0.5) F(1) F(1)\n",
    )]);
    assert!(
        close(&ends(&s), &[[-1.0, 0.0, 0.0], [-1.866, 0.5, 0.0]]),
        "{:?}",
        ends(&s)
    );
    // Without `_` nothing bends.
    let straight =
        grown_from_files(&[("plant.l", "derivation length: 0\nAxiom: +(90) F(1) F(1)\n")]);
    assert!(close(
        &ends(&straight),
        &[[-1.0, 0.0, 0.0], [-2.0, 0.0, 0.0]]
    ));
}

/// END: after a predefined surface, the turtle stands at the surface's END POINT (in the
/// surface's frame, over its SIZE, times the scale).
#[test]
fn a_surface_moves_the_turtle_to_its_end_point() {
    let patch = "0.00 0.00 0.00  1.00 0.00 0.00  2.00 0.00 0.00  3.00 0.00 0.00\n\
                 0.00 1.00 0.00  1.00 1.00 0.00  2.00 1.00 0.00  3.00 1.00 0.00\n\
                 0.00 2.00 0.00  1.00 2.00 0.00  2.00 2.00 0.00  3.00 2.00 0.00\n\
                 0.00 4.00 0.00  1.00 4.00 0.00  2.00 4.00 0.00  3.00 4.00 0.00\n";
    let surface = format!(
        "0 4 0 4 0 0\nCONTACT POINT X: 0 Y: 0 Z: 0\nEND POINT X: 0 Y: 4 Z: 0\n\
         HEADING X: 0 Y: 1 Z: 0\nUP X: 0 Y: 0 Z: 1\nSIZE: 4\nleaf\n\
         TOP COLOR: 1 DIFFUSE: 0 BOTTOM COLOR: 1 DIFFUSE: 0\nAL: ~ A: ~ AR: ~\n\
         L: ~ R: ~\nBL: ~ B: ~ BR: ~\n{patch}"
    );
    let s = grown_from_files(&[
        ("plant.l", "derivation length: 0\nAxiom: F(1) ~q(2) F(1)\n"),
        ("plant.v", "surface: q q.s 1\n"),
        ("q.s", &surface),
    ]);
    // END POINT 4 of SIZE 4 is one unit, scaled by 2: the second F starts at y = 3.
    assert!(
        close(&ends(&s), &[[0.0, 1.0, 0.0], [0.0, 4.0, 0.0]]),
        "{:?}",
        ends(&s)
    );
    assert_eq!(s.branches()[1].start, [0.0, 3.0, 0.0]);
    // A surface whose HEADING and UP are not the turtle's axes, after a roll: where the
    // real cpfg starts the second F for this file.
    let turned = surface
        .replace("END POINT X: 0 Y: 4 Z: 0", "END POINT X: 1 Y: 2 Z: 3")
        .replace("HEADING X: 0 Y: 1 Z: 0", "HEADING X: 1 Y: 0 Z: 0")
        .replace("UP X: 0 Y: 0 Z: 1", "UP X: 0 Y: 1 Z: 0");
    assert!(turned.contains("HEADING X: 1"), "{turned}");
    let s = grown_from_files(&[
        (
            "plant.l",
            "derivation length: 0\nAxiom: F(1) /(30) ~q(2) F(1)\n",
        ),
        ("plant.v", "angle factor: 8\nsurface: q q.s 1\n"),
        ("q.s", &turned),
    ]);
    let start = s.branches()[1].start;
    for (got, want) in start.iter().zip([-0.616_025_4_f32, 2.5, -0.933_012_7]) {
        assert!((got - want).abs() < 1e-5, "{start:?}");
    }
}

/// FUNC: `func()` as cpfg computes it: each value where the curve's x comes within 0.001
/// of the x asked for (by bisection), `samples:` of them precomputed and interpolated.
/// These are cpfg's own values for this curve (0.1 at 0, 1 from 0.05 to 0.5, 0.1 at 1).
#[test]
fn func_reads_cpfgs_sample_table() {
    let s = grown_from_files(&[
        (
            "plant.l",
            "derivation length: 1\nAxiom: A\nA --> F(func(1,0)) F(func(1,0.02)) F(func(1,0.5))\n",
        ),
        ("plant.v", "function: w.func 100\n"),
        (
            "w.func",
            "fver 1 1\nname: W\nsamples: 100\nflip: off\npoints: 4\n\
             0.000000 0.100000\n0.050000 1.000000\n0.500000 1.000000\n1.000000 0.100000\n",
        ),
    ]);
    let lengths: Vec<f32> = s.branches().iter().map(|b| b.end[1] - b.start[1]).collect();
    for (got, want) in lengths.iter().zip([0.110506, 0.301662, 0.719684]) {
        assert!((got - want).abs() < 1e-5, "{lengths:?}");
    }
}

/// Organs of a negative diameter (a function a hair below 0) draw at its magnitude, as
/// cpfg's do, instead of stopping the model.
#[test]
fn a_negative_organ_size_draws_its_magnitude() {
    let ls = LSystem::parse("derivation length: 0\nAxiom: F @O(-0.5)\n").unwrap();
    let s = ls.skeleton(&LsystemOptions::default()).unwrap();
    assert_eq!(s.organs()[0].size, 0.5);
}

/// TIL: cpfg keeps `~l(s)` and `@o(r)` as two modules (`~` then `l(s)`), so productions
/// for `l` and `o` rewrite the module after a `~` or `@`.
#[test]
fn productions_rewrite_what_follows_tilde_and_at() {
    let text =
        "derivation length: 2\nAxiom: F ~k(1) @o(1) k(5)\nk(s) --> k(s*3)\no(r) --> o(r+2)\n";
    assert_eq!(derived(text), "F~k(9)@o(5)k(45)");
    // A successor that starts with a module of several characters keeps the `~` alone.
    let other = "derivation length: 1\nAxiom: ~k(1)\nk(s) --> Fk(s)\n";
    assert_eq!(derived(other), "~Fk(1)");
}

/// RND: a grammar with `seed:` is stochastic as cpfg's: drand48 seeded by
/// seed48({seed, 0, 155}), one draw for every module of cpfg's string (one a character:
/// `@Gs` is three), every applicable production weighed (1 without a probability). The
/// expected strings are the real cpfg's for these grammars.
#[test]
fn stochastic_grammars_draw_as_cpfg() {
    let text = |n: u32| {
        format!(
            "seed: 7\nderivation length: {n}\nAxiom: @Gs A ~k(1) A\nA --> A B : 1\nA --> A C : 2\n\
             k(s) --> k(s+1) : 1\nk(s) --> k(s+10) : 1\n"
        )
    };
    assert_eq!(derived(&text(1)), "@GsAB~k(11)AC");
    assert_eq!(derived(&text(2)), "@GsACB~k(12)ACC");
    assert_eq!(derived(&text(4)), "@GsABBCB~k(32)ACBCC");
    // Without `seed:` cpfg is deterministic: the first applicable production.
    let none = text(2).replace("seed: 7\n", "");
    assert_eq!(derived(&none), "@GsABB~k(3)ABB");
    // ran() draws from cpfg's erand48 words {0x330E, 0, 0}: 0.1708..., then 0.7499...
    assert_eq!(
        derived("derivation length: 1\nAxiom: A\nA --> F(ran(1)) F(ran(10))\n"),
        "F(0.17082803)F(7.4990196)"
    );
}

/// cpfg passes over blanks between `@` and its letters (`@ Tx(1)` is `@Tx(1)`).
#[test]
fn blanks_after_at_are_passed_over() {
    assert_eq!(
        derived("derivation length: 0\nAxiom: F @ Tx(1) F @\tGs\n"),
        "F@Tx(1)F@Gs"
    );
}

/// A `]` in a right context must meet the `]` that ends the branch (cpfg's answers):
/// `B > ]E` does not match in `A[B[C]D]E` (D comes first); `B > =]E` does.
#[test]
fn a_closing_bracket_in_a_right_context_must_come_next() {
    let text = |ctx: &str| format!("derivation length: 1\nAxiom: A[B[C]D]E\nB > {ctx} --> X\n");
    assert_eq!(derived(&text("]E")), "A[B[C]D]E");
    assert_eq!(derived(&text("=]E")), "A[X[C]D]E");
    assert_eq!(
        derived("derivation length: 1\nAxiom: A[B]E\nB > ]E --> X\n"),
        "A[X]E"
    );
}

/// A `%` cuts as the rewriting reaches it, as cpfg's: context before it still sees what it
/// cuts during that step, and a stochastic grammar draws for the `%` but not for what it
/// cuts (the strings are the real cpfg's).
#[test]
fn a_cut_happens_as_the_rewriting_reaches_it() {
    let text = "derivation length: 1\nconsider: AB[]\nAxiom: A[%B(5)]\nA > [B(x)] --> C(x)\n";
    assert_eq!(derived(text), "C(5)[]");
    let drawn = "seed: 3\nderivation length: 2\nAxiom: A[K%FF]A\nA --> AB : 1\nA --> AC : 1\n";
    assert_eq!(derived(drawn), "ABC[K]ABC");
}

/// HMM-DEPTH: cpfg's InterpretHomomorphism rewrites a module of the string at depth 0,
/// the modules of that successor at depth 1, and so on; a module at `maximum depth:` is
/// drawn as it is. At every depth the first rule in file order whose predecessor (one
/// module or several of the same successor), context and condition match applies, and
/// context is read around the string's module whose rewriting began it all. Segments
/// (count, and the bounding box of their end points) as the real cpfg draws them with
/// `maximum depth: 3`.
#[test]
fn homomorphism_depth_is_applied_as_cpfg_applies_it() {
    #[rustfmt::skip]
    let cases: &[(&str, &str, usize, Option<[f32; 4]>)] = &[
        // axiom, rules, cpfg's segments, cpfg's box (min x, max x, min y, max y)
        ("FBF", "B --> FB\nF --> G[+F]", 14, None),
        ("FBF", "B --> F[+B]B\nF --> FF", 28, None),
        ("BF", "BF --> FBF", 4, None),
        ("BF", "BF --> F[+BF]BF", 15, Some([-2.7071, 0.0, 0.0, 4.0])),
        ("FBFBF", "BF --> F[+BF]BF", 31, None),
        ("CBF", "C < B --> F[+B]B", 8, Some([-1.7071, 0.0, 0.0, 4.0])),
        ("BF", "B > F --> F[+B]B", 8, None),
        ("FBFBF", "B > F --> F[+B]B", 17, Some([-1.7071, 0.0, 0.0, 9.0])),
        ("BF", "B --> F[+B]B\nBF --> FBF", 8, None),
        ("FBFBF", "B --> F[+B]B\nBF --> FBF", 17, None),
        ("FBF", "B --> F[-B]\nF --> B", 4, None),
    ];
    for &(axiom, rules, segments, bbox) in cases {
        let text = format!(
            "Lsystem: 1\nderivation length: 1\nAxiom: A\nA --> {axiom}\nhomomorphism\n\
             maximum depth: 3\n{rules}\nendlsystem\n"
        );
        let ls = LSystem::parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        let s = ls.skeleton(&LsystemOptions::default()).unwrap();
        assert_eq!(s.len(), segments, "{axiom} with {rules:?}");
        if let Some([x0, x1, y0, y1]) = bbox {
            let (mut lo, mut hi) = (glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN));
            for b in s.branches() {
                for p in [b.start(), b.end()] {
                    lo = lo.min(p);
                    hi = hi.max(p);
                }
            }
            let got = [lo.x, hi.x, lo.y, hi.y];
            for (g, w) in got.iter().zip([x0, x1, y0, y1]) {
                assert!((g - w).abs() < 1e-3, "{axiom} with {rules:?}: box {got:?}");
            }
        }
    }
}
