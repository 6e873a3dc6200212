//! The Unity C# binding (`bindings/unity/Arbor.cs`) compiled with Mono's `mcs` and run with
//! `mono` against the shared library cargo built for this test run. Required when `CI` is
//! set; skipped with a note elsewhere if Mono is missing.

mod common;
use common::{have, lib_dir, run};

use std::path::Path;
use std::process::Command;

#[test]
fn unity_binding_runs_under_mono() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lib_dir = lib_dir();
    if !have("mcs") {
        return;
    }
    let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ArborTest.exe");
    run(Command::new("mcs")
        .arg(format!("-out:{}", exe.display()))
        .arg(root.join("bindings/unity/Arbor.cs"))
        .arg(root.join("bindings/unity/tests/ArborTest.cs")));
    let text = run(Command::new("mono")
        .arg(&exe)
        .env("LD_LIBRARY_PATH", &lib_dir));
    assert!(text.contains(" 0 failed"), "{text}");
    println!("{text}");
}
