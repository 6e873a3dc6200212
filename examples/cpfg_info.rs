//! Reads a cpfg file as cpfg does and prints what it grows: `cargo run --example cpfg_info
//! -- FILE.l [STEPS]` (the derived string's first 600 characters, counts, the log).
use arbor::lsystem::{LSystem, LsystemOptions};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: cpfg_info FILE.l [STEPS]");
        std::process::exit(2);
    };
    let options = LsystemOptions::default().steps(args.get(2).and_then(|s| s.parse().ok()));
    let result = LSystem::from_file(path, None).and_then(|ls| {
        let s = ls.derive(&options)?;
        let text = ls.format(&s);
        let head: String = text.chars().take(600).collect();
        println!("{} modules: {head}", s.len());
        let sk = ls.interpret(&s, &options)?;
        println!(
            "{} branches, {} organs, {} leaf sites, {} polygons; angle {}",
            sk.len(),
            sk.organs().len(),
            sk.leaves().len(),
            sk.polygons().len(),
            ls.view().angle_increment
        );
        for w in ls.warnings() {
            println!("warning: {w}");
        }
        print!("{}", s.log());
        Ok(())
    });
    if let Err(e) = result {
        eprintln!("{path}: {e}");
        std::process::exit(1);
    }
}
