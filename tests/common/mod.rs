//! Helpers shared by the tests that build and run programs against the library.
#![allow(dead_code)]

pub mod pictures;

use std::path::PathBuf;
use std::process::Command;

/// Runs `cmd`, fails the test with its output unless it succeeds, returns its output.
pub fn run(cmd: &mut Command) -> String {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{cmd:?} failed:\n{text}");
    text
}

/// Where cargo put `libarbor.a` and `libarbor.so` for this test run: `target/<profile>/deps/`
/// beside the test binary. (The copies one level up are refreshed less reliably when
/// builds with different features alternate.)
pub fn lib_dir() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap().to_path_buf();
    if deps.join("libarbor.a").exists() {
        deps
    } else {
        deps.parent().unwrap().to_path_buf()
    }
}

/// Fails the test when `tool` does not run: every suite runs, none is skipped. The
/// message says how to get it (the test command, `tools/test`, installs everything in
/// `tools/deps.txt`).
pub fn require(tool: &str) {
    if Command::new(tool).arg("--version").output().is_err() {
        missing(tool);
    }
}

/// Fails the test: `what` is not installed, with the line that installs it.
pub fn missing(what: &str) -> ! {
    panic!(
        "{what} is not installed, so this suite cannot run. `tools/test` installs everything \
         the tests need, or run: {}",
        install_line()
    );
}

/// The apt-get line for everything in `tools/deps.txt` (what `tools/deps --line` prints).
pub fn install_line() -> String {
    let list = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/deps.txt"),
    )
    .unwrap_or_default();
    let packages: Vec<&str> = list
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| l.split_whitespace().nth(1))
        .collect();
    format!("sudo apt-get install -y {}", packages.join(" "))
}

/// The runnable blocks of a document (relative to the checkout) as `tools/readme-blocks`
/// finds them, in order: `(Some(path), text)` for a file to write, `(None, script)` for a
/// shell block. `out` is a scratch folder.
pub fn runnable_blocks(doc: &str, out: &std::path::Path) -> Vec<(Option<String>, String)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let _ = std::fs::remove_dir_all(out);
    run(Command::new("bash")
        .arg(root.join("tools/readme-blocks"))
        .arg(root.join(doc))
        .arg(out));
    let mut files: Vec<PathBuf> = std::fs::read_dir(out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            if p.extension().is_some_and(|x| x == "file") {
                let (path, body) = text.split_once('\n').unwrap();
                (Some(path.to_string()), body.to_string())
            } else {
                (None, text)
            }
        })
        .collect()
}
