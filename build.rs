//! Gives the shared library a SONAME on ELF platforms: `libarbor.so.0.2` for 0.2.x (in
//! 0.y releases the ABI may change from one y to the next), so hosts record that name and
//! not a bare `libarbor.so`. `packaging/install.sh` installs `libarbor.so.0.2.z` with the
//! symlinks `libarbor.so.0.2` and `libarbor.so`.

fn main() {
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    let major = std::env::var("CARGO_PKG_VERSION_MAJOR").unwrap_or_default();
    let minor = std::env::var("CARGO_PKG_VERSION_MINOR").unwrap_or_default();
    if matches!(
        os.as_str(),
        "linux" | "android" | "freebsd" | "netbsd" | "openbsd" | "dragonfly"
    ) {
        let soname = if major == "0" {
            format!("libarbor.so.0.{minor}")
        } else {
            format!("libarbor.so.{major}")
        };
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,{soname}");
        link_soname_in_build_folder(&soname);
    }
    println!("cargo:rerun-if-changed=build.rs");
}

/// A program linked against `target/<profile>/libarbor.so` records the SONAME and looks
/// for that name when it starts, so the build folder gets `libarbor.so.0.<minor>` as a
/// link to `libarbor.so` (dangling until the library is linked, a moment later). Cargo's
/// output folder is three levels above this script's OUT_DIR
/// (`target/<profile>/build/arbor-<hash>/out`).
fn link_soname_in_build_folder(soname: &str) {
    let Some(out) = std::env::var_os("OUT_DIR") else {
        return;
    };
    let Some(folder) = std::path::Path::new(&out).ancestors().nth(3) else {
        return;
    };
    let link = folder.join(soname);
    if std::fs::read_link(&link).is_ok_and(|to| to == std::path::Path::new("libarbor.so")) {
        return;
    }
    let _ = std::fs::remove_file(&link);
    #[cfg(unix)]
    if let Err(e) = std::os::unix::fs::symlink("libarbor.so", &link) {
        println!("cargo:warning=cannot link {}: {e}", link.display());
    }
}
