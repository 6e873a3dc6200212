//! Profiling helper: the first write a host does, as `cargo bench --bench host` times it:
//! grow the 1996 tree (a, n = 20 by default), then size and write its mesh into buffers
//! touched beforehand, `REPS` times, printing the time of the plan (the size call) and of
//! the write: `cargo run --release --example profile_first_write -- [LETTER] [N] [THREADS]
//! [REPS] [compact]` (`compact`: 20-byte compact vertices instead of the 32-byte ones).
use arbor::mesh::{
    MeshOptions, MeshPlan, Topology, Vertex, VertexCompact, VertexFormat, VertexSlot,
};
use std::time::{Duration, Instant};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let letter = args.get(1).and_then(|s| s.chars().next()).unwrap_or('a');
    let mut p = arbor::models::honda::HondaParams::preset(letter).unwrap();
    p.steps = args.get(2).map_or(20, |s| s.parse().unwrap());
    let threads = args.get(3).map_or(0, |s| s.parse().unwrap());
    let reps: u32 = args.get(4).map_or(5, |s| s.parse().unwrap());
    let compact = args.get(5).is_some_and(|s| s == "compact");
    let mut o = MeshOptions::default();
    if compact {
        o.vertex_format = VertexFormat::Compact;
    }
    o.topology = if letter == 'a' {
        Topology::TriangleList
    } else {
        Topology::TriangleStripRestart
    };
    let s = arbor::models::honda::build(&p).unwrap();
    let size = MeshPlan::new(&s, &o).unwrap().size();
    let one = Vertex {
        position: [1.0; 3],
        normal: [1.0; 3],
        uv: [1.0; 2],
    };
    if compact {
        let v = vec![VertexCompact::encode(&one, 1.0); size.vertices];
        run(&p, &o, threads, v, reps);
    } else {
        run(&p, &o, threads, vec![one; size.vertices], reps);
    }
}

/// Sizes and writes fresh trees of `p` into `v` (and touched indices) on `threads`,
/// `reps` times.
fn run<V: VertexSlot>(
    p: &arbor::models::honda::HondaParams,
    o: &MeshOptions,
    threads: u32,
    mut v: Vec<V>,
    reps: u32,
) {
    let on = || arbor::progress::Run::default().threads(threads);
    let s = arbor::models::honda::build(p).unwrap();
    let size = MeshPlan::new(&s, o).unwrap().size();
    let mut i = vec![std::mem::MaybeUninit::new(0x0101_0101u32); size.indices];
    let (mut plan_t, mut write_t) = (Duration::MAX, Duration::MAX);
    for _ in 0..reps {
        let fresh = arbor::models::honda::build(p).unwrap();
        let t = Instant::now();
        let plan = MeshPlan::new_in(&fresh, o, &on()).unwrap();
        let t1 = t.elapsed();
        let t = Instant::now();
        plan.write_uninit_in(&fresh, &mut v, &mut i, &mut on())
            .unwrap();
        let t2 = t.elapsed();
        plan_t = plan_t.min(t1);
        write_t = write_t.min(t2);
    }
    println!(
        "{} branches, {} vertices, {} indices: plan {plan_t:?}, write {write_t:?} (best of {reps})",
        s.len(),
        size.vertices,
        size.indices
    );
}
