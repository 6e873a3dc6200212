//! What a tree grows from, and the one way to grow it: used by forests, the command-line
//! tool and the C constructors alike.

use crate::error::Result;
use crate::lsystem::{LSystem, LsystemOptions};
use crate::models::growth::{GrowthParams, World, WorldOptions};
use crate::models::honda::{self, HondaParams};
use crate::progress::Run;
use crate::skeleton::Skeleton;

/// What one tree grows from.
#[derive(Clone, Copy, Debug)]
pub enum Source<'a> {
    /// The 1996 model with these parameters. A non-zero seed gives seeded
    /// [`Variation`](honda::Variation) (its default amounts), so neighbours differ; seed 0
    /// grows the model as written.
    Honda(HondaParams),
    /// A grammar with derivation options. The seed varies the plant: it becomes the
    /// options' `variation_seed`, mixed into the grammar's own `seed:` (or the options'
    /// `seed`), so each seed grows a distinct tree even from a file that fixes its seed;
    /// seed 0 grows the grammar's tree as written.
    Grammar(&'a LSystem, LsystemOptions),
    /// A self-organizing tree of this species grown alone for this many cycles, planted at
    /// the origin of a default world (a shadow world, 20 units wide and tall) seeded with
    /// the seed, which also turns its first bud.
    Growth(GrowthParams, u32),
}

impl Source<'_> {
    /// The tree's skeleton for `seed`.
    pub fn grow(&self, seed: u64) -> Result<Skeleton> {
        self.grow_in(seed, &mut Run::default())
    }

    /// [`grow`](Self::grow) in `run`: a grammar reports
    /// [`Stage::Derivation`](crate::progress::Stage::Derivation) and interpretation, a
    /// self-organizing tree [`Stage::Growth`](crate::progress::Stage::Growth) (the 1996
    /// model, which takes microseconds, reports nothing).
    pub fn grow_in(&self, seed: u64, run: &mut Run<'_>) -> Result<Skeleton> {
        match *self {
            Source::Honda(p) => honda::build_varied(&p, &honda::Variation::default().seed(seed)),
            Source::Grammar(ls, o) => ls.skeleton_in(&o.variation_seed(seed), run),
            Source::Growth(species, cycles) => {
                let mut world = World::new(&WorldOptions::default().seed(seed))?;
                world.plant(&species, [0.0, 0.0, 0.0], seed)?;
                world.step_in(cycles, run)?;
                world.tree(0)
            }
        }
    }

    /// Whether `self` and `other` grow the same tree for the same seed: equal parameters,
    /// or the same grammar object with equal options.
    pub(crate) fn same(&self, other: &Source<'_>) -> bool {
        match (self, other) {
            (Source::Honda(x), Source::Honda(y)) => x == y,
            (Source::Grammar(x, ox), Source::Grammar(y, oy)) => std::ptr::eq(*x, *y) && ox == oy,
            (Source::Growth(x, cx), Source::Growth(y, cy)) => x == y && cx == cy,
            _ => false,
        }
    }
}
