//! Property tests over hostile input: random grammars built from the language's pieces,
//! random mutations of the shipped grammars, and random bytes. Whatever comes in, arbor
//! answers `Ok` or an error (a parse error has a position), never panics, stays within
//! its limits, and puts no NaN in any buffer. `ARBOR_FUZZ_CASES=N` runs N cases per
//! property (default 256); regressions found are kept in `tests/fuzz.proptest-regressions`.

use arbor::Error;
use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::mesh::{self, Axes, Joints, LeafOptions, MeshOptions, Tip, Topology, UpAxis, Winding};
use proptest::prelude::*;
use proptest::strategy::ValueTree;

/// How many inputs reached the mesher (printed by `report`, to show the generators reach
/// deep into the pipeline rather than stopping at parse errors).
static MESHED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

fn cases() -> u32 {
    std::env::var("ARBOR_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256)
}

/// Grows, interprets and meshes `text` with small limits; checks every property.
/// The slowest input per kilobyte seen by `check` (milliseconds per KiB, bytes), printed
/// when it grows (`--nocapture` shows it).
static SLOWEST: std::sync::Mutex<(f64, usize)> = std::sync::Mutex::new((0.0, 0));

fn check(text: &str) -> Result<(), TestCaseError> {
    check_with(text, Conventions::default())
}

/// An engine's conventions and the mesher's shape options, drawn at random beside each
/// grammar: every normal must be unit length under each of them.
#[derive(Clone, Copy, Debug)]
struct Conventions {
    up_axis: UpAxis,
    winding: Winding,
    scale: f32,
    axes: Axes,
    joints: Joints,
    curve_rings: u32,
}

impl Default for Conventions {
    fn default() -> Self {
        let o = MeshOptions::default();
        Conventions {
            up_axis: o.up_axis,
            winding: o.winding,
            scale: o.scale,
            axes: o.axes,
            joints: o.joints,
            curve_rings: o.curve_rings,
        }
    }
}

impl Conventions {
    fn apply(self, o: MeshOptions) -> MeshOptions {
        o.up_axis(self.up_axis)
            .winding(self.winding)
            .scale(self.scale)
            .axes(self.axes)
            .joints(self.joints)
            .curve_rings(self.curve_rings)
    }
}

fn conventions() -> impl Strategy<Value = Conventions> {
    (
        prop::sample::select(vec![UpAxis::Y, UpAxis::Z]),
        prop::sample::select(vec![Winding::CounterClockwise, Winding::Clockwise]),
        prop::sample::select(vec![1.0f32, 0.01, 100.0, 1e-20, 1e20]),
        prop::sample::select(vec![Axes::Arbor, Axes::Unity, Axes::Unreal]),
        prop::sample::select(vec![Joints::Separate, Joints::Mitred]),
        prop::sample::select(vec![0u32, 3]),
    )
        .prop_map(|(up_axis, winding, scale, axes, joints, curve_rings)| {
            // An engine preset sets the up axis and winding itself.
            let (up_axis, winding) = match axes {
                Axes::Arbor => (up_axis, winding),
                _ => (UpAxis::Y, Winding::CounterClockwise),
            };
            Conventions {
                up_axis,
                winding,
                scale,
                axes,
                joints,
                curve_rings,
            }
        })
}

fn check_with(text: &str, conventions: Conventions) -> Result<(), TestCaseError> {
    let start = std::time::Instant::now();
    let r = check_inner(text, conventions);
    let ms = start.elapsed().as_secs_f64() * 1e3;
    let per_kib = ms / (text.len().max(64) as f64 / 1024.0);
    let mut slowest = SLOWEST.lock().unwrap_or_else(|e| e.into_inner());
    if per_kib > slowest.0 {
        *slowest = (per_kib, text.len());
        println!(
            "slowest so far: {per_kib:.2} ms per KiB ({} bytes, {ms:.2} ms)",
            text.len()
        );
    }
    r
}

fn check_inner(text: &str, conventions: Conventions) -> Result<(), TestCaseError> {
    let ls = match LSystem::parse(text) {
        Ok(ls) => ls,
        Err(Error::Parse { line, column, .. }) => {
            prop_assert!(line >= 1 && column >= 1);
            return Ok(());
        }
        Err(e) => return Err(TestCaseError::fail(format!("parse gave {e}"))),
    };
    let options = LsystemOptions::default()
        .steps(Some(ls.derivation_length().min(6)))
        .max_modules(20_000)
        .max_params(40_000)
        .max_branches(20_000)
        .max_work(2_000_000);
    let string = match ls.derive(&options) {
        Ok(s) => s,
        Err(Error::LimitExceeded { .. } | Error::Eval { .. } | Error::InvalidArgument { .. }) => {
            return Ok(());
        }
        Err(e) => return Err(TestCaseError::fail(format!("derive gave {e}"))),
    };
    prop_assert!(string.len() <= 20_000);
    let skeleton = match ls.interpret(&string, &options) {
        Ok(s) => s,
        Err(Error::LimitExceeded { .. } | Error::Eval { .. } | Error::InvalidArgument { .. }) => {
            return Ok(());
        }
        Err(e) => return Err(TestCaseError::fail(format!("interpret gave {e}"))),
    };
    prop_assert!(skeleton.len() <= 20_000);
    MESHED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    for topology in Topology::ALL {
        let o = conventions.apply(
            MeshOptions::default()
                .topology(topology)
                .radial_segments(4)
                .tip(Tip::Point)
                .base_cap(true)
                .smooth_taper(true),
        );
        let m = match mesh::tubes(&skeleton, &o) {
            Ok(m) => m,
            // A scale that takes the tree past the f32 range is refused by name.
            Err(e @ Error::InvalidArgument { .. }) if conventions.scale != 1.0 => {
                prop_assert!(e.to_string().contains("scale"), "{e}");
                return Ok(());
            }
            Err(e) => return Err(TestCaseError::fail(e.to_string())),
        };
        for v in &m.vertices {
            prop_assert!(
                v.position
                    .iter()
                    .chain(&v.normal)
                    .chain(&v.uv)
                    .all(|x| x.is_finite())
            );
        }
        let n = m.vertices.len() as u32;
        prop_assert!(m.indices.iter().all(|&i| i < n || i == u32::MAX));
        unit_normals(&m, "bark")?;
        // The baked leaves (prefab quads at sites and tips, polygons, organs), in these
        // conventions and in each engine's.
        for axes in [conventions.axes, Axes::Arbor, Axes::Unity, Axes::Unreal] {
            let o = match axes {
                Axes::Arbor => o.axes(axes),
                _ => o
                    .axes(axes)
                    .up_axis(UpAxis::Y)
                    .winding(Winding::CounterClockwise),
            };
            let leaves = LeafOptions::default().tips(true);
            match mesh::leaf_mesh(&skeleton, &leaves, &o) {
                Ok(m) => unit_normals(&m, "leaves")?,
                Err(Error::LimitExceeded { .. } | Error::InvalidArgument { .. }) => {}
                Err(e) => return Err(TestCaseError::fail(format!("leaf mesh gave {e}"))),
            }
        }
    }
    Ok(())
}

/// Every normal of `m` is unit length (within 1e-3).
fn unit_normals(m: &mesh::Mesh, what: &str) -> Result<(), TestCaseError> {
    for (k, v) in m.vertices.iter().enumerate() {
        let l = v.normal.iter().map(|x| x * x).sum::<f32>().sqrt();
        prop_assert!(
            (l - 1.0).abs() < 1e-3,
            "{what} vertex {k}: normal {:?} of length {l}",
            v.normal
        );
    }
    Ok(())
}

const SYMBOLS: &[&str] = &[
    "F", "G", "f", "g", "+", "-", "&", "^", "/", "\\", "|", "$", "!", "#", "%", "~", "{", ".", "}",
    "A", "B", "X", "@M", "@R", "@v",
];

/// Fragments of cpfg files that fit together (directives, blocks, statements, arrays,
/// predecessors of several modules, TAB continuations, organs)...
const CPFG_GOOD: &[&str] = &[
    "#define A0(x) (x)+1",
    "#define B0 A0(2)",
    "#define C0(x, y) x##y",
    "#if B0 > 2\n#define K 3\n#else\n#define K 4\n#endif",
    "#ifdef A0\n#undef A0\n#endif",
    "Lsystem: 1",
    "derivation length: K",
    "Start: { i = 0; srand(3); }",
    "StartEach: { i = i + 1; if (i > 3) stop(); }",
    "EndEach: { printf(\"%g %d %5.2f\\n\", i, i, a[0]); }",
    "End: { do { i = i - 1; } while (i > 0); }",
    "define: { array a[3] = { 1, 2, 3 }, m[2][2]; }",
    "A(x) : { y = x * 2; } y < 9 { a[1] = y; } --> A(y)B",
    "A(x) : * { while (x < 5) { x = x + 1; } } --> A(x)F(x)",
    "X(n) : n < 6 --> F(a[n % 3])[+X(n + 1)@O(1)]X(n + 1)",
    "AB --> C@o(2)",
    "[A(x)B] --> [C(x);]",
    "B > C(y) : y > 1 --> F(y)~l",
    "C(x) --> %F(x)",
    "D --> ;(3)F,F_(0.1)\n\t[-F]+F(2)",
    // A leaf polygon that, at a full turn per `+`, runs out and back along one line
    // (no area: its normal is a sum of rounding errors).
    "angle increment: 360",
    "X(n) : n >= 6 --> [{+F(1)-F(1)-F(1)+|+F(1)-F(1)-F(1)}]",
    "ring lsystem",
    "homomorphism: warnings\nmaximum depth: 5\nB --> F@O(0.5)\nAB --> FF",
    "decomposition\nmaximum depth: 50\nX(n) : n > 100 --> X(n - 1)F",
    "F(x) --> F(func(1, x))",
    "F(x) --> F(curveX(1, x))",
    "A(x) : { a[x] = 1; } --> A(x)",
    "A : { while (1) { j = j + 1; } } --> A",
    "// comment { --> }",
    "/* a comment\n over lines */",
];

/// ... and fragments that break them.
const CPFG_BAD: &[&str] = &[
    "#define E E\nAxiom: E",
    "#else",
    "#endif",
    "#if 1",
    "#include \"x.h\"",
    "x = ;",
    "{",
    "}",
    "\\",
    "/* open",
    "endlsystem",
    "#define M(a, b) a b\nAxiom: M(F,",
];

/// A cpfg file from the fragments: mostly good ones around one axiom, sometimes a bad one.
fn cpfg_file() -> impl Strategy<Value = String> {
    (
        prop::collection::vec(prop::sample::select(CPFG_GOOD), 0..10),
        prop::sample::select(&["Axiom: A(1)B[C(2)]D", "Axiom: X(0)", "Axiom: AB(1)C(2)"][..]),
        prop::option::weighted(0.25, prop::sample::select(CPFG_BAD)),
        0usize..12,
    )
        .prop_map(|(mut parts, axiom, bad, at)| {
            let n = parts.len();
            parts.insert(at.min(n), axiom);
            if let Some(b) = bad {
                let n = parts.len();
                parts.insert((at * 7) % (n + 1), b);
            }
            parts.join("\n")
        })
}

fn expr() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        6 => (-1000.0f64..1000.0).prop_map(|v| format!("{v:.3}")),
        3 => Just("x".to_string()),
        3 => Just("y".to_string()),
        1 => Just("1e308".to_string()),
        1 => Just("0".to_string()),
    ];
    leaf.prop_recursive(4, 24, 3, |inner| {
        prop_oneof![
            (
                inner.clone(),
                prop::sample::select(vec!["+", "-", "*", "/", "^", "<", ">=", "&&", "%"]),
                inner.clone()
            )
                .prop_map(|(a, op, b)| format!("({a} {op} {b})")),
            (
                prop::sample::select(vec![
                    "sin", "cos", "fabs", "ran", "floor", "log", "sqrt", "exp"
                ]),
                inner.clone()
            )
                .prop_map(|(f, a)| format!("{f}({a})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("nran({a}, {b})")),
            (inner.clone(), inner.clone(), inner)
                .prop_map(|(c, a, b)| format!("({c} ? {a} : {b})")),
        ]
    })
}

fn module(params: bool) -> impl Strategy<Value = String> {
    (
        prop::sample::select(SYMBOLS),
        prop::collection::vec(expr(), 0..3),
    )
        .prop_map(move |(s, args)| {
            if params && !args.is_empty() {
                format!("{s}({})", args.join(","))
            } else {
                s.to_string()
            }
        })
}

/// Modules, some wrapped in a branch, so brackets balance (unbalanced text is the
/// mutation property's business).
fn successor() -> impl Strategy<Value = String> {
    prop::collection::vec((module(true), module(true), 0u8..4), 0..8).prop_map(|m| {
        m.into_iter()
            .map(|(a, b, k)| match k {
                0 => format!("[{a}{b}]"),
                1 => format!("[{a}]{b}"),
                _ => format!("{a}{b}"),
            })
            .collect()
    })
}

/// `text` with the names `x` and `y` (whole identifiers only) replaced by numbers.
fn numbers_for_xy(text: &str) -> String {
    let mut out = String::new();
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        match word.as_str() {
            "x" => out.push_str("1.5"),
            "y" => out.push_str("(-2)"),
            w => out.push_str(w),
        }
        word.clear();
    };
    for c in text.chars() {
        if c.is_ascii_alphanumeric() || c == '_' {
            word.push(c);
        } else {
            flush(&mut word, &mut out);
            out.push(c);
        }
    }
    flush(&mut word, &mut out);
    out
}

fn grammar() -> impl Strategy<Value = String> {
    let production = (
        prop::sample::select(vec!["A(x,y)", "X(x)", "F(x)", "B", "F"]),
        prop::option::of(prop::sample::select(vec!["A < ", "F < ", "B(p) < "])),
        prop::option::of(prop::sample::select(vec![" > B", " > [F]", " > X(q)"])),
        prop::option::of(expr()),
        successor(),
        prop::option::of(0.0f64..5.0),
    )
        .prop_map(|(pred, lc, rc, cond, succ, prob)| {
            let mut s = String::new();
            s += lc.unwrap_or("");
            s += pred;
            s += rc.unwrap_or("");
            if let Some(c) = cond {
                s += &format!(" : {c}");
            }
            s += " --> ";
            s += if succ.is_empty() { "*" } else { &succ };
            if let Some(p) = prob {
                s += &format!(" : {p:.2}");
            }
            s
        });
    (
        successor(),
        prop::collection::vec(production, 0..6),
        0u32..8,
        prop::option::of(prop::sample::select(vec![
            "ignore: +-",
            "consider: AB",
            "tropism: T: 0 -1 0 E: 0.5",
            "angle increment: 1e30",
            "angle increment: 360",
            "homomorphism\nmaximum depth: 50\nA --> F[+A][-A]",
            "decomposition\nmaximum depth: 5\nB --> FB",
        ])),
    )
        .prop_map(|(axiom, prods, n, extra)| {
            // x and y are parameters inside productions; in the axiom they stand for
            // the numbers 1.5 and -2 (a `#define` would replace them everywhere, as
            // cpfg's C preprocessor does).
            let axiom = if axiom.is_empty() {
                "F".to_string()
            } else {
                numbers_for_xy(&axiom)
            };
            let mut s = format!("derivation length: {n}\nAxiom: {axiom}\n");
            for p in prods {
                s += &p;
                s += "\n";
            }
            if let Some(e) = extra {
                s += e;
                s += "\n";
            }
            s
        })
}

fn shipped() -> Vec<String> {
    let dir = format!("{}/examples/grammars", env!("CARGO_MANIFEST_DIR"));
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "l"))
        .collect();
    v.sort();
    v.into_iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    #[test]
    fn random_grammars_never_panic(text in grammar(), conventions in conventions()) {
        check_with(&text, conventions)?;
    }

    /// cpfg files as written: preprocessor directives, blocks, statements, arrays,
    /// predecessors of several modules, TAB continuations and organs, shuffled and cut.
    #[test]
    fn random_cpfg_files_never_panic(
        text in cpfg_file(),
        cut in 0usize..400,
        conventions in conventions(),
    ) {
        let end = (0..=cut.min(text.len())).rev().find(|&k| text.is_char_boundary(k)).unwrap_or(0);
        check_with(&text, conventions)?;
        check_with(&text[..end], conventions)?;
    }

    #[test]
    fn mutated_shipped_grammars_never_panic(
        which in 0usize..31,
        edits in prop::collection::vec((0usize..4000, 0u8..4, any::<char>()), 1..6),
        conventions in conventions(),
    ) {
        let all = shipped();
        let mut chars: Vec<char> = all[which % all.len()].chars().collect();
        for (at, kind, c) in edits {
            let at = at % (chars.len() + 1);
            match kind {
                0 => chars.insert(at, c),
                1 if at < chars.len() => { chars.remove(at); }
                2 if at < chars.len() => chars[at] = c,
                _ => {
                    // A character the grammar gives meaning to.
                    let special = ['[', ']', '(', ')', ':', '-', '>', '<', '\n', '{', '*'];
                    chars.insert(at, special[c as usize % special.len()]);
                }
            }
        }
        check_with(&chars.into_iter().collect::<String>(), conventions)?;
    }

    /// A planar tree (each `/(180)` leaves a rounding error of 1e-16 off its plane) with
    /// a leaf polygon that, at a full turn per `+`, runs out and back along one line: the
    /// Newell sum of such a polygon is rounding error, sometimes so small that its square
    /// is subnormal, where glam's normalize gives a vector of the wrong length.
    #[test]
    fn degenerate_leaf_polygons_have_unit_normals(
        a in 1u32..90,
        b in 1u32..6,
        c in 1u32..180,
        conventions in conventions(),
    ) {
        let text = format!(
            "angle increment: 360\nAxiom: F(13)/(180)+({a})F({b})/(180)-({c})F(2)\
             [{{+F(1)-F(1)-F(1)+|+F(1)-F(1)-F(1)}}]"
        );
        check_with(&text, conventions)?;
    }

    #[test]
    fn random_text_never_panics(text in "\\PC{0,200}") {
        check(&text)?;
    }
}

#[test]
fn random_cpfg_files_reach_the_mesher() {
    // The fragments are useful only if a fair share of their files grow.
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let strategy = cpfg_file();
    let (mut meshed, total) = (0, 400);
    let mut errors = std::collections::BTreeMap::<String, usize>::new();
    for _ in 0..total {
        let text = strategy.new_tree(&mut runner).unwrap().current();
        let before = MESHED.load(std::sync::atomic::Ordering::Relaxed);
        if let Err(e) = LSystem::parse(&text) {
            let key: String = e.to_string().chars().skip(30).take(40).collect();
            *errors.entry(key).or_default() += 1;
        }
        check(&text).unwrap();
        meshed += (MESHED.load(std::sync::atomic::Ordering::Relaxed) > before) as usize;
    }
    println!("{meshed} of {total} random cpfg files were meshed; parse errors: {errors:#?}");
    assert!(
        meshed * 4 >= total,
        "only {meshed} of {total} random cpfg files got to the mesher"
    );
}

#[test]
fn random_grammars_reach_the_mesher() {
    // The grammar generator is useful only if many of its grammars parse and grow.
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let (mut meshed, total) = (0, 200);
    for _ in 0..total {
        let text = grammar().new_tree(&mut runner).unwrap().current();
        let before = MESHED.load(std::sync::atomic::Ordering::Relaxed);
        if std::env::var_os("ARBOR_FUZZ_VERBOSE").is_some() {
            if let Err(e) = LSystem::parse(&text) {
                println!("{e}\n{text}\n----");
            }
        }
        check(&text).unwrap();
        meshed += (MESHED.load(std::sync::atomic::Ordering::Relaxed) > before) as usize;
    }
    println!("{meshed} of {total} random grammars were meshed");
    assert!(
        meshed * 4 >= total,
        "only {meshed} of {total} random grammars got to the mesher"
    );
}

#[test]
fn numerical_edge_cases_give_finite_buffers() {
    for text in [
        "Axiom: $F$+$F",                           // $ with the heading parallel to up
        "Axiom: F(0)F(0)[+F(0)]F",                 // zero-length internodes
        "Axiom: !(0)F!(0)F[+!(0)F]",               // zero radius
        "tropism: T: 0 1 0 E: 1\nAxiom: FFF[+FF]", // tropism parallel to the heading
        "tropism: T: 0 -1 0 E: 50\nAxiom: FFFF",   // tropism against the heading, huge e
        "Axiom: @R(0,0,0)F@R(0,-1,0)F",            // degenerate and downward headings
        "Axiom: |F|F[&(180)F]",                    // turning back on itself
        "Axiom: @M(1e30,0,0)F(1e30)",              // far away and long
        "Axiom: F(1e-30)F(1e-30)",                 // tiny
        "Axiom: !(1e30)F",                         // huge width
        "Axiom: +(1e30)F-(1e30)F/(1e30)F",         // huge angles
    ] {
        check(text).unwrap_or_else(|e| panic!("{text}: {e}"));
        // And each really reaches the mesher or names why not.
        let ls = LSystem::parse(text).unwrap();
        let s = ls.skeleton(&LsystemOptions::default());
        if let Ok(s) = s {
            mesh::tubes(&s, &MeshOptions::default()).unwrap_or_else(|e| panic!("{text}: {e}"));
        }
    }
}
