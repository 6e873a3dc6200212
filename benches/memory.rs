//! Peak heap memory along the scale sweep, with a counting global allocator
//! (`peak_alloc`): for the 1996 tree a with n = 10 … 22, the peak bytes alive while going
//! from parameters (direct builder) or from grammar text to the mesh buffers, against the
//! bytes of those final buffers. Goal: peak ≤ 1.5 × output. Then self-organizing growth:
//! the peak heap of a world (the forest of the growth benchmark, and one tree) against
//! its shadow grid (4 bytes per cell) and the most internodes it held, as bytes per
//! internode beyond the grid.
//!
//! `cargo bench --bench memory`

use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::mesh;
use arbor::models::growth::{GrowthParams, Species, World, WorldOptions};
use arbor::models::honda;
use peak_alloc::PeakAlloc;

#[path = "../tests/common/forest.rs"]
mod forest;

#[global_allocator]
static ALLOC: PeakAlloc = PeakAlloc;

fn main() {
    // Run by `cargo test --benches` too: then only the two smallest sizes.
    let quick = std::env::args().any(|a| a == "--test" || a == "--quick");
    let path = format!("{}/examples/grammars/honda_a.l", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).unwrap();
    let options = mesh::MeshOptions::default().radial_segments(6);
    println!(
        "{:>10} {:>14} {:>14} {:>7} {:>14} {:>7}",
        "internodes", "output bytes", "direct peak", "ratio", "grammar peak", "ratio"
    );
    let steps: &[u32] = if quick {
        &[10, 13]
    } else {
        &[10, 13, 16, 19, 22]
    };
    let mut worst: f64 = 0.0;
    for &n in steps {
        // Direct: parameters → skeleton → mesh buffers.
        let base = ALLOC.current_usage();
        ALLOC.reset_peak_usage();
        let mut params = honda::HondaParams::preset('a').unwrap();
        params.steps = n;
        let skeleton = honda::build(&params).unwrap();
        let m = mesh::tubes(&skeleton, &options).unwrap();
        drop(skeleton);
        let output = m.vertices.len() * std::mem::size_of::<mesh::Vertex>()
            + m.indices.len() * 4
            + m.ranges.len() * std::mem::size_of::<mesh::BranchRange>();
        let direct = ALLOC.peak_usage() - base;
        drop(m);

        // Grammar: text → parse → derive → interpret → mesh buffers.
        let base = ALLOC.current_usage();
        ALLOC.reset_peak_usage();
        let lo = LsystemOptions::default()
            .steps(Some(n))
            .max_modules(usize::MAX)
            .max_params(usize::MAX);
        let skeleton = LSystem::parse(&text).unwrap().skeleton(&lo).unwrap();
        let m = mesh::tubes(&skeleton, &options).unwrap();
        drop(skeleton);
        let grammar = ALLOC.peak_usage() - base;
        drop(m);

        let (rd, rg) = (
            direct as f64 / output as f64,
            grammar as f64 / output as f64,
        );
        worst = worst.max(rd).max(rg);
        println!(
            "{:>10} {:>14} {:>14} {:>7.2} {:>14} {:>7.2}",
            (1u64 << n) - 1,
            output,
            direct,
            rd,
            grammar,
            rg
        );
    }
    println!("worst peak / output: {worst:.2} (goal <= 1.5)");
    growth(quick);
}

/// Peak heap of growing worlds: grid bytes (as grown by the end) plus bytes per internode
/// held.
fn growth(quick: bool) {
    println!(
        "\n{:>28} {:>7} {:>12} {:>12} {:>12} {:>10}",
        "world", "cycles", "internodes", "grid bytes", "peak bytes", "B/intern."
    );
    let forest_cycles: &[u32] = if quick { &[5, 10] } else { &[5, 10, 15, 25] };
    let mut runs: Vec<(&str, u32)> = vec![("one tree (default species)", 10)];
    runs.extend(forest_cycles.iter().map(|&c| ("forest of 100, seeding", c)));
    for (what, cycles) in runs {
        let base = ALLOC.current_usage();
        ALLOC.reset_peak_usage();
        let forest = what.starts_with("forest");
        let w = if forest {
            let mut species = GrowthParams::preset(Species::Decurrent);
            species.seed_age = 20;
            forest::forest_world(WorldOptions::default(), &species)
        } else {
            let mut w = World::new(&WorldOptions::default()).unwrap();
            w.plant(&GrowthParams::default(), [0.0, 0.0, 0.0], 1)
                .unwrap();
            w
        };
        let mut w = w;
        let mut most = w.branch_count();
        for _ in 0..cycles {
            w.step(1).unwrap();
            most = most.max(w.branch_count());
        }
        let peak = ALLOC.peak_usage() - base;
        // The grid grows with what the trees shade (its last size; while it is re-laid
        // the old and the new one are both held).
        let grid = w.grid_bytes();
        drop(w);
        println!(
            "{:>28} {:>7} {:>12} {:>12} {:>12} {:>10.0}",
            what,
            cycles,
            most,
            grid,
            peak,
            peak.saturating_sub(grid) as f64 / most as f64
        );
    }
}
