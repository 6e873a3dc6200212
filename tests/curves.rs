//! Curves: records for shaders round-trip to the mesh, smoothing keeps joints.

use arbor::mesh::{self, Joints, MeshOptions};
use arbor::models::honda::{self, HondaParams};
use glam::Vec3;

/// A curve record's ends are the centres of its branch's rings in the mesh (separate
/// joints: each branch has its own start and end ring), and its arc length and v chain
/// match the mesh's texture v.
#[test]
fn curve_records_round_trip_to_the_mesh() {
    let s = honda::build(&HondaParams::preset('d').unwrap()).unwrap();
    let o = MeshOptions::default().joints(Joints::Separate);
    let m = mesh::tubes(&s, &o).unwrap();
    let records = mesh::curve_records(&s);
    assert_eq!(records.len(), s.len());
    let ring = (o.radial_segments + 1) as usize;
    let centre = |first: usize| {
        m.vertices[first..first + ring - 1]
            .iter()
            .map(|v| Vec3::from(v.position))
            .sum::<Vec3>()
            / (ring - 1) as f32
    };
    for (i, r) in records.iter().enumerate() {
        let b = &s.branches()[i];
        let first = m.ranges[i].first_vertex as usize;
        let end = centre(first + ring);
        let curve_end = Vec3::from(r.p3);
        assert!(
            end.distance(curve_end) < 1e-3,
            "branch {i}: {end} vs {curve_end}"
        );
        // The start ring sits one parent radius back along the branch (sunk).
        let sink = if b.parent == arbor::skeleton::NO_PARENT {
            0.0
        } else {
            s.branches()[b.parent as usize].end_radius
        };
        let dir = (b.end() - b.start()).normalize();
        let start = Vec3::from(r.p0) - dir * sink;
        assert!(centre(first).distance(start) < 1e-3, "branch {i} start");
        // v at the end ring = (v0 + length) / texture scale.
        let v_end = m.vertices[first + ring].uv[1];
        assert!(
            (v_end - (r.v0 + r.length)).abs() < 1e-3 * (1.0 + v_end),
            "branch {i} v"
        );
    }
    let growth = mesh::curve_growth_records(&s);
    let a = mesh::animation(&s, &o).unwrap();
    for (i, g) in growth.iter().enumerate() {
        let first = m.ranges[i].first_vertex as usize;
        // The animation stream's start ring has growth = grow_start, the end ring grow_end.
        assert!((a[first].growth - g.grow_start).abs() < 1e-6, "branch {i}");
        assert!(
            (a[first + ring].growth - g.grow_end).abs() < 1e-6,
            "branch {i}"
        );
    }
}

/// A grammar's generalized cylinder (`@Gs` … `@Ge`) sets the curves of the internodes
/// drawn inside it from the turtle's path: C¹ through its joints; branches outside it stay
/// straight.
#[test]
fn generalized_cylinders_set_curves_from_the_turtle_path() {
    use arbor::lsystem::{LSystem, LsystemOptions};
    let ls =
        LSystem::parse("Axiom: F(1) [+(40) F(1)] @Gs F(1) @Gc(2) +(30) F(1) +(30) F(1) @Ge F(1)")
            .unwrap();
    let s = ls.skeleton(&LsystemOptions::default()).unwrap();
    assert_eq!(s.len(), 6);
    assert!(s.has_curves());
    let straight = |i: usize| s.curve(i).is_straight(1e-5);
    assert!(straight(0) && straight(1), "outside the cylinder");
    assert!(!straight(2) && !straight(3) && !straight(4), "inside it");
    assert!(straight(5), "after @Ge");
    for (a, b) in [(2usize, 3usize), (3, 4)] {
        let (ta, tb) = (
            s.curve(a).tangent(1.0).normalize(),
            s.curve(b).tangent(0.0).normalize(),
        );
        assert!(
            ta.cross(tb).length() < 1e-5 && ta.dot(tb) > 0.0,
            "C1 at the joint {a}-{b}"
        );
        assert_eq!(s.curve(a).p3, s.curve(b).p0);
    }
    // A sweep follows it.
    let m = arbor::mesh::tubes(&s, &arbor::MeshOptions::default().curve_rings(3)).unwrap();
    assert!(!m.indices.is_empty());
}
