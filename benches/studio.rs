//! The studio's interactive paths, as a host runs them through the C ABI:
//!
//! - `slider`: after a slider change, one tree (the default species) planted on a terrain
//!   (`arbor_world_plant_on_ground`), regrown to 30 cycles and its curve records written
//!   (`arbor_tree_curve_records_write`): the goal is 50 ms;
//! - `forest_terrain_50`: the growth model report's forest, 100 trees 5 apart on a rolling
//!   terrain with seeding (seed age 20, as benches/growth.rs), grown 50 cycles on all cores with the `parallel`
//!   feature: the report's time is 870 ms. Units of work (internode-cycles, as in
//!   `benches/growth.rs`) are printed first, counted through the Rust API.
//!
//! `cargo bench --bench studio --features parallel`.

use arbor::ffi::{
    ArborGrowthParams, ArborStatus, ArborTree, ArborWorld, ArborWorldOptions,
    arbor_growth_params_preset, arbor_tree_branch_count, arbor_tree_curve_records_write,
    arbor_tree_free, arbor_world_create, arbor_world_free, arbor_world_options_init,
    arbor_world_plant_on_ground, arbor_world_set_ground, arbor_world_step, arbor_world_tree,
};
use arbor::mesh::CurveRecord;
use arbor::models::growth::{GrowthParams, HeightField, Species, World, WorldOptions};
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::mem::{MaybeUninit, size_of};

const N: u32 = 61;

/// The terrain's heights: 61 x 61 samples a unit apart from (-30, -30), 0..4 units.
fn heights() -> Vec<f32> {
    (0..N * N)
        .map(|k| {
            let (x, z) = ((k % N) as f32 - 30.0, (k / N) as f32 - 30.0);
            2.5 + 1.5 * (x * 0.17).sin() * (z * 0.13).cos() + 0.02 * x
        })
        .collect()
}

fn species(seeding: bool) -> ArborGrowthParams {
    let mut p = MaybeUninit::<ArborGrowthParams>::zeroed();
    // SAFETY: `p` is writable for its full size.
    let s = unsafe {
        arbor_growth_params_preset(
            Species::Decurrent as u32,
            p.as_mut_ptr(),
            size_of::<ArborGrowthParams>(),
        )
    };
    assert_eq!(s, ArborStatus::Ok);
    // SAFETY: the preset wrote every field.
    let mut p = unsafe { p.assume_init() };
    if seeding {
        p.seed_age = 20;
    }
    p
}

/// A world on the terrain, with `trees` trees 5 apart (1 or 100), grown `cycles`.
fn grow(trees: usize, cycles: u32, seeding: bool) -> *mut ArborWorld {
    let mut o = MaybeUninit::<ArborWorldOptions>::zeroed();
    // SAFETY: `o` is writable for its full size.
    unsafe { arbor_world_options_init(o.as_mut_ptr(), size_of::<ArborWorldOptions>()) };
    // SAFETY: init wrote every field.
    let mut o = unsafe { o.assume_init() };
    o.min = [-30.0, 0.0, -30.0];
    o.max = [30.0, 24.0, 30.0];
    o.parallel = 1;
    let mut w = std::ptr::null_mut();
    let h = heights();
    let p = species(seeding);
    // SAFETY: valid options, heights and species; `w` is written on success.
    unsafe {
        assert_eq!(arbor_world_create(&o, &mut w), ArborStatus::Ok);
        assert_eq!(
            arbor_world_set_ground(w, h.as_ptr(), N, N, 1.0, -30.0, -30.0),
            ArborStatus::Ok
        );
        for k in 0..trees {
            let (x, z) = if trees == 1 {
                (0.0, 0.0)
            } else {
                ((k / 10) as f32 * 5.0 - 22.5, (k % 10) as f32 * 5.0 - 22.5)
            };
            let s = arbor_world_plant_on_ground(w, &p, x, z, 0, k as u64, std::ptr::null_mut());
            assert_eq!(s, ArborStatus::Ok);
        }
        assert_eq!(arbor_world_step(w, cycles), ArborStatus::Ok);
    }
    w
}

/// Internode-cycles of the same forest grown through the Rust API.
fn units(trees: usize, cycles: u32) -> u64 {
    let mut w = World::new(
        &WorldOptions::default()
            .min([-30.0, 0.0, -30.0])
            .max([30.0, 24.0, 30.0]),
    )
    .unwrap();
    w.set_ground(HeightField::new(N, N, 1.0, [-30.0, -30.0], heights()).unwrap())
        .unwrap();
    let mut p = GrowthParams::preset(Species::Decurrent);
    p.seed_age = 20;
    for k in 0..trees {
        let (x, z) = ((k / 10) as f32 * 5.0 - 22.5, (k % 10) as f32 * 5.0 - 22.5);
        w.plant_on_ground(&p, [x, z], 0, k as u64).unwrap();
    }
    let mut total = 0u64;
    for _ in 0..cycles {
        let before = w.branch_count() as u64;
        w.step(1).unwrap();
        total += before + (w.branch_count() as u64).saturating_sub(before);
    }
    println!(
        "forest_terrain_50: {} trees at the end, {} branches, {total} units of work",
        w.tree_count(),
        w.branch_count()
    );
    total
}

fn bench(c: &mut Criterion) {
    units(100, 50);
    let mut g = c.benchmark_group("studio");
    g.sample_size(20);
    g.bench_function("slider", |b| {
        b.iter(|| {
            let w = grow(1, 30, false);
            let mut t: *mut ArborTree = std::ptr::null_mut();
            // SAFETY: a live world; `t` written on success and freed below.
            unsafe {
                assert_eq!(arbor_world_tree(w, 0, &mut t), ArborStatus::Ok);
                let n = arbor_tree_branch_count(t);
                let mut records: Vec<MaybeUninit<CurveRecord>> = Vec::with_capacity(n);
                let s = arbor_tree_curve_records_write(t, records.as_mut_ptr().cast(), n);
                assert_eq!(s, ArborStatus::Ok);
                black_box(&records);
                arbor_tree_free(t);
                arbor_world_free(w);
            }
        })
    });
    g.sample_size(10);
    g.bench_function("forest_terrain_50", |b| {
        b.iter(|| {
            let w = grow(100, 50, true);
            // SAFETY: made by grow, freed once.
            unsafe { arbor_world_free(black_box(w)) }
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
