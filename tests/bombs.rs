//! Growth bombs stop at their limits within a stated budget: under default limits each
//! bomb returns `LimitExceeded` naming the limit and the step in under 10 seconds (a
//! robustness bound, not a speed target) and with less than 1 GiB of heap at its peak,
//! measured by a counting allocator.

use arbor::Error;
use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::models::honda::{self, HondaParams};
use peak_alloc::PeakAlloc;
use std::time::{Duration, Instant};

#[global_allocator]
static ALLOC: PeakAlloc = PeakAlloc;

/// The allocator's counts are global: each test measures alone.
static ALONE: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn alone() -> std::sync::MutexGuard<'static, ()> {
    ALONE.lock().unwrap_or_else(|e| e.into_inner())
}

const TIME_BUDGET: Duration = Duration::from_secs(10);
const MEMORY_BUDGET: usize = 1 << 30;

fn within_budget(what: &str, f: impl FnOnce() -> Result<(), Error>) {
    let base = ALLOC.current_usage();
    ALLOC.reset_peak_usage();
    let start = Instant::now();
    let result = f();
    let (elapsed, peak) = (start.elapsed(), ALLOC.peak_usage() - base);
    match result {
        Err(Error::LimitExceeded {
            limit_name, step, ..
        }) => {
            assert!(!limit_name.is_empty(), "{what}");
            println!("{what}: {limit_name} at step {step:?}, {elapsed:?}, peak {peak} bytes");
        }
        other => panic!("{what}: expected LimitExceeded, got {other:?}"),
    }
    assert!(elapsed < TIME_BUDGET, "{what} took {elapsed:?}");
    assert!(peak < MEMORY_BUDGET, "{what} peaked at {peak} bytes");
}

#[test]
fn growth_bombs_stop_within_budget() {
    let _alone = alone();
    let grow = |text: &str| {
        let ls = LSystem::parse(text).unwrap();
        ls.skeleton(&LsystemOptions::default()).map(|_| ())
    };
    within_budget("F -> FF, 60 steps", || {
        grow("derivation length: 60\nAxiom: F\nF --> FF")
    });
    within_budget("parametric doubling", || {
        grow("derivation length: 60\nAxiom: A(1)\nA(x) --> A(x*2)[+A(x+1)]A(x/2)")
    });
    within_budget("interpretation without end", || {
        grow(
            "derivation length: 12\nAxiom: X\nX --> XX\nhomomorphism\nmaximum depth: 1000\nX --> F[+X][-X]",
        )
    });
    within_budget("decomposition without end", || {
        grow("derivation length: 3\nAxiom: X\ndecomposition\nmaximum depth: 1000\nX --> XX")
    });
    within_budget("1996 model, n = 60, min = 0", || {
        let mut p = HondaParams::preset('a').unwrap();
        p.steps = 60;
        honda::build(&p).map(|_| ())
    });
}

/// Output limits stop leaves, meshes and forests before their memory is spent: each call
/// below would need gigabytes under the defaults; with a small limit it fails naming the
/// limit, well inside a budget of 64 MiB.
#[test]
fn output_limits_stop_before_the_memory_is_spent() {
    let _alone = alone();
    use arbor::forest::{self, Item, Placed, Source};
    use arbor::mesh::{self, LeafOptions, MeshOptions};
    let mut p = HondaParams::preset('a').unwrap();
    p.steps = 16;
    let tree = honda::build(&p).unwrap();
    let small = |what: &str, limit: &str, f: &dyn Fn() -> Result<(), Error>| {
        let base = ALLOC.current_usage();
        ALLOC.reset_peak_usage();
        match f() {
            Err(Error::LimitExceeded { limit_name, .. }) => assert_eq!(limit_name, limit, "{what}"),
            other => panic!("{what}: expected LimitExceeded, got {other:?}"),
        }
        let peak = ALLOC.peak_usage() - base;
        println!("{what}: {limit}, peak {peak} bytes");
        assert!(peak < 64 << 20, "{what} peaked at {peak} bytes");
    };
    // 32,768 tips × 64 leaves: 2 M leaves (and 8 M baked vertices) under the defaults.
    let leaves = LeafOptions::default()
        .tips(true)
        .density(64.0)
        .max_leaves(1000);
    small("leaf instances", "max_leaves", &|| {
        mesh::leaf_instances(&tree, &leaves, &MeshOptions::default()).map(|_| ())
    });
    small("baked leaves", "max_leaves", &|| {
        mesh::leaf_mesh_size(&tree, &leaves, &MeshOptions::default()).map(|_| ())
    });
    let capped = MeshOptions::default()
        .max_vertices(10_000)
        .radial_segments(64);
    small("mesh", "max_vertices", &|| {
        mesh::mesh_size(&tree, &capped).map(|_| ())
    });
    let placed: Vec<Placed<'_>> = (0..4)
        .map(|k| Placed {
            item: Item {
                source: Source::Honda(p),
                seed: k,
            },
            position: [k as f32 * 300.0, 0.0, 0.0],
            rotation: 0.0,
            scale: 1.0,
        })
        .collect();
    // 4 trees of 65,535 branches × 64 sides would be ~17 M vertices (540 MiB): refused
    // after planning, before any tree is meshed.
    let forest_options = MeshOptions::default()
        .max_vertices(1_000_000)
        .radial_segments(64);
    small("forest", "max_vertices", &|| {
        forest::merged(&placed, &forest_options).map(|_| ())
    });
}

/// steady_state_65535_steps.l: a string that stays at 16.7 M modules would cost hours over
/// 65,535 steps; the work limit stops it (here set to 2^26 modules, reached after the
/// doubling steps; the default is 2^28).
#[test]
fn the_work_limit_stops_a_steady_state_derivation() {
    let _alone = alone();
    let text = "Lsystem: 1\nderivation length: 65535\nAxiom: A(0)\nA(n) : n < 24 --> A(n+1)A(n+1)\nendlsystem";
    let ls = LSystem::parse(text).unwrap();
    within_budget("steady state, 65,535 steps", || {
        ls.derive(&LsystemOptions::default().max_work(1 << 26))
            .map(|_| ())
    });
    let err = ls
        .derive(&LsystemOptions::default().max_work(1 << 20))
        .unwrap_err();
    assert!(err.to_string().contains("max_work"), "{err}");
    assert_eq!(arbor::limits::DEFAULT_MAX_WORK, 1 << 28);
}

/// A derivation length of four billion steps on a one-module string: every step spends at
/// least 64 modules of `max_work`, so the default limit ends it (after 4,194,304 steps)
/// within the budget, naming max_work.
#[test]
fn billions_of_steps_on_a_short_string_meet_the_work_limit() {
    let _alone = alone();
    for text in [
        "derivation length: 4000000000\nAxiom: A\nA --> A\n",
        // Not a lookup-table grammar: a parameter and a condition.
        "derivation length: 4000000000\nAxiom: A(0)\nA(n) : n >= 0 --> A(n)\n",
    ] {
        let ls = LSystem::parse(text).unwrap();
        within_budget("four billion steps", || {
            ls.derive(&LsystemOptions::default()).map(|_| ())
        });
        let err = ls.derive(&LsystemOptions::default()).unwrap_err();
        assert!(err.to_string().contains("max_work"), "{err}");
    }
}

/// prune_long_branch.l: one internode thousands of times longer than the others no longer
/// fills (length / cell)³ grid cells.
#[test]
fn pruning_a_very_long_branch_stays_small() {
    let _alone = alone();
    let ls = LSystem::parse(
        "Lsystem: 1\nderivation length: 10\nAxiom: F[+(45)&(35)F(10000)]\nF --> FF\nendlsystem",
    )
    .unwrap();
    let s = ls.skeleton(&LsystemOptions::default()).unwrap();
    assert_eq!(s.len(), 1025);
    let base = ALLOC.current_usage();
    ALLOC.reset_peak_usage();
    let start = Instant::now();
    let p = arbor::skeleton::prune::prune_collisions(&s);
    let (took, peak) = (start.elapsed(), ALLOC.peak_usage() - base);
    println!(
        "long branch: {} removed, {took:?}, peak {peak} bytes",
        p.removed
    );
    assert!(peak < 16 << 20, "peak {peak} bytes");
    assert!(took < TIME_BUDGET, "{took:?}");
}

/// cpfg files as written bring their own bombs: macros that multiply, conditionals nested
/// without end, statement loops that never stop, arrays past the limit. Each stops with a
/// clear error inside the same time and memory budget.
#[test]
fn preprocessor_and_statement_bombs_stop_within_budget() {
    let _alone = alone();
    let measure = |what: &str, text: &str, expect: &str| {
        let base = ALLOC.current_usage();
        ALLOC.reset_peak_usage();
        let start = Instant::now();
        let r = LSystem::parse(text).and_then(|ls| ls.skeleton(&LsystemOptions::default()));
        let (elapsed, peak) = (start.elapsed(), ALLOC.peak_usage() - base);
        let e = r.expect_err(what).to_string();
        println!("{what}: {elapsed:?}, peak {peak} bytes: {e}");
        assert!(e.contains(expect), "{what}: {e}");
        assert!(elapsed < TIME_BUDGET, "{what} took {elapsed:?}");
        assert!(peak < MEMORY_BUDGET, "{what} peaked at {peak} bytes");
    };
    let mut doubling = String::from("#define M0 F\n");
    for i in 1..64 {
        doubling += &format!("#define M{i} M{} M{}\n", i - 1, i - 1);
    }
    doubling += "Axiom: M63\n";
    measure(
        "macros that double 63 times",
        &doubling,
        "macro expansion produces more than",
    );
    measure(
        "10^5 nested #if",
        &"#if 1\n".repeat(100_000),
        "nested deeper than",
    );
    measure(
        "a statement loop that never ends",
        "derivation length: 1\nAxiom: A\nA : * { while (1) { i = i + 1; } } --> A\n",
        "max_work",
    );
    measure(
        "an array past the limit",
        "define: { array a[4096][4096]; }\nAxiom: F\n",
        "arrays of at most 4194304 values",
    );
    measure(
        "a 16 MiB line of macro calls",
        &format!("#define A(x) x x\nAxiom: {}\n", "A(F)".repeat(4_000_000)),
        "at most 1048576 bytes",
    );
    measure(
        "a 0.8 MiB line of nested macro calls",
        &format!(
            "#define A(x) x x\n#define B(x) A(A(A(A(A(x)))))\nAxiom: {}\n",
            "B(F)".repeat(200_000)
        ),
        "macro expansion produces more than",
    );
}
