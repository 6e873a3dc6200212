//! Self-organizing growth as a host runs it, through the C ABI (`arbor_world_create`,
//! `arbor_world_plant`, `arbor_world_step`, `arbor_world_free`; no allocator tuning): one
//! tree of the default species for 10 cycles, and a forest of 100 trees on a 10 × 10 grid
//! with seeding for 25 and 50 cycles (the anchors of GROWTH.md), serial
//! (`ArborWorldOptions.parallel = 0`) and, with the `parallel` feature, on all cores.
//! Throughput is in branches of the grown world; each row's units of work (internode-cycles:
//! every living internode of every tree each cycle, plus births) are printed first, counted
//! by growing the same world through the Rust API, so time per unit is time / units.
//!
//! `cargo bench --bench growth` (add `--features parallel` for the parallel rows).

use arbor::ffi::{
    ArborGrowthParams, ArborStatus, ArborWorld, ArborWorldOptions, arbor_growth_params_init,
    arbor_growth_params_preset, arbor_world_branch_count, arbor_world_create, arbor_world_free,
    arbor_world_options_init, arbor_world_plant, arbor_world_step,
};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use std::mem::{MaybeUninit, size_of};

#[path = "../tests/common/forest.rs"]
mod forest;

/// A world the host owns, freed on drop.
struct HostWorld(*mut ArborWorld);

impl Drop for HostWorld {
    fn drop(&mut self) {
        // SAFETY: made by arbor_world_create, freed once.
        unsafe { arbor_world_free(self.0) }
    }
}

impl HostWorld {
    fn new(min: [f32; 3], max: [f32; 3], parallel: bool) -> Self {
        let mut o = MaybeUninit::<ArborWorldOptions>::zeroed();
        // SAFETY: `o` is writable for its full size (as arbor_world_options_default()).
        unsafe { arbor_world_options_init(o.as_mut_ptr(), size_of::<ArborWorldOptions>()) };
        // SAFETY: init wrote every field over zeroed memory.
        let mut o = unsafe { o.assume_init() };
        o.min = min;
        o.max = max;
        o.parallel = u32::from(parallel);
        let mut w = std::ptr::null_mut();
        // SAFETY: the options are readable and `w` writable.
        assert_eq!(unsafe { arbor_world_create(&o, &mut w) }, ArborStatus::Ok);
        HostWorld(w)
    }

    fn plant(&mut self, p: &ArborGrowthParams, at: [f32; 3], seed: u64) {
        // SAFETY: the world is live; `p` and `at` are readable; no tree id asked.
        let s = unsafe { arbor_world_plant(self.0, p, at.as_ptr(), seed, std::ptr::null_mut()) };
        assert_eq!(s, ArborStatus::Ok);
    }

    fn step(&mut self, cycles: u32) {
        // SAFETY: the world is live.
        assert_eq!(unsafe { arbor_world_step(self.0, cycles) }, ArborStatus::Ok);
    }

    fn branches(&self) -> usize {
        // SAFETY: the world is live.
        unsafe { arbor_world_branch_count(self.0) }
    }
}

fn params(species: Option<u32>) -> ArborGrowthParams {
    let mut p = MaybeUninit::<ArborGrowthParams>::zeroed();
    let size = size_of::<ArborGrowthParams>();
    match species {
        // SAFETY: `p` is writable for `size` bytes.
        Some(s) => {
            assert_eq!(
                unsafe { arbor_growth_params_preset(s, p.as_mut_ptr(), size) },
                ArborStatus::Ok
            )
        }
        // SAFETY: as above.
        None => unsafe { arbor_growth_params_init(p.as_mut_ptr(), size) },
    }
    // SAFETY: written above over zeroed memory.
    unsafe { p.assume_init() }
}

fn one_tree(parallel: bool) -> HostWorld {
    let mut w = HostWorld::new([-10.0, 0.0, -10.0], [10.0, 20.0, 10.0], parallel);
    w.plant(&params(None), [0.0, 0.0, 0.0], 1);
    w.step(10);
    w
}

fn forest(parallel: bool, cycles: u32) -> HostWorld {
    let mut w = HostWorld::new([-30.0, 0.0, -30.0], [30.0, 20.0, 30.0], parallel);
    // ARBOR_SPECIES_DECURRENT, seeding from age 20.
    let mut species = params(Some(1));
    species.seed_age = 20;
    for i in 0..10 {
        for j in 0..10 {
            let at = [i as f32 * 5.0 - 22.5, 0.0, j as f32 * 5.0 - 22.5];
            w.plant(&species, at, (i * 10 + j) as u64);
        }
    }
    w.step(cycles);
    w
}

/// The units of work of growing `world` for `cycles` (not timed): internode-cycles, births.
fn units(mut world: arbor::models::growth::World, cycles: u32) -> (u64, u64) {
    let shed = |w: &arbor::models::growth::World| -> usize {
        (0..w.tree_count()).map(|i| w.shed_count(i).unwrap()).sum()
    };
    let (mut alive, mut births) = (0u64, 0u64);
    for _ in 0..cycles {
        let (n0, s0) = (world.branch_count(), shed(&world));
        alive += n0 as u64;
        world.step(1).unwrap();
        births += (world.branch_count() + shed(&world) - n0 - s0) as u64;
    }
    (alive, births)
}

/// The bench's worlds through the Rust API, for counting their work.
fn rust_world(forest: bool) -> arbor::models::growth::World {
    use arbor::models::growth::{GrowthParams, Species, World, WorldOptions};
    if !forest {
        let mut w = World::new(&WorldOptions::default()).unwrap();
        w.plant(&GrowthParams::default(), [0.0, 0.0, 0.0], 1)
            .unwrap();
        return w;
    }
    let mut species = GrowthParams::preset(Species::Decurrent);
    species.seed_age = 20;
    forest::forest_world(WorldOptions::default(), &species)
}

fn bench_growth(c: &mut Criterion) {
    for (name, forest, cycles) in [
        ("one tree", false, 10),
        ("forest", true, 25),
        ("forest", true, 50),
    ] {
        let (alive, births) = units(rust_world(forest), cycles);
        eprintln!(
            "units of work, {name}, {cycles} cycles: {} ({alive} internode-cycles + {births} births)",
            alive + births
        );
    }
    let mut group = c.benchmark_group("growth");
    group.sample_size(10);
    let modes: &[bool] = if cfg!(feature = "parallel") {
        &[false, true]
    } else {
        &[false]
    };
    let mode = |parallel: bool| if parallel { "parallel" } else { "serial" };
    // The trees first in both modes, so both are measured in the same state of the process
    // (run after the serial forests, the parallel row's tree once measured 40% slower than
    // the serial row's, though the two take the same time in a direct loop).
    for &parallel in modes {
        let n = one_tree(parallel).branches();
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(
            BenchmarkId::new(format!("one_tree_10_cycles_{n}_branches"), mode(parallel)),
            |b| b.iter(|| black_box(one_tree(parallel)).branches()),
        );
    }
    for &parallel in modes {
        let mode = mode(parallel);
        for cycles in [25, 50] {
            let n = forest(parallel, cycles).branches();
            group.throughput(Throughput::Elements(n as u64));
            group.bench_function(
                BenchmarkId::new(format!("forest_100_{cycles}_cycles_{n}_branches"), mode),
                |b| b.iter(|| black_box(forest(parallel, cycles)).branches()),
            );
        }
    }
    group.finish();
}

criterion_group!(benches, bench_growth);
criterion_main!(benches);
