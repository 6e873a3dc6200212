//! Many trees at once: a forest from a list of tree sources and seeds, each grown and
//! meshed independently. With the `parallel` feature the trees are built on all cores
//! (rayon); the result is identical to [`build_serial`], tree by tree and byte by byte.

use crate::error::Result;
use crate::honda::{self, HondaParams};
use crate::lsystem::{LSystem, LsystemOptions};
use crate::mesh::{self, Mesh, MeshOptions};

/// What one tree of the forest grows from.
#[derive(Clone, Copy, Debug)]
pub enum Source<'a> {
    /// The 1996 model with these parameters.
    Honda(HondaParams),
    /// A grammar with derivation options (its `seed` is replaced by the item's seed).
    Grammar(&'a LSystem, LsystemOptions),
}

/// One tree of a forest.
#[derive(Clone, Copy, Debug)]
pub struct Item<'a> {
    /// What it grows from.
    pub source: Source<'a>,
    /// Its seed (for stochastic grammars; the 1996 model has no randomness).
    pub seed: u64,
}

fn build_one(item: &Item<'_>, options: &MeshOptions) -> Result<Mesh> {
    let skeleton = match item.source {
        Source::Honda(p) => honda::build(&p)?,
        Source::Grammar(ls, o) => ls.skeleton(&LsystemOptions {
            seed: item.seed,
            ..o
        })?,
    };
    mesh::tubes(&skeleton, options)
}

/// Grows and meshes every item one after another.
pub fn build_serial(items: &[Item<'_>], options: &MeshOptions) -> Result<Vec<Mesh>> {
    items.iter().map(|i| build_one(i, options)).collect()
}

/// Grows and meshes every item; on all cores with the `parallel` feature, else serially.
/// The first error (in item order) is returned.
pub fn build(items: &[Item<'_>], options: &MeshOptions) -> Result<Vec<Mesh>> {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        items.par_iter().map(|i| build_one(i, options)).collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        build_serial(items, options)
    }
}
