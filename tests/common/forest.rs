//! The 100-tree forest of the growth tests and benchmarks: trees 5 apart on a 10 × 10
//! grid in a 60 × 20 × 60 box (shared with `#[path]` by the benches and examples).

use arbor::models::growth::{GrowthParams, World, WorldOptions};

/// The forest's box, as `options` otherwise has it.
pub fn forest_options(options: WorldOptions) -> WorldOptions {
    options.min([-30.0, 0.0, -30.0]).max([30.0, 20.0, 30.0])
}

/// A world of `options`' box planted with 100 trees of `species`, 5 apart.
pub fn forest_world(options: WorldOptions, species: &GrowthParams) -> World {
    let mut w = World::new(&forest_options(options)).unwrap();
    for i in 0..10 {
        for j in 0..10 {
            let at = [i as f32 * 5.0 - 22.5, 0.0, j as f32 * 5.0 - 22.5];
            w.plant(species, at, (i * 10 + j) as u64).unwrap();
        }
    }
    w
}
