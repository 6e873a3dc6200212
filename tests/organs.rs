//! The turtle's other organs: `@O` spheres and `@o`/`@c` discs in the baked organ mesh
//! (every topology, outward normals, counter-clockwise front faces), and `;`/`,` colour
//! indices per branch and per organ.

use arbor::lsystem::LSystem;
use arbor::mesh::{LeafOptions, MeshOptions, Topology, Triangles, leaf_mesh, leaf_mesh_size};
use arbor::skeleton::{ORGAN_DISC, ORGAN_SPHERE};
use glam::Vec3;

fn grow(text: &str) -> arbor::skeleton::Skeleton {
    LSystem::parse(text)
        .unwrap()
        .skeleton(&Default::default())
        .unwrap()
}

#[test]
fn spheres_and_discs_are_recorded_where_the_turtle_stands() {
    let s = grow("Axiom: !(3)F(2)@O[+(90)f(4)@o(1)]@c(2)F@O(0.5)");
    let o = s.organs();
    assert_eq!(o.len(), 4);
    assert_eq!((o[0].kind, o[0].size, o[0].branch), (ORGAN_SPHERE, 3.0, 0));
    assert_eq!(o[0].position, [0.0, 2.0, 0.0]);
    assert_eq!((o[1].kind, o[1].size), (ORGAN_DISC, 1.0));
    assert!((Vec3::from(o[1].position) - Vec3::new(-4.0, 2.0, 0.0)).length() < 1e-5);
    assert_eq!((o[2].kind, o[2].size), (ORGAN_DISC, 2.0));
    assert_eq!((o[3].kind, o[3].size, o[3].branch), (ORGAN_SPHERE, 0.5, 1));
}

#[test]
fn organs_are_meshed_in_every_topology_with_outward_faces() {
    let s = grow("Axiom: F(2)@O(2)[+(60)F@o(1)]F@O(1)");
    let leaves = LeafOptions::default();
    let mut triangles = None;
    for topology in [
        Topology::TriangleList,
        Topology::TriangleStripRestart,
        Topology::TriangleStripDegenerate,
    ] {
        let options = MeshOptions::default().topology(topology).radial_segments(8);
        let m = leaf_mesh(&s, &leaves, &options).unwrap();
        let size = leaf_mesh_size(&s, &leaves, &options).unwrap();
        assert_eq!(
            (m.vertices.len(), m.indices.len()),
            (size.vertices, size.indices)
        );
        // Two spheres of 5 rings of 9 and one disc of 8 corners.
        assert_eq!(m.vertices.len(), 2 * 5 * 9 + 8);
        let tris: Vec<[u32; 3]> = Triangles::new(&m.indices, topology).collect();
        // A sphere: 4 bands of 8 quads, less the 16 triangles that collapse at the poles
        // (zero area, skipped by strips, kept by lists); the disc: 6 triangles.
        let nondegenerate = |t: &&[u32; 3]| {
            let p = |i: u32| Vec3::from(m.vertices[i as usize].position);
            (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length() > 1e-9
        };
        let real = tris.iter().filter(nondegenerate).count();
        assert_eq!(real, 2 * (4 * 16 - 16) + 6, "{topology:?}");
        if let Some(previous) = triangles {
            assert_eq!(real, previous, "the same triangles in every topology");
        }
        triangles = Some(real);
        for t in tris.iter().filter(nondegenerate) {
            let p = |i: u32| Vec3::from(m.vertices[i as usize].position);
            let face = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
            let normal: Vec3 = t
                .iter()
                .map(|&i| Vec3::from(m.vertices[i as usize].normal))
                .sum();
            assert!(face.dot(normal) > 0.0, "{topology:?}: a face turns inward");
        }
        // Sphere vertices lie on their sphere, normals radial and unit.
        for (k, v) in m.vertices[..45].iter().enumerate() {
            let d = Vec3::from(v.position) - Vec3::new(0.0, 2.0, 0.0);
            assert!((d.length() - 1.0).abs() < 1e-5, "vertex {k}");
            assert!((Vec3::from(v.normal) - d).length() < 1e-5, "vertex {k}");
            assert!(v.uv.iter().all(|c| (0.0..=1.0).contains(c)));
        }
    }
    // Without polygons the organ mesh leaves them out too.
    let none = LeafOptions::default().polygons(false);
    assert_eq!(
        leaf_mesh(&s, &none, &MeshOptions::default())
            .unwrap()
            .vertices
            .len(),
        0
    );
}

#[test]
fn colour_indices_follow_semicolon_and_comma() {
    let s = grow("Axiom: F;F;(7)F[,F@O],F");
    assert_eq!(s.colors(), &[1, 2, 7, 6, 6]);
    assert_eq!(s.organs()[0].color, 6);
    // No `;` or `,`: no colours kept.
    assert!(grow("Axiom: FF").colors().is_empty());
    // The view file's initial colour and increment.
    let ls =
        LSystem::parse_with_view("Axiom: F;F", "initial color: 15\ncolor increment: 2\n").unwrap();
    assert_eq!(
        ls.skeleton(&Default::default()).unwrap().colors(),
        &[15, 17]
    );
    // Pruning keeps the colours of the branches it keeps.
    let p = arbor::skeleton::prune::prune_collisions(&s);
    assert_eq!(p.skeleton.colors().len(), p.skeleton.len());
}
