//! Engine presets: Unity and Unreal are left-handed, so arbor converts into them by a
//! mirror, as their importers do; a rotation (the old `up_axis = Z` recipe) would show
//! every tree mirrored there. A chirality measure that a mirror flips tells them apart:
//! the signed volume of consecutive branch directions along tree g's axes, read from the
//! mesh each preset writes.

use arbor::export;
use arbor::forest::{Item, Placed, Source};
use arbor::mesh::{self, Axes, LeafOptions, Mesh, MeshOptions, UpAxis, Winding};
use arbor::models::honda::{self, HondaParams};
use arbor::scene::Scene;
use arbor::skeleton::{NO_PARENT, Skeleton};
use glam::{Mat3, Quat, Vec3};

/// The mean of each branch's vertices in `m` (a point of the branch's tube that every
/// linear map of the output carries along).
fn centroids(m: &Mesh) -> Vec<Option<Vec3>> {
    m.ranges
        .iter()
        .map(|r| {
            let vs =
                &m.vertices[r.first_vertex as usize..(r.first_vertex + r.vertex_count) as usize];
            (!vs.is_empty())
                .then(|| vs.iter().map(|v| Vec3::from(v.position)).sum::<Vec3>() / vs.len() as f32)
        })
        .collect()
}

/// Σ det(d_gp, d_p, d_i) / Σ |det(...)| over every branch i with two generations above
/// it, where d_x is the step from x's parent's centroid to x's: +1 a consistently
/// right-handed spiral, −1 its mirror image, near 0 no handedness.
fn chirality(s: &Skeleton, m: &Mesh) -> f64 {
    let c = centroids(m);
    let parent = |i: usize| {
        let p = s.branches()[i].parent;
        (p != NO_PARENT).then_some(p as usize)
    };
    let step = |i: usize| Some((c[i]? - c[parent(i)?]?).as_dvec3());
    let (mut signed, mut total) = (0.0f64, 0.0f64);
    for i in 0..s.len() {
        let Some(p) = parent(i) else { continue };
        let (Some(di), Some(dp)) = (step(i), step(p)) else {
            continue;
        };
        let Some(dg) = parent(p).and_then(step) else {
            continue;
        };
        let v = dg.dot(dp.cross(di));
        signed += v;
        total += v.abs();
    }
    signed / total
}

fn tree(name: char) -> Skeleton {
    honda::build(&HondaParams::preset(name).unwrap()).unwrap()
}

fn with(axes: Axes) -> MeshOptions {
    MeshOptions::default().axes(axes)
}

#[test]
fn presets_mirror_so_trees_keep_their_handedness() {
    let rotated = MeshOptions::default().up_axis(UpAxis::Z);
    for name in ['g', 'h', 'i'] {
        let s = tree(name);
        let y_up = chirality(&s, &mesh::tubes(&s, &MeshOptions::default()).unwrap());
        let z_rot = chirality(&s, &mesh::tubes(&s, &rotated).unwrap());
        let unity = chirality(&s, &mesh::tubes(&s, &with(Axes::Unity)).unwrap());
        let unreal = chirality(&s, &mesh::tubes(&s, &with(Axes::Unreal)).unwrap());
        println!(
            "tree {name}: chirality Y up {y_up:+.4}, Z up by rotation {z_rot:+.4}, \
             Unity {unity:+.4}, Unreal {unreal:+.4}"
        );
        assert!(y_up.abs() > 0.05, "tree {name} has a handedness: {y_up}");
        // The numbers of a left-handed space, read as the engine reads them, show the
        // same tree exactly when their chirality is the opposite of the right-handed one.
        assert!(
            (unity + y_up).abs() < 1e-4,
            "Unity mirrors: {unity} vs {y_up}"
        );
        assert!(
            (unreal + y_up).abs() < 1e-4,
            "Unreal mirrors: {unreal} vs {y_up}"
        );
        // A rotation keeps the numbers' chirality: in a left-handed engine the tree
        // would spiral the wrong way.
        assert!((z_rot - y_up).abs() < 1e-4, "a rotation keeps it: {z_rot}");
    }
    // The measure sees a tree's own handedness: tree g with its divergence angles turned
    // the other way spirals the other way (not an exact mirror image: the model's
    // horizontal reference does not turn with them).
    let g = HondaParams::preset('g').unwrap();
    let mut mirrored = g;
    mirrored.phi1 = -g.phi1;
    mirrored.phi2 = -g.phi2;
    let (a, b) = (tree('g'), honda::build(&mirrored).unwrap());
    let ca = chirality(&a, &mesh::tubes(&a, &MeshOptions::default()).unwrap());
    let cb = chirality(&b, &mesh::tubes(&b, &MeshOptions::default()).unwrap());
    println!("tree g {ca:+.4}, with divergence angles negated {cb:+.4}");
    assert!(ca * cb < 0.0 && ca.abs() > 0.1 && cb.abs() > 0.1);
}

#[test]
fn presets_map_axes_units_and_winding_as_the_engines_do() {
    let s = tree('g');
    // Swept branches (rings along the curve) map the same way.
    let swept = |axes| (with(axes)).curve_rings(2);
    let (b2, u2) = (
        mesh::tubes(&s, &swept(Axes::Arbor)).unwrap(),
        mesh::tubes(&s, &swept(Axes::Unity)).unwrap(),
    );
    for (b, u) in b2.vertices.iter().zip(&u2.vertices) {
        assert_eq!(u.position, [-b.position[0], b.position[1], b.position[2]]);
        assert_eq!(u.normal, [-b.normal[0], b.normal[1], b.normal[2]]);
    }
    let base = mesh::tubes(&s, &MeshOptions::default()).unwrap();
    let unity = mesh::tubes(&s, &with(Axes::Unity)).unwrap();
    let unreal = mesh::tubes(&s, &with(Axes::Unreal)).unwrap();
    assert_eq!(base.vertices.len(), unity.vertices.len());
    assert_eq!(base.vertices.len(), unreal.vertices.len());
    for ((b, u), r) in base
        .vertices
        .iter()
        .zip(&unity.vertices)
        .zip(&unreal.vertices)
    {
        let [x, y, z] = b.position;
        // Unity: x mirrored, exactly.
        assert_eq!(u.position, [-x, y, z]);
        assert_eq!(u.normal, [-b.normal[0], b.normal[1], b.normal[2]]);
        assert_eq!(u.uv, b.uv);
        // Unreal: centimetres, Y and Z swapped.
        let want = Vec3::new(x, z, y) * 100.0;
        let got = Vec3::from(r.position);
        assert!(
            (got - want).length() <= 1e-4 * want.length().max(1.0),
            "{got} vs {want}"
        );
        let n = Vec3::new(b.normal[0], b.normal[2], b.normal[1]);
        assert!(
            (Vec3::from(r.normal) - n).length() < 1e-6,
            "{:?} vs {n}",
            r.normal
        );
    }
    // Winding by the cross product of each triangle's edges against its vertices'
    // normals: out for arbor and Unity (Unity's RecalculateNormals agrees), in for
    // Unreal (Epic's clockwise convention), in for arbor asked for clockwise.
    let facing = |m: &Mesh| {
        let (mut out, mut all) = (0usize, 0usize);
        for [a, b, c] in m.triangles() {
            let p = |i: u32| Vec3::from(m.vertices[i as usize].position);
            let n: Vec3 = [a, b, c]
                .iter()
                .map(|&i| Vec3::from(m.vertices[i as usize].normal))
                .sum();
            let cross = (p(b) - p(a)).cross(p(c) - p(a));
            if cross.length() > 1e-6 * (p(b) - p(a)).length_squared().max(1e-12) {
                all += 1;
                out += usize::from(cross.dot(n) > 0.0);
            }
        }
        out as f64 / all as f64
    };
    let cw = mesh::tubes(&s, &MeshOptions::default().winding(Winding::Clockwise)).unwrap();
    let f = [facing(&base), facing(&unity), facing(&unreal), facing(&cw)];
    println!(
        "triangles whose edges' cross product points out: arbor {:.4}, Unity {:.4}, Unreal {:.4}, arbor clockwise {:.4}",
        f[0], f[1], f[2], f[3]
    );
    assert!(f[0] > 0.99 && f[1] > 0.99, "{f:?}");
    assert!(f[2] < 0.01 && f[3] < 0.01, "{f:?}");
}

#[test]
fn leaf_instances_land_where_the_baked_leaves_do_in_every_preset() {
    let s = tree('g');
    let leaves = LeafOptions::default().tips(true);
    for (axes, mirror, units) in [
        (Axes::Arbor, Mat3::IDENTITY, 1.0),
        (
            Axes::Unity,
            Mat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0)),
            1.0,
        ),
        (
            Axes::Unreal,
            Mat3::from_cols(Vec3::X, Vec3::Z, Vec3::Y),
            100.0,
        ),
    ] {
        let o = with(axes);
        let baked = mesh::leaf_mesh(&s, &leaves, &o).unwrap();
        let inst = mesh::leaf_instances(&s, &leaves, &o).unwrap();
        let prefab = mesh::LeafPrefab::quad();
        assert!(!inst.is_empty());
        assert_eq!(baked.vertices.len(), inst.len() * prefab.vertices.len());
        let mut worst = 0.0f32;
        for (l, chunk) in inst
            .iter()
            .zip(baked.vertices.chunks(prefab.vertices.len()))
        {
            let q = Quat::from_array(l.rotation);
            assert!((q.length() - 1.0).abs() < 1e-5, "{axes:?}: a rotation");
            for (v, b) in prefab.vertices.iter().zip(chunk) {
                // The engine imports the prefab mirrored as it imports everything.
                let p = mirror * Vec3::from(v.position);
                let at = Vec3::from(l.position) + q * (p * l.scale);
                worst = worst.max((at - Vec3::from(b.position)).length() / units);
            }
        }
        println!(
            "{axes:?}: {} leaf instances, worst gap to the baked leaves {worst:e} model units",
            inst.len()
        );
        assert!(worst < 1e-3, "{axes:?}: {worst}");
    }
}

#[test]
fn presets_refuse_conflicting_options_by_name() {
    let s = tree('a');
    let leaves = LeafOptions::default();
    let placed = [Placed {
        item: Item {
            source: Source::Honda(HondaParams::preset('a').unwrap()),
            seed: 0,
        },
        position: [0.0; 3],
        rotation: 0.0,
        scale: 1.0,
    }];
    // What every glTF writer (tree, baked and instanced leaves, merged forest, forest nodes;
    // binary and JSON) says of a set of options: its errors, or None where it writes.
    let gltf = |o: &MeshOptions| -> Vec<Option<String>> {
        [true, false]
            .into_iter()
            .flat_map(|binary| {
                [
                    export::gltf_bytes(&s, o, None, binary).err(),
                    export::gltf_bytes(&s, o, Some(&leaves), binary).err(),
                    export::gltf_bytes_instanced(&s, o, &leaves, binary).err(),
                    forest_bytes(Scene::forest, &placed, o, binary).err(),
                    forest_bytes(Scene::forest_nodes, &placed, o, binary).err(),
                ]
            })
            .map(|e| e.map(|e| e.to_string()))
            .collect()
    };
    // A preset with its own up axis or winding contradicts itself: glTF, which writes its
    // own conventions, refuses it too, with the same error.
    for (o, field) in [
        (
            MeshOptions::default()
                .axes(Axes::Unity)
                .winding(Winding::Clockwise),
            "winding",
        ),
        (
            MeshOptions::default().axes(Axes::Unreal).up_axis(UpAxis::Z),
            "up_axis",
        ),
    ] {
        let e = mesh::tubes(&s, &o).unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
        for (k, g) in gltf(&o).into_iter().enumerate() {
            assert_eq!(g.as_deref(), Some(e.as_str()), "glTF writer {k}");
        }
    }
    // A scale that leaves the f32 range only in the preset's units (Unreal's centimetres):
    // the mesh writer refuses it by name; glTF, written in arbor's units, writes.
    // 1e37 leaves the range in either space (as a number in Unreal's units, and at the
    // tree's 364 units in arbor's); 1e34 only at the tree's extent in Unreal's.
    for (scale, gltf_writes) in [(1e37, false), (1e34, true)] {
        let o = MeshOptions::default().axes(Axes::Unreal).scale(scale);
        let e = mesh::tubes(&s, &o).unwrap_err().to_string();
        assert!(e.contains("scale"), "{e}");
        let g = gltf(&o);
        if gltf_writes {
            assert!(g.iter().all(Option::is_none), "{g:?}");
        } else {
            assert!(
                g.iter()
                    .all(|e| e.as_ref().is_some_and(|e| e.contains("`scale`"))),
                "{g:?}"
            );
        }
    }
}

/// A forest's glTF file as a host makes it: the scene in glTF's conventions, then its bytes.
fn forest_bytes(
    scene: fn(&[arbor::forest::Placed<'_>], &MeshOptions) -> arbor::Result<Scene>,
    placed: &[arbor::forest::Placed<'_>],
    o: &MeshOptions,
    binary: bool,
) -> arbor::Result<Vec<u8>> {
    let s = scene(placed, &export::gltf_mesh_options(o)?)?;
    export::gltf_scene_bytes(&s, o, binary)
}
