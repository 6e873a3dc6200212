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
    }
    println!("cargo:rerun-if-changed=build.rs");
}
