//! Self-organizing trees (Pałubicki et al. 2009): trees that grow cycle by cycle toward
//! light and space, shade each other and shed what starves.
//!
//! A [`World`] holds the trees and one environment they share: shadow propagation in a
//! voxel grid, or space colonization with attraction markers ([`Environment`]). Each
//! [`World::step`] runs one growth cycle for every tree: light and the optimal direction
//! at every bud; a basipetal pass that gathers light; an acropetal pass that splits the
//! vigour by the extended Borchert–Honda model (apical control λ, vigour multiplier α);
//! new shoots of ⌊v⌋ internodes heading between the previous heading, the environment's
//! direction and tropism; shedding of branches whose vigour no longer pays for their size;
//! pipe-model radii that never shrink; and, optionally, seeding of new trees.
//!
//! A snapshot of any tree ([`World::tree`]) is an ordinary [`Skeleton`]: `birth` is the
//! growth cycle that made each branch, `order` its branching order, and every living bud
//! is a leaf site, so meshes, leaves, LOD, animation and export work on it unchanged.
//!
//! ```
//! use arbor::models::growth::{GrowthParams, Species, World, WorldOptions};
//!
//! let mut world = World::new(&WorldOptions::default())?;
//! world.plant(&GrowthParams::preset(Species::Excurrent), [0.0, 0.0, 0.0], 1)?;
//! world.step(8)?;
//! let tree = world.tree(0)?;
//! assert!(tree.len() > 20);
//! # Ok::<(), arbor::Error>(())
//! ```

mod env;
mod ground;
mod params;
mod tree;

use crate::error::{Error, Result};
use crate::progress::Run;
use crate::skeleton::Skeleton;
use env::Env;
use glam::Vec3;
use tree::Tree;

pub use env::{MAX_OBSTACLES, Obstacle};
pub use ground::{HeightField, MAX_GROUND_SAMPLES, SpeciesMap};
pub use params::{GrowthParams, Species};

/// How a world's trees perceive light and space (C: ArborEnvironment, in
/// ArborWorldOptions.environment).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Environment {
    /// Shadow propagation in a voxel grid: every bud casts a pyramid of shadow below it.
    /// The default.
    #[default]
    Shadow = 0,
    /// Space colonization: buds compete for attraction markers scattered in the box.
    SpaceColonization = 1,
}

crate::enums::numbered!(Environment as "ArborEnvironment" {
    Shadow = "shadow",
    SpaceColonization = "space-colonization",
});

crate::options::options! {
/// The world: its box, its environment and its limits. Plain data; `Default` gives the
/// documented defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldOptions {
    /// Shadow (default) or space colonization.
    pub environment: Environment = Environment::Shadow,
    /// Lower corner of the box trees grow in (world units, Y up). Default (-10, 0, -10).
    pub min: [f32; 3] = [-10.0, 0.0, -10.0],
    /// Upper corner. Default (10, 20, 10).
    pub max: [f32; 3] = [10.0, 20.0, 10.0],
    /// Voxel edge of the shadow grid, or the spacing of attraction markers (one per cell,
    /// jittered). Finite, > 0. Default 0.25 (one internode of the presets).
    pub cell_size: f32 = 0.25, checked Above(0.0), "a finite number > 0",
    /// Seeds the markers and the seeding of new trees. Default 0.
    pub seed: u64 = 0,
    /// Shadow a bud casts into its own cell and the layer below (`a`), > 0. Default 0.2.
    pub shadow_strength: f32 = 0.2, checked Above(0.0), "a finite number > 0",
    /// Falloff per layer (`b` > 1: layer q gets a*b^-q). Default 2.
    pub shadow_falloff: f32 = 2.0, checked Above(1.0), "a finite number > 1",
    /// Layers of the shadow pyramid below a bud (`q_max`), 0..=16. Default 5.
    pub shadow_depth: u32 = 5, checked AtMost(16), "0..=16 layers",
    /// Full exposure (`C`), > 0. Default 1.5.
    pub full_light: f32 = 1.5, checked Above(0.0), "a finite number > 0",
    /// Most cells the grid may have (4 bytes each for shadow; never more than 2^31): the
    /// box's cells at `cell_size`, and the shadow grid as it grows with what is shaded (a
    /// step, plant or obstacle that would pass it is `LimitExceeded`, the world unchanged).
    /// Default 2^25 (128 MiB).
    pub max_cells: usize = 1 << 25,
    /// Growth stops with `LimitExceeded` naming `max_branches` before the world's
    /// internodes would pass this. Default 2^24.
    pub max_branches: usize = crate::limits::DEFAULT_MAX_BRANCHES,
    /// Most trees (seeding stops adding trees at this count). Default 1,024.
    pub max_trees: usize = 1024,
}
}

impl WorldOptions {
    /// [`Error::InvalidArgument`] naming the first option out of its range, or
    /// [`Error::LimitExceeded`] when the grid would pass `max_cells`.
    pub fn validate(&self) -> Result<()> {
        let finite = |p: &[f32; 3]| p.iter().all(|v| v.is_finite());
        if !(finite(&self.min) && finite(&self.max)) {
            return Err(Error::invalid("min/max", "the box corners must be finite"));
        }
        if (0..3).any(|k| self.max[k] <= self.min[k]) {
            return Err(Error::invalid(
                "max",
                format!(
                    "{:?}; expected greater than min {:?} on every axis",
                    self.max, self.min
                ),
            ));
        }
        self.check_fields()?;
        let cells = self.cells();
        // A cell index shares 32 bits with a flag: no grid has more than 2^31 cells.
        let most = self.max_cells.min(env::MOST_CELLS);
        if cells > most as u128 {
            return Err(Error::LimitExceeded {
                limit_name: "max_cells",
                what: "grid cells of the world box at this cell_size",
                limit: most as u64,
                requested: u64::try_from(cells).unwrap_or(u64::MAX),
                step: None,
            });
        }
        Ok(())
    }

    /// Cells of the world box at `cell_size` (saturating).
    fn cells(&self) -> u128 {
        (0..3)
            .map(|k| {
                let n = ((self.max[k] - self.min[k]) as f64 / self.cell_size as f64).ceil();
                if n.is_finite() {
                    n.max(1.0) as u128
                } else {
                    u128::MAX
                }
            })
            .fold(1u128, |a, n| a.saturating_mul(n))
    }
}

/// Trees growing together, sharing light and space (see the module documentation).
#[derive(Clone, Debug)]
pub struct World {
    options: WorldOptions,
    env: Env,
    trees: Vec<Tree>,
    /// Each tree's species slot (a number of the host's; a seedling takes its parent's).
    slots: Vec<u32>,
    cycle: u32,
    rng: crate::rng::Rng,
}

impl World {
    /// An empty world; fails naming the first bad option, or with `LimitExceeded` when
    /// the grid would pass `max_cells` (before it is allocated).
    pub fn new(options: &WorldOptions) -> Result<Self> {
        options.validate()?;
        Ok(World {
            options: *options,
            env: Env::new(options)?,
            trees: Vec::new(),
            slots: Vec::new(),
            cycle: 0,
            rng: crate::rng::Rng::new(options.seed ^ 0x5EED_F0E5_7000_0001),
        })
    }

    /// The world's options.
    pub fn options(&self) -> &WorldOptions {
        &self.options
    }

    /// Plants a tree of `species` with its base at `position` (inside the box): one
    /// internode pointing up, with a terminal and a lateral bud. `seed` turns its first
    /// lateral bud. Returns its index (planting order). Its species slot is 0
    /// ([`plant_in_slot`](Self::plant_in_slot) chooses).
    pub fn plant(&mut self, species: &GrowthParams, position: [f32; 3], seed: u64) -> Result<u32> {
        self.plant_in_slot(species, position, 0, seed)
    }

    /// [`plant`](Self::plant) in species slot `slot`: a number of the caller's that the
    /// tree and its seedlings carry ([`tree_slot`](Self::tree_slot),
    /// [`set_species`](Self::set_species)).
    pub fn plant_in_slot(
        &mut self,
        species: &GrowthParams,
        position: [f32; 3],
        slot: u32,
        seed: u64,
    ) -> Result<u32> {
        species.validate()?;
        if !position.iter().all(|v| v.is_finite()) || !self.env.inside(Vec3::from(position)) {
            return Err(Error::invalid(
                "position",
                format!(
                    "{position:?}; expected a point inside the world box {:?}..{:?}",
                    self.options.min, self.options.max
                ),
            ));
        }
        if self.trees.len() >= self.options.max_trees {
            return Err(Error::LimitExceeded {
                limit_name: "max_trees",
                what: "trees",
                limit: self.options.max_trees as u64,
                requested: self.trees.len() as u64 + 1,
                step: None,
            });
        }
        self.check_branches(1)?;
        let end = Vec3::from(position) + Vec3::Y * species.internode_length;
        self.env.cover([end])?;
        let tree = Tree::plant(*species, Vec3::from(position), seed, self.cycle, &self.env);
        tree.cast(&mut self.env, 1);
        // One tree's first shadow: a handful of cells, sorted on the calling thread.
        self.env.flush(false);
        self.trees.push(tree);
        self.slots.push(slot);
        Ok(self.trees.len() as u32 - 1)
    }

    /// Plants a tree standing on the ground at (x, z) ([`ground_height`](Self::ground_height))
    /// in species slot `slot`, as [`plant_in_slot`](Self::plant_in_slot).
    pub fn plant_on_ground(
        &mut self,
        species: &GrowthParams,
        [x, z]: [f32; 2],
        slot: u32,
        seed: u64,
    ) -> Result<u32> {
        let y = self.ground_height(x, z);
        self.plant_in_slot(species, [x, y, z], slot, seed)
    }

    /// Lays `ground` under the world: trees planted with
    /// [`plant_on_ground`](Self::plant_on_ground) and seedlings stand on it, and no bud
    /// below it gets light (nor casts shadow that reaches the buds above). Only while the
    /// world is empty (no tree and no obstacle; else `InvalidArgument`), and every height
    /// must lie inside the box in y. A flat ground at the box's floor grows exactly the
    /// trees of a world without one.
    pub fn set_ground(&mut self, ground: HeightField) -> Result<()> {
        if !self.trees.is_empty() || self.env.has_obstacles() {
            return Err(Error::invalid(
                "ground",
                format!(
                    "the world already holds {} trees and {} obstacles; expected the ground laid first",
                    self.trees.len(),
                    self.env.obstacle_count()
                ),
            ));
        }
        let (low, high) = ground.range();
        if low < self.options.min[1] || high >= self.options.max[1] {
            return Err(Error::invalid(
                "ground",
                format!(
                    "heights {low}..={high}; expected inside the world box's y range {}..{}",
                    self.options.min[1], self.options.max[1]
                ),
            ));
        }
        self.env.set_ground(ground);
        Ok(())
    }

    /// The height field under the world, or none (the box's floor).
    pub fn ground(&self) -> Option<&HeightField> {
        self.env.ground()
    }

    /// The ground's height at (x, z): the height field's, or the box's floor.
    pub fn ground_height(&self, x: f32, z: f32) -> f32 {
        self.env
            .ground()
            .map_or(self.options.min[1], |g| g.height(x, z))
    }

    /// Plants the world from a species map ([`SpeciesMap::points`], seeded by `seed`):
    /// each point a tree of `species[slot]` standing on the ground, in that slot, its
    /// own seed drawn from `seed`; points outside the box are left out. Returns the new
    /// trees' indices. All or nothing: a slot past `species`, a bad species, more trees
    /// than `max_trees` or internodes than `max_branches` leave the world as it was.
    pub fn plant_map(
        &mut self,
        map: &SpeciesMap,
        species: &[GrowthParams],
        seed: u64,
    ) -> Result<Vec<u32>> {
        for s in species {
            s.validate()?;
        }
        let room = self.options.max_trees.saturating_sub(self.trees.len());
        let points = map.points(seed, room)?;
        if let Some(&(x, z, slot)) = points.iter().find(|p| p.2 as usize >= species.len()) {
            return Err(Error::invalid(
                "slots",
                format!(
                    "species slot {slot} at ({x}, {z}); expected below the {} species given",
                    species.len()
                ),
            ));
        }
        let inside: Vec<[f32; 3]> = points
            .iter()
            .map(|&(x, z, _)| [x, self.ground_height(x, z), z])
            .collect();
        let keep: Vec<usize> = (0..points.len())
            .filter(|&k| self.env.inside(Vec3::from(inside[k])))
            .collect();
        self.check_branches(keep.len())?;
        let ends: Vec<Vec3> = keep
            .iter()
            .map(|&k| {
                Vec3::from(inside[k]) + Vec3::Y * species[points[k].2 as usize].internode_length
            })
            .collect();
        self.env.cover(ends)?;
        let mut rng = crate::rng::Rng::new(seed ^ 0x91A7_0000_0000_0001);
        let mut ids = Vec::with_capacity(keep.len());
        for k in keep {
            let slot = points[k].2;
            let p = species[slot as usize];
            let tree = Tree::plant(
                p,
                Vec3::from(inside[k]),
                rng.next_u64(),
                self.cycle,
                &self.env,
            );
            tree.cast(&mut self.env, 1);
            self.trees.push(tree);
            self.slots.push(slot);
            ids.push(self.trees.len() as u32 - 1);
        }
        self.env.flush(false);
        Ok(ids)
    }

    /// The species slot of tree `index` (what it was planted in; a seedling: its
    /// parent's); an index past the end is `InvalidArgument`.
    pub fn tree_slot(&self, index: usize) -> Result<u32> {
        self.slots.get(index).copied().ok_or_else(|| {
            Error::invalid(
                "index",
                format!("tree {index}; the world has {} trees", self.trees.len()),
            )
        })
    }

    /// Gives every tree in species slot `slot`, and the seedlings they drop from now on,
    /// the parameters `species` (what a slider in a host changes); returns how many
    /// trees changed. A bad parameter: `InvalidArgument`, nothing changed.
    pub fn set_species(&mut self, slot: u32, species: &GrowthParams) -> Result<usize> {
        species.validate()?;
        let mut n = 0;
        for (t, &s) in self.trees.iter_mut().zip(&self.slots) {
            if s == slot {
                t.species = *species;
                n += 1;
            }
        }
        Ok(n)
    }

    /// Adds an obstacle: it casts shadow (shadow worlds) or removes the markers inside it
    /// (space colonization).
    ///
    /// Its cost is in proportion to the cells its bounds cover (and the columns below
    /// them), not to the obstacles already there; a world holds at most
    /// [`MAX_OBSTACLES`] (then `LimitExceeded`).
    pub fn add_obstacle(&mut self, obstacle: Obstacle) -> Result<()> {
        self.add_obstacle_in(obstacle, &mut Run::default())
    }

    /// [`add_obstacle`](Self::add_obstacle) in `run`, reporting
    /// [`Stage::Growth`](crate::progress::Stage) as it goes through the obstacle's layers;
    /// `false` from the callback stops with `Cancelled` and the world is as it was.
    pub fn add_obstacle_in(&mut self, obstacle: Obstacle, run: &mut Run<'_>) -> Result<()> {
        obstacle.validate()?;
        let mut p = Run::new(run.callback());
        self.env.add_obstacle(&obstacle, &mut p)?;
        for t in &mut self.trees {
            t.darken(&obstacle);
        }
        p.report(crate::progress::Stage::Growth, 1.0)
    }

    fn check_branches(&self, more: usize) -> Result<()> {
        let now = self.branch_count();
        if now + more > self.options.max_branches {
            return Err(Error::LimitExceeded {
                limit_name: "max_branches",
                what: "internodes of the world",
                limit: self.options.max_branches as u64,
                requested: (now + more) as u64,
                step: Some(self.cycle),
            });
        }
        Ok(())
    }

    /// Runs `cycles` growth cycles for every tree. A cycle that would pass `max_branches`
    /// stops with `LimitExceeded` before it grows anything; the world stays as it was
    /// after the last whole cycle.
    pub fn step(&mut self, cycles: u32) -> Result<()> {
        self.step_in(cycles, &mut Run::default())
    }

    /// [`step`](Self::step) in `run`: on the calling thread when the run asks for one
    /// thread, else the trees of a cycle grow and the shadow grid is updated on all cores
    /// with the `parallel` feature (the result is identical to the serial path; a world
    /// under 4,096 internodes stays on the calling thread, where waking threads would cost
    /// more than they give), reporting
    /// [`Stage::Growth`](crate::progress::Stage) before every cycle and at the end (on the
    /// calling thread); `false` from the callback stops with [`Error::Cancelled`] before
    /// the next cycle, the world as it was after the last whole cycle.
    pub fn step_in(&mut self, cycles: u32, run: &mut Run<'_>) -> Result<()> {
        let parallel = run.threads_or(0) != 1;
        for k in 0..cycles {
            if run.active() {
                run.report(crate::progress::Stage::Growth, k as f64 / cycles as f64)?;
            }
            self.cycle_once(parallel)?;
        }
        if run.active() {
            run.report(crate::progress::Stage::Growth, 1.0)?;
        }
        Ok(())
    }

    fn cycle_once(&mut self, parallel: bool) -> Result<()> {
        let cycle = self.cycle + 1;
        // Threads pay only for enough work (waking one costs tens of microseconds).
        let parallel = parallel && self.branch_count() >= 4096;
        // 1–5: light and direction at every bud from the shared environment, then the
        // basipetal and acropetal passes, shedding and the new shoots, planned per tree
        // (in parallel with the `parallel` feature). The shadow is read where each bud
        // is; colonization first needs every bud of every tree.
        let plans: Vec<tree::Plan> = match self.env.kind() {
            Environment::Shadow => {
                let env = &self.env;
                each(&mut self.trees, parallel, |t| {
                    t.plan_cycle(&ShadowLight(env), cycle)
                })
            }
            Environment::SpaceColonization => {
                let buds: Vec<Vec<env::Bud>> = each(&mut self.trees, parallel, |t| {
                    let mut b = Vec::new();
                    t.buds(&mut b);
                    b
                });
                let species: Vec<GrowthParams> = self.trees.iter().map(|t| t.species).collect();
                let light = self.env.colonize(&buds, &species);
                let mut work: Vec<(&mut Tree, &[(f32, Vec3)])> = self
                    .trees
                    .iter_mut()
                    .zip(light.iter().map(|l| l.as_slice()))
                    .collect();
                each(&mut work, parallel, |(t, l)| {
                    t.plan_cycle(&Markers(l), cycle)
                })
            }
        };
        let new: usize = plans.iter().map(|p| p.new_internodes()).sum();
        self.check_branches(new)?;
        // The sky is open: the grid grows to hold the new buds' shadow before they cast,
        // its values moving to their new places on one thread while the trees grow and
        // shed on the others (in parallel with the `parallel` feature: growing reads no
        // shadow). The shadow changes they make go to the shared grid in tree order, so
        // the result does not depend on the thread count.
        let ends = env::bounds(plans.iter().flat_map(|p| p.ends()));
        let mut work: Vec<(&mut Tree, tree::Plan)> = self.trees.iter_mut().zip(plans).collect();
        self.env.cover_while(ends, parallel, |env| {
            each(&mut work, parallel, |(t, plan)| {
                t.grow(std::mem::take(plan), env, cycle)
            });
        })?;
        drop(work);
        // 7: seeding.
        let mut seedlings = Vec::new();
        let mut seedling_slots = Vec::new();
        let most = self.options.max_trees;
        for (t, &slot) in self.trees.iter().zip(&self.slots) {
            t.seeds(cycle, &mut self.rng, most, &mut seedlings);
            seedling_slots.resize(seedlings.len(), slot);
        }
        // Internodes of the world, counted once and then kept up as seedlings are planted.
        let mut branches = self.branch_count();
        for ((species, mut at), slot) in seedlings.into_iter().zip(seedling_slots) {
            // Seeds land on the ground.
            if let Some(g) = self.env.ground() {
                at.y = g.height(at.x, at.z);
            }
            if self.trees.len() >= self.options.max_trees || !self.env.inside(at) {
                continue;
            }
            if branches >= self.options.max_branches {
                break;
            }
            let end = at + Vec3::Y * species.internode_length;
            // A seed germinates only where enough light reaches the ground (shadow
            // worlds: the buds as the last cycle left them).
            if self.env.kind() == Environment::Shadow
                && self.env.ground_q(at) < species.germination_light
            {
                continue;
            }
            if self.env.cover([end]).is_err() {
                break;
            }
            let seed = self.rng.next_u64();
            let tree = Tree::plant(species, at, seed, cycle, &self.env);
            tree.cast(&mut self.env, 1);
            self.trees.push(tree);
            self.slots.push(slot);
            branches += 1;
        }
        // The trees' changes, in tree order, then the seedlings' buds.
        let casts: Vec<&[(env::Key, i32)]> =
            self.trees.iter().map(|t| t.casts.as_slice()).collect();
        self.env.flush_with(&casts, parallel);
        self.cycle = cycle;
        Ok(())
    }

    /// Growth cycles run so far.
    pub fn cycle(&self) -> u32 {
        self.cycle
    }

    /// Bytes of the shadow grid now: 4 per cell. It holds nothing until the first bud
    /// casts, then the cells the buds' shadow reaches with room to spare, and grows (in
    /// place) with the trees, since the sky is open; 0 in a colonization world.
    pub fn grid_bytes(&self) -> usize {
        self.env.grid_cells() * 4
    }

    /// Number of trees (planted and seeded).
    pub fn tree_count(&self) -> usize {
        self.trees.len()
    }

    /// Living internodes of all trees.
    pub fn branch_count(&self) -> usize {
        self.trees.iter().map(|t| t.len()).sum()
    }

    /// Internodes shed so far by tree `index`.
    pub fn shed_count(&self, index: usize) -> Result<usize> {
        Ok(self.tree_ref(index)?.shed)
    }

    fn tree_ref(&self, index: usize) -> Result<&Tree> {
        self.trees.get(index).ok_or_else(|| {
            Error::invalid(
                "index",
                format!("{index}; the world has {} trees", self.trees.len()),
            )
        })
    }

    /// A snapshot of tree `index` (planting order) as an ordinary skeleton: `birth` is the
    /// cycle that made each branch, `order` its branching order, radii from the pipe
    /// model, and a leaf site at every living bud.
    pub fn tree(&self, index: usize) -> Result<Skeleton> {
        Ok(self.tree_ref(index)?.skeleton())
    }

    /// The largest relative vigour residual of the last cycle's splits over every
    /// branching point of every tree: |v - v_main - v_lateral| / v (0 up to rounding: the
    /// extended Borchert-Honda split conserves vigour).
    pub fn vigour_residual(&self) -> f32 {
        self.trees.iter().map(|t| t.residual).fold(0.0, f32::max)
    }
}

/// The light of a shadow world: Q from the bud's cell, V from the shadow's gradient there.
struct ShadowLight<'a>(&'a Env);

impl tree::Light for ShadowLight<'_> {
    const ORDERED: bool = false;
    #[inline]
    fn q(&self, _: u32, word: env::Key) -> f32 {
        self.0.shadow_q(word)
    }
    fn v(&self, _: u32, word: env::Key) -> Vec3 {
        self.0.shadow_v(word)
    }
    #[inline]
    fn prefetch(&self, word: env::Key) {
        self.0.prefetch(word)
    }
    #[inline]
    fn prefetch_v(&self, word: env::Key) {
        self.0.prefetch_v(word)
    }
    fn read_ahead(&self) -> bool {
        // Past 4 MiB of cells a bud's read is a cache miss more often than not.
        self.0.grid_cells() > READ_AHEAD_CELLS
    }
}

/// Cells of the shadow grid past which the buds' light is read in a pass of its own.
const READ_AHEAD_CELLS: usize = 1 << 20;

/// The light of a colonization world, found for every bud before planning (bud order).
struct Markers<'a>(&'a [(f32, Vec3)]);

impl tree::Light for Markers<'_> {
    const ORDERED: bool = true;
    #[inline]
    fn q(&self, ordinal: u32, _: env::Key) -> f32 {
        self.0.get(ordinal as usize).map_or(0.0, |l| l.0)
    }
    fn v(&self, ordinal: u32, _: env::Key) -> Vec3 {
        self.0.get(ordinal as usize).map_or(Vec3::ZERO, |l| l.1)
    }
}

/// `f` of every element, on all cores with the `parallel` feature (and `parallel` set).
fn each<T: Send, R: Send>(
    items: &mut [T],
    parallel: bool,
    f: impl Fn(&mut T) -> R + Sync + Send,
) -> Vec<R> {
    #[cfg(feature = "parallel")]
    if parallel && items.len() > 1 {
        use rayon::prelude::*;
        return items.par_iter_mut().map(f).collect();
    }
    let _ = parallel;
    items.iter_mut().map(f).collect()
}
