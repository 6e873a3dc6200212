//! The Khronos glTF-Validator (npm `gltf-validator`, which `tools/test` installs into
//! target/gltf-validator, or `ARBOR_GLTF_VALIDATOR` names), run on written files.

use std::path::{Path, PathBuf};
use std::process::Command;

fn validator_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("ARBOR_GLTF_VALIDATOR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("target/gltf-validator"));
    dir.join("node_modules/gltf-validator")
        .is_dir()
        .then_some(dir)
}

/// Fails unless every file passes the validator with 0 errors and 0 warnings; returns its
/// report.
pub fn assert_valid(files: &[PathBuf]) -> String {
    let Some(dir) = validator_dir() else {
        panic!(
            "the Khronos glTF-Validator is not installed in target/gltf-validator: \
             `tools/test` installs it (or `tools/deps test`)"
        );
    };
    let out = Command::new("node")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/validate-gltf.mjs"))
        .args(files)
        .env("NODE_PATH", dir.join("node_modules"))
        .output()
        .expect("node runs");
    let report = String::from_utf8_lossy(&out.stdout).into_owned();
    println!("{report}");
    assert!(
        out.status.success(),
        "validator: {report}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        report.matches("0 errors, 0 warnings").count(),
        files.len(),
        "{report}"
    );
    report
}
