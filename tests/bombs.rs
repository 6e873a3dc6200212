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
