//! Grows the nine trees a–i of the 1996 paper, writes each as an OBJ file (bark and
//! leaves as two groups) and prints a table of branches, vertices, triangles per level of
//! detail, leaves, and milliseconds per tree.
//!
//! ```text
//! cargo run --release --example trees -- [OUT_DIR] [RADIAL_SEGMENTS]
//! ```
//! OUT_DIR defaults to `out/`, RADIAL_SEGMENTS to 8.

use arbor::export::save_obj_parts;
use arbor::mesh::{self, LeafOptions, MeshOptions, Tip};
use arbor::models::honda::{self, HondaParams, PRESET_NAMES};
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let dir = PathBuf::from(args.next().unwrap_or_else(|| "out".to_string()));
    let radial_segments = match args.next() {
        Some(s) => s.parse()?,
        None => 8,
    };
    std::fs::create_dir_all(&dir)?;
    let options = MeshOptions::default()
        .radial_segments(radial_segments)
        .smooth_taper(true)
        .tip(Tip::Point)
        .base_cap(true)
        .texture_scale(20.0);
    // Two coarser levels: fewer sides on thin branches, then thin twigs dropped.
    let levels = [
        options,
        options.min_radial_segments(3),
        options
            .radial_segments((radial_segments / 2).max(3))
            .min_radial_segments(3)
            .cull_radius(0.6),
    ];
    let leaves = LeafOptions::default().tips(true).size(8.0);

    println!(
        "{:<4} {:>8} {:>17} {:>17} {:>17} {:>6} {:>8} {:>8}  file",
        "tree",
        "branches",
        "LOD0 verts/tris",
        "LOD1 verts/tris",
        "LOD2 verts/tris",
        "leaves",
        "grow ms",
        "mesh ms"
    );
    for name in PRESET_NAMES {
        let params = HondaParams::preset(name).expect("every preset name is known");
        let t0 = Instant::now();
        let skeleton = honda::build(&params)?;
        let t1 = Instant::now();
        let lods = mesh::mesh_lods(&skeleton, &levels)?;
        let leaf_mesh = mesh::leaf_mesh(&skeleton, &leaves, &options)?;
        let t2 = Instant::now();
        let path = dir.join(format!("tree_{name}.obj"));
        save_obj_parts(&[("bark", &lods[0].mesh), ("leaves", &leaf_mesh)], &path)?;
        let ms = |a: Instant, b: Instant| (b - a).as_secs_f64() * 1e3;
        let level = |k: usize| format!("{}/{}", lods[k].vertex_count, lods[k].triangle_count);
        println!(
            "{:<4} {:>8} {:>17} {:>17} {:>17} {:>6} {:>8.3} {:>8.3}  {}",
            name,
            skeleton.len(),
            level(0),
            level(1),
            level(2),
            leaf_mesh.vertices.len() / 4,
            ms(t0, t1),
            ms(t1, t2),
            path.display()
        );
    }
    Ok(())
}
