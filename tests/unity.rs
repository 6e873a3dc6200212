//! The Unity C# binding (`bindings/unity/Arbor.cs`) compiled with Mono's `mcs` and run with
//! `mono` against the shared library cargo built for this test run. Required when `CI` is
//! set; skipped with a note elsewhere if Mono is missing.

use std::path::Path;
use std::process::Command;

#[test]
fn unity_binding_runs_under_mono() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lib_dir = std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .to_path_buf();
    if Command::new("mcs").arg("--version").output().is_err() {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI is set but mono-mcs is not installed"
        );
        eprintln!("note: mcs not installed; the Unity binding test is skipped");
        return;
    }
    let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ArborTest.exe");
    let out = Command::new("mcs")
        .arg(format!("-out:{}", exe.display()))
        .arg(root.join("bindings/unity/Arbor.cs"))
        .arg(root.join("bindings/unity/tests/ArborTest.cs"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "mcs failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let out = Command::new("mono")
        .arg(&exe)
        .env("LD_LIBRARY_PATH", &lib_dir)
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{text}");
    assert!(text.contains(" 0 failed"), "{text}");
    println!("{text}");
}
