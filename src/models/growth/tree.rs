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

/// One internode (metamer): it ends in a node that holds a terminal bud (until the main
/// axis grows on) and a lateral bud (until a lateral shoot grows from it).
#[derive(Clone, Copy, Debug)]
struct Node {
    start: Vec3,
    end: Vec3,
    /// Unit heading.
    dir: Vec3,
    /// Unit direction of the lateral bud.
    lat_dir: Vec3,
    parent: u32,
    /// The internode continuing the axis, [`BUD`] or [`GONE`].
    main: u32,
    /// The first internode of the lateral shoot, [`BUD`] or [`GONE`].
    lateral: u32,
    birth: u32,
    order: u32,
    /// Angle of the lateral bud about the heading, degrees.
    phyllo: f32,
    /// Radius^pipe_exponent; never shrinks.
    rn: f32,
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

#[derive(Clone, Debug)]
pub(crate) struct Tree {
    pub(crate) species: GrowthParams,
    nodes: Vec<Node>,
    base: Vec3,
    planted: u32,
    /// Internodes shed so far.
    pub(crate) shed: usize,
    /// Largest vigour residual of the last cycle's splits (a conservation check).
    pub(crate) residual: f32,
    /// Vigour at the base in the last cycle.
    root_vigour: f32,
    /// Scratch of the passes, kept to avoid allocating each cycle.
    q: Vec<f32>,
    qm: Vec<f32>,
    ql: Vec<f32>,
    vig: Vec<f32>,
    desc: Vec<u32>,
    own: Vec<[(f32, Vec3); 2]>,
    dead: Vec<bool>,
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
        let node = Node {
            start: base,
            end: base + dir * species.internode_length,
            dir,
            lat_dir: lateral(dir, phyllo, species.branch_angle),
            parent: NO_PARENT,
            main: BUD,
            lateral: BUD,
            birth: cycle,
            order: 0,
            phyllo,
            rn: libm::powf(species.tip_radius, species.pipe_exponent),
        };
        Tree {
            species,
            nodes: vec![node],
            base,
            planted: cycle,
            shed: 0,
            residual: 0.0,
            root_vigour: 0.0,
            q: Vec::new(),
            qm: Vec::new(),
            ql: Vec::new(),
            vig: Vec::new(),
            desc: Vec::new(),
            own: Vec::new(),
            dead: Vec::new(),
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Adds (`sign` 1) or removes (−1) the shadow of every living bud.
    pub(crate) fn cast(&self, env: &mut Env, sign: f32) {
        for n in &self.nodes {
            let buds = u8::from(n.main == BUD) + u8::from(n.lateral == BUD);
            if buds > 0 {
                env.cast(n.end, sign * buds as f32);
            }
        }
    }

    /// The living buds, terminal before lateral, in internode order: the order of the
    /// light slice [`Tree::plan_cycle`] takes.
    pub(crate) fn buds(&self, out: &mut Vec<Bud>) {
        out.clear();
        for n in &self.nodes {
            if n.main == BUD {
                out.push(Bud {
                    position: n.end,
                    direction: n.dir,
                });
            }
            if n.lateral == BUD {
                out.push(Bud {
                    position: n.end,
                    direction: n.lat_dir,
                });
            }
        }
    }

    /// Plans one cycle from the light and direction at every bud, asked of `light` with
    /// the bud's position and direction in [`Tree::buds`] order: the basipetal pass, the
    /// vigour split, shedding and the new shoots.
    pub(crate) fn plan_cycle(
        &mut self,
        mut light: impl FnMut(Vec3, Vec3) -> (f32, Vec3),
        cycle: u32,
    ) -> Plan {
        let p = self.species;
        let n = self.nodes.len();
        // Light of each node's buds, in bud order.
        let mut own = std::mem::take(&mut self.own);
        own.clear();
        for node in &self.nodes {
            let mut pair = [(0.0, Vec3::ZERO); 2];
            if node.main == BUD {
                pair[0] = light(node.end, node.dir);
            }
            if node.lateral == BUD {
                pair[1] = light(node.end, node.lat_dir);
            }
            own.push(pair);
        }
        // Basipetal: light above each internode, split into main and lateral.
        self.q.clear();
        self.q.resize(n, 0.0);
        self.qm.clear();
        self.qm.resize(n, 0.0);
        self.ql.clear();
        self.ql.resize(n, 0.0);
        self.desc.clear();
        self.desc.resize(n, 1);
        for i in (0..n).rev() {
            let node = self.nodes[i];
            let side = |slot: u32, bud: f32, q: &[f32]| match slot {
                BUD => bud,
                GONE => 0.0,
                c => q[c as usize],
            };
            self.qm[i] = side(node.main, own[i][0].0, &self.q);
            self.ql[i] = side(node.lateral, own[i][1].0, &self.q);
            self.q[i] = self.qm[i] + self.ql[i];
            for c in [node.main, node.lateral] {
                if is_child(c) {
                    self.desc[i] += self.desc[c as usize];
                }
            }
        }
        // One acropetal pass: the extended Borchert–Honda split of the vigour, shedding
        // (a lateral branch whose vigour no longer pays for its size goes, with everything
        // above it) and the new shoots (a bud with vigour v grows ⌊v⌋ internodes, at most
        // max_shoot). An internode's vigour is set by its parent, before it is visited.
        self.vig.clear();
        self.vig.resize(n, 0.0);
        self.vig[0] = p.vigor_multiplier * self.q[0];
        let lambda = p.apical_control;
        let mut residual = 0.0f32;
        let mut plan = Plan::default();
        let mut dead = std::mem::take(&mut self.dead);
        dead.clear();
        dead.resize(n, false);
        let up = Vec3::Y;
        for i in 0..n {
            let node = self.nodes[i];
            let v = self.vig[i];
            // Shedding.
            if i > 0 {
                let parent = node.parent as usize;
                if dead[parent] {
                    dead[i] = true;
                } else if p.shed_multiplier > 0.0
                    && self.nodes[parent].lateral == i as u32
                    && cycle.saturating_sub(node.birth) > p.shed_delay
                {
                    let cost = p.shed_multiplier * libm::powf(self.desc[i] as f32, p.shed_exponent);
                    if v < cost {
                        dead[i] = true;
                        plan.sheds = true;
                    }
                }
            }
            // The split.
            let (qm, ql) = (self.qm[i], self.ql[i]);
            let denom = lambda * qm + (1.0 - lambda) * ql;
            let (vm, vl) = if denom > 0.0 {
                (v * lambda * qm / denom, v * (1.0 - lambda) * ql / denom)
            } else {
                (0.0, 0.0)
            };
            if denom > 0.0 {
                residual = residual.max((v - vm - vl).abs() / v.max(1e-30));
            }
            for (k, (slot, share)) in [(node.main, vm), (node.lateral, vl)]
                .into_iter()
                .enumerate()
            {
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
                let env_dir = own[i][k].1;
                let mut heading = if k == 0 { node.dir } else { node.lat_dir };
                let mut at = node.end;
                let mut phyllo = node.phyllo;
                let order = node.order + k as u32;
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
        self.own = own;
        plan.dead = dead;
        plan
    }

    /// Carries out a plan: buds that grew or were shed take their shadow away, new buds
    /// add theirs, shed subtrees are removed (indices stay parents-before-children).
    pub(crate) fn grow(&mut self, plan: Plan, env: &mut Env, cycle: u32) {
        self.residual = plan.residual;
        self.root_vigour = plan.root_vigour;
        let tip_rn = libm::powf(self.species.tip_radius, self.species.pipe_exponent);
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
            let p = &mut self.nodes[parent as usize];
            if nw.main {
                if p.main == BUD {
                    env.cast(p.end, -1.0);
                }
                p.main = me;
            } else {
                if p.lateral == BUD {
                    env.cast(p.end, -1.0);
                }
                p.lateral = me;
            }
            self.nodes.push(Node {
                start: nw.start,
                end: nw.end,
                dir: nw.dir,
                lat_dir: nw.lat_dir,
                parent,
                main: BUD,
                lateral: BUD,
                birth: cycle,
                order: nw.order,
                phyllo: nw.phyllo,
                rn: tip_rn,
            });
            // Its lateral bud and its terminal bud (taken away again if the chain goes on;
            // the two cancel before the grid is touched).
            env.cast(nw.end, 2.0);
        }
        let mut dead = plan.dead;
        if plan.sheds {
            self.shed_subtrees(&mut dead, env);
        }
        self.dead = dead;
        self.update_radii(tip_rn);
    }

    /// The pipe model, tips to root: r^n of an internode is the sum over its children (the
    /// tip radius at a tip), and never less than it has been.
    fn update_radii(&mut self, tip_rn: f32) {
        for i in (0..self.nodes.len()).rev() {
            let node = self.nodes[i];
            let mut rn = 0.0;
            let mut children = false;
            for c in [node.main, node.lateral] {
                if is_child(c) {
                    rn += self.nodes[c as usize].rn;
                    children = true;
                }
            }
            let rn = if children { rn } else { tip_rn };
            let node = &mut self.nodes[i];
            node.rn = node.rn.max(rn);
        }
    }

    /// Removes the internodes marked in `dead` (the plan's marks, for the internodes
    /// that existed when it was made), taking their buds' shadow away; indices stay
    /// parents-before-children. The internodes are compacted in place, with the scratch
    /// of the plan (no allocation in proportion to the tree).
    fn shed_subtrees(&mut self, dead: &mut Vec<bool>, env: &mut Env) {
        let n = self.nodes.len();
        // Internodes grown this cycle never grow on a shed one.
        dead.resize(n, false);
        let mut new_index = std::mem::take(&mut self.desc);
        new_index.clear();
        new_index.resize(n, NO_PARENT);
        let mut kept = 0usize;
        for i in 0..n {
            let node = self.nodes[i];
            if dead[i] {
                let buds = u8::from(node.main == BUD) + u8::from(node.lateral == BUD);
                if buds > 0 {
                    env.cast(node.end, -(buds as f32));
                }
                continue;
            }
            new_index[i] = kept as u32;
            self.nodes[kept] = node;
            kept += 1;
        }
        self.nodes.truncate(kept);
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
        for node in &mut self.nodes {
            if node.parent != NO_PARENT {
                node.parent = new_index[node.parent as usize];
            }
            node.main = map(node.main);
            node.lateral = map(node.lateral);
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
        let mut parts = SkeletonParts {
            branches: Vec::with_capacity(self.nodes.len()),
            ..Default::default()
        };
        for (i, n) in self.nodes.iter().enumerate() {
            let r = radius(n.rn);
            let end_radius = if is_child(n.main) {
                radius(self.nodes[n.main as usize].rn)
            } else {
                tip.min(r)
            };
            parts.branches.push(Branch {
                start: n.start.to_array(),
                end: n.end.to_array(),
                start_radius: r,
                end_radius,
                parent: n.parent,
                birth: n.birth,
                order: n.order,
                flags: 0,
            });
            for (slot, heading) in [(n.main, n.dir), (n.lateral, n.lat_dir)] {
                if slot == BUD {
                    parts.leaves.push(LeafSite {
                        position: n.end.to_array(),
                        heading: heading.to_array(),
                        up: perpendicular(heading).to_array(),
                        branch: i as u32,
                        birth: n.birth,
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
