//! Mesh invariants on every preset and every topology.

use arbor::Error;
use arbor::honda::{self, HondaParams, PRESET_NAMES};
use arbor::mesh::{self, Mesh, MeshOptions, RESTART_INDEX, Topology, Triangles, Vertex};
use arbor::skeleton::{Branch, NO_PARENT, Skeleton};
use glam::Vec3;

fn tree(name: char) -> Skeleton {
    honda::build(&HondaParams::preset(name).unwrap()).unwrap()
}

fn options(radial_segments: u32, topology: Topology) -> MeshOptions {
    MeshOptions {
        radial_segments,
        topology,
    }
}

fn pos(v: &Vertex) -> Vec3 {
    Vec3::from_array(v.position)
}

/// Rotates a triangle so its smallest index comes first (same winding).
fn canonical([a, b, c]: [u32; 3]) -> [u32; 3] {
    if a <= b && a <= c {
        [a, b, c]
    } else if b <= a && b <= c {
        [b, c, a]
    } else {
        [c, a, b]
    }
}

fn check_invariants(name: char, s: &Skeleton, segments: u32) {
    let list = mesh::tubes(s, &options(segments, Topology::TriangleList)).unwrap();
    let ring = segments as usize + 1;
    assert_eq!(list.vertices.len(), s.len() * 2 * ring);
    assert_eq!(list.indices.len(), s.len() * 6 * segments as usize);
    let nv = list.vertices.len() as u32;

    for (i, v) in list.vertices.iter().enumerate() {
        let finite = v.position.iter().chain(&v.normal).chain(&v.uv);
        assert!(finite.clone().all(|x| x.is_finite()), "{name}: vertex {i}");
        let n = Vec3::from_array(v.normal);
        assert!((n.length() - 1.0).abs() < 1e-5, "{name}: normal {i} {n}");
        assert!((0.0..=1.0).contains(&v.uv[0]) && (0.0..=1.0).contains(&v.uv[1]));
    }

    // Triangle list: indices in range, no degenerate triangle, faces agree with normals.
    let list_tris: Vec<[u32; 3]> = list.triangles().collect();
    assert_eq!(list_tris.len() * 3, list.indices.len());
    for (k, &[a, b, c]) in list_tris.iter().enumerate() {
        assert!(
            a < nv && b < nv && c < nv,
            "{name}: triangle {k} out of range"
        );
        assert!(
            a != b && b != c && a != c,
            "{name}: triangle {k} degenerate"
        );
        let (pa, pb, pc) = (
            pos(&list.vertices[a as usize]),
            pos(&list.vertices[b as usize]),
            pos(&list.vertices[c as usize]),
        );
        let face = (pb - pa).cross(pc - pa);
        assert!(face.length() > 0.0, "{name}: triangle {k} has no area");
        let avg: Vec3 = [a, b, c]
            .iter()
            .map(|&i| Vec3::from_array(list.vertices[i as usize].normal))
            .sum();
        let agree = face.normalize().dot(avg.normalize());
        assert!(agree > 0.7, "{name}: triangle {k} faces away ({agree})");
    }

    // Both strip layouts: same vertices, and they decode to the list's triangles.
    let expected: Vec<[u32; 3]> = list_tris.iter().copied().map(canonical).collect();
    for topology in [
        Topology::TriangleStripRestart,
        Topology::TriangleStripDegenerate,
    ] {
        let strip = mesh::tubes(s, &options(segments, topology)).unwrap();
        assert_eq!(strip.vertices, list.vertices, "{name} {topology:?}");
        for &i in &strip.indices {
            let restart = topology == Topology::TriangleStripRestart && i == RESTART_INDEX;
            assert!(i < nv || restart, "{name} {topology:?}: index {i}");
        }
        let got: Vec<[u32; 3]> = strip.triangles().map(canonical).collect();
        assert_eq!(got, expected, "{name} {topology:?}");
        let restarts = strip
            .indices
            .iter()
            .filter(|&&i| i == RESTART_INDEX)
            .count();
        match topology {
            Topology::TriangleStripRestart => assert_eq!(restarts, s.len() - 1),
            _ => assert_eq!(restarts, 0),
        }
        let size = mesh::mesh_size(s, &options(segments, topology)).unwrap();
        assert_eq!(size.indices, strip.indices.len());
    }
}

#[test]
fn invariants_hold_on_every_preset_and_topology() {
    for name in PRESET_NAMES {
        let s = tree(name);
        for segments in [3, 8] {
            check_invariants(name, &s, segments);
        }
    }
    check_invariants('c', &tree('c'), 64);
    check_invariants('d', &tree('d'), 17);
}

fn single(start_radius: f32, end_radius: f32, dir: Vec3) -> Skeleton {
    Skeleton::new(vec![Branch {
        start: [1.0, 2.0, 3.0],
        end: (Vec3::new(1.0, 2.0, 3.0) + dir).to_array(),
        start_radius,
        end_radius,
        parent: NO_PARENT,
        ..Default::default()
    }])
    .unwrap()
}

#[test]
fn cone_normals_tilt_toward_the_narrow_end() {
    let s = single(2.0, 1.0, Vec3::new(0.0, 10.0, 0.0));
    let m = mesh::tubes(&s, &MeshOptions::default()).unwrap();
    let expected_tilt = 1.0 / 101f32.sqrt();
    for v in &m.vertices {
        assert!((v.normal[1] - expected_tilt).abs() < 1e-6, "{:?}", v.normal);
    }
    // Rings sit at the right radius around the axis.
    for (k, v) in m.vertices.iter().enumerate() {
        let p = pos(v) - Vec3::new(1.0, 2.0, 3.0);
        let r = (p.x * p.x + p.z * p.z).sqrt();
        let want = if k < 9 { 2.0 } else { 1.0 };
        assert!((r - want).abs() < 1e-5, "vertex {k}: radius {r}");
    }
}

#[test]
fn uv_seam_is_duplicated_and_v_runs_along_the_branch() {
    for dir in [Vec3::Y, Vec3::NEG_Y, Vec3::new(3.0, -1.0, 2.0), Vec3::Z] {
        let s = single(1.0, 1.0, dir);
        let segments = 6usize;
        let m = mesh::tubes(&s, &options(segments as u32, Topology::TriangleList)).unwrap();
        let (bottom, top) = m.vertices.split_at(segments + 1);
        for ring in [bottom, top] {
            assert_eq!(ring[0].position, ring[segments].position, "{dir}");
            assert_eq!(ring[0].uv[0], 0.0);
            assert_eq!(ring[segments].uv[0], 1.0);
        }
        assert!(bottom.iter().all(|v| v.uv[1] == 0.0));
        assert!(top.iter().all(|v| v.uv[1] == 1.0));
        // Normals are perpendicular to a cylinder's axis.
        for v in &m.vertices {
            assert!(Vec3::from_array(v.normal).dot(dir.normalize()).abs() < 1e-5);
        }
    }
}

#[test]
fn too_small_buffers_are_refused_and_left_untouched() {
    let s = tree('c');
    for topology in Topology::ALL {
        let o = options(5, topology);
        let size = mesh::mesh_size(&s, &o).unwrap();
        let sentinel = Vertex {
            position: [7.0; 3],
            ..Default::default()
        };
        for (dv, di) in [(1, 0), (0, 1), (size.vertices, 0), (0, size.indices)] {
            let mut v = vec![sentinel; size.vertices - dv.min(size.vertices)];
            let mut i = vec![0xABu32; size.indices - di.min(size.indices)];
            if dv == 0 && di == 0 {
                continue;
            }
            let e = mesh::write_mesh(&s, &o, &mut v, &mut i).unwrap_err();
            assert!(matches!(e, Error::BufferTooSmall { .. }), "{e}");
            assert!(v.iter().all(|x| *x == sentinel));
            assert!(i.iter().all(|&x| x == 0xAB));
        }
        // A larger buffer is fine; only the prefix is written.
        let mut v = vec![sentinel; size.vertices + 3];
        let mut i = vec![0xABu32; size.indices + 3];
        assert_eq!(mesh::write_mesh(&s, &o, &mut v, &mut i).unwrap(), size);
        assert!(v[size.vertices..].iter().all(|x| *x == sentinel));
        assert!(i[size.indices..].iter().all(|&x| x == 0xAB));
    }
}

#[test]
fn meshes_over_65536_vertices_index_with_32_bits() {
    let s = tree('f');
    let m: Mesh = mesh::tubes(&s, &MeshOptions::default()).unwrap();
    assert!(m.vertices.len() > 65_536);
    let max = *m.indices.iter().max().unwrap();
    assert_eq!(max as usize, m.vertices.len() - 1);
    // The last branch's triangles reach the last vertices, not wrapped ones.
    let last: Vec<[u32; 3]> = Triangles::new(&m.indices, m.topology).collect();
    assert!(last.last().unwrap().iter().all(|&i| i >= 65_536));
}

#[test]
fn empty_skeleton_gives_empty_buffers() {
    for topology in Topology::ALL {
        let m = mesh::tubes(&Skeleton::default(), &options(8, topology)).unwrap();
        assert!(m.vertices.is_empty() && m.indices.is_empty());
    }
}

#[test]
fn output_is_deterministic() {
    let s = tree('h');
    let a = mesh::tubes(&s, &MeshOptions::default()).unwrap();
    let b = mesh::tubes(&s, &MeshOptions::default()).unwrap();
    assert_eq!(
        bytemuck::cast_slice::<Vertex, u8>(&a.vertices),
        bytemuck::cast_slice::<Vertex, u8>(&b.vertices)
    );
    assert_eq!(a.indices, b.indices);
}
