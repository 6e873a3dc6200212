//! One self-organizing tree: its internodes and buds, and the passes of a growth cycle.

use super::GrowthParams;
use super::env::{Bud, Env};
use crate::skeleton::{Branch, LeafSite, NO_PARENT, Skeleton, SkeletonParts};
use glam::Vec3;

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
    start: Vec3,
    end: Vec3,
    dir: Vec3,
    lat_dir: Vec3,
    phyllo: f32,
    order: u32,
}

/// What one cycle will do to a tree, planned while the environment is only read.
#[derive(Debug, Default)]
pub(crate) struct Plan {
    new: Vec<New>,
    /// Some subtree is shed this cycle.
    sheds: bool,
    /// Per existing internode: shed this cycle (the root of a shed subtree or above one).
    dead: Vec<bool>,
    residual: f32,
    root_vigour: f32,
}

impl Plan {
    pub(crate) fn new_internodes(&self) -> usize {
        self.new.len()
    }
}

/// Where a cycle's planning reads the environment: the light `Q` at every bud, in bud
/// order (terminal before lateral, in internode order), and the optimal direction `V`
/// only at the buds that grow, by the bud's ordinal in that order.
pub(crate) trait Light {
    fn q(&mut self, at: Vec3, dir: Vec3) -> f32;
    fn v(&self, ordinal: u32, at: Vec3) -> Vec3;
}

/// A tree's internodes (metamers), one entry per internode in each array (structure of
/// arrays, so each pass of a cycle streams only the fields it reads). Internode `i` ends
/// in a node that holds a terminal bud (until the main axis grows on) and a lateral bud
/// (until a lateral shoot grows from it).
#[derive(Clone, Debug, Default)]
struct Nodes {
    start: Vec<Vec3>,
    end: Vec<Vec3>,
    /// Unit heading.
    dir: Vec<Vec3>,
    /// Unit direction of the lateral bud.
    lat_dir: Vec<Vec3>,
    parent: Vec<u32>,
    /// [the internode continuing the axis, the first of the lateral shoot]: an index,
    /// [`BUD`] or [`GONE`].
    kids: Vec<[u32; 2]>,
    birth: Vec<u32>,
    order: Vec<u32>,
    /// Angle of the lateral bud about the heading, degrees.
    phyllo: Vec<f32>,
    /// Radius^pipe_exponent; never shrinks.
    rn: Vec<f32>,
}

struct NodeInit {
    start: Vec3,
    end: Vec3,
    dir: Vec3,
    lat_dir: Vec3,
    parent: u32,
    birth: u32,
    order: u32,
    phyllo: f32,
    rn: f32,
}

impl Nodes {
    fn len(&self) -> usize {
        self.parent.len()
    }

    fn push(&mut self, n: NodeInit) {
        self.start.push(n.start);
        self.end.push(n.end);
        self.dir.push(n.dir);
        self.lat_dir.push(n.lat_dir);
        self.parent.push(n.parent);
        self.kids.push([BUD, BUD]);
        self.birth.push(n.birth);
        self.order.push(n.order);
        self.phyllo.push(n.phyllo);
        self.rn.push(n.rn);
    }

    /// Moves internode `from` to `to` (`to` ≤ `from`).
    fn move_to(&mut self, from: usize, to: usize) {
        self.start[to] = self.start[from];
        self.end[to] = self.end[from];
        self.dir[to] = self.dir[from];
        self.lat_dir[to] = self.lat_dir[from];
        self.parent[to] = self.parent[from];
        self.kids[to] = self.kids[from];
        self.birth[to] = self.birth[from];
        self.order[to] = self.order[from];
        self.phyllo[to] = self.phyllo[from];
        self.rn[to] = self.rn[from];
    }

    fn truncate(&mut self, n: usize) {
        self.start.truncate(n);
        self.end.truncate(n);
        self.dir.truncate(n);
        self.lat_dir.truncate(n);
        self.parent.truncate(n);
        self.kids.truncate(n);
        self.birth.truncate(n);
        self.order.truncate(n);
        self.phyllo.truncate(n);
        self.rn.truncate(n);
    }
}

#[derive(Clone, Debug)]
pub(crate) struct Tree {
    pub(crate) species: GrowthParams,
    nodes: Nodes,
    base: Vec3,
    planted: u32,
    /// Internodes shed so far.
    pub(crate) shed: usize,
    /// Largest vigour residual of the last cycle's splits (a conservation check).
    pub(crate) residual: f32,
    /// Vigour at the base in the last cycle.
    root_vigour: f32,
    /// Scratch of the passes, kept to avoid allocating each cycle.
    /// Per internode: light of its [terminal, lateral] buds, then light above each side.
    own: Vec<[f32; 2]>,
    split: Vec<[f32; 2]>,
    /// Ordinal of the internode's first bud in bud order.
    ordinal: Vec<u32>,
    q: Vec<f32>,
    vig: Vec<f32>,
    desc: Vec<u32>,
    dead: Vec<bool>,
    /// Per internode: the shedding cost shed_multiplier·desc^shed_exponent for the
    /// descendant count in `cost_desc` (recomputed only when the count changes).
    cost: Vec<f32>,
    cost_desc: Vec<u32>,
    /// The shadow changes of the last [`Tree::grow`], in the order made: (cell, buds
    /// added there, negative for removed).
    pub(crate) casts: Vec<(u32, f32)>,
    /// The new internodes' buffer, handed from plan to plan.
    new_buf: Vec<New>,
}

/// Records a shadow change of `count` buds at `p` (nothing outside a shadow world).
#[inline]
fn cast(env: &Env, out: &mut Vec<(u32, f32)>, p: Vec3, count: f32) {
    if let Some(cell) = env.shadow_cell(p) {
        out.push((cell, count));
    }
}

/// A unit vector perpendicular to unit `h`, continuous except near −Y.
fn perpendicular(h: Vec3) -> Vec3 {
    crate::geom::transport::ring_basis(h.as_dvec3()).0.as_vec3()
}

/// The lateral bud direction of an internode heading `h`, turned `phyllo` degrees about it.
fn lateral(h: Vec3, phyllo: f32, branch_angle: f32) -> Vec3 {
    let e = perpendicular(h);
    let (s, c) = libm::sincosf(phyllo.to_radians());
    let side = e * c + h.cross(e) * s;
    let (sb, cb) = libm::sincosf(branch_angle.to_radians());
    (h * cb + side * sb).normalize_or_zero()
}

impl Tree {
    /// A new tree: one internode pointing up with a terminal and a lateral bud.
    pub(crate) fn plant(species: GrowthParams, base: Vec3, seed: u64, cycle: u32) -> Self {
        let phyllo = (crate::rng::Rng::new(seed).next_f64() * 360.0) as f32;
        let dir = Vec3::Y;
        let mut nodes = Nodes::default();
        nodes.push(NodeInit {
            start: base,
            end: base + dir * species.internode_length,
            dir,
            lat_dir: lateral(dir, phyllo, species.branch_angle),
            parent: NO_PARENT,
            birth: cycle,
            order: 0,
            phyllo,
            rn: libm::powf(species.tip_radius, species.pipe_exponent),
        });
        Tree {
            species,
            nodes,
            base,
            planted: cycle,
            shed: 0,
            residual: 0.0,
            root_vigour: 0.0,
            own: Vec::new(),
            split: Vec::new(),
            ordinal: Vec::new(),
            q: Vec::new(),
            vig: Vec::new(),
            desc: Vec::new(),
            dead: Vec::new(),
            cost: Vec::new(),
            cost_desc: Vec::new(),
            casts: Vec::new(),
            new_buf: Vec::new(),
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Adds (`sign` 1) or removes (−1) the shadow of every living bud.
    pub(crate) fn cast(&self, env: &mut Env, sign: f32) {
        for (k, end) in self.nodes.kids.iter().zip(&self.nodes.end) {
            let buds = u8::from(k[0] == BUD) + u8::from(k[1] == BUD);
            if buds > 0 {
                env.cast(*end, sign * buds as f32);
            }
        }
    }

    /// The living buds, terminal before lateral, in internode order: the order of the
    /// light [`Tree::plan_cycle`] asks for.
    pub(crate) fn buds(&self, out: &mut Vec<Bud>) {
        out.clear();
        let n = &self.nodes;
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
                    direction: n.lat_dir[i],
                });
            }
        }
    }

    /// Plans one cycle from the light at every bud: the basipetal pass, the vigour split,
    /// shedding and the new shoots (which ask `light` for the optimal direction).
    pub(crate) fn plan_cycle(&mut self, light: &mut impl Light, cycle: u32) -> Plan {
        let p = self.species;
        let nodes = &self.nodes;
        let n = nodes.len();
        // Light of each internode's buds, in bud order.
        self.own.clear();
        self.ordinal.clear();
        let mut ordinal = 0u32;
        for i in 0..n {
            let [m, l] = nodes.kids[i];
            self.ordinal.push(ordinal);
            let mut pair = [0.0f32; 2];
            if m == BUD {
                pair[0] = light.q(nodes.end[i], nodes.dir[i]);
                ordinal += 1;
            }
            if l == BUD {
                pair[1] = light.q(nodes.end[i], nodes.lat_dir[i]);
                ordinal += 1;
            }
            self.own.push(pair);
        }
        // Basipetal: light above each internode, split into main and lateral, and the
        // number of internodes at and above each.
        self.q.clear();
        self.q.resize(n, 0.0);
        self.split.clear();
        self.split.resize(n, [0.0; 2]);
        self.desc.clear();
        self.desc.resize(n, 1);
        for i in (0..n).rev() {
            let kids = nodes.kids[i];
            let mut pair = [0.0f32; 2];
            let mut desc = 1u32;
            for k in 0..2 {
                pair[k] = match kids[k] {
                    BUD => self.own[i][k],
                    GONE => 0.0,
                    c => {
                        desc += self.desc[c as usize];
                        self.q[c as usize]
                    }
                };
            }
            self.split[i] = pair;
            self.q[i] = pair[0] + pair[1];
            self.desc[i] = desc;
        }
        // One acropetal pass: the extended Borchert–Honda split of the vigour, shedding
        // (a lateral branch whose vigour no longer pays for its size goes, with everything
        // above it) and the new shoots (a bud with vigour v grows ⌊v⌋ internodes, at most
        // max_shoot). An internode's vigour is set by its parent, before it is visited.
        self.vig.clear();
        self.vig.resize(n, 0.0);
        self.vig[0] = p.vigor_multiplier * self.q[0];
        self.cost.resize(n, 0.0);
        self.cost_desc.resize(n, 0);
        let lambda = p.apical_control;
        let mut residual = 0.0f32;
        let mut plan = Plan {
            new: std::mem::take(&mut self.new_buf),
            ..Plan::default()
        };
        let mut dead = std::mem::take(&mut self.dead);
        dead.clear();
        dead.resize(n, false);
        let up = Vec3::Y;
        for i in 0..n {
            let kids = nodes.kids[i];
            let v = self.vig[i];
            // Shedding.
            if i > 0 {
                let parent = nodes.parent[i] as usize;
                if dead[parent] {
                    dead[i] = true;
                } else if p.shed_multiplier > 0.0
                    && nodes.kids[parent][1] == i as u32
                    && cycle.saturating_sub(nodes.birth[i]) > p.shed_delay
                {
                    let d = self.desc[i];
                    if self.cost_desc[i] != d {
                        self.cost[i] = p.shed_multiplier * libm::powf(d as f32, p.shed_exponent);
                        self.cost_desc[i] = d;
                    }
                    if v < self.cost[i] {
                        dead[i] = true;
                        plan.sheds = true;
                    }
                }
            }
            // The split.
            let [qm, ql] = self.split[i];
            let denom = lambda * qm + (1.0 - lambda) * ql;
            let (vm, vl) = if denom > 0.0 {
                (v * lambda * qm / denom, v * (1.0 - lambda) * ql / denom)
            } else {
                (0.0, 0.0)
            };
            if denom > 0.0 {
                residual = residual.max((v - vm - vl).abs() / v.max(1e-30));
            }
            for (k, share) in [vm, vl].into_iter().enumerate() {
                let slot = kids[k];
                if is_child(slot) {
                    self.vig[slot as usize] = share;
                    continue;
                }
                // Shoots, from the living buds of living internodes.
                if slot != BUD || dead[i] || share < 1.0 {
                    continue;
                }
                let count = (share.floor() as u32).min(p.max_shoot);
                let length = p.internode_length * (share / count as f32).min(2.0);
                // The terminal bud comes first in bud order.
                let bud = self.ordinal[i] + u32::from(k == 1 && kids[0] == BUD);
                let env_dir = light.v(bud, nodes.end[i]);
                let mut heading = if k == 0 {
                    nodes.dir[i]
                } else {
                    nodes.lat_dir[i]
                };
                let mut at = nodes.end[i];
                let mut phyllo = nodes.phyllo[i];
                let order = nodes.order[i] + k as u32;
                for j in 0..count {
                    heading = (heading + env_dir * p.environment_weight + up * p.tropism)
                        .try_normalize()
                        .unwrap_or(heading);
                    phyllo = (phyllo + p.phyllotaxis) % 360.0;
                    let end = at + heading * length;
                    plan.new.push(New {
                        parent: if j == 0 {
                            i as u32
                        } else {
                            plan.new.len() as u32 - 1
                        },
                        chain: j > 0,
                        main: k == 0 || j > 0,
                        start: at,
                        end,
                        dir: heading,
                        lat_dir: lateral(heading, phyllo, p.branch_angle),
                        phyllo,
                        order,
                    });
                    at = end;
                }
            }
        }
        plan.residual = residual;
        plan.root_vigour = self.vig[0];
        plan.dead = dead;
        plan
    }

    /// Carries out a plan: buds that grew or were shed take their shadow away, new buds
    /// add theirs, shed subtrees are removed (indices stay parents-before-children).
    pub(crate) fn grow(&mut self, mut plan: Plan, env: &Env, cycle: u32) {
        self.casts.clear();
        self.residual = plan.residual;
        self.root_vigour = plan.root_vigour;
        let tip_rn = libm::powf(self.species.tip_radius, self.species.pipe_exponent);
        let changed = !plan.new.is_empty() || plan.sheds;
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
                cast(env, &mut self.casts, self.nodes.end[parent as usize], -1.0);
            }
            *slot = me;
            self.nodes.push(NodeInit {
                start: nw.start,
                end: nw.end,
                dir: nw.dir,
                lat_dir: nw.lat_dir,
                parent,
                birth: cycle,
                order: nw.order,
                phyllo: nw.phyllo,
                rn: tip_rn,
            });
            // Its lateral bud and its terminal bud (taken away again if the chain goes on;
            // the two cancel before the grid is touched).
            cast(env, &mut self.casts, nw.end, 2.0);
        }
        let mut dead = std::mem::take(&mut plan.dead);
        if plan.sheds {
            self.shed_subtrees(&mut dead, env);
        }
        self.dead = dead;
        plan.new.clear();
        self.new_buf = plan.new;
        // Without new or shed internodes the radii are where the last cycle left them.
        if changed {
            self.update_radii(tip_rn);
        }
    }

    /// The pipe model, tips to root: r^n of an internode is the sum over its children (the
    /// tip radius at a tip), and never less than it has been.
    fn update_radii(&mut self, tip_rn: f32) {
        let nodes = &mut self.nodes;
        for i in (0..nodes.len()).rev() {
            let mut rn = 0.0;
            let mut children = false;
            for c in nodes.kids[i] {
                if is_child(c) {
                    rn += nodes.rn[c as usize];
                    children = true;
                }
            }
            let rn = if children { rn } else { tip_rn };
            nodes.rn[i] = nodes.rn[i].max(rn);
        }
    }

    /// Removes the internodes marked in `dead` (the plan's marks, for the internodes
    /// that existed when it was made), taking their buds' shadow away; indices stay
    /// parents-before-children. The internodes are compacted in place, with the scratch
    /// of the plan (no allocation in proportion to the tree).
    fn shed_subtrees(&mut self, dead: &mut Vec<bool>, env: &Env) {
        let n = self.nodes.len();
        // Internodes grown this cycle never grow on a shed one.
        dead.resize(n, false);
        let mut new_index = std::mem::take(&mut self.desc);
        new_index.clear();
        new_index.resize(n, NO_PARENT);
        self.cost.resize(n, 0.0);
        self.cost_desc.resize(n, 0);
        let mut kept = 0usize;
        for i in 0..n {
            if dead[i] {
                let [m, l] = self.nodes.kids[i];
                let buds = u8::from(m == BUD) + u8::from(l == BUD);
                if buds > 0 {
                    cast(env, &mut self.casts, self.nodes.end[i], -(buds as f32));
                }
                continue;
            }
            new_index[i] = kept as u32;
            if kept != i {
                self.nodes.move_to(i, kept);
                self.cost[kept] = self.cost[i];
                self.cost_desc[kept] = self.cost_desc[i];
            }
            kept += 1;
        }
        self.nodes.truncate(kept);
        self.cost.truncate(kept);
        self.cost_desc.truncate(kept);
        self.shed += n - kept;
        let map = |slot: u32| {
            if is_child(slot) {
                match new_index[slot as usize] {
                    NO_PARENT => GONE,
                    j => j,
                }
            } else {
                slot
            }
        };
        for i in 0..kept {
            let p = self.nodes.parent[i];
            if p != NO_PARENT {
                self.nodes.parent[i] = new_index[p as usize];
            }
            let [m, l] = self.nodes.kids[i];
            self.nodes.kids[i] = [map(m), map(l)];
        }
        self.desc = new_index;
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

    /// The tree as a skeleton: one branch per internode, radii from the pipe model
    /// (start: this internode's; end: its continuation's, or the tip radius), a leaf site
    /// at every living bud.
    pub(crate) fn skeleton(&self) -> Skeleton {
        let inv = 1.0 / self.species.pipe_exponent;
        let radius = |rn: f32| libm::powf(rn, inv);
        let tip = self.species.tip_radius;
        let n = &self.nodes;
        let mut parts = SkeletonParts {
            branches: Vec::with_capacity(n.len()),
            ..Default::default()
        };
        for i in 0..n.len() {
            let r = radius(n.rn[i]);
            let [m, l] = n.kids[i];
            let end_radius = if is_child(m) {
                radius(n.rn[m as usize])
            } else {
                tip.min(r)
            };
            parts.branches.push(Branch {
                start: n.start[i].to_array(),
                end: n.end[i].to_array(),
                start_radius: r,
                end_radius,
                parent: n.parent[i],
                birth: n.birth[i],
                order: n.order[i],
                flags: 0,
            });
            for (slot, heading) in [(m, n.dir[i]), (l, n.lat_dir[i])] {
                if slot == BUD {
                    parts.leaves.push(LeafSite {
                        position: n.end[i].to_array(),
                        heading: heading.to_array(),
                        up: perpendicular(heading).to_array(),
                        branch: i as u32,
                        birth: n.birth[i],
                    });
                }
            }
        }
        Skeleton::from_trusted(parts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fuzzer found an infinite root vigour asking for 2^32 seedlings (22 GB): the
    /// count is bounded by what the world can take.
    #[test]
    fn seeding_never_asks_for_more_trees_than_the_world_holds() {
        let species = GrowthParams {
            seed_age: 1,
            ..GrowthParams::default()
        };
        let mut t = Tree::plant(species, Vec3::ZERO, 1, 0);
        let mut rng = crate::rng::Rng::new(3);
        for vigour in [f32::INFINITY, f32::MAX, 1e30] {
            t.root_vigour = vigour;
            let mut out = Vec::new();
            t.seeds(5, &mut rng, 16, &mut out);
            assert_eq!(out.len(), 16, "vigour {vigour}");
        }
        t.root_vigour = 20.0;
        let mut out = Vec::new();
        t.seeds(5, &mut rng, 16, &mut out);
        assert_eq!(out.len(), 2, "ln 20 = 2.99");
    }
}
