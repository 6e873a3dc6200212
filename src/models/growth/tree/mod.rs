//! One self-organizing tree: its internodes and buds, and the passes of a growth cycle.

use super::GrowthParams;
use super::env::{Bud, DARK, Env, Key};
use crate::skeleton::NO_PARENT;
use glam::Vec3;
use nodes::{NodeInit, Nodes};

mod directions;
mod nodes;
mod snapshot;

use directions::{branch_turn, lateral, perpendicular};

/// `main` / `lateral` of an internode whose bud is alive there.
const BUD: u32 = u32::MAX;
/// `main` / `lateral` of an internode whose bud or branch there is gone (shed).
const GONE: u32 = u32::MAX - 1;

fn is_child(slot: u32) -> bool {
    slot < GONE
}

/// A new internode planned for this cycle.
#[derive(Clone, Copy, Debug)]
struct New {
    /// Parent: an existing internode index, or (with `chain`) the previous new one.
    parent: u32,
    chain: bool,
    /// Continues the parent's axis (main) or starts a lateral shoot.
    main: bool,
    end: Vec3,
    dir: Vec3,
    phyllo: f32,
    order: u32,
    along: u32,
}

/// What one cycle will do to a tree, planned while the environment is only read.
#[derive(Debug, Default)]
pub(crate) struct Plan {
    new: Vec<New>,
    /// The internodes at the base of the subtrees shed this cycle.
    shed: Vec<u32>,
    residual: f32,
    root_vigour: f32,
    /// The whole tree starves: it dies this cycle.
    die: bool,
}

impl Plan {
    pub(crate) fn new_internodes(&self) -> usize {
        self.new.len()
    }

    /// Where the new internodes end (where their buds will be).
    pub(crate) fn ends(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.new.iter().map(|n| n.end)
    }
}

/// Where a cycle's planning reads the environment: the light `Q` at a bud and the optimal
/// direction `V` (asked only where a shoot grows). A bud is known by its ordinal in bud
/// order (terminal before lateral, in internode order), counted only for a light that
/// says it is `ORDERED`, and by its internode's cell word ([`Env::cell_word`]).
pub(crate) trait Light {
    const ORDERED: bool;
    fn q(&self, ordinal: u32, word: Key) -> f32;
    fn v(&self, ordinal: u32, word: Key) -> Vec3;
    /// Whether the buds' light is best read in a pass of its own before the basipetal
    /// pass (a light of the cell only, from memory too large for the caches).
    fn read_ahead(&self) -> bool {
        false
    }
    /// Asks the memory for what [`Light::q`] of `word` will read (a hint: nothing
    /// changes).
    #[inline]
    fn prefetch(&self, _word: Key) {}
    /// Asks the memory for what [`Light::v`] of `word` will read (a hint).
    #[inline]
    fn prefetch_v(&self, _word: Key) {}
}

/// Shoots ahead of the one grown whose optimal direction is prefetched.
const PREFETCH_V: usize = 8;

/// Buds ahead of the one read that a read-ahead pass prefetches.
const PREFETCH: usize = 64;

/// The passes' working arrays, one set per thread and reused from cycle to cycle and tree
/// to tree, so a world's memory holds only the internodes themselves.
#[derive(Default)]
struct Scratch {
    /// Ordinal of each internode's first bud in bud order (only for an ordered light).
    ordinal: Vec<u32>,
    /// Light gathered above each internode: [main side, lateral side].
    split: Vec<[f32; 2]>,
    /// Internodes at and above each internode; the new indices while shedding.
    desc: Vec<u32>,
    vig: Vec<f32>,
    dead: Vec<bool>,
    /// The internodes of the subtrees being shed, with their living buds.
    walk: Vec<(u32, u32)>,
    /// The buds that grow a shoot this cycle: (internode, 0 terminal / 1 lateral, vigour).
    shoots: Vec<(u32, u32, f32)>,
    /// Shedding costs by species: ((shed_multiplier, shed_exponent) bits, the cost
    /// multiplier·d^exponent of d internodes for d below [`COSTS`], NaN until needed).
    costs: Vec<((u32, u32), Vec<f32>)>,
}

/// A tree's shed internodes are removed from its store when they are more than one in
/// this many of the internodes stored.
const DEAD_SHARE: usize = 8;

/// Descendant counts whose shedding cost a thread keeps (larger ones are computed).
const COSTS: usize = 4096;

impl Scratch {
    /// The shedding cost of a branch of `d` internodes: multiplier·d^exponent, as
    /// `libm::powf` gives it, remembered per species for small counts.
    fn cost(&mut self, table: usize, p: &GrowthParams, d: u32) -> f32 {
        let compute = || p.shed_multiplier * libm::powf(d as f32, p.shed_exponent);
        let Some(slot) = self.costs[table].1.get_mut(d as usize) else {
            return compute();
        };
        if slot.is_nan() {
            *slot = compute();
        }
        *slot
    }

    /// The index of the cost table of `p`'s shedding parameters (made when new; a thread
    /// keeps the tables of at most eight species).
    fn cost_table(&mut self, p: &GrowthParams) -> usize {
        let key = (p.shed_multiplier.to_bits(), p.shed_exponent.to_bits());
        if let Some(k) = self.costs.iter().position(|(k, _)| *k == key) {
            return k;
        }
        if self.costs.len() >= 8 {
            self.costs.clear();
        }
        self.costs.push((key, vec![f32::NAN; COSTS]));
        self.costs.len() - 1
    }
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

#[derive(Clone, Debug)]
pub(crate) struct Tree {
    pub(crate) species: GrowthParams,
    nodes: Nodes,
    base: Vec3,
    planted: u32,
    /// Internodes shed so far.
    pub(crate) shed: usize,
    /// Shed internodes still stored (see [`Tree::shed_subtrees`]), and the first of
    /// them (`usize::MAX` when none).
    dead: usize,
    first_dead: usize,
    /// Largest vigour residual of the last cycle's splits (a conservation check).
    pub(crate) residual: f32,
    /// Vigour at the base in the last cycle.
    root_vigour: f32,
    /// The last cycle grew or shed internodes and the radii do not show it yet: the
    /// next basipetal pass (or a snapshot) brings them up to date.
    radii_stale: bool,
    /// The shadow changes of the last [`Tree::grow`], in the order made: (cell, buds
    /// added there, negative for removed).
    pub(crate) casts: Vec<(Key, i32)>,
    /// The plans' buffers (new internodes, shed subtrees), handed from plan to plan.
    new_buf: Vec<New>,
    shed_buf: Vec<u32>,
}

/// Living buds of an internode with these children.
#[inline]
fn buds([m, l]: [u32; 2]) -> u32 {
    u32::from(m == BUD) + u32::from(l == BUD)
}

/// The pipe model at internode `i` (its children already done): r^n is the sum over its
/// children (the tip radius at a tip), and never less than it has been.
/// Without a branch on what a slot holds (not predictable): a slot without a child adds
/// nothing, reading internode i's own entry.
#[inline]
fn pipe(kids: &[[u32; 2]], rn: &mut [f32], i: usize, tip_rn: f32) {
    let (mut sum, mut children) = (0.0f32, false);
    for c in kids[i] {
        let child = is_child(c);
        let j = if child { c as usize } else { i };
        sum += if child { rn[j] } else { 0.0 };
        children |= child;
    }
    let sum = if children { sum } else { tip_rn };
    rn[i] = rn[i].max(sum);
}

impl Tree {
    /// A new tree: one internode pointing up with a terminal and a lateral bud.
    pub(crate) fn plant(
        species: GrowthParams,
        base: Vec3,
        seed: u64,
        cycle: u32,
        env: &Env,
    ) -> Self {
        let phyllo = (crate::rng::Rng::new(seed).next_f64() * 360.0) as f32;
        let dir = Vec3::Y;
        let end = base + dir * species.internode_length;
        let mut nodes = Nodes::default();
        nodes.push(NodeInit {
            end,
            dir,
            parent: NO_PARENT,
            birth: cycle,
            order: 0,
            phyllo,
            rn: libm::powf(species.tip_radius, species.pipe_exponent),
            cell: env.cell_word(end),
            along: 0,
        });
        Tree {
            species,
            nodes,
            base,
            planted: cycle,
            shed: 0,
            dead: 0,
            first_dead: usize::MAX,
            residual: 0.0,
            root_vigour: 0.0,
            radii_stale: false,
            casts: Vec::new(),
            new_buf: Vec::new(),
            shed_buf: Vec::new(),
        }
    }

    /// Living internodes.
    pub(crate) fn len(&self) -> usize {
        self.nodes.len() - self.dead
    }

    /// Where internode `i` starts: its parent's end, the base for the root.
    fn start(&self, i: usize) -> Vec3 {
        match self.nodes.parent[i] {
            NO_PARENT => self.base,
            p => self.nodes.end[p as usize],
        }
    }

    /// The direction of internode `i`'s lateral bud.
    fn lateral_dir(&self, i: usize, branch: (f32, f32)) -> Vec3 {
        lateral(self.nodes.dir[i], self.nodes.phyllo[i], branch)
    }

    /// Every living bud's cell word and bud count (`sign` times the buds there).
    fn bud_cells(&self, sign: i32) -> impl Iterator<Item = (Key, i32)> + '_ {
        self.nodes
            .kids
            .iter()
            .zip(&self.nodes.cell)
            .filter(|(k, _)| buds(**k) > 0)
            .map(move |(k, &word)| (word, sign * buds(*k) as i32))
    }

    /// Adds (`sign` 1) or removes (−1) the shadow of every living bud.
    pub(crate) fn cast(&self, env: &mut Env, sign: i32) {
        for (word, count) in self.bud_cells(sign) {
            env.cast(word, count);
        }
    }

    /// Finds again which buds get no light (after an obstacle was placed).
    /// Buds inside a new obstacle get no light (their cells stay).
    pub(crate) fn darken(&mut self, o: &super::Obstacle) {
        for (word, end) in self.nodes.cell.iter_mut().zip(&self.nodes.end) {
            if o.contains(*end) {
                *word |= DARK;
            }
        }
    }

    /// The living buds, terminal before lateral, in internode order: the order of the
    /// light [`Tree::plan_cycle`] asks for.
    pub(crate) fn buds(&self, out: &mut Vec<Bud>) {
        out.clear();
        let n = &self.nodes;
        let branch = branch_turn(self.species.branch_angle);
        for i in 0..n.len() {
            let [m, l] = n.kids[i];
            if m == BUD {
                out.push(Bud {
                    position: n.end[i],
                    direction: n.dir[i],
                });
            }
            if l == BUD {
                out.push(Bud {
                    position: n.end[i],
                    direction: self.lateral_dir(i, branch),
                });
            }
        }
    }

    /// Plans one cycle from the light at every bud: the basipetal pass, the vigour split,
    /// shedding and the new shoots (which ask `light` for the optimal direction).
    pub(crate) fn plan_cycle<L: Light>(&mut self, light: &L, cycle: u32) -> Plan {
        SCRATCH.with_borrow_mut(|s| self.plan_with(light, cycle, s))
    }

    fn plan_with<L: Light>(&mut self, light: &L, cycle: u32, s: &mut Scratch) -> Plan {
        let mut plan = Plan {
            new: std::mem::take(&mut self.new_buf),
            shed: std::mem::take(&mut self.shed_buf),
            ..Plan::default()
        };
        if self.nodes.len() == 0 {
            return plan;
        }
        self.light_pass(light, s);
        let p = &self.species;
        let age = cycle.saturating_sub(self.planted);
        // The whole tree is a branch of the ground: it dies when it starves as one.
        let [qm, ql] = s.split[0];
        if p.shed_light > 0.0 && age > p.shed_delay && qm + ql < p.shed_light * s.desc[0] as f32 {
            plan.die = true;
            return plan;
        }
        plan.residual = self.vigour_pass(cycle, s, &mut plan);
        if p.max_age > 0 && age >= p.max_age {
            s.shoots.clear();
        }
        self.grow_shoots(light, s, &mut plan);
        plan.root_vigour = s.vig[0];
        plan
    }

    /// Apical control and vigour multiplier at `age` cycles: from the young values to
    /// the adult ones, linearly over `maturity_age`.
    fn aged(&self, age: u32) -> (f32, f32) {
        let p = &self.species;
        if age >= p.maturity_age {
            return (p.apical_control, p.vigor_multiplier);
        }
        let t = age as f32 / p.maturity_age as f32;
        (
            p.young_apical_control + (p.apical_control - p.young_apical_control) * t,
            p.young_vigor_multiplier + (p.vigor_multiplier - p.young_vigor_multiplier) * t,
        )
    }

    /// Basipetal, with the light of each bud: light above each internode, split into main
    /// and lateral, and the number of internodes at and above each (and the pipe model's
    /// radii, when they are stale).
    #[inline]
    fn light_pass<L: Light>(&mut self, light: &L, s: &mut Scratch) {
        let p = self.species;
        let nodes = &mut self.nodes;
        let n = nodes.len();
        if L::ORDERED {
            s.ordinal.clear();
            let mut ordinal = 0u32;
            for &kids in &nodes.kids {
                s.ordinal.push(ordinal);
                ordinal += buds(kids);
            }
        }
        // Where the grid is larger than the caches, the buds' cells are asked for a few
        // dozen internodes ahead of the one whose light is read (a cache miss each in a
        // forest), so more of them are under way at once.
        let ahead = !L::ORDERED && light.read_ahead();
        // Basipetal, with the light of each bud: light above each internode, split into
        // main and lateral, and the number of internodes at and above each.
        s.split.clear();
        s.split.resize(n, [0.0; 2]);
        s.desc.clear();
        s.desc.resize(n, 1);
        let (stale, tip_rn) = (self.radii_stale, libm::powf(p.tip_radius, p.pipe_exponent));
        self.radii_stale = false;
        if ahead {
            for i in (n.saturating_sub(PREFETCH)..n).rev() {
                light.prefetch(nodes.cell[i]);
            }
        }
        for i in (0..n).rev() {
            let kids = nodes.kids[i];
            if ahead
                && let Some(a) = i.checked_sub(PREFETCH)
                && buds(nodes.kids[a]) > 0
            {
                light.prefetch(nodes.cell[a]);
            }
            if stale {
                pipe(&nodes.kids, &mut nodes.rn, i, tip_rn);
            }
            // The light of each slot's bud: of its cell (one read an internode), or of
            // its ordinal for an ordered light (the terminal bud before the lateral).
            let word = nodes.cell[i];
            let q = if L::ORDERED {
                let first = s.ordinal[i];
                let at = |k: usize, bud: u32| {
                    if kids[k] == BUD {
                        light.q(bud, word)
                    } else {
                        0.0
                    }
                };
                [at(0, first), at(1, first + u32::from(kids[0] == BUD))]
            } else {
                let q = if buds(kids) > 0 {
                    light.q(0, word)
                } else {
                    0.0
                };
                [q, q]
            };
            // The slots read without a branch (a bud's light, a child's sums, or
            // nothing), since which of bud, child and gone a slot holds is not
            // predictable; a slot that holds no child reads internode i's own (unused)
            // entries.
            let (mut pair, mut desc) = ([0.0f32; 2], 1u32);
            for k in 0..2 {
                let c = kids[k];
                let child = is_child(c);
                let j = if child { c as usize } else { i };
                let [m, l] = s.split[j];
                pair[k] = if c == BUD {
                    q[k]
                } else if child {
                    m + l
                } else {
                    0.0
                };
                desc += if child { s.desc[j] } else { 0 };
            }
            s.split[i] = pair;
            s.desc[i] = desc;
        }
    }

    /// One acropetal pass: the extended Borchert-Honda split of the vigour, shedding into
    /// `plan` and the shoots to grow (in `s.shoots`); returns the largest relative
    /// residual of the split.
    #[inline]
    fn vigour_pass(&self, cycle: u32, s: &mut Scratch, plan: &mut Plan) -> f32 {
        let p = self.species;
        let nodes = &self.nodes;
        let n = nodes.len();
        // One acropetal pass: the extended Borchert–Honda split of the vigour, shedding
        // (a lateral branch whose vigour no longer pays for its size goes, with everything
        // above it) and the new shoots (a bud with vigour v grows ⌊v⌋ internodes, at most
        // max_shoot). An internode's vigour is set by its parent, before it is visited.
        let (lambda, alpha) = self.aged(cycle.saturating_sub(self.planted));
        s.vig.clear();
        s.vig.resize(n + 1, 0.0);
        s.vig[0] = alpha * (s.split[0][0] + s.split[0][1]);
        // A node's fate is set by its parent, before it is visited: dead with its parent,
        // or shed as a lateral branch; a slot without a child writes the spare entry at n.
        s.dead.clear();
        s.dead.resize(n + 1, false);
        s.shoots.clear();
        let mut residual = 0.0f32;
        let costs = s.cost_table(&p);
        for i in 0..n {
            let kids = nodes.kids[i];
            let v = s.vig[i];
            let dead = s.dead[i];
            // The split.
            let [qm, ql] = s.split[i];
            let (wm, wl) = (lambda * qm, (1.0 - lambda) * ql);
            let denom = wm + wl;
            // One division a node (two cost a fifth of the pass).
            let r = if denom > 0.0 { v / denom } else { 0.0 };
            let (vm, vl) = (r * wm, r * wl);
            // The largest |v − vm − vl| / v, divided only where it grows.
            let miss = (v - vm - vl).abs();
            if denom > 0.0 && miss > residual * v.max(1e-30) {
                residual = residual.max(miss / v.max(1e-30));
            }
            for (k, share) in [vm, vl].into_iter().enumerate() {
                let slot = kids[k];
                // A child's vigour, written without a branch: a bud's or a gone
                // branch's share goes to the spare slot at `n`.
                let to = if is_child(slot) { slot as usize } else { n };
                s.vig[to] = share;
                s.dead[to] = dead;
                // Shoots, from the living buds of living internodes (made below, so
                // this loop stays small).
                if slot == BUD && share >= 1.0 && !dead {
                    s.shoots.push((i as u32, k as u32, share));
                }
            }
            // Shedding: a lateral branch whose light or vigour no longer pays for its
            // size goes, with everything above it.
            let c = kids[1] as usize;
            if !dead
                && is_child(kids[1])
                && cycle.saturating_sub(nodes.birth[c]) > p.shed_delay
                && ((p.shed_light > 0.0
                    && s.split[c][0] + s.split[c][1] < p.shed_light * s.desc[c] as f32)
                    || (p.shed_multiplier > 0.0 && vl < s.cost(costs, &p, s.desc[c])))
            {
                s.dead[c] = true;
                plan.shed.push(c as u32);
            }
        }
        // In internode order (found at their parents).
        plan.shed.sort_unstable();
        residual
    }

    /// The new shoots: a bud with vigour v grows floor(v) internodes (at most max_shoot),
    /// bent toward the environment's optimal direction and up.
    #[inline]
    fn grow_shoots<L: Light>(&self, light: &L, s: &Scratch, plan: &mut Plan) {
        let p = self.species;
        let nodes = &self.nodes;
        let up = Vec3::Y;
        let branch = branch_turn(p.branch_angle);
        // Where the buds' light is read ahead, the grid is too large for the caches.
        let prefetch = !L::ORDERED && light.read_ahead();
        for (j, &(i, k, share)) in s.shoots.iter().enumerate() {
            if let Some(&(ahead, _, _)) = s.shoots.get(j + PREFETCH_V).filter(|_| prefetch) {
                light.prefetch_v(nodes.cell[ahead as usize]);
            }
            let (i, kids) = (i as usize, nodes.kids[i as usize]);
            let count = (share.floor() as u32).min(p.max_shoot);
            let length = p.internode_length * (share / count as f32).min(2.0);
            // The terminal bud comes first in bud order.
            let bud = if L::ORDERED {
                s.ordinal[i] + u32::from(k == 1 && kids[0] == BUD)
            } else {
                0
            };
            let env_dir = light.v(bud, nodes.cell[i]);
            let mut heading = if k == 0 {
                nodes.dir[i]
            } else {
                lateral(nodes.dir[i], nodes.phyllo[i], branch)
            };
            let mut at = nodes.end[i];
            let mut phyllo = nodes.phyllo[i];
            let order = nodes.order[i] + k;
            // Internodes since the branch left the trunk: a lateral of a lateral goes on
            // counting, so a whole limb hangs more the farther it reaches.
            let first = if k == 0 || order > 1 {
                nodes.along[i] + 1
            } else {
                0
            };
            for j in 0..count {
                let along = first + j;
                // A lateral axis hangs more the longer it is.
                let tropism = if order > 0 {
                    p.tropism - p.droop * along as f32
                } else {
                    p.tropism
                };
                heading = (heading + env_dir * p.environment_weight + up * tropism)
                    .try_normalize()
                    .unwrap_or(heading);
                phyllo = (phyllo + p.phyllotaxis) % 360.0;
                let end = at + heading * length;
                if p.max_height > 0.0 && end.y - self.base.y > p.max_height {
                    break;
                }
                plan.new.push(New {
                    parent: if j == 0 {
                        i as u32
                    } else {
                        plan.new.len() as u32 - 1
                    },
                    chain: j > 0,
                    main: k == 0 || j > 0,
                    end,
                    dir: heading,
                    phyllo,
                    order,
                    along,
                });
                at = end;
            }
        }
    }

    /// Carries out a plan: buds that grew or were shed take their shadow away, new buds
    /// add theirs, shed subtrees are removed (indices stay parents-before-children).
    pub(crate) fn grow(&mut self, plan: Plan, env: &Env, cycle: u32) {
        self.casts.clear();
        self.residual = plan.residual;
        self.root_vigour = plan.root_vigour;
        let tip_rn = libm::powf(self.species.tip_radius, self.species.pipe_exponent);
        if plan.die {
            // Every bud's shadow goes with the tree.
            let gone: Vec<(Key, i32)> = self
                .bud_cells(-1)
                .filter_map(|(word, count)| env.change(word, count))
                .collect();
            self.casts.extend(gone);
            self.shed += self.len();
            (self.dead, self.first_dead) = (0, usize::MAX);
            self.nodes.truncate(0);
            self.radii_stale = false;
            self.recycle(plan);
            return;
        }
        let changed = !plan.new.is_empty() || !plan.shed.is_empty();
        // New internodes, appended in plan order (a chain's parent comes first), so the
        // k-th new one is internode base + k.
        let base = self.nodes.len() as u32;
        for (k, nw) in plan.new.iter().enumerate() {
            let parent = if nw.chain {
                base + nw.parent
            } else {
                nw.parent
            };
            let me = base + k as u32;
            let side = usize::from(!nw.main);
            let slot = &mut self.nodes.kids[parent as usize][side];
            if *slot == BUD {
                match self.casts.last_mut() {
                    // The previous new internode's buds were the last change: one net
                    // change per cell (its lateral bud stays, its terminal bud grew).
                    Some(last) if nw.chain => last.1 -= 1,
                    _ => self
                        .casts
                        .extend(env.change(self.nodes.cell[parent as usize], -1)),
                }
            }
            *slot = me;
            let word = env.cell_word(nw.end);
            self.nodes.push(NodeInit {
                end: nw.end,
                dir: nw.dir,
                parent,
                birth: cycle,
                order: nw.order,
                phyllo: nw.phyllo,
                rn: tip_rn,
                cell: word,
                along: nw.along,
            });
            // Its lateral bud and its terminal bud (taken away again if the chain goes on;
            // the two cancel before the grid is touched).
            self.casts.extend(env.change(word, 2));
        }
        if !plan.shed.is_empty() {
            SCRATCH.with_borrow_mut(|s| self.shed_subtrees(&plan.shed, env, s));
        }
        self.recycle(plan);
        // Without new or shed internodes the radii are where the last cycle left them.
        self.radii_stale |= changed;
    }

    /// Keeps a carried-out plan's buffers for the next plan.
    fn recycle(&mut self, mut plan: Plan) {
        plan.new.clear();
        plan.shed.clear();
        (self.new_buf, self.shed_buf) = (plan.new, plan.shed);
    }

    /// Sheds the subtrees whose base internodes are `roots` (in increasing order;
    /// internodes grown this cycle never grow on a shed one), taking their buds' shadow
    /// away: each subtree is walked from its root, so shedding costs what it sheds, not
    /// the tree. The shed internodes stay stored, unlinked (no internode lists them, and
    /// they list no children or buds), so every pass reads them as a bare internode
    /// nobody asks about, until they pass one in [`DEAD_SHARE`] of the store: then
    /// [`Tree::compact`] removes them all at once, instead of moving the tree down every
    /// cycle something is shed.
    fn shed_subtrees(&mut self, roots: &[u32], env: &Env, s: &mut Scratch) {
        let nodes = &mut self.nodes;
        // Each subtree walked from its root (one still listed by its parent: a root
        // inside another's subtree is walked with it), each internode unlinked as it is
        // met: (internode, its living buds).
        let walk = &mut s.walk;
        walk.clear();
        for &r in roots {
            let p = nodes.parent[r as usize];
            if p == NO_PARENT || !nodes.kids[p as usize].contains(&r) {
                continue;
            }
            for slot in &mut nodes.kids[p as usize] {
                if *slot == r {
                    *slot = GONE;
                }
            }
            let mut k = walk.len();
            walk.push((r, 0));
            while k < walk.len() {
                let i = walk[k].0 as usize;
                let kids = std::mem::replace(&mut nodes.kids[i], [GONE, GONE]);
                walk[k].1 = buds(kids);
                walk.extend(kids.into_iter().filter(|&c| is_child(c)).map(|c| (c, 0)));
                k += 1;
            }
        }
        // Their buds' shadow taken away in internode order.
        walk.sort_unstable_by_key(|&(i, _)| i);
        for &(i, buds) in walk.iter() {
            if buds > 0 {
                self.casts
                    .extend(env.change(nodes.cell[i as usize], -(buds as i32)));
            }
        }
        let Some(&(first, _)) = walk.first() else {
            return;
        };
        let (first, count) = (first as usize, walk.len());
        let n = nodes.len();
        self.shed += count;
        self.dead += count;
        self.first_dead = self.first_dead.min(first);
        if self.dead * DEAD_SHARE > n {
            self.compact(s);
        }
    }

    /// Removes the shed internodes still stored, keeping the order of the others
    /// (parents before children): one forward pass finds where each goes (an internode
    /// lives when its parent lists it), then each run of kept internodes moves down at
    /// once and the links are renumbered. With the thread's scratch (no allocation in
    /// proportion to the tree).
    fn compact(&mut self, s: &mut Scratch) {
        let n = self.nodes.len();
        let first = self.first_dead.min(n);
        (self.dead, self.first_dead) = (0, usize::MAX);
        let new_index = &mut s.desc;
        new_index.clear();
        new_index.resize(n - first, NO_PARENT);
        let nodes = &mut self.nodes;
        // The side of internode `i`'s parent it grows on: 0 continues the axis.
        let side = |nodes: &Nodes, i: usize, parent: u32| {
            usize::from(parent != NO_PARENT && nodes.order[i] != nodes.order[parent as usize])
        };
        let mut kept = first;
        for i in first..n {
            if nodes.lives(i) {
                new_index[i - first] = kept as u32;
                kept += 1;
            }
        }
        let mut i = first;
        while i < n {
            let to = new_index[i - first];
            if to == NO_PARENT {
                i += 1;
                continue;
            }
            let start = i;
            while i < n && new_index[i - first] != NO_PARENT {
                i += 1;
            }
            if to as usize != start {
                nodes.move_run(start..i, to as usize);
            }
        }
        for k in first..kept {
            let p = nodes.parent[k];
            let parent = if p == NO_PARENT || (p as usize) < first {
                p
            } else {
                new_index[p as usize - first]
            };
            nodes.parent[k] = parent;
            if parent != NO_PARENT {
                let side = side(nodes, k, parent);
                nodes.kids[parent as usize][side] = k as u32;
            }
        }
        nodes.truncate(kept);
    }

    /// Seeds this tree drops this cycle: (species, position on the ground), at most
    /// `most` (a world cannot take more trees than that).
    pub(crate) fn seeds(
        &self,
        cycle: u32,
        rng: &mut crate::rng::Rng,
        most: usize,
        out: &mut Vec<(GrowthParams, Vec3)>,
    ) {
        let p = &self.species;
        if p.seed_age == 0
            || cycle.saturating_sub(self.planted) <= p.seed_age
            || self.root_vigour <= 1.0
        {
            return;
        }
        let log = libm::logf(self.root_vigour);
        // ln of the vigour, bounded: a huge (or infinite) vigour may not ask for more
        // seedlings than the world can hold.
        let count =
            (log.floor().min(u32::MAX as f32) as u32).min(most.min(u32::MAX as usize) as u32);
        let reach = log * p.seed_spread;
        for _ in 0..count {
            let angle = rng.next_f64() as f32 * std::f32::consts::TAU;
            let dist = reach * (rng.next_f64() as f32).sqrt();
            let (s, c) = libm::sincosf(angle);
            out.push((*p, self.base + Vec3::new(c * dist, 0.0, s * dist)));
        }
    }
}

#[cfg(test)]
mod tests;
