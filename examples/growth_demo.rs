//! Grows self-organizing trees (every species, both environments) and a forest of 100
//! trees on a 10 × 10 grid with seeding, and prints sizes and timings:
//! `cargo run --release --example growth_demo [forest [CYCLES [REPEATS]]]`.
use arbor::models::growth::{Environment, GrowthParams, Species, World, WorldOptions};

fn main() -> Result<(), arbor::Error> {
    let only_forest = std::env::args().any(|a| a == "forest");
    for env in [Environment::Shadow, Environment::SpaceColonization] {
        if only_forest {
            break;
        }
        for species in Species::ALL {
            let mut w = World::new(&WorldOptions::default().environment(env))?;
            w.plant(&GrowthParams::preset(species), [0.0, 0.0, 0.0], 1)?;
            let t = std::time::Instant::now();
            w.step(10)?;
            let s = w.tree(0)?;
            let (lo, hi) = s.bounds().unwrap();
            println!(
                "{env:?} {species:?}: {} branches, shed {}, height {:.2}, width {:.2}, {:?}",
                s.len(),
                w.shed_count(0)?,
                hi.y - lo.y,
                (hi.x - lo.x).max(hi.z - lo.z),
                t.elapsed()
            );
        }
    }
    let cycles: u32 = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(50);
    let repeats: u32 = std::env::args()
        .nth(3)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1);
    for _ in 0..repeats {
        forest(cycles)?;
    }
    Ok(())
}

fn forest(cycles: u32) -> Result<(), arbor::Error> {
    let mut w = World::new(
        &WorldOptions::default()
            .min([-30.0, 0.0, -30.0])
            .max([30.0, 20.0, 30.0]),
    )?;
    let mut species = GrowthParams::preset(Species::Decurrent);
    species.seed_age = 20;
    for i in 0..10 {
        for j in 0..10 {
            w.plant(
                &species,
                [i as f32 * 5.0 - 22.5, 0.0, j as f32 * 5.0 - 22.5],
                (i * 10 + j) as u64,
            )?;
        }
    }
    let t = std::time::Instant::now();
    w.step(cycles)?;
    let e = t.elapsed();
    println!(
        "forest: {} trees, {} branches after {cycles} cycles, {e:?}: {:.2} M branches/s",
        w.tree_count(),
        w.branch_count(),
        w.branch_count() as f64 / e.as_secs_f64() / 1e6
    );
    Ok(())
}
