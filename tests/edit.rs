//! One-branch rewrites: after an edit, rewriting only what changed inside the buffers of
//! the complete mesh equals a full write, byte for byte.

use arbor::geom::Curve;
use arbor::mesh::{Axes, MeshOptions, MeshPlan, Tip, Topology, Vertex};
use arbor::models::honda::{self, HondaParams};
use arbor::skeleton::Skeleton;
use glam::Vec3;

fn bent(s: &Skeleton, i: usize, by: Vec3) -> (Curve, f32, f32) {
    let c = s.curve(i);
    let b = &s.branches()[i];
    (
        Curve {
            p1: c.p1 + by * 0.5,
            p2: c.p2 - by * 0.25,
            p3: c.p3 + by,
            ..c
        },
        b.start_radius * 0.9,
        b.end_radius * 0.8,
    )
}

#[test]
fn rewrites_equal_full_writes_for_twigs_interior_branches_and_roots() {
    let mut checked = 0;
    for name in ['a', 'g'] {
        let base = honda::build(&HondaParams::preset(name).unwrap()).unwrap();
        let adjacency = base.adjacency().clone();
        let twig = (0..base.len())
            .rev()
            .find(|&i| adjacency.is_tip(i))
            .unwrap();
        let interior = adjacency.children(0)[0] as usize;
        for smooth in [false, true] {
            for curve_rings in [0, 2] {
                for (topology, axes) in Topology::ALL
                    .into_iter()
                    .flat_map(|t| [Axes::Arbor, Axes::Unity, Axes::Unreal].map(|a| (t, a)))
                {
                    for (i, what) in [(twig, "twig"), (interior, "interior"), (0, "root")] {
                        let mut s = base.clone();
                        if smooth {
                            s.smooth(1.0).unwrap();
                        }
                        let o = MeshOptions::default()
                            .topology(topology)
                            .curve_rings(curve_rings)
                            .tip(Tip::Cap)
                            .smooth_taper(true)
                            .axes(axes);
                        let mut plan = MeshPlan::new(&s, &o).unwrap();
                        let size = plan.size();
                        let mut v = vec![Vertex::default(); size.vertices];
                        let mut idx = vec![0u32; size.indices];
                        plan.write(&s, &mut v, &mut idx).unwrap();
                        let (curve, r0, r1) = bent(&s, i, Vec3::new(0.4, -0.3, 0.2));
                        s.set_curve(i, &curve, r0, r1).unwrap();
                        let changed = plan.update_after_edit(&s, i).unwrap();
                        plan.rewrite(&s, &changed, &mut v).unwrap();
                        let fresh = MeshPlan::new(&s, &o).unwrap().mesh(&s).unwrap();
                        let what = format!(
                            "tree {name} {what} smooth {smooth} rings {curve_rings} {topology:?} {axes:?}"
                        );
                        assert_eq!(
                            bytemuck::cast_slice::<Vertex, u8>(&v),
                            bytemuck::cast_slice::<Vertex, u8>(&fresh.vertices),
                            "{what}: vertices"
                        );
                        assert_eq!(idx, fresh.indices, "{what}: indices");
                        if what.contains("twig") {
                            assert!(changed.len() <= 2, "{what}: only the twig and its parent");
                        }
                        checked += 1;
                    }
                }
            }
        }
    }
    assert_eq!(checked, 2 * 2 * 2 * 3 * 3 * 3);
}

#[test]
fn edits_that_would_change_the_ranges_are_refused() {
    let mut s = honda::build(&HondaParams::preset('a').unwrap()).unwrap();
    let o = MeshOptions::default();
    let mut plan = MeshPlan::new(&s, &o).unwrap();
    // Bend the trunk's continuation back on itself: its joint stops being mitred.
    let i = s.adjacency().children(0)[0] as usize;
    let b = s.branches()[i];
    let back = b.start() - (b.end() - b.start());
    let c = Curve::straight(b.start(), back);
    s.set_curve(i, &c, b.start_radius, b.end_radius).unwrap();
    let err = plan.update_after_edit(&s, i).unwrap_err().to_string();
    assert!(err.contains("write the mesh again"), "{err}");
    // LOD on: sides depend on every radius.
    let lod = MeshOptions::default().min_radial_segments(3);
    let mut plan = MeshPlan::new(&s, &lod).unwrap();
    assert!(plan.update_after_edit(&s, 1).is_err());
    assert!(
        MeshPlan::new(&s, &o)
            .unwrap()
            .update_after_edit(&s, 1_000_000)
            .is_err()
    );
}
