use super::*;

/// Shedding as it was first written, one internode moved at a time: what
/// [`Tree::shed_subtrees`] is checked against.
fn shed_one_at_a_time(t: &mut Tree, roots: &[u32], env: &Env) {
    let n = t.nodes.len();
    let first = roots.first().map_or(n, |&r| r as usize);
    let mut new_index = vec![NO_PARENT; n - first];
    let nodes = &mut t.nodes;
    let mut roots = roots.iter().copied().peekable();
    let mut kept = first;
    for i in first..n {
        let p = nodes.parent[i];
        let parent = if p == NO_PARENT || (p as usize) < first {
            p
        } else {
            new_index[p as usize - first]
        };
        let root = roots.next_if_eq(&(i as u32)).is_some();
        let side =
            usize::from(parent != NO_PARENT && nodes.order[i] != nodes.order[parent as usize]);
        if root || (p != NO_PARENT && parent == NO_PARENT) {
            let buds = buds(nodes.kids[i]);
            if buds > 0 {
                t.casts.extend(env.change(nodes.cell[i], -(buds as i32)));
            }
            if parent != NO_PARENT {
                nodes.kids[parent as usize][side] = GONE;
            }
            continue;
        }
        new_index[i - first] = kept as u32;
        if kept != i {
            for v in [
                &mut nodes.parent,
                &mut nodes.birth,
                &mut nodes.order,
                &mut nodes.along,
            ] {
                v[kept] = v[i];
            }
            nodes.end[kept] = nodes.end[i];
            nodes.dir[kept] = nodes.dir[i];
            nodes.kids[kept] = nodes.kids[i];
            nodes.phyllo[kept] = nodes.phyllo[i];
            nodes.rn[kept] = nodes.rn[i];
            nodes.cell[kept] = nodes.cell[i];
        }
        nodes.parent[kept] = parent;
        if parent != NO_PARENT {
            nodes.kids[parent as usize][side] = kept as u32;
        }
        kept += 1;
    }
    nodes.truncate(kept);
    t.shed += n - kept;
}

/// The shadow light, with its buds read ahead or not.
struct Ahead<'a>(&'a Env, bool);

impl Light for Ahead<'_> {
    const ORDERED: bool = false;
    fn q(&self, _: u32, word: Key) -> f32 {
        self.0.shadow_q(word)
    }
    fn v(&self, _: u32, word: Key) -> Vec3 {
        self.0.shadow_v(word)
    }
    fn read_ahead(&self) -> bool {
        self.1
    }
}

/// Reading the buds' light in a pass of its own plans what reading it in the
/// basipetal pass plans, bit for bit, cycle after cycle of a growing tree.
#[test]
fn light_read_ahead_plans_the_same_cycle() {
    let mut w = super::super::World::new(&super::super::WorldOptions::default()).unwrap();
    w.plant(&GrowthParams::default(), [0.0, 0.0, 0.0], 1)
        .unwrap();
    let mut planned = 0;
    for cycle in 1..=14 {
        w.step(1).unwrap();
        let mut a = w.trees[0].clone();
        let mut b = w.trees[0].clone();
        let (pa, pb) = (
            a.plan_cycle(&Ahead(&w.env, true), cycle + 1),
            b.plan_cycle(&Ahead(&w.env, false), cycle + 1),
        );
        // Debug prints each float's shortest exact form: equal text, equal bits.
        assert_eq!(format!("{pa:?}"), format!("{pb:?}"), "cycle {cycle}");
        planned += pa.new_internodes();
    }
    assert!(planned > 100, "only {planned} internodes planned");
}

/// Random trees (each internode on a free side of an earlier one, a lateral one order
/// up, buds and gone slots where no internode grows) and random sets of roots to shed:
/// links, fields and shadow changes as moving one internode at a time gives them.
#[test]
fn shedding_runs_at_once_is_shedding_one_at_a_time() {
    let env = Env::new(&super::super::WorldOptions::default()).unwrap();
    let mut rng = crate::rng::Rng::new(17);
    let mut r = move |n: u64| rng.next_u64() % n.max(1);
    let mut shed_some = 0;
    for _ in 0..300 {
        let mut t = Tree::plant(GrowthParams::default(), Vec3::ZERO, 1, 0, &env);
        t.nodes = Nodes::default();
        let n = 1 + r(60) as usize;
        for i in 0..n {
            let free: Vec<(usize, usize)> = (0..i)
                .flat_map(|p| [(p, 0), (p, 1)])
                .filter(|&(p, k)| t.nodes.kids[p][k] == BUD)
                .collect();
            let (parent, order) = if i == 0 || free.is_empty() {
                (NO_PARENT, 0)
            } else {
                let (p, k) = free[r(free.len() as u64) as usize];
                t.nodes.kids[p][k] = i as u32;
                (p as u32, t.nodes.order[p] + k as u32)
            };
            t.nodes.push(NodeInit {
                end: Vec3::new(i as f32, r(100) as f32, 0.5),
                dir: Vec3::Y,
                parent,
                birth: r(30) as u32,
                order,
                phyllo: r(360) as f32,
                rn: r(1000) as f32,
                cell: r(1 << 40),
                along: r(9) as u32,
            });
            if r(5) == 0 {
                t.nodes.kids[i][r(2) as usize] = GONE;
            }
        }
        let roots: Vec<u32> = (1..n as u32).filter(|_| r(6) == 0).collect();
        let mut reference = t.clone();
        shed_one_at_a_time(&mut reference, &roots, &env);
        SCRATCH.with_borrow_mut(|s| t.shed_subtrees(&roots, &env, s));
        assert_eq!(t.len(), reference.len(), "roots {roots:?}");
        SCRATCH.with_borrow_mut(|s| t.compact(s));
        assert_eq!(t.dead, 0);
        shed_some += usize::from(t.shed > 0);
        let n = &t.nodes;
        let m = &reference.nodes;
        assert_eq!(
            (&n.parent, &n.kids, &n.birth, &n.order, &n.along),
            (&m.parent, &m.kids, &m.birth, &m.order, &m.along),
            "roots {roots:?}"
        );
        assert_eq!(
            (&n.end, &n.dir, &n.phyllo, &n.rn, &n.cell),
            (&m.end, &m.dir, &m.phyllo, &m.rn, &m.cell)
        );
        assert_eq!((t.shed, &t.casts), (reference.shed, &reference.casts));
    }
    assert!(shed_some > 200, "only {shed_some} trees shed anything");
}

/// Shed internodes left stored until they are many give the skeletons that removing
/// them every cycle gives, byte for byte, through cycles that shed and compact.
#[test]
fn shed_internodes_kept_until_compaction_change_nothing() {
    use super::super::{Species, World, WorldOptions};
    for species in [Species::Bush, Species::Decurrent] {
        let mut kept = World::new(&WorldOptions::default()).unwrap();
        kept.plant(&GrowthParams::preset(species), [0.0; 3], 3)
            .unwrap();
        let mut removed = kept.clone();
        let (mut stored, mut compacted) = (0, 0);
        for cycle in 1..=45 {
            kept.step(1).unwrap();
            removed.step(1).unwrap();
            for t in &mut removed.trees {
                SCRATCH.with_borrow_mut(|s| t.compact(s));
            }
            let t = &kept.trees[0];
            stored += usize::from(t.dead > 0);
            compacted += usize::from(t.dead == 0 && t.shed > 0);
            assert_eq!(t.len(), removed.trees[0].len(), "cycle {cycle}");
            assert_eq!(
                format!("{:?}", t.skeleton()),
                format!("{:?}", removed.trees[0].skeleton()),
                "{species:?}, cycle {cycle}"
            );
        }
        assert!(
            stored > 5 && compacted > 0,
            "{species:?}: {stored}, {compacted}"
        );
    }
}

/// A fuzzer found an infinite root vigour asking for 2^32 seedlings (22 GB): the
/// count is bounded by what the world can take.
#[test]
fn seeding_never_asks_for_more_trees_than_the_world_holds() {
    let species = GrowthParams {
        seed_age: 1,
        ..GrowthParams::default()
    };
    let env = Env::new(&super::super::WorldOptions::default()).unwrap();
    let mut t = Tree::plant(species, Vec3::ZERO, 1, 0, &env);
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
