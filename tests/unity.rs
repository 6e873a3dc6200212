//! The Unity package (`bindings/unity/`): its binding (`Runtime/Arbor.cs`) compiled with
//! Mono's `mcs` and run with `mono` against the shared library cargo built for this test
//! run; its Unity-only helpers and sample compiled with `UNITY_5_3_OR_NEWER` against
//! stand-ins of the UnityEngine types they use, and run; the package's files checked.
//! Required when `CI` is set; skipped with a note elsewhere if Mono is missing.

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
        .arg(root.join("bindings/unity/Runtime/Arbor.cs"))
        .arg(root.join("bindings/unity/Tests~/ArborTest.cs")));
    let text = run(Command::new("mono")
        .arg(&exe)
        .env("LD_LIBRARY_PATH", &lib_dir));
    assert!(text.contains(" 0 failed"), "{text}");
    println!("{text}");
}

#[test]
fn unity_helpers_compile_against_unityengine_and_fill_a_mesh() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lib_dir = lib_dir();
    if !have("mcs") {
        return;
    }
    let u = root.join("bindings/unity");
    let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join("UnityHelpersTest.exe");
    run(Command::new("mcs")
        .arg("-define:UNITY_5_3_OR_NEWER")
        .arg(format!("-out:{}", exe.display()))
        .arg(u.join("Runtime/Arbor.cs"))
        .arg(u.join("Tests~/UnityStubs.cs"))
        .arg(u.join("Tests~/UnityHelpersTest.cs"))
        .arg(u.join("Samples~/GrowATree/GrowATree.cs")));
    let text = run(Command::new("mono")
        .arg(&exe)
        .env("LD_LIBRARY_PATH", &lib_dir));
    assert!(text.contains("unity helpers: 0 failed"), "{text}");
}

/// The package has what Unity's package manager reads: package.json, an assembly
/// definition, a .meta (with a unique GUID) beside every file and folder Unity imports,
/// and plugin import settings per platform.
#[test]
fn the_unity_package_is_complete() {
    let u = Path::new(env!("CARGO_MANIFEST_DIR")).join("bindings/unity");
    let pkg = std::fs::read_to_string(u.join("package.json")).unwrap();
    assert!(
        pkg.contains(&format!("\"version\": \"{}\"", env!("CARGO_PKG_VERSION"))),
        "{pkg}"
    );
    assert!(u.join("Runtime/Arbor.Runtime.asmdef").is_file());
    let mut guids = std::collections::HashSet::new();
    let mut stack = vec![u.join("Runtime")];
    let mut imported = vec![u.join("package.json"), u.join("Runtime")];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "meta") {
                let text = std::fs::read_to_string(&p).unwrap();
                let guid = text
                    .lines()
                    .find_map(|l| l.strip_prefix("guid: "))
                    .unwrap()
                    .to_string();
                assert_eq!(guid.len(), 32, "{}", p.display());
                assert!(guids.insert(guid), "duplicate GUID in {}", p.display());
                continue;
            }
            if p.is_dir() {
                stack.push(p.clone());
            }
            imported.push(p);
        }
    }
    for p in &imported {
        let meta = p.with_file_name(format!("{}.meta", p.file_name().unwrap().to_string_lossy()));
        assert!(meta.is_file(), "{} has no .meta", p.display());
    }
    for plugin in [
        "Linux/x86_64/libarbor.so",
        "Windows/x86_64/arbor.dll",
        "macOS/libarbor.dylib",
    ] {
        let meta =
            std::fs::read_to_string(u.join(format!("Runtime/Plugins/{plugin}.meta"))).unwrap();
        assert!(meta.contains("PluginImporter:"), "{plugin}");
    }
}
