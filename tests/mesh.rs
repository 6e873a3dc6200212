//! Mesh invariants on every preset and shipped grammar, every topology and the option
//! combinations, plus the properties of each option.

use arbor::Error;
use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::mesh::{
    self, Joints, Mesh, MeshOptions, RESTART_INDEX, Tip, Topology, Triangles, UpAxis, Vertex,
    Winding,
};
use arbor::models::honda::{self, HondaParams, PRESET_NAMES};
use arbor::skeleton::{Branch, NO_PARENT, Skeleton};
use glam::Vec3;

fn tree(name: char) -> Skeleton {
    honda::build(&HondaParams::preset(name).unwrap()).unwrap()
}

fn all_skeletons() -> Vec<(String, Skeleton)> {
    let mut out: Vec<(String, Skeleton)> = PRESET_NAMES
        .iter()
        .map(|&n| (format!("preset {n}"), tree(n)))
        .collect();
    let dir = format!("{}/examples/grammars", env!("CARGO_MANIFEST_DIR"));
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "l"))
        .collect();
    paths.sort();
    for path in paths {
        let ls = LSystem::parse(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let s = ls.skeleton(&LsystemOptions::default()).unwrap();
        out.push((path.file_stem().unwrap().to_string_lossy().into_owned(), s));
    }
    out
}

fn pos(v: &Vertex) -> Vec3 {
    Vec3::from_array(v.position)
}

/// The triangles of `t` as a set: each canonical, then sorted (topologies and windings
/// order their triangles for the vertex cache each in its own way).
fn triangle_set(t: impl Iterator<Item = [u32; 3]>) -> Vec<[u32; 3]> {
    let mut v: Vec<[u32; 3]> = t.map(canonical).collect();
    v.sort_unstable();
    v
}

fn canonical([a, b, c]: [u32; 3]) -> [u32; 3] {
    if a <= b && a <= c {
        [a, b, c]
    } else if b <= a && b <= c {
        [b, c, a]
    } else {
        [c, a, b]
    }
}

/// The option combinations every skeleton is meshed with (topology set per run).
fn combos() -> Vec<(&'static str, MeshOptions)> {
    let d = MeshOptions::default();
    vec![
        ("default", d),
        (
            "separate joints, 3 sides",
            d.joints(Joints::Separate).radial_segments(3),
        ),
        (
            "taper and caps",
            d.smooth_taper(true)
                .base_cap(true)
                .tip(Tip::Cap)
                .radial_segments(5)
                .texture_scale(7.5),
        ),
        (
            "points, clockwise, Z up, scaled",
            d.tip(Tip::Point)
                .winding(Winding::Clockwise)
                .up_axis(UpAxis::Z)
                .scale(2.5)
                .radial_segments(6),
        ),
        (
            "LOD and cull",
            d.radial_segments(12)
                .min_radial_segments(3)
                .cull_radius(0.3)
                .base_cap(true)
                .tip(Tip::Point),
        ),
    ]
}

/// The inverse of the output conventions, to check geometry in the skeleton's frame.
fn to_model(o: &MeshOptions, v: [f32; 3], is_position: bool) -> Vec3 {
    let v = Vec3::from_array(v);
    let v = match o.up_axis {
        UpAxis::Y => v,
        UpAxis::Z => Vec3::new(v.x, v.z, -v.y),
    };
    if is_position { v / o.scale } else { v }
}

fn check(name: &str, s: &Skeleton, label: &str, o: MeshOptions) {
    let list_options = o.topology(Topology::TriangleList);
    let list = mesh::tubes(s, &list_options).unwrap();
    let nv = list.vertices.len() as u32;
    let what = format!("{name} / {label}");

    // Ranges tile both buffers exactly, in branch order.
    assert_eq!(list.ranges.len(), s.len(), "{what}");
    let (mut v, mut i) = (0u32, 0u32);
    for r in &list.ranges {
        assert_eq!((r.first_vertex, r.first_index), (v, i), "{what}");
        v += r.vertex_count;
        i += r.index_count;
    }
    assert_eq!(
        (v as usize, i as usize),
        (list.vertices.len(), list.indices.len()),
        "{what}"
    );

    for (k, vert) in list.vertices.iter().enumerate() {
        let all = vert.position.iter().chain(&vert.normal).chain(&vert.uv);
        assert!(all.clone().all(|x| x.is_finite()), "{what}: vertex {k}");
        let n = Vec3::from_array(vert.normal);
        assert!((n.length() - 1.0).abs() < 1e-4, "{what}: normal {k} {n}");
    }
    // Normals point away from the axis of the branch that owns the vertex.
    for (b, r) in s.branches().iter().zip(&list.ranges) {
        let (a0, a1) = (b.start(), b.end());
        let axis = (a1 - a0).try_normalize().unwrap_or(Vec3::Y);
        for k in r.first_vertex..r.first_vertex + r.vertex_count {
            let vert = &list.vertices[k as usize];
            let p = to_model(&o, vert.position, true);
            let n = to_model(&o, vert.normal, false);
            let rel = p - a0;
            let radial = rel - axis * rel.dot(axis);
            assert!(
                n.dot(radial) >= -1e-3 * radial.length().max(1.0),
                "{what}: vertex {k} normal points into its branch"
            );
        }
    }

    let tris: Vec<[u32; 3]> = list.triangles().collect();
    let clockwise = o.winding == Winding::Clockwise;
    for (k, &[a, b, c]) in tris.iter().enumerate() {
        assert!(
            a < nv && b < nv && c < nv,
            "{what}: triangle {k} out of range"
        );
        assert!(
            a != b && b != c && a != c,
            "{what}: triangle {k} degenerate"
        );
        let (pa, pb, pc) = (
            to_model(&o, list.vertices[a as usize].position, true),
            to_model(&o, list.vertices[b as usize].position, true),
            to_model(&o, list.vertices[c as usize].position, true),
        );
        let face = (pb - pa).cross(pc - pa);
        assert!(face.length() > 0.0, "{what}: triangle {k} has no area");
        let avg: Vec3 = [a, b, c]
            .iter()
            .map(|&i| to_model(&o, list.vertices[i as usize].normal, false))
            .sum();
        let agree = face.normalize().dot(avg.normalize());
        let agree = if clockwise { -agree } else { agree };
        assert!(
            agree > 0.7,
            "{what}: triangle {k} winds the wrong way ({agree})"
        );
    }

    let expected = triangle_set(tris.iter().copied());
    for topology in [
        Topology::TriangleStripRestart,
        Topology::TriangleStripDegenerate,
    ] {
        let strip = mesh::tubes(s, &o.topology(topology)).unwrap();
        assert_eq!(strip.vertices, list.vertices, "{what} {topology:?}");
        for &i in &strip.indices {
            let restart = topology == Topology::TriangleStripRestart && i == RESTART_INDEX;
            assert!(i < nv || restart, "{what} {topology:?}: index {i}");
        }
        let got = triangle_set(strip.triangles());
        assert_eq!(got, expected, "{what} {topology:?}");
        let size = mesh::mesh_size(s, &o.topology(topology)).unwrap();
        assert_eq!(size.indices, strip.indices.len());
        let total: u32 = strip.ranges.iter().map(|r| r.index_count).sum();
        assert_eq!(total as usize, strip.indices.len(), "{what} {topology:?}");
    }
}

#[test]
fn invariants_on_every_preset_grammar_and_option_combination() {
    for (name, s) in all_skeletons() {
        for (label, o) in combos() {
            check(&name, &s, label, o);
        }
    }
}

/// Counts edges used by exactly one triangle, with vertices at the same position welded
/// (the seam vertex is duplicated for its uv, at a bit-identical position).
fn boundary_edges(m: &Mesh) -> usize {
    let mut weld = std::collections::HashMap::new();
    let id: Vec<u32> = m
        .vertices
        .iter()
        .enumerate()
        .map(|(i, v)| *weld.entry(v.position.map(f32::to_bits)).or_insert(i as u32))
        .collect();
    let mut count = std::collections::HashMap::new();
    for t in m.triangles() {
        let [a, b, c] = t.map(|i| id[i as usize]);
        for (x, y) in [(a, b), (b, c), (c, a)] {
            *count.entry((x.min(y), x.max(y))).or_insert(0) += 1;
        }
    }
    count.values().filter(|&&n| n == 1).count()
}

fn chain(k: usize) -> Skeleton {
    let ls = LSystem::parse(&format!(
        "angle increment: 30\nAxiom: !(1){}",
        "F+F&F-F^"
            .repeat(k)
            .chars()
            .take(2 * k - 1)
            .collect::<String>()
    ))
    .unwrap();
    let s = ls.skeleton(&LsystemOptions::default()).unwrap();
    assert_eq!(s.len(), k);
    s
}

#[test]
fn mitred_axes_are_watertight() {
    for k in [1, 2, 5, 9] {
        let s = chain(k);
        for segments in [3, 8, 13] {
            let o = MeshOptions::default().radial_segments(segments);
            let m = mesh::tubes(&s, &o).unwrap();
            assert_eq!(boundary_edges(&m), 2 * segments as usize, "k = {k}");
            assert_eq!(m.vertices.len(), (k + 1) * (segments as usize + 1));
            let separate = mesh::tubes(&s, &o.joints(Joints::Separate)).unwrap();
            assert_eq!(boundary_edges(&separate), 2 * segments as usize * k);
        }
    }
}

fn axis_starts(s: &Skeleton) -> usize {
    let b = s.branches();
    b.iter()
        .filter(|x| x.parent == NO_PARENT || b[x.parent as usize].order != x.order)
        .count()
}

#[test]
fn counts_follow_the_formula() {
    for name in PRESET_NAMES {
        let s = tree(name);
        let n = s.len();
        let axes = axis_starts(&s);
        for segments in [3usize, 8] {
            let ring = segments + 1;
            let o = |topology, tip, base_cap| {
                MeshOptions::default()
                    .radial_segments(segments as u32)
                    .topology(topology)
                    .tip(tip)
                    .base_cap(base_cap)
            };
            let size = mesh::mesh_size(&s, &o(Topology::TriangleList, Tip::Open, false)).unwrap();
            assert_eq!(size.vertices, (n + axes) * ring, "{name}");
            assert_eq!(size.indices, n * 6 * segments);
            let restart =
                mesh::mesh_size(&s, &o(Topology::TriangleStripRestart, Tip::Open, false)).unwrap();
            // A tube starting an axis is two strips: its first quad (4 indices, of which
            // 2 repeat) and the rest, joined by a restart or by two join indices.
            assert_eq!(restart.indices, n * 2 * ring + (n - 1) + 3 * axes);
            let degenerate =
                mesh::mesh_size(&s, &o(Topology::TriangleStripDegenerate, Tip::Open, false))
                    .unwrap();
            assert_eq!(degenerate.indices, n * 2 * ring + 2 * (n - 1) + 4 * axes);
            // Every axis has one tip; the one root gets the base cap.
            let capped = mesh::mesh_size(&s, &o(Topology::TriangleList, Tip::Cap, true)).unwrap();
            assert_eq!(capped.vertices, size.vertices + (axes + 1) * segments);
            assert_eq!(
                capped.indices,
                size.indices + (axes + 1) * 3 * (segments - 2)
            );
            let pointed =
                mesh::mesh_size(&s, &o(Topology::TriangleList, Tip::Point, false)).unwrap();
            assert_eq!(pointed.vertices, size.vertices + axes * segments);
            assert_eq!(pointed.indices, size.indices + axes * 3 * segments);
            // What is written is what was counted.
            let m = mesh::tubes(&s, &o(Topology::TriangleList, Tip::Point, true)).unwrap();
            let sz = mesh::mesh_size(&s, &o(Topology::TriangleList, Tip::Point, true)).unwrap();
            assert_eq!(
                (m.vertices.len(), m.indices.len()),
                (sz.vertices, sz.indices)
            );
        }
    }
}

/// Unit direction from a ring's center to its seam vertex.
fn seam(m: &Mesh, first_vertex: u32, center: Vec3) -> Vec3 {
    (pos(&m.vertices[first_vertex as usize]) - center).normalize()
}

/// Without the turtle's frames (a host's own skeleton), ring frames are carried by
/// parallel transport: a seam turns no more than its branch bends.
#[test]
fn seams_do_not_twist_along_an_axis() {
    for name in PRESET_NAMES {
        let mut parts = tree(name).into_parts();
        parts.ups.clear();
        let s = parts.build().unwrap();
        assert!(!s.has_frames());
        let segments = 8u32;
        let o = MeshOptions::default()
            .joints(Joints::Separate)
            .radial_segments(segments);
        let m = mesh::tubes(&s, &o).unwrap();
        let b = s.branches();
        for (i, child) in b.iter().enumerate() {
            if child.parent == NO_PARENT {
                continue;
            }
            let p = child.parent as usize;
            let parent = &b[p];
            let bend = (parent.end() - parent.start())
                .normalize()
                .angle_between((child.end() - child.start()).normalize());
            let sink = parent.end_radius;
            let dir = (child.end() - child.start()).normalize();
            let child_seam = seam(&m, m.ranges[i].first_vertex, child.start() - dir * sink);
            let parent_seam = seam(&m, m.ranges[p].first_vertex + segments + 1, parent.end());
            let twist = parent_seam.angle_between(child_seam);
            assert!(
                twist <= bend + 1e-3,
                "tree {name} branch {i}: seam turns {twist} for a bend of {bend}"
            );
        }
    }
}

/// With the turtle's frames, every ring a branch starts on its own begins its seam at the
/// turtle's up vector (so `/` and `\` reach the bark); a continuing branch that shares its
/// parent's mitred ring carries that ring's frame instead.
#[test]
fn seams_follow_the_turtle_up_vector() {
    for name in PRESET_NAMES {
        let s = tree(name);
        assert!(s.has_frames());
        let o = MeshOptions::default().joints(Joints::Separate);
        let m = mesh::tubes(&s, &o).unwrap();
        for (i, b) in s.branches().iter().enumerate() {
            let dir = (b.end() - b.start()).normalize();
            let sink = if b.parent == NO_PARENT {
                0.0
            } else {
                s.branches()[b.parent as usize].end_radius
            };
            let up = s.up(i).unwrap();
            let want = (up - dir * up.dot(dir)).normalize();
            let got = seam(&m, m.ranges[i].first_vertex, b.start() - dir * sink);
            assert!(
                got.angle_between(want) < 1e-3,
                "tree {name} branch {i}: seam {got} vs turtle up {want}"
            );
        }
    }
}

#[test]
fn v_is_arc_length_from_the_root() {
    let s = tree('h');
    let o = MeshOptions::default().texture_scale(4.0);
    let m = mesh::tubes(&s, &o).unwrap();
    let b = s.branches();
    let mut arc = vec![0.0f32; b.len()];
    for (i, x) in b.iter().enumerate() {
        let before = if x.parent == NO_PARENT {
            0.0
        } else {
            arc[x.parent as usize]
        };
        arc[i] = before + x.length();
        // The end ring is the last ring the branch owns.
        let r = m.ranges[i];
        let end_ring = r.first_vertex + r.vertex_count - 9;
        for k in end_ring..end_ring + 9 {
            let v = m.vertices[k as usize].uv[1];
            assert!(
                (v - arc[i] / 4.0).abs() < 1e-3 * arc[i].max(1.0),
                "branch {i}: {v}"
            );
        }
    }
}

#[test]
fn smooth_taper_takes_the_radius_of_the_continuation() {
    let s = tree('a');
    let o = MeshOptions::default()
        .smooth_taper(true)
        .joints(Joints::Separate);
    let m = mesh::tubes(&s, &o).unwrap();
    let b = s.branches();
    for (i, x) in b.iter().enumerate() {
        let cont = b
            .iter()
            .position(|c| c.parent == i as u32 && c.order == x.order);
        let want = cont.map_or(x.end_radius, |c| b[c].start_radius);
        let first_end = m.ranges[i].first_vertex + 9;
        let r = (pos(&m.vertices[first_end as usize]) - x.end()).length();
        assert!(
            (r - want).abs() < 1e-3 * want.max(1.0),
            "branch {i}: {r} vs {want}"
        );
    }
}

#[test]
fn lod_levels_shrink_and_cull_whole_subtrees() {
    let s = tree('b');
    let levels: Vec<MeshOptions> = [(16u32, 0.0f32), (8, 0.5), (4, 1.5)]
        .iter()
        .map(|&(segments, cull)| {
            MeshOptions::default()
                .radial_segments(segments)
                .min_radial_segments(3)
                .cull_radius(cull)
        })
        .collect();
    let lods = mesh::mesh_lods(&s, &levels).unwrap();
    assert_eq!(lods.len(), 3);
    for w in lods.windows(2) {
        assert!(w[1].vertex_count < w[0].vertex_count);
        assert!(w[1].triangle_count < w[0].triangle_count);
    }
    let b = s.branches();
    let last = &lods[2].mesh;
    for (i, x) in b.iter().enumerate() {
        let kept = last.ranges[i].vertex_count > 0;
        let thick = x.start_radius.max(x.end_radius) >= 1.5;
        let parent_kept = x.parent == NO_PARENT || last.ranges[x.parent as usize].vertex_count > 0;
        assert_eq!(kept, thick && parent_kept, "branch {i}");
    }
    // The trunk keeps the most sides; the thinnest kept branches the fewest.
    let trunk = lods[0].mesh.ranges[0].vertex_count;
    assert_eq!(trunk, 2 * 17);
    assert!(
        lods[0]
            .mesh
            .ranges
            .iter()
            .any(|r| r.vertex_count > 0 && r.vertex_count <= 2 * 4)
    );
}

#[test]
fn host_conventions_transform_the_same_mesh() {
    let s = tree('g');
    let base = mesh::tubes(&s, &MeshOptions::default()).unwrap();
    let cw = mesh::tubes(&s, &MeshOptions::default().winding(Winding::Clockwise)).unwrap();
    assert_eq!(cw.vertices, base.vertices);
    let flipped = triangle_set(base.triangles().map(|[a, b, c]| [a, c, b]));
    assert_eq!(triangle_set(cw.triangles()), flipped);
    let z = mesh::tubes(&s, &MeshOptions::default().up_axis(UpAxis::Z).scale(0.01)).unwrap();
    for (a, b) in base.vertices.iter().zip(&z.vertices) {
        let [x, y, zz] = a.position;
        let want = [x * 0.01, -zz * 0.01, y * 0.01];
        for (got, want) in b.position.iter().zip(want) {
            assert!((got - want).abs() < 1e-4);
        }
        let want = [a.normal[0], -a.normal[2], a.normal[1]];
        for (got, want) in b.normal.iter().zip(want) {
            assert!((got - want).abs() < 1e-6, "normals rotate with the mesh");
        }
        assert_eq!(b.uv, a.uv);
    }
    assert_eq!(z.indices, base.indices);
}

#[test]
fn lateral_rings_are_sunk_into_the_parent() {
    let s = tree('e');
    let m = mesh::tubes(&s, &MeshOptions::default()).unwrap();
    let b = s.branches();
    for (i, x) in b.iter().enumerate().skip(1) {
        let parent = &b[x.parent as usize];
        if parent.order == x.order {
            continue;
        }
        // The lateral's start ring center lies inside the parent's tube.
        let dir = (x.end() - x.start()).normalize();
        let center = x.start() - dir * parent.end_radius;
        let ring: Vec3 = (0..8)
            .map(|k| pos(&m.vertices[(m.ranges[i].first_vertex + k) as usize]))
            .sum::<Vec3>()
            / 8.0;
        assert!(
            (ring - center).length() < 1e-3 * parent.end_radius.max(1.0),
            "branch {i}"
        );
        let pa = parent.start();
        let pd = (parent.end() - pa).normalize();
        let rel = center - pa;
        let dist = (rel - pd * rel.dot(pd)).length();
        assert!(dist <= parent.end_radius + 1e-3, "branch {i}");
    }
}

#[test]
fn too_small_buffers_are_refused_and_left_untouched() {
    let s = tree('c');
    for topology in Topology::ALL {
        let o = MeshOptions::default()
            .radial_segments(5)
            .topology(topology)
            .tip(Tip::Point);
        let size = mesh::mesh_size(&s, &o).unwrap();
        let sentinel = Vertex {
            position: [7.0; 3],
            ..Default::default()
        };
        for (dv, di) in [(1, 0), (0, 1), (size.vertices, 0), (0, size.indices)] {
            let mut v = vec![sentinel; size.vertices - dv];
            let mut i = vec![0xABu32; size.indices - di];
            let e = mesh::write_mesh(&s, &o, &mut v, &mut i).unwrap_err();
            assert!(matches!(e, Error::BufferTooSmall { .. }), "{e}");
            assert!(v.iter().all(|x| *x == sentinel));
            assert!(i.iter().all(|&x| x == 0xAB));
        }
        let mut v = vec![sentinel; size.vertices + 3];
        let mut i = vec![0xABu32; size.indices + 3];
        assert_eq!(mesh::write_mesh(&s, &o, &mut v, &mut i).unwrap(), size);
        assert!(v[size.vertices..].iter().all(|x| *x == sentinel));
        assert!(i[size.indices..].iter().all(|&x| x == 0xAB));
        let owned = mesh::tubes(&s, &o).unwrap();
        assert_eq!(&v[..size.vertices], &owned.vertices[..]);
        assert_eq!(&i[..size.indices], &owned.indices[..]);
    }
}

#[test]
fn meshes_over_65536_vertices_index_with_32_bits() {
    let s = tree('f');
    let o = MeshOptions::default().radial_segments(16);
    let m = mesh::tubes(&s, &o).unwrap();
    assert!(m.vertices.len() > 65_536);
    let max = *m.indices.iter().max().unwrap();
    assert_eq!(max as usize, m.vertices.len() - 1);
    let last: Vec<[u32; 3]> = Triangles::new(&m.indices, m.topology).collect();
    assert!(last.last().unwrap().iter().all(|&i| i >= 65_536));
}

#[test]
fn empty_skeleton_gives_empty_buffers() {
    for topology in Topology::ALL {
        let o = MeshOptions::default().topology(topology);
        let m = mesh::tubes(&Skeleton::default(), &o).unwrap();
        assert!(m.vertices.is_empty() && m.indices.is_empty());
    }
}

#[test]
fn cone_normals_tilt_toward_the_narrow_end() {
    let s = Skeleton::new(vec![Branch {
        start: [1.0, 2.0, 3.0],
        end: [1.0, 12.0, 3.0],
        start_radius: 2.0,
        end_radius: 1.0,
        parent: NO_PARENT,
        ..Default::default()
    }])
    .unwrap();
    let m = mesh::tubes(&s, &MeshOptions::default()).unwrap();
    let expected_tilt = 1.0 / 101f32.sqrt();
    for v in &m.vertices {
        assert!((v.normal[1] - expected_tilt).abs() < 1e-6, "{:?}", v.normal);
    }
    for (k, v) in m.vertices.iter().enumerate() {
        let p = pos(v) - Vec3::new(1.0, 2.0, 3.0);
        let r = (p.x * p.x + p.z * p.z).sqrt();
        let want = if k < 9 { 2.0 } else { 1.0 };
        assert!((r - want).abs() < 1e-5, "vertex {k}: radius {r}");
    }
}

#[test]
fn output_is_deterministic() {
    let s = tree('h');
    let o = MeshOptions::default().tip(Tip::Point).base_cap(true);
    let a = mesh::tubes(&s, &o).unwrap();
    let b = mesh::tubes(&s, &o).unwrap();
    assert_eq!(
        bytemuck::cast_slice::<Vertex, u8>(&a.vertices),
        bytemuck::cast_slice::<Vertex, u8>(&b.vertices)
    );
    assert_eq!(a.indices, b.indices);
}

/// Every vertex normal is the analytic normal of its tube as drawn, within 0.1°: on a ring
/// of its own, the normal of its branch's cone (from the radius of the ring it starts at,
/// shared or sunk, to its end radius, over the height it is drawn); on a mitred ring,
/// shared by two cones, the mean of the two cones' normals there. The drawn radii and
/// heights are measured from the mesh itself.
#[test]
fn vertex_normals_are_the_normals_of_the_surface_as_drawn() {
    let sides = 8usize;
    let ring = sides + 1;
    let limit = 0.1f32.to_radians();
    let (mut worst, mut checked) = (0.0f32, 0usize);
    for (name, s) in all_skeletons() {
        for (what, o) in [
            ("mitred", MeshOptions::default()),
            (
                "mitred, smooth taper",
                MeshOptions::default().smooth_taper(true),
            ),
            ("separate", MeshOptions::default().joints(Joints::Separate)),
        ] {
            let m = mesh::tubes(&s, &o).unwrap();
            let b = s.branches();
            let v = &m.vertices;
            let dir = |i: usize| (b[i].end() - b[i].start()).normalize();
            // Distance of a point from branch i's axis line.
            let off_axis = |i: usize, p: Vec3| {
                let rel = p - b[i].end();
                (rel - dir(i) * rel.dot(dir(i))).length()
            };
            let (mut start_ring, mut end_ring) = (vec![0usize; b.len()], vec![0usize; b.len()]);
            let mut own_start = vec![false; b.len()];
            let mut shared_by = vec![None; b.len()];
            for (i, r) in m.ranges.iter().enumerate() {
                own_start[i] = r.vertex_count as usize == 2 * ring;
                assert!(
                    own_start[i] || r.vertex_count as usize == ring,
                    "{name}: branch {i}"
                );
                end_ring[i] = r.first_vertex as usize + if own_start[i] { ring } else { 0 };
                if own_start[i] {
                    start_ring[i] = r.first_vertex as usize;
                } else {
                    let p = b[i].parent as usize;
                    start_ring[i] = end_ring[p];
                    shared_by[p] = Some(i);
                }
            }
            // The cone of branch i as drawn: (start radius, end radius, height).
            let cone = |i: usize| {
                let r1 = off_axis(i, pos(&v[end_ring[i]]));
                if own_start[i] {
                    let center: Vec3 =
                        (0..sides).map(|j| pos(&v[start_ring[i] + j])).sum::<Vec3>() / sides as f32;
                    let r0 = (pos(&v[start_ring[i]]) - center).length();
                    (r0, r1, (b[i].end() - center).dot(dir(i)))
                } else {
                    let p = b[i].parent as usize;
                    (off_axis(p, pos(&v[start_ring[i]])), r1, b[i].length())
                }
            };
            // The analytic outward normal of branch i's cone at point x.
            let analytic = |i: usize, x: Vec3| {
                let (r0, r1, h) = cone(i);
                let rel = x - b[i].end();
                let radial = (rel - dir(i) * rel.dot(dir(i))).normalize();
                (radial * h + dir(i) * (r0 - r1)).normalize()
            };
            for i in 0..b.len() {
                let mut rings = vec![end_ring[i]];
                if own_start[i] {
                    rings.push(start_ring[i]);
                }
                for first in rings {
                    for (k, vertex) in v.iter().enumerate().skip(first).take(ring) {
                        let x = pos(vertex);
                        let want = match shared_by[i] {
                            Some(c) if first == end_ring[i] => {
                                (analytic(i, x) + analytic(c, x)).normalize()
                            }
                            _ => analytic(i, x),
                        };
                        let normal = Vec3::from_array(vertex.normal);
                        let angle = normal.angle_between(want);
                        worst = worst.max(angle);
                        checked += 1;
                        assert!(
                            angle < limit,
                            "{name} ({what}): branch {i} vertex {k}: normal {normal} is {}° \
                             from the analytic {want}",
                            angle.to_degrees()
                        );
                    }
                }
            }
        }
    }
    assert!(checked > 100_000, "{checked} vertices checked");
    println!(
        "{checked} vertex normals, worst {}° from the analytic normal",
        worst.to_degrees()
    );
}

/// `mesh::tubes` fills buffers it does not zero first: over memory that held other bytes
/// (freed just before, so the allocator hands it back), every vertex and index equals
/// those of a write into buffers filled with a sentinel, which no slot keeps.
#[test]
fn owned_meshes_are_written_whole_over_reused_memory() {
    let sentinel = Vertex {
        position: [7.0; 3],
        normal: [-3.0; 3],
        uv: [9.0; 2],
    };
    let mut combos = combos();
    combos.push(("sweep", MeshOptions::default().curve_rings(3).tip(Tip::Cap)));
    for name in ['a', 'c', 'g'] {
        let s = tree(name);
        for (label, o) in &combos {
            for topology in Topology::ALL {
                let o = o.topology(topology);
                let size = mesh::mesh_size(&s, &o).unwrap();
                let mut v = vec![sentinel; size.vertices];
                let mut i = vec![0xABAB_ABABu32; size.indices];
                mesh::write_mesh(&s, &o, &mut v, &mut i).unwrap();
                assert!(!v.contains(&sentinel), "{name} {label} {topology:?}");
                assert!(!i.contains(&0xABAB_ABAB), "{name} {label} {topology:?}");
                // Garbage where the owned buffers will likely be allocated.
                drop(std::hint::black_box(vec![0xA5u8; size.vertices * 32]));
                drop(std::hint::black_box(vec![0x5Au8; size.indices * 4]));
                let owned = mesh::tubes(&s, &o).unwrap();
                let same = bytemuck::cast_slice::<Vertex, u8>(&v)
                    == bytemuck::cast_slice::<Vertex, u8>(&owned.vertices);
                assert!(same, "{name} {label} {topology:?}: vertices");
                assert_eq!(i, owned.indices, "{name} {label} {topology:?}: indices");
            }
        }
    }
}
