//! Profiling helper: mesh the 1996 tree a with n = 20 (1,048,575 internodes) ten times.
fn main() {
    let mut p = arbor::models::honda::HondaParams::preset('a').unwrap();
    p.steps = std::env::args().nth(1).map_or(20, |s| s.parse().unwrap());
    let s = arbor::models::honda::build(&p).unwrap();
    let o = arbor::mesh::MeshOptions::default();
    let size = arbor::mesh::mesh_size(&s, &o).unwrap();
    let mut v = vec![arbor::mesh::Vertex::default(); size.vertices];
    let mut i = vec![0u32; size.indices];
    let t = std::time::Instant::now();
    for _ in 0..10 {
        arbor::mesh::write_mesh(&s, &o, &mut v, &mut i).unwrap();
    }
    println!("{:?} per mesh", t.elapsed() / 10);
}
