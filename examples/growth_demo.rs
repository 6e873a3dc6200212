//! Grows a self-organizing tree and a small forest and prints their sizes and timings.
use arbor::models::growth::{Environment, GrowthParams, Species, World, WorldOptions};

fn main() -> Result<(), arbor::Error> {
    let only_forest = std::env::args().any(|a| a == "forest");
    for env in [Environment::Shadow, Environment::SpaceColonization] {
        if only_forest {
            break;
        }
        for species in Species::ALL {
            let mut w = World::new(&WorldOptions {
                environment: env,
                ..Default::default()
            })?;
            w.plant(&GrowthParams::preset(species), [0.0, 0.0, 0.0], 1)?;
            let t = std::time::Instant::now();
            w.step(12)?;
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
    let mut w = World::new(&WorldOptions {
        min: [-30.0, 0.0, -30.0],
        max: [30.0, 25.0, 30.0],
        ..Default::default()
    })?;
    for i in 0..10 {
        for j in 0..10 {
            w.plant(
                &GrowthParams {
                    seed_age: 0,
                    ..GrowthParams::preset(Species::Decurrent)
                },
                [i as f32 * 5.0 - 22.5, 0.0, j as f32 * 5.0 - 22.5],
                (i * 10 + j) as u64,
            )?;
        }
    }
    let t = std::time::Instant::now();
    w.step(20)?;
    println!(
        "forest: {} trees, {} branches, {:?}",
        w.tree_count(),
        w.branch_count(),
        t.elapsed()
    );
    Ok(())
}
