//! Grows the nine trees a–i of the 1996 paper, writes each as an OBJ file and prints a
//! table of branches, vertices, triangles and time per tree.
//!
//! ```text
//! cargo run --release --example trees -- [OUT_DIR] [RADIAL_SEGMENTS]
//! ```
//! OUT_DIR defaults to `out/`, RADIAL_SEGMENTS to 8.

use arbor::export::save_obj;
use arbor::honda::{self, HondaParams, PRESET_NAMES};
use arbor::mesh::{self, MeshOptions};
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
    let options = MeshOptions {
        radial_segments,
        ..Default::default()
    };

    println!(
        "{:<4} {:>9} {:>9} {:>10} {:>10} {:>9} {:>9}  file",
        "tree", "branches", "vertices", "triangles", "build ms", "mesh ms", "obj ms"
    );
    for name in PRESET_NAMES {
        let params = HondaParams::preset(name).expect("every preset name is known");
        let t0 = Instant::now();
        let skeleton = honda::build(&params)?;
        let t1 = Instant::now();
        let mesh = mesh::tubes(&skeleton, &options)?;
        let t2 = Instant::now();
        let path = dir.join(format!("tree_{name}.obj"));
        save_obj(&mesh, &path)?;
        let t3 = Instant::now();
        let ms = |a: Instant, b: Instant| (b - a).as_secs_f64() * 1e3;
        println!(
            "{:<4} {:>9} {:>9} {:>10} {:>10.3} {:>9.3} {:>9.3}  {}",
            name,
            skeleton.len(),
            mesh.vertices.len(),
            mesh.triangles().count(),
            ms(t0, t1),
            ms(t1, t2),
            ms(t2, t3),
            path.display()
        );
    }
    Ok(())
}
