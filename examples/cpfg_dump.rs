//! Writes what arbor derives and draws for one cpfg model, in the form the headless cpfg
//! of `../shared/cpfg-oracle` dumps, for `tools/cpfg-compare`:
//! `cargo run --release --example cpfg_dump -- FILE.l PREFIX [VIEW.v]` writes
//! `PREFIX.str` (a module a line: name, TAB, its parameters joined by commas),
//! `PREFIX.seg` (a branch a line: x0 y0 z0 x1 y1 z1) and `PREFIX.meta` (`status ok`, or
//! `status error` and the message).
use arbor::lsystem::{LSystem, LsystemOptions};
use std::fmt::Write as _;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(path), Some(prefix)) = (args.get(1), args.get(2)) else {
        eprintln!("usage: cpfg_dump FILE.l PREFIX [VIEW.v]");
        std::process::exit(2);
    };
    let view = args.get(3).map(std::path::PathBuf::from);
    let options = LsystemOptions::default();
    let result = LSystem::from_file(path, view.as_deref()).and_then(|ls| {
        let string = ls.derive(&options)?;
        let mut text = String::with_capacity(string.len() * 16);
        for i in 0..string.len() {
            text.push_str(ls.symbol_name(string.symbol(i)));
            text.push('\t');
            for (k, v) in string.params(i).iter().enumerate() {
                if k > 0 {
                    text.push(',');
                }
                let _ = write!(text, "{v:e}");
            }
            text.push('\n');
        }
        let skeleton = ls.interpret(&string, &options)?;
        let mut segments = String::with_capacity(skeleton.len() * 64);
        for b in skeleton.branches() {
            let [x0, y0, z0] = b.start;
            let [x1, y1, z1] = b.end;
            let _ = writeln!(segments, "{x0:e} {y0:e} {z0:e} {x1:e} {y1:e} {z1:e}");
        }
        Ok((text, segments))
    });
    let write = |ext: &str, text: &str| {
        std::fs::write(format!("{prefix}.{ext}"), text).unwrap_or_else(|e| {
            eprintln!("cpfg_dump: cannot write {prefix}.{ext}: {e}");
            std::process::exit(1);
        })
    };
    match result {
        Ok((text, segments)) => {
            write("str", &text);
            write("seg", &segments);
            write("meta", "status\tok\n");
        }
        Err(e) => {
            write(
                "meta",
                &format!("status\terror\t{}\n", e.to_string().replace('\n', " ")),
            );
            std::process::exit(1);
        }
    }
}
