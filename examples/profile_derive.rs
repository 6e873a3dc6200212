//! Profiling helper: derive (and interpret) one shipped grammar ten times.
fn main() {
    let name = std::env::args().nth(1).unwrap_or("honda_g".into());
    let steps: u32 = std::env::args().nth(2).map_or(18, |s| s.parse().unwrap());
    let interpret = std::env::args().nth(3).is_some();
    let text = std::fs::read_to_string(format!("examples/grammars/{name}.l")).unwrap();
    let ls = arbor::lsystem::LSystem::parse(&text).unwrap();
    let o = arbor::lsystem::LsystemOptions::default().steps(Some(steps));
    let s = ls.derive(&o).unwrap();
    let t = std::time::Instant::now();
    let mut n = 0;
    for _ in 0..10 {
        n = if interpret {
            ls.interpret(&s, &o).unwrap().len()
        } else {
            ls.derive(&o).unwrap().len()
        };
    }
    println!("{n} {:?} per call", t.elapsed() / 10);
}
