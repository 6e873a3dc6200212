fn main() {
    let mut p = arbor::models::honda::HondaParams::preset('a').unwrap();
    p.steps = 20;
    let s = arbor::models::honda::build(&p).unwrap();
    let o = arbor::mesh::MeshOptions::default().threads(1);
    let mut best = (f64::MAX, f64::MAX);
    let size = arbor::mesh::mesh_size(&s, &o).unwrap();
    let mut v = vec![
        arbor::mesh::Vertex {
            position: [1.0; 3],
            normal: [1.0; 3],
            uv: [1.0; 2]
        };
        size.vertices
    ];
    let mut i = vec![1u32; size.indices];
    for _ in 0..8 {
        let t = std::time::Instant::now();
        let plan = arbor::mesh::MeshPlan::new(&s, &o).unwrap();
        let a = t.elapsed().as_secs_f64();
        let t = std::time::Instant::now();
        plan.write(&s, &mut v, &mut i).unwrap();
        let b = t.elapsed().as_secs_f64();
        best = (best.0.min(a), best.1.min(b));
    }
    println!("plan {:.1} ms, write {:.1} ms", best.0 * 1e3, best.1 * 1e3);
}
