//! Helpers shared by the tests that build and run programs against the library.
#![allow(dead_code)]

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

/// Whether `tool` runs; a missing tool fails the test when `CI` is set and is skipped
/// with a note otherwise.
pub fn have(tool: &str) -> bool {
    let found = Command::new(tool).arg("--version").output().is_ok();
    if !found {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI is set but {tool} is not installed"
        );
        eprintln!("note: {tool} not installed; skipped");
    }
    found
}
