//! Sweeps: `curve_rings` inner rings along each branch's curve.

use arbor::mesh::{self, Joints, MeshOptions, Tip, Topology};
use arbor::models::honda::{self, HondaParams, PRESET_NAMES};
use arbor::skeleton::Skeleton;
use glam::Vec3;

fn smoothed(name: char) -> Skeleton {
    let mut s = honda::build(&HondaParams::preset(name).unwrap()).unwrap();
    s.smooth(1.0).unwrap();
    s
}

/// Every inner ring's vertices lie on the circle of the tube around the curve: at the
/// interpolated radius from the curve's point, perpendicular to its tangent.
#[test]
fn swept_vertices_lie_on_the_tube_around_their_curve() {
    let k = 4usize;
    for name in PRESET_NAMES {
        let s = smoothed(name);
        let o = MeshOptions::default()
            .curve_rings(k as u32)
            .joints(Joints::Separate);
        let m = mesh::tubes(&s, &o).unwrap();
        let ring = (o.radial_segments + 1) as usize;
        let mut worst = 0.0f32;
        for (i, r) in m.ranges.iter().enumerate() {
            let b = &s.branches()[i];
            let c = s.curve(i);
            assert_eq!(
                r.vertex_count as usize,
                (k + 2) * ring,
                "tree {name} branch {i}"
            );
            for j in 1..=k {
                let t = j as f32 / (k + 1) as f32;
                let (centre, tangent) = (c.point(t), c.tangent(t).normalize());
                let radius = b.start_radius + (b.end_radius - b.start_radius) * t;
                for v in 0..ring {
                    let p = Vec3::from(m.vertices[r.first_vertex as usize + j * ring + v].position);
                    let off = p - centre;
                    let scale = radius.max(1e-3);
                    let err =
                        ((off.length() - radius).abs() / scale).max(off.dot(tangent).abs() / scale);
                    worst = worst.max(err);
                    assert!(err < 2e-3, "tree {name} branch {i} ring {j}: {err}");
                }
            }
        }
        println!(
            "tree {name}: inner ring vertices within {worst:.2e} of the tube (relative to the radius)"
        );
    }
}

/// A sweep is a valid mesh in every topology: sizes as asked, indices in range, the strips
/// decode to the list's triangles, unit normals, and faces that agree with their normals.
#[test]
fn sweeps_are_valid_meshes_in_every_topology() {
    for name in PRESET_NAMES {
        let s = smoothed(name);
        for (joints, tip, base_cap, lod) in [
            (Joints::Mitred, Tip::Open, false, 0),
            (Joints::Separate, Tip::Point, true, 0),
            (Joints::Mitred, Tip::Cap, true, 0),
            (Joints::Mitred, Tip::Open, false, 3),
        ] {
            let base = MeshOptions::default()
                .curve_rings(3)
                .joints(joints)
                .tip(tip)
                .base_cap(base_cap)
                .min_radial_segments(lod);
            let list = mesh::tubes(&s, &base).unwrap();
            let size = mesh::mesh_size(&s, &base).unwrap();
            assert_eq!(
                (list.vertices.len(), list.indices.len()),
                (size.vertices, size.indices)
            );
            let nv = list.vertices.len() as u32;
            let tris: Vec<[u32; 3]> = list.triangles().collect();
            let mut agree_min = 1.0f32;
            for &[a, b, c] in &tris {
                assert!(a < nv && b < nv && c < nv);
                let p = |i: u32| Vec3::from(list.vertices[i as usize].position);
                let face = (p(b) - p(a)).cross(p(c) - p(a));
                if face.length() < 1e-9 {
                    continue;
                }
                let avg: Vec3 = [a, b, c]
                    .iter()
                    .map(|&i| Vec3::from(list.vertices[i as usize].normal))
                    .sum();
                agree_min = agree_min.min(face.normalize().dot(avg.normalize()));
            }
            println!("tree {name} {joints:?}: worst face agreement {agree_min:.3}");
            // Tree f's outer twigs are thicker (radius 1) than they are long (0.8): a sweep
            // of a tube wider than its curve's bend folds there, as any sweep would.
            if name != 'f' {
                assert!(
                    agree_min > 0.5,
                    "tree {name} {joints:?}: faces disagree ({agree_min})"
                );
            }
            for v in &list.vertices {
                let n = Vec3::from(v.normal);
                assert!((n.length() - 1.0).abs() < 1e-4, "unit normals");
                assert!(v.position.iter().chain(&v.uv).all(|x| x.is_finite()));
            }
            for topology in [
                Topology::TriangleStripRestart,
                Topology::TriangleStripDegenerate,
            ] {
                let o = base.topology(topology);
                let m = mesh::tubes(&s, &o).unwrap();
                assert_eq!(m.vertices, list.vertices);
                let got: Vec<[u32; 3]> = m.triangles().collect();
                assert_eq!(got.len(), tris.len(), "{topology:?}");
            }
            let a = mesh::animation(&s, &base).unwrap();
            assert_eq!(
                a.len(),
                list.vertices.len(),
                "one animation element per vertex"
            );
        }
    }
}

/// With inner rings on straight branches the rings fall on the cone between the end
/// rings, and v runs by arc length: the same surface, finer.
#[test]
fn inner_rings_on_straight_branches_subdivide_the_cone() {
    let s = honda::build(&HondaParams::preset('c').unwrap()).unwrap();
    let plain = mesh::tubes(&s, &MeshOptions::default().joints(Joints::Separate)).unwrap();
    let swept = mesh::tubes(
        &s,
        &MeshOptions::default()
            .joints(Joints::Separate)
            .curve_rings(2),
    )
    .unwrap();
    let ring = 9usize;
    for (i, (a, b)) in plain.ranges.iter().zip(&swept.ranges).enumerate() {
        let (a0, b0) = (a.first_vertex as usize, b.first_vertex as usize);
        for v in 0..ring {
            let (pa, pb) = (&plain.vertices[a0 + v], &swept.vertices[b0 + v]);
            assert!(
                Vec3::from(pa.position).distance(Vec3::from(pb.position)) < 1e-3,
                "branch {i} start"
            );
            let (ea, eb) = (
                &plain.vertices[a0 + ring + v],
                &swept.vertices[b0 + 3 * ring + v],
            );
            assert!(
                Vec3::from(ea.position).distance(Vec3::from(eb.position)) < 1e-3,
                "branch {i} end"
            );
            assert!(
                (ea.uv[1] - eb.uv[1]).abs() < 1e-3,
                "branch {i}: v at the end"
            );
        }
    }
    assert!(
        mesh::mesh_size(&s, &MeshOptions::default().curve_rings(65))
            .unwrap_err()
            .to_string()
            .contains("curve_rings")
    );
}
