//! OBJ files written by arbor read back with tobj, an independent parser.

use arbor::export::{save_obj, write_obj};
use arbor::mesh::{self, MeshOptions, Topology};
use arbor::models::honda::{self, HondaParams, PRESET_NAMES};

#[test]
fn every_preset_reads_back_with_tobj() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("obj");
    std::fs::create_dir_all(&dir).unwrap();
    for name in PRESET_NAMES {
        let skeleton = honda::build(&HondaParams::preset(name).unwrap()).unwrap();
        let topology = Topology::ALL[(name as usize) % 3];
        let options = MeshOptions::default().radial_segments(5).topology(topology);
        let m = mesh::tubes(&skeleton, &options).unwrap();
        let path = dir.join(format!("tree_{name}.obj"));
        save_obj(&m, &path).unwrap();

        let (models, _) = tobj::load_obj(&path, &tobj::GPU_LOAD_OPTIONS).unwrap();
        assert_eq!(models.len(), 1);
        let obj = &models[0].mesh;
        assert_eq!(obj.positions.len(), m.vertices.len() * 3, "tree {name}");
        assert_eq!(obj.normals.len(), m.vertices.len() * 3);
        assert_eq!(obj.texcoords.len(), m.vertices.len() * 2);
        let triangles: Vec<[u32; 3]> = m.triangles().collect();
        assert_eq!(obj.indices.len(), triangles.len() * 3, "tree {name}");
        // Vertex k of the OBJ (as tobj orders them) has the position, normal and uv of the
        // vertex that the same triangle corner names in arbor's mesh.
        for (corner, (&i, &want)) in obj
            .indices
            .iter()
            .zip(triangles.iter().flatten())
            .enumerate()
        {
            let (i, v) = (i as usize, &m.vertices[want as usize]);
            let p = &obj.positions[3 * i..3 * i + 3];
            let n = &obj.normals[3 * i..3 * i + 3];
            let t = &obj.texcoords[2 * i..2 * i + 2];
            assert_eq!(p, v.position, "tree {name} corner {corner}");
            assert_eq!(n, v.normal, "tree {name} corner {corner}");
            assert_eq!(t, v.uv, "tree {name} corner {corner}");
        }
    }
}

#[test]
fn obj_header_counts_triangles_of_strips() {
    let skeleton = honda::build(&HondaParams::preset('c').unwrap()).unwrap();
    let options = MeshOptions::default()
        .radial_segments(4)
        .topology(Topology::TriangleStripDegenerate);
    let m = mesh::tubes(&skeleton, &options).unwrap();
    let mut text = Vec::new();
    write_obj(&m, &mut text).unwrap();
    let text = String::from_utf8(text).unwrap();
    let faces = text.lines().filter(|l| l.starts_with("f ")).count();
    assert_eq!(faces, 510 * 2 * 4);
    let header = format!("{} vertices, 4080 triangles", m.vertices.len());
    assert!(text.lines().next().unwrap().contains(&header));
}

#[test]
fn bark_and_leaves_read_back_as_two_groups() {
    use arbor::export::save_obj_parts;
    use arbor::mesh::LeafOptions;
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("obj");
    std::fs::create_dir_all(&dir).unwrap();
    let skeleton = honda::build(&HondaParams::preset('g').unwrap()).unwrap();
    for topology in Topology::ALL {
        let options = MeshOptions::default()
            .topology(topology)
            .tip(arbor::mesh::Tip::Point);
        let bark = mesh::tubes(&skeleton, &options).unwrap();
        let leaf_options = LeafOptions::default().tips(true).size(6.0);
        let leaves = mesh::leaf_mesh(&skeleton, &leaf_options, &options).unwrap();
        let path = dir.join(format!("tree_g_{topology:?}.obj"));
        save_obj_parts(&[("bark", &bark), ("leaves", &leaves)], &path).unwrap();
        let (models, _) = tobj::load_obj(&path, &tobj::GPU_LOAD_OPTIONS).unwrap();
        assert_eq!(models.len(), 2);
        for (model, (name, m)) in models.iter().zip([("bark", &bark), ("leaves", &leaves)]) {
            assert_eq!(model.name, name);
            let obj = &model.mesh;
            let triangles: Vec<[u32; 3]> = m.triangles().collect();
            assert_eq!(obj.indices.len(), triangles.len() * 3, "{name}");
            // Every corner of every triangle: the same vertex, the same order.
            for (&i, &want) in obj.indices.iter().zip(triangles.iter().flatten()) {
                let (i, v) = (i as usize, &m.vertices[want as usize]);
                assert_eq!(&obj.positions[3 * i..3 * i + 3], v.position);
                assert_eq!(&obj.normals[3 * i..3 * i + 3], v.normal);
                assert_eq!(&obj.texcoords[2 * i..2 * i + 2], v.uv);
            }
        }
    }
}
