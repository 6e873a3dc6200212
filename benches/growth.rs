//! Self-organizing growth: one tree of the default species for 10 cycles, and a forest of
//! 100 trees on a 10 × 10 grid with seeding for 50 cycles (the anchors of GROWTH.md),
//! serial (`WorldOptions::parallel = false`) and, with the `parallel` feature, on all
//! cores. Throughput is in branches of the grown world.
//!
//! `cargo bench --bench growth` (add `--features parallel` for the parallel rows).

use arbor::models::growth::{GrowthParams, Species, World, WorldOptions};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

fn one_tree(parallel: bool) -> World {
    let mut w = World::new(&WorldOptions {
        parallel,
        ..Default::default()
    })
    .unwrap();
    w.plant(&GrowthParams::default(), [0.0, 0.0, 0.0], 1)
        .unwrap();
    w.step(10).unwrap();
    w
}

fn forest(parallel: bool, cycles: u32) -> World {
    let mut w = World::new(&WorldOptions {
        min: [-30.0, 0.0, -30.0],
        max: [30.0, 20.0, 30.0],
        parallel,
        ..Default::default()
    })
    .unwrap();
    let species = GrowthParams {
        seed_age: 20,
        ..GrowthParams::preset(Species::Decurrent)
    };
    for i in 0..10 {
        for j in 0..10 {
            let at = [i as f32 * 5.0 - 22.5, 0.0, j as f32 * 5.0 - 22.5];
            w.plant(&species, at, (i * 10 + j) as u64).unwrap();
        }
    }
    w.step(cycles).unwrap();
    w
}

fn bench_growth(c: &mut Criterion) {
    let mut group = c.benchmark_group("growth");
    group.sample_size(10);
    let modes: &[bool] = if cfg!(feature = "parallel") {
        &[false, true]
    } else {
        &[false]
    };
    for &parallel in modes {
        let mode = if parallel { "parallel" } else { "serial" };
        let n = one_tree(parallel).branch_count();
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(
            BenchmarkId::new(format!("one_tree_10_cycles_{n}_branches"), mode),
            |b| b.iter(|| black_box(one_tree(parallel)).branch_count()),
        );
        for cycles in [25, 50] {
            let n = forest(parallel, cycles).branch_count();
            group.throughput(Throughput::Elements(n as u64));
            group.bench_function(
                BenchmarkId::new(format!("forest_100_{cycles}_cycles_{n}_branches"), mode),
                |b| b.iter(|| black_box(forest(parallel, cycles)).branch_count()),
            );
        }
    }
    group.finish();
}

criterion_group!(benches, bench_growth);
criterion_main!(benches);
