//! A chain of levels of detail of one tree, bark and leaves together: each level with
//! fewer sides, its twigs culled by their size on screen where it is drawn, and its leaves
//! thinned and enlarged (fewer, larger leaves: the crown keeps its area and colour, and
//! the leaves that stay are where they were, so a host's dithered cross-fade does not
//! pop), within a budget of the full tree's triangles, with the screen coverage below
//! which the next level takes over.
//!
//! ```
//! use arbor::lod::{chain, LodOptions};
//! use arbor::mesh::{LeafOptions, MeshOptions};
//!
//! let tree = arbor::models::honda::build(&arbor::HondaParams::preset('b').unwrap()).unwrap();
//! let leaves = LeafOptions::default().tips(true).density(4.0).size(6.0);
//! let levels = chain(&tree, &MeshOptions::default(), Some(&leaves), None, &LodOptions::default())?;
//! assert_eq!(levels.len(), 4);
//! for pair in levels.windows(2) {
//!     assert!(pair[1].triangles < pair[0].triangles);
//!     assert!(pair[1].screen_coverage <= pair[0].screen_coverage);
//! }
//! # Ok::<(), arbor::Error>(())
//! ```

use crate::error::{Error, Result};
use crate::mesh::{self, LeafOptions, Mesh, MeshOptions};
use crate::raster::{Surface, Target, View};
use crate::skeleton::Skeleton;
use crate::texture::Image;
use glam::Vec3;

/// The screen height, in pixels, the screen coverages are reckoned for (a 1080p screen).
pub const REFERENCE_PIXELS: f32 = 1080.0;

/// The bark's share of a level's budget where the tree has leaves (the leaves, which
/// make most of a crown's outline, get the rest) when the switches are not fitted.
pub const BARK_SHARE: f32 = 0.3;

/// The bark's shares of a level's budget a chain that fits its switches tries, keeping
/// the one whose silhouette is nearest the full tree's.
pub const BARK_SHARES: [f32; 4] = [0.1, 0.2, 0.35, 0.55];

/// The powers a chain that fits its switches enlarges a level's inside leaves by, as
/// fractions of [`LeafOptions::keep_enlarge`](crate::mesh::LeafOptions::keep_enlarge):
/// the candidates are made with the first, and the one picked is tried with the others
/// (a weeping or narrow crown seen small keeps its outline better with its inside leaves
/// a little smaller: the willow's and the poplar's last levels).
pub const ENLARGE_SHARES: [f32; 2] = [1.0, 0.8];

/// Joints along an axis that move it by less than this many pixels where a level is
/// first drawn are removed ([`collapse`]).
pub const COLLAPSE_PIXELS: f32 = 0.5;

crate::options::options! {
/// How a chain of levels of detail is made. `Default` gives the documented defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodOptions {
    /// Mesh levels, the full tree (level 0) included, 1..=8. Default 4.
    pub levels: u32 = 4, checked In(1, 8), "1..=8 levels",
    /// Level 1's triangles at most this fraction of the full tree's, in (0, 1]. Default 0.4.
    pub budget: f32 = 0.4, checked AboveTo(0.0, 1.0), "0 < budget <= 1",
    /// Each further level's budget is the one before times this, in (0, 1]. Default 0.5
    /// (40%, 20%, 10%... of the full tree).
    pub step: f32 = 0.5, checked AboveTo(0.0, 1.0), "0 < step <= 1",
    /// The screen coverage (the fraction of the screen's height the tree's height covers)
    /// below which level 1 takes over from the full tree, in (0, 1]. Default 0.5.
    pub coverage: f32 = 0.5, checked AboveTo(0.0, 1.0), "0 < coverage <= 1",
    /// Each further switch is at the one before times this, in (0, 1). Default 0.5.
    pub coverage_step: f32 = 0.5, checked AboveTo(0.0, 0.99), "0 < coverage_step < 1",
    /// The intersection over union each level's silhouette keeps with the full tree's
    /// where it is first drawn, 0..=1: a switch coverage is lowered (by 40% a time, down
    /// to [`MIN_COVERAGE`]) until the level's [`silhouette`], drawn by
    /// [`raster`](crate::raster), keeps it on average: the candidates are compared from
    /// four directions, the best then measured from sixteen others (eight where the level
    /// is first drawn 64 pixels or more across). 0: the switches as
    /// `coverage` and `coverage_step` put them. Default 0.91.
    pub silhouette: f32 = 0.91, checked In(0.0, 1.0), "0..=1",
    /// Threads the silhouettes are drawn on: 0 (the default), the machine's cores; 1, the
    /// calling thread.
    pub threads: u32 = 0,
}
}

impl LodOptions {
    /// Refuses options out of their documented ranges, naming the first.
    pub fn validate(&self) -> Result<()> {
        self.check_fields()
    }

    /// The fraction of the full tree's triangles level `level` may have (1 for level 0).
    pub fn budget_of(&self, level: u32) -> f32 {
        match level {
            0 => 1.0,
            l => self.budget * self.step.powi(l as i32 - 1),
        }
    }

    /// The screen coverage below which level `level + 1` takes over from `level`.
    pub fn coverage_of(&self, level: u32) -> f32 {
        self.coverage * self.coverage_step.powi(level as i32)
    }
}

/// One level of a [`chain`].
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    /// The bark.
    pub bark: Mesh,
    /// The baked leaves (none when the chain was made without leaves).
    pub leaves: Option<Mesh>,
    /// The options the bark was meshed with.
    pub mesh_options: MeshOptions,
    /// The options the leaves were baked with (their `keep` the level's share).
    pub leaf_options: Option<LeafOptions>,
    /// Drawn while the tree covers at least this fraction of the screen's height (the
    /// last level: down to this coverage, below which an impostor or nothing takes over).
    pub screen_coverage: f32,
    /// Triangles of bark and leaves (degenerate strip joins not counted).
    pub triangles: usize,
    /// The mean intersection over union of this level's [`silhouette`] with the full
    /// tree's where it is first drawn (the previous level's switch), from sixteen
    /// directions (eight from 64 pixels across) other than the four its candidates were
    /// compared from (a figure that did not pick it): at least [`LodOptions::silhouette`]
    /// unless the level could not keep it even at [`MIN_COVERAGE`]. 1 for the full tree;
    /// 0 when not measured (`silhouette` 0).
    pub silhouette: f32,
    /// For each branch of the tree, the branch of the skeleton this level's bark was
    /// meshed from (one range of `bark` each; see [`collapse_merged`]) it was merged into;
    /// empty where that skeleton is the tree's own (the full tree).
    pub merged: Vec<u32>,
}

/// The levels of detail of `skeleton` meshed with `mesh` (level 0: as it is) and, when
/// given, its baked `leaves`: each further level with fewer sides (half the one before's,
/// at least 3), its axes straightened where that moves them by less than
/// [`COLLAPSE_PIXELS`] at the coverage where it is first drawn (for a tree as tall as
/// `skeleton`, on a screen of [`REFERENCE_PIXELS`]), its branches that give the outline
/// least for their triangles removed (each with what grows on it; leaves stay where they
/// were) until the bark is within its share of the budget (never its roots), and the
/// leaves thinned ([`LeafOptions::keep`]) to fill the rest.
/// Each switch is then lowered
/// until the level's silhouette keeps [`LodOptions::silhouette`] (the leaves alpha-tested
/// against `atlas`, the leaf atlas they sample, when given).
pub fn chain(
    skeleton: &Skeleton,
    mesh: &MeshOptions,
    leaves: Option<&LeafOptions>,
    atlas: Option<&Image>,
    lod: &LodOptions,
) -> Result<Vec<Level>> {
    lod.validate()?;
    mesh.validate()?;
    // The silhouettes sample a small copy of the atlas (the full one misses the cache).
    let small = atlas.map(|a| a.downsampled(SILHOUETTE_ATLAS));
    let atlas = small.as_ref();
    let (full, shape) = prepare(skeleton, mesh, leaves, lod.threads)?;
    fit(full, mesh.up(), atlas, lod, &shape)
}

/// The chain from `full` on: level k's candidates made by `shape` (from the options of
/// level k - 1, its budget in triangles and the coverage where it is first drawn) at the
/// coverage from the ladder of `lod`, lowered by 40% a time until the best of them keeps
/// `lod.silhouette`.
fn fit(
    full: Level,
    up: Vec3,
    atlas: Option<&Image>,
    lod: &LodOptions,
    shape: &Shape<'_>,
) -> Result<Vec<Level>> {
    let make = |before: &MeshOptions, budget: usize, c: f32| {
        shape.levels(before, budget, c, lod.silhouette > 0.0)
    };
    let full_triangles = full.triangles;
    let frame = Frame::of(&full, up);
    let (dirs, check8, check16) = (
        fit_directions(up),
        check_directions(up, 8),
        check_directions(up, 16),
    );
    let mut out = vec![full];
    let mut ceiling = 1.0f32;
    // The full tree's silhouettes, by side in pixels and direction, drawn once.
    let mut full_masks: std::collections::HashMap<(u32, bool), Vec<Vec<bool>>> = Default::default();
    for level in 1..lod.levels {
        let budget = (lod.budget_of(level) * full_triangles as f32) as usize;
        // The level is made for the coverage its ladder gives, then drawn nearer no more
        // than where its silhouette holds.
        let mut c = lod.coverage_of(level - 1).min(ceiling);
        let before = out[level as usize - 1].mesh_options;
        let mut made_for = c;
        let mut candidates = make(&before, budget, c)?;
        let over = |candidates: &[Level]| -> Result<()> {
            match candidates.iter().find(|m| m.triangles > budget.max(1)) {
                Some(m) => Err(Error::invalid(
                    "lod",
                    format!(
                        "level {level} keeps {} triangles; expected at most {budget} (of the \
                         full tree's {full_triangles})",
                        m.triangles
                    ),
                )),
                None => Ok(()),
            }
        };
        over(&candidates)?;
        let (made, iou) = match &frame {
            Some(frame) if lod.silhouette > 0.0 => loop {
                let px = frame.pixels(c);
                let full_level = &out[0];
                let mean = |m: &Level, dirs: &[Vec3], full: &[Vec<bool>]| {
                    let each =
                        on_threads(lod.threads, dirs, |&d| silhouette(m, atlas, frame, d, px));
                    let sum: f32 = each
                        .iter()
                        .zip(full)
                        .map(|(b, a)| crate::raster::iou(a, b))
                        .sum();
                    sum / dirs.len() as f32
                };
                // Each candidate's mean IoU from the directions; the best is kept.
                let full = full_masks.entry((px, false)).or_insert_with(|| {
                    on_threads(lod.threads, &dirs, |&d| {
                        silhouette(full_level, atlas, frame, d, px)
                    })
                });
                let (best, mut iou) = candidates
                    .iter()
                    .enumerate()
                    .map(|(k, m)| (k, mean(m, &dirs, full)))
                    .fold((0, -1.0f32), |b, x| if x.1 > b.1 { x } else { b });
                // The best with its inside leaves enlarged less, on the same bark: kept
                // where its silhouette is nearer.
                let mut variant: Option<Level> = None;
                for &e in &ENLARGE_SHARES[1..] {
                    if let Some(v) = shape.variant(&candidates[best], e)? {
                        let w = mean(&v, &dirs, full);
                        if w > iou {
                            (variant, iou) = (Some(v), w);
                        }
                    }
                }
                let picked = variant.as_ref().unwrap_or(&candidates[best]);
                // The best, picked on those directions, measured again from others: the
                // figure it was picked by is the luckiest of the candidates' and flatters
                // it (tree a's level 1: 0.964 from the four, 0.920 from 32 others).
                let iou = if iou >= lod.silhouette || c <= MIN_COVERAGE {
                    // Sixteen where a level is small (its figure moves by a tenth between
                    // neighbouring directions), eight where it is large.
                    let check = if px < 64 { &check16 } else { &check8 };
                    let full = full_masks.entry((px, true)).or_insert_with(|| {
                        on_threads(lod.threads, check, |&d| {
                            silhouette(full_level, atlas, frame, d, px)
                        })
                    });
                    mean(picked, check, full)
                } else {
                    iou
                };
                if iou >= lod.silhouette || c <= MIN_COVERAGE {
                    break (variant.unwrap_or_else(|| candidates[best].clone()), iou);
                }
                c = (c * 0.6).max(MIN_COVERAGE);
                // Drawn three times farther than it was made for: made again for there
                // (axes straightened further, so more branches fit the bark's share).
                if c < made_for / 3.0 {
                    made_for = c;
                    candidates = make(&before, budget, c)?;
                    over(&candidates)?;
                }
            },
            _ => (candidates[0].clone(), 0.0),
        };
        out[level as usize - 1].screen_coverage = c;
        ceiling = c;
        out.push(Level {
            screen_coverage: lod.coverage_of(level).min(c),
            silhouette: iou,
            ..made
        });
    }
    Ok(out)
}

/// `f` of each item, on a thread each unless `threads` is 1 (0: the machine's cores);
/// the results in order.
fn on_threads<T: Sync, R: Send>(threads: u32, items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let cores = match threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        t => t as usize,
    };
    if cores <= 1 || items.len() <= 1 {
        return items.iter().map(f).collect();
    }
    std::thread::scope(|s| {
        let f = &f;
        let handles: Vec<_> = items.iter().map(|x| s.spawn(move || f(x))).collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("a silhouette's thread does not panic"))
            .collect()
    })
}

/// The full level of `skeleton` and what its thinner levels are made from.
fn prepare<'a>(
    skeleton: &'a Skeleton,
    mesh: &'a MeshOptions,
    leaves: Option<&'a LeafOptions>,
    threads: u32,
) -> Result<(Level, Shape<'a>)> {
    let height = skeleton
        .bounds()
        .map_or(0.0, |(lo, hi)| (hi - lo).max_element());
    // The bark and the leaves side by side; the leaves placed once for every level.
    let leaf_mesh = || -> Result<Option<(Mesh, mesh::Placed)>> {
        match leaves {
            Some(l) => {
                let placed = mesh::place_all(skeleton, l, mesh)?;
                let full = mesh::leaf_mesh_placed(skeleton, &placed, &l.clone().keep(1.0), mesh)?;
                Ok(Some((full, placed)))
            }
            None => Ok(None),
        }
    };
    let (bark, leaf_mesh) = if threads == 1 {
        (mesh::tubes(skeleton, mesh), leaf_mesh())
    } else {
        std::thread::scope(|s| {
            let bark = s.spawn(|| mesh::tubes(skeleton, mesh));
            let leaves = leaf_mesh();
            (
                bark.join().expect("meshing the bark does not panic"),
                leaves,
            )
        })
    };
    let (bark, leaf_mesh) = (bark?, leaf_mesh?);
    let (leaf_mesh, placed) = match leaf_mesh {
        Some((m, p)) => (Some(m), Some(p)),
        None => (None, None),
    };
    let full_triangles = count(&bark) + leaf_mesh.as_ref().map_or(0, count);
    // How many leaves there are, each of how many triangles (the rest of the leaf mesh,
    // the turtle's polygons and organs, is not thinned).
    let (leaf_count, per_leaf) = match (leaves, &placed) {
        (Some(l), Some(p)) => (p.len(), l.shape().triangles.len()),
        _ => (0, 0),
    };
    let leaf_rest = leaf_mesh
        .as_ref()
        .map_or(0, |m| count(m).saturating_sub(leaf_count * per_leaf));
    let full = Level {
        bark,
        leaves: leaf_mesh,
        mesh_options: *mesh,
        leaf_options: leaves.map(|l| l.clone().keep(1.0)),
        screen_coverage: 1.0,
        triangles: full_triangles,
        silhouette: 1.0,
        merged: Vec::new(),
    };
    let shape = Shape {
        threads,
        placed,
        skeleton,
        mesh,
        leaves,
        height,
        leaf_count,
        per_leaf,
        leaf_rest,
    };
    Ok((full, shape))
}

/// What every level of a chain is made from.
struct Shape<'a> {
    /// Threads the candidates are made on (as [`LodOptions::threads`]).
    threads: u32,
    /// The leaves, placed once.
    placed: Option<mesh::Placed>,
    skeleton: &'a Skeleton,
    mesh: &'a MeshOptions,
    leaves: Option<&'a LeafOptions>,
    height: f32,
    leaf_count: usize,
    per_leaf: usize,
    leaf_rest: usize,
}

impl Shape<'_> {
    /// The candidates for a level (see [`level`](Self::level)): the bark's
    /// share of the budget each of [`BARK_SHARES`] when `several` (a chain that fits its
    /// switches picks the one whose silhouette is nearest, then tries it with the other
    /// [`ENLARGE_SHARES`]: [`variant`](Self::variant)), else [`BARK_SHARE`]; the leaves
    /// enlarged by their own `keep_enlarge`.
    fn levels(
        &self,
        before: &MeshOptions,
        budget: usize,
        c: f32,
        several: bool,
    ) -> Result<Vec<Level>> {
        if several && self.leaf_count > 0 {
            on_threads(self.threads, &BARK_SHARES, |&share| {
                self.level(before, budget, c, share)
            })
            .into_iter()
            .collect()
        } else {
            Ok(vec![self.level(before, budget, c, BARK_SHARE)?])
        }
    }

    /// `level` (one of [`levels`](Self::levels)' candidates) with its inside leaves
    /// enlarged by `enlarge` of the leaves' `keep_enlarge` instead, on the same bark; none
    /// where it has no leaves or keeps them all.
    fn variant(&self, level: &Level, enlarge: f32) -> Result<Option<Level>> {
        let (Some(base), Some(placed), Some(l), Some(leaves)) = (
            self.leaves,
            &self.placed,
            &level.leaf_options,
            &level.leaves,
        ) else {
            return Ok(None);
        };
        if l.keep >= 1.0 {
            return Ok(None);
        }
        let l = l.clone().keep_enlarge(base.keep_enlarge * enlarge);
        let baked = mesh::leaf_mesh_placed(self.skeleton, placed, &l, self.mesh)?;
        Ok(Some(Level {
            bark: level.bark.clone(),
            triangles: level.triangles - count(leaves) + count(&baked),
            leaves: Some(baked),
            leaf_options: Some(l),
            mesh_options: level.mesh_options,
            screen_coverage: level.screen_coverage,
            silhouette: level.silhouette,
            merged: level.merged.clone(),
        }))
    }

    /// Level `level` within `budget` triangles, first drawn at coverage `c`: half the
    /// sides of `before`'s, axes straightened for that size, the branches that give the
    /// outline least for their triangles removed until the bark is at most `share` of
    /// the budget when there are leaves, the leaves filling the rest.
    fn level(&self, before: &MeshOptions, budget: usize, c: f32, share: f32) -> Result<Level> {
        // The bark's share of the budget, or more where the leaves need less.
        let leaf_full = self.leaf_count * self.per_leaf + self.leaf_rest;
        let bark_share = ((budget as f32 * share) as usize).max(budget.saturating_sub(leaf_full));
        let (bark, o, merged) =
            level_bark(self.skeleton, self.mesh, before, self.height, bark_share, c)?;
        let bark_triangles = count(&bark);
        let (leaf_mesh, leaf_options) = match (self.leaves, &self.placed) {
            (Some(l), Some(placed)) if self.leaf_count > 0 && self.per_leaf > 0 => {
                let room = budget.saturating_sub(bark_triangles + self.leaf_rest);
                let keep = mesh::keep_for(self.leaf_count, room / self.per_leaf);
                let l = l.clone().keep(keep);
                let baked = mesh::leaf_mesh_placed(self.skeleton, placed, &l, self.mesh)?;
                (Some(baked), Some(l))
            }
            _ => (None, self.leaves.cloned()),
        };
        let triangles = bark_triangles + leaf_mesh.as_ref().map_or(0, count);
        Ok(Level {
            bark,
            leaves: leaf_mesh,
            mesh_options: o,
            leaf_options,
            screen_coverage: c,
            triangles,
            silhouette: 0.0,
            merged,
        })
    }
}

/// A level's bark: `skeleton` with half the sides of `before`'s options, its axes
/// collapsed for coverage `c` (a tree `height` model units tall), then its thinnest
/// branches removed ([`prune`]) until it has at most `share` triangles; with the options
/// it was meshed with and where each branch was merged.
fn level_bark(
    skeleton: &Skeleton,
    mesh: &MeshOptions,
    before: &MeshOptions,
    height: f32,
    share: usize,
    c: f32,
) -> Result<(Mesh, MeshOptions, Vec<u32>)> {
    let mut o = *before;
    o.radial_segments = (o.radial_segments / 2).max(3);
    o.min_radial_segments = match o.min_radial_segments {
        0 => 0,
        m => m.min(o.radial_segments).max(3),
    };
    let pixel = height / (c * REFERENCE_PIXELS);
    o.cull_radius = mesh.cull_radius;
    // Axes straightened first (up to 4 times the tolerance), then branches removed while
    // the bark is over its share, those that give the outline least for their triangles
    // first, in an order that never empties a level (its roots stay) nor takes every
    // branch of one kind at once. No twig goes for being thin alone: a willow's hanging
    // twigs are each far under a pixel, and together half its outline.
    // Fewer sides draw a thinner branch (a polygon inside the circle): each branch is
    // widened so it is as wide as the full tree draws it, on average over the directions
    // it is seen from (a trunk one or two pixels wide otherwise breaks up at its switch).
    let collapse = |tolerance: f32| -> Result<(Skeleton, Vec<u32>)> {
        let (collapsed, merged) = collapse_merged(skeleton, tolerance)?;
        Ok((widened(collapsed, mesh, &o)?, merged))
    };
    let mut tolerance = COLLAPSE_PIXELS * pixel;
    let (mut collapsed, mut merged) = collapse(tolerance)?;
    let mut bark = mesh::tubes(&collapsed, &o)?;
    for _ in 0..2 {
        if count(&bark) <= share {
            break;
        }
        tolerance *= 2.0;
        (collapsed, merged) = collapse(tolerance)?;
        bark = mesh::tubes(&collapsed, &o)?;
    }
    // Each pruning reckons a branch's triangles from this mesh; the next mesh may differ
    // by a few joins, so a second round takes what is left over.
    for _ in 0..4 {
        let (pruned, map) = prune(&collapsed, &merged, &bark, share)?;
        if pruned.len() == collapsed.len() {
            break;
        }
        (collapsed, merged) = (pruned, map);
        bark = mesh::tubes(&collapsed, &o)?;
    }
    // The roots alone over the share (a trunk of many rings): they are culled too.
    let mut tries = 0;
    while count(&bark) > share && tries < 40 {
        o.cull_radius = if o.cull_radius > 0.0 {
            o.cull_radius * 1.25
        } else {
            1e-3 * height.max(f32::MIN_POSITIVE)
        };
        bark = mesh::tubes(&collapsed, &o)?;
        tries += 1;
    }
    Ok((bark, o, merged))
}

/// `skeleton` (a level's skeleton, `merged` mapping the tree's branches to it, `bark` its
/// mesh) with branches removed, each with its whole subtree, while the triangles `bark`
/// gives the rest (each branch's share of its indices) are over `share`. A branch's worth
/// is the outline it draws for its triangles (its side's area, length times diameter, over
/// its triangles), at least that of any branch growing on it, so twigs go before what
/// bears them; the least worth first, branches of equal worth in the order of a rank
/// fixed by the tree's first branch in each (a tree of equal branches loses some of them,
/// not all); never a root. With the tree's branches mapped to the pruned skeleton (a
/// removed branch's to its nearest kept ancestor).
fn prune(
    skeleton: &Skeleton,
    merged: &[u32],
    bark: &Mesh,
    share: usize,
) -> Result<(Skeleton, Vec<u32>)> {
    use crate::skeleton::NO_PARENT;
    let b = skeleton.branches();
    let adjacency = skeleton.adjacency();
    let indices: u64 = bark.ranges.iter().map(|r| r.index_count as u64).sum();
    let per_index = count(bark) as f64 / indices.max(1) as f64;
    let triangles = |i: usize| {
        bark.ranges
            .get(i)
            .map_or(0.0, |r| r.index_count as f64 * per_index)
    };
    // The first of the tree's branches merged into each branch: its rank.
    let mut first = vec![u32::MAX; b.len()];
    for (i, &m) in merged.iter().enumerate() {
        if let Some(f) = first.get_mut(m as usize) {
            *f = (*f).min(i as u32);
        }
    }
    let mut worth: Vec<f32> = (0..b.len())
        .map(|i| {
            let diameter = 2.0 * b[i].start_radius.max(b[i].end_radius);
            diameter * b[i].length() / (triangles(i) as f32).max(1.0)
        })
        .collect();
    // Parents come before their children: a branch worth at least what grows on it.
    for i in (0..b.len()).rev() {
        let p = b[i].parent;
        if p != NO_PARENT {
            worth[p as usize] = worth[p as usize].max(worth[i]);
        }
    }
    let mut order: Vec<(f32, u64, usize)> = (0..b.len())
        .filter(|&i| b[i].parent != NO_PARENT)
        .map(|i| {
            let rank = crate::rng::Rng::new(u64::from(first[i]) ^ 0x5EED_F1EA).next_u64();
            (worth[i], rank, i)
        })
        .collect();
    order.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    let mut total = count(bark) as f64;
    let mut removed = vec![false; b.len()];
    let mut stack = Vec::new();
    for &(_, _, i) in &order {
        if total <= share as f64 {
            break;
        }
        if removed[i] {
            continue;
        }
        stack.push(i);
        while let Some(k) = stack.pop() {
            if !removed[k] {
                removed[k] = true;
                total -= triangles(k);
                stack.extend(adjacency.children(k).iter().map(|&c| c as usize));
            }
        }
    }
    let (parts, new_index) = crate::skeleton::prune::kept(skeleton, &removed);
    // A removed branch is merged into its nearest kept ancestor (parents come first).
    let mut nearest = new_index;
    for (i, x) in b.iter().enumerate() {
        if removed[i] {
            nearest[i] = nearest[x.parent as usize];
        }
    }
    Ok((
        Skeleton::from_trusted(parts),
        merged.iter().map(|&m| nearest[m as usize]).collect(),
    ))
}

/// `n` directions, none of [`fit_directions`], that check the level a fit picked.
fn check_directions(up: Vec3, n: usize) -> Vec<Vec3> {
    let a = up.any_orthonormal_vector();
    let b = up.cross(a);
    (0..n)
        .map(|k| {
            let t = std::f32::consts::TAU * (k as f32 + 0.62) / n as f32;
            let y = [0.28, -0.05, 0.12, -0.22][k % 4];
            (a * t.cos() + b * t.sin() + up * y).normalize()
        })
        .collect()
}

fn fit_directions(up: Vec3) -> Vec<Vec3> {
    let (a, b) = (
        up.any_orthonormal_vector(),
        up.cross(up.any_orthonormal_vector()),
    );
    [(0.0f32, 0.0f32), (1.6, 0.0), (3.3, 0.25), (4.8, -0.1)]
        .iter()
        .map(|&(t, y)| (a * t.cos() + b * t.sin() - up * y).normalize())
        .collect()
}

/// The largest side, in pixels, of the leaf atlas a chain's silhouettes sample (a larger
/// one is [downsampled](Image::downsampled)).
pub const SILHOUETTE_ATLAS: u32 = 256;

/// The smallest switch coverage [`chain`] sets.
pub const MIN_COVERAGE: f32 = 0.01;

/// How a tree is framed for its silhouettes: its bounding sphere, and its height along
/// the up axis.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// The bounding sphere's centre.
    pub centre: Vec3,
    /// The bounding sphere's radius.
    pub radius: f32,
    /// The tree's extent along the up axis.
    pub height: f32,
    /// The up axis.
    pub up: Vec3,
}

impl Frame {
    /// The frame of a level's bark and leaves; none without vertices.
    pub fn of(level: &Level, up: Vec3) -> Option<Frame> {
        let surfaces = surfaces(level, None);
        let (centre, radius) = crate::raster::bounds(&surfaces)?;
        let (lo, hi) = surfaces
            .iter()
            .flat_map(|s| &s.mesh.vertices)
            .map(|v| Vec3::from(v.position).dot(up))
            .fold((f32::MAX, f32::MIN), |(lo, hi), y| (lo.min(y), hi.max(y)));
        Some(Frame {
            centre,
            radius,
            height: (hi - lo).max(f32::MIN_POSITIVE),
            up,
        })
    }

    /// The side, in pixels, of the square around the bounding sphere where the tree's
    /// height covers `coverage` of a screen [`REFERENCE_PIXELS`] high (at least 8).
    pub fn pixels(&self, coverage: f32) -> u32 {
        ((coverage * REFERENCE_PIXELS * 2.0 * self.radius / self.height).round() as u32)
            .clamp(8, 4096)
    }

    /// The view from `dir` of the bounding sphere's square.
    pub fn view(&self, dir: Vec3) -> View {
        View::looking(self.centre, dir, self.up, self.radius)
    }
}

/// The level of `levels` (a [`chain`]) an impostor of views `cell` pixels across is best
/// baked from: the last that is first drawn with the tree's bounding square at least
/// `cell` pixels across ([`Frame::pixels`] of the switch before it). Each level is made
/// for where it is first drawn (its axes straightened by up to [`COLLAPSE_PIXELS`] there,
/// the branches that give the outline least pruned, its leaves thinned), so a level made
/// for a smaller size shows its straightened and missing twigs in views larger than that;
/// one made for at least the views' size looks as the full tree does in them, with fewer
/// triangles to draw. The full tree (0) when no level is first drawn that large.
pub fn impostor_source(levels: &[Level], cell: u32) -> usize {
    let Some(frame) = levels
        .first()
        .and_then(|l| Frame::of(l, l.mesh_options.up()))
    else {
        return 0;
    };
    (1..levels.len())
        .take_while(|&k| frame.pixels(levels[k - 1].screen_coverage) >= cell)
        .last()
        .unwrap_or(0)
}

/// A level as the rasterizer draws it: the bark brown and opaque, the leaves green (or
/// `atlas`, the leaf atlas they sample), alpha-tested at one half and two-sided.
pub fn surfaces<'a>(level: &'a Level, atlas: Option<&'a Image>) -> Vec<Surface<'a>> {
    let clockwise = level.mesh_options.reversed();
    let mut out = vec![Surface {
        mesh: &level.bark,
        texture: None,
        color: [92, 64, 44],
        alpha_cutoff: 0,
        double_sided: false,
        clockwise,
    }];
    if let Some(m) = &level.leaves {
        out.push(Surface {
            mesh: m,
            texture: atlas,
            color: [70, 120, 50],
            alpha_cutoff: 128,
            double_sided: true,
            clockwise,
        });
    }
    out
}

/// Samples a pixel's side in a [`silhouette`] (at most: the supersampled square is at
/// most 1024 samples a side).
pub const SILHOUETTE_SAMPLES: u32 = 4;

/// Which pixels a level covers seen from `dir`, in a square of `pixels` around `frame`:
/// those at least half covered, of [`SILHOUETTE_SAMPLES`]² samples each (what a viewer
/// sees at that size: a crown's gaps and twigs narrower than a pixel average out, as they
/// do on screen with multisampling or filtered alpha).
pub fn silhouette(
    level: &Level,
    atlas: Option<&Image>,
    frame: &Frame,
    dir: Vec3,
    pixels: u32,
) -> Vec<bool> {
    let ss = SILHOUETTE_SAMPLES.min(1024 / pixels.max(1)).max(1);
    let side = pixels * ss;
    let mut t = Target::coverage_only(side, side);
    t.draw(&frame.view(dir), &surfaces(level, atlas));
    coverage_mask(&t.mask(), pixels, ss)
}

/// How far the silhouette measure itself moves at `pixels`: the intersection over union
/// of `level`'s [`silhouette`] from `dir` with the same level drawn `shift` pixels off
/// along the image's diagonal (right and up). A copy of the tree that differs from it only
/// in where its pixel grid falls (an impostor's views are resampled, a level's vertices
/// move) keeps no more than this: twigs a pixel wide flip in and out of the mask. A
/// figure below 0.9 at a quarter pixel means that at this size the measure cannot tell a
/// good level or impostor from a shifted copy of the tree.
pub fn silhouette_floor(
    level: &Level,
    atlas: Option<&Image>,
    frame: &Frame,
    dir: Vec3,
    pixels: u32,
    shift: f32,
) -> f32 {
    let view = frame.view(dir);
    let pixel = 2.0 * frame.radius / pixels.max(1) as f32;
    let moved = Frame {
        centre: frame.centre + (view.right + view.up) * (shift * pixel),
        ..*frame
    };
    crate::raster::iou(
        &silhouette(level, atlas, frame, dir, pixels),
        &silhouette(level, atlas, &moved, dir, pixels),
    )
}

/// Pixels of a `pixels`-square mask at least half covered by the samples of a
/// `pixels * ss` square one.
pub fn coverage_mask(samples: &[bool], pixels: u32, ss: u32) -> Vec<bool> {
    let (n, ss) = (pixels as usize, ss as usize);
    let side = n * ss;
    let mut count = vec![0u32; n * n];
    for (y, row) in samples.chunks_exact(side).enumerate() {
        let out = &mut count[(y / ss) * n..(y / ss + 1) * n];
        for (x, &m) in row.iter().enumerate() {
            out[x / ss] += u32::from(m);
        }
    }
    let half = (ss * ss) as u32;
    count.into_iter().map(|c| 2 * c >= half).collect()
}

fn count(m: &Mesh) -> usize {
    m.triangles().count()
}

/// `skeleton`'s bark with the joints along each axis removed where the axis bends by no
/// more than `tolerance` (model units) from a straight line between the joints kept
/// (at most 32 branches a segment): fewer rings, the same outline at a distance. Lateral
/// branches keep their places (they start inside the merged segment).
pub fn collapse(skeleton: &Skeleton, tolerance: f32) -> Result<Skeleton> {
    collapse_merged(skeleton, tolerance).map(|(s, _)| s)
}

/// [`collapse`], and for each branch of `skeleton` the branch of the collapsed skeleton it
/// was merged into (what a level's skin follows: a vertex of a merged branch rides the
/// bone of the member nearest it).
pub fn collapse_merged(skeleton: &Skeleton, tolerance: f32) -> Result<(Skeleton, Vec<u32>)> {
    use crate::skeleton::{Branch, NO_PARENT, SkeletonParts};
    let b = skeleton.branches();
    let adjacency = skeleton.adjacency();
    let mut out: Vec<Branch> = Vec::with_capacity(b.len());
    // Each original branch's merged branch, and each merged branch's joints so far.
    let mut seg_of = vec![0u32; b.len()];
    let mut joints: Vec<Vec<Vec3>> = Vec::new();
    let mut last_of_seg: Vec<u32> = Vec::new();
    for (i, x) in b.iter().enumerate() {
        let parent = x.parent;
        let extends = parent != NO_PARENT
            && adjacency.continuation(parent as usize) == Some(i as u32)
            && last_of_seg[seg_of[parent as usize] as usize] == parent
            && {
                let s = seg_of[parent as usize] as usize;
                let start = out[s].start();
                let mut points = joints[s].clone();
                points.push(x.start());
                points.len() < 32
                    && points
                        .iter()
                        .all(|&p| off_line(p, start, x.end()) <= tolerance)
            };
        if extends {
            let s = seg_of[parent as usize] as usize;
            joints[s].push(x.start());
            out[s].end = x.end;
            out[s].end_radius = x.end_radius;
            last_of_seg[s] = i as u32;
            seg_of[i] = s as u32;
        } else {
            seg_of[i] = out.len() as u32;
            out.push(Branch {
                parent: if parent == NO_PARENT {
                    NO_PARENT
                } else {
                    seg_of[parent as usize]
                },
                ..*x
            });
            joints.push(Vec::new());
            last_of_seg.push(i as u32);
        }
    }
    let collapsed = SkeletonParts {
        branches: out,
        ..SkeletonParts::default()
    }
    .build()?;
    Ok((collapsed, seg_of))
}

/// The mean width of a regular polygon of `sides` sides inscribed in a circle, over all
/// the directions it is seen from across its axis, as a fraction of the circle's: its
/// perimeter over the circle's, `n sin(pi / n) / pi` (Cauchy: a convex shape's mean width
/// is its perimeter over pi).
pub fn polygon_width(sides: u32) -> f32 {
    let n = sides.max(3) as f64;
    (n * (std::f64::consts::PI / n).sin() / std::f64::consts::PI) as f32
}

/// `skeleton` with each branch's radii multiplied by the mean width of the polygon `full`
/// meshes it with over that of the polygon `level` does ([`polygon_width`]); itself where
/// no branch has fewer sides.
fn widened(skeleton: Skeleton, full: &MeshOptions, level: &MeshOptions) -> Result<Skeleton> {
    let (before, after) = (
        mesh::branch_sides(&skeleton, full)?,
        mesh::branch_sides(&skeleton, level)?,
    );
    if before.iter().zip(&after).all(|(b, a)| a >= b || *a == 0) {
        return Ok(skeleton);
    }
    let mut parts = skeleton.into_parts();
    for ((b, &n0), &n) in parts.branches.iter_mut().zip(&before).zip(&after) {
        if n > 0 && n0 > n {
            let f = polygon_width(n0 as u32) / polygon_width(n as u32);
            b.start_radius *= f;
            b.end_radius *= f;
        }
    }
    parts.build()
}

/// The distance of `p` from the segment `a`..`b`.
fn off_line(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let d = b - a;
    let t = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * t)).length()
}
