fn main() {
    let reps: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(200);
    let mut p = arbor::models::honda::HondaParams::preset('a').unwrap();
    p.steps = 10;
    let o = arbor::mesh::MeshOptions::default().radial_segments(8);
    let mut best = f64::MAX;
    let mut tris = 0;
    for _ in 0..reps {
        let t = std::time::Instant::now();
        let s = arbor::models::honda::build(&p).unwrap();
        let m = arbor::mesh::tubes(&s, &o).unwrap();
        tris = m.indices.len() / 3;
        best = best.min(t.elapsed().as_secs_f64());
    }
    println!(
        "{tris} triangles, best {:.1} us, {:.1} M tri/s",
        best * 1e6,
        tris as f64 / best / 1e6
    );
}
