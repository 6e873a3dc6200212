//! The committed `include/arbor.h` must be exactly what cbindgen generates from `src/ffi`.
//! Run with `ARBOR_BLESS_HEADER=1` to rewrite it after changing the C ABI.

use std::path::Path;

#[test]
fn committed_header_matches_cbindgen() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(root.join("cbindgen.toml")).unwrap();
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_crate(root)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header")
        .write(&mut generated);
    let generated = String::from_utf8(generated).unwrap();
    let path = root.join("include/arbor.h");
    if std::env::var_os("ARBOR_BLESS_HEADER").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "include/arbor.h is stale: run `ARBOR_BLESS_HEADER=1 cargo test --test header` \
         and commit the result"
    );
}

/// The header is ASCII: a compiler reading it in a legacy code page (MSVC without
/// `/utf-8`) sees exactly what arbor wrote. Its text comes from the Rust docs of the types
/// it declares, so those docs keep to ASCII too.
#[test]
fn the_header_is_ascii() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(root.join("include/arbor.h")).unwrap();
    let bad: Vec<String> = header
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.is_ascii())
        .map(|(i, l)| format!("{}: {l}", i + 1))
        .collect();
    assert!(
        bad.is_empty(),
        "non-ASCII lines in include/arbor.h:\n{}",
        bad.join("\n")
    );
}
