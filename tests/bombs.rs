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
    let leaves = LeafOptions {
        tips: true,
        density: 64.0,
        max_leaves: 1000,
        ..Default::default()
    };
    small("leaf instances", "max_leaves", &|| {
        mesh::leaf_instances(&tree, &leaves, &MeshOptions::default()).map(|_| ())
    });
    small("baked leaves", "max_leaves", &|| {
        mesh::leaf_mesh_size(&tree, &leaves, &MeshOptions::default()).map(|_| ())
    });
    let capped = MeshOptions {
        max_vertices: 10_000,
        radial_segments: 64,
        ..Default::default()
    };
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
    let forest_options = MeshOptions {
        max_vertices: 1_000_000,
        radial_segments: 64,
        ..Default::default()
    };
    small("forest", "max_vertices", &|| {
        forest::merged(&placed, &forest_options).map(|_| ())
    });
}
