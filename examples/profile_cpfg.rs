//! Profiling helper: reads, derives and interprets one cpfg model `REPS` times and prints
//! the best time of each stage: `cargo run --release --example profile_cpfg -- FILE.l
//! [VIEW.v] [REPS]`.
use arbor::lsystem::{LSystem, LsystemOptions};
use std::time::{Duration, Instant};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: profile_cpfg FILE.l [VIEW.v] [REPS]");
        std::process::exit(2);
    };
    let view = args
        .get(2)
        .filter(|a| a.ends_with(".v"))
        .map(std::path::PathBuf::from);
    let reps: u32 = args.last().and_then(|a| a.parse().ok()).unwrap_or(20);
    let options = LsystemOptions::default();
    let mut best = [Duration::MAX; 3];
    let (mut modules, mut branches) = (0, 0);
    for _ in 0..reps {
        let t = Instant::now();
        let ls = LSystem::from_file(path, view.as_deref()).expect("read");
        let read = t.elapsed();
        let t = Instant::now();
        let s = ls.derive(&options).expect("derive");
        let derive = t.elapsed();
        let t = Instant::now();
        let sk = ls.interpret(&s, &options).expect("interpret");
        let interpret = t.elapsed();
        (modules, branches) = (s.len(), sk.len());
        for (b, d) in best.iter_mut().zip([read, derive, interpret]) {
            *b = (*b).min(d);
        }
    }
    println!(
        "{modules} modules, {branches} branches: read {:?}, derive {:?}, interpret {:?} (best of {reps})",
        best[0], best[1], best[2]
    );
}
