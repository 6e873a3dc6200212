//! Build + mesh from parameters (the peers' mesh rows: the 1996 tree built from its
//! preset, then `mesh::tubes` as a triangle list), timed as the best of 7 rounds of at
//! least 0.3 s each. Compiled twice by run.sh: against a baseline commit and against this
//! checkout, with `build_mesh` from the adapter that fits each one's API.

include!("adapter.rs");

fn time<F: FnMut() -> usize>(mut f: F) -> f64 {
    let mut best = f64::MAX;
    for _ in 0..7 {
        let t0 = std::time::Instant::now();
        let mut k = 0;
        while t0.elapsed().as_secs_f64() < 0.3 {
            std::hint::black_box(f());
            k += 1;
        }
        best = best.min(t0.elapsed().as_secs_f64() / k as f64);
    }
    best
}

fn main() {
    // `once`: each tree built and meshed once, for an instruction count (callgrind).
    if std::env::args().nth(1).as_deref() == Some("once") {
        for (name, steps) in [('a', 14u32), ('f', 15)] {
            println!("{name}{steps} {}", build_mesh(name, steps, 8));
        }
        return;
    }
    for (name, steps, sides) in [('a', 10u32, 8u32), ('a', 14, 8), ('f', 15, 8)] {
        let mut tris = 0;
        let t = time(|| {
            tris = build_mesh(name, steps, sides);
            tris
        });
        println!("{name}{steps} {sides} {tris} {:.2}", tris as f64 / t / 1e6);
    }
}
