//! `packaging/install.sh` into a scratch prefix, then a C host built the usual ways:
//! `pkg-config --cflags --libs arbor`, and CMake's `find_package(arbor)` with the
//! `arbor::arbor` and `arbor::arbor_static` targets. pkg-config and cmake are required when
//! `CI` is set.

mod common;
use common::{lib_dir, require, run};

use std::path::{Path, PathBuf};
use std::process::Command;

const APP: &str = r#"#include <arbor.h>
#include <stdio.h>
#include <string.h>
int main(void) {
  ArborHondaParams p;
  ArborTree *t = NULL;
  if (arbor_honda_preset('d', &p) || arbor_tree_from_honda(&p, &t)) return 1;
  size_t n = arbor_tree_branch_count(t);
  arbor_tree_free(t);
  printf("%s %zu\n", arbor_version(), n);
  return n == 1023 && strcmp(arbor_version(), ARBOR_VERSION_STRING_FOR_TEST) == 0 ? 0 : 2;
}
"#;

/// Installs into a scratch prefix of its own (tests run in parallel).
fn setup_in(name: &str) -> (PathBuf, PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lib_dir = lib_dir();
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&work);
    let prefix = work.join("prefix");
    run(Command::new("sh")
        .arg(root.join("packaging/install.sh"))
        .arg(&prefix)
        .arg(&lib_dir));
    let app = APP.replace(
        "ARBOR_VERSION_STRING_FOR_TEST",
        &format!("\"{}\"", env!("CARGO_PKG_VERSION")),
    );
    std::fs::write(work.join("app.c"), app).unwrap();
    (work, prefix)
}

#[test]
fn pkg_config_and_cmake_find_the_installed_library() {
    let (work, prefix) = setup_in("packaging");
    let pc = std::fs::read_to_string(prefix.join("lib/pkgconfig/arbor.pc")).unwrap();
    assert!(pc.contains(&format!("Version: {}", env!("CARGO_PKG_VERSION"))));
    let supp = std::fs::read_to_string(prefix.join("share/arbor/valgrind.supp")).unwrap();
    assert!(supp.contains("Memcheck:Leak"), "{supp}");
    require("pkg-config");
    let flags = run(Command::new("pkg-config")
        .args(["--cflags", "--libs", "arbor"])
        .env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig")));
    let exe = work.join("app_pkgconfig");
    run(Command::new("cc")
        .arg(work.join("app.c"))
        .args(flags.split_whitespace())
        .arg("-o")
        .arg(&exe));
    let out = run(Command::new(&exe).env("LD_LIBRARY_PATH", prefix.join("lib")));
    assert!(out.contains(" 1023"), "{out}");
    require("cmake");
    let project = work.join("cmake");
    std::fs::create_dir_all(&project).unwrap();
    std::fs::copy(work.join("app.c"), project.join("app.c")).unwrap();
    std::fs::write(
        project.join("CMakeLists.txt"),
        "cmake_minimum_required(VERSION 3.16)\nproject(app C)\n\
         find_package(arbor 0.2 CONFIG REQUIRED)\n\
         add_executable(app_shared app.c)\ntarget_link_libraries(app_shared PRIVATE arbor::arbor)\n\
         add_executable(app_static app.c)\ntarget_link_libraries(app_static PRIVATE arbor::arbor_static)\n",
    )
    .unwrap();
    let build = cmake_build(&project, &prefix);
    for exe in ["app_shared", "app_static"] {
        let out = run(&mut Command::new(build.join(exe)));
        assert!(out.contains(" 1023"), "{exe}: {out}");
    }
}

/// The shared library records its SONAME (libarbor.so.0.<minor> for 0.x), and the install
/// has the versioned file with its two links.
#[test]
fn the_shared_library_has_a_soname_and_versioned_links() {
    let (_, prefix) = setup_in("packaging_soname");
    let (major, minor) = (
        env!("CARGO_PKG_VERSION_MAJOR"),
        env!("CARGO_PKG_VERSION_MINOR"),
    );
    let soname = if major == "0" {
        format!("libarbor.so.0.{minor}")
    } else {
        format!("libarbor.so.{major}")
    };
    let lib = prefix.join("lib");
    let real = format!("libarbor.so.{}", env!("CARGO_PKG_VERSION"));
    assert!(lib.join(&real).is_file());
    assert_eq!(
        std::fs::read_link(lib.join(&soname)).unwrap(),
        Path::new(&real)
    );
    assert_eq!(
        std::fs::read_link(lib.join("libarbor.so")).unwrap(),
        Path::new(&soname)
    );
    require("readelf");
    let dynamic = run(Command::new("readelf").arg("-d").arg(lib.join(&real)));
    assert!(
        dynamic.contains(&format!("Library soname: [{soname}]")),
        "{dynamic}"
    );
}

/// A C program linked statically with the documented line,
/// `cc app.c $(pkg-config --cflags --libs arbor-static)`: no libarbor at run time.
#[test]
fn a_static_link_with_pkg_config_works() {
    require("pkg-config");
    let (work, prefix) = setup_in("packaging_static");
    let exe = work.join("app_static_pc");
    run(Command::new("sh")
        .arg("-c")
        .arg("cc app.c $(pkg-config --cflags --libs arbor-static) -o app_static_pc")
        .current_dir(&work)
        .env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig")));
    let out = run(Command::new(&exe).env_remove("LD_LIBRARY_PATH"));
    assert!(out.contains(" 1023"), "{out}");
    let dynamic = run(Command::new("readelf").arg("-d").arg(&exe));
    assert!(
        !dynamic.contains("libarbor"),
        "linked statically: {dynamic}"
    );
}

/// A program linked against the build folder's `libarbor.so` (the README's first C
/// command) starts: the build folder has the SONAME's file too. `cargo test` leaves the
/// shared library in `deps/` only, so the test runs `cargo build --lib` itself, into a
/// target folder of its own (the test's own folder is locked while tests run).
#[test]
fn a_program_linked_in_the_build_folder_starts() {
    let (work, _) = setup_in("packaging_build_folder");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("packaging_cargo_build");
    run(Command::new(env!("CARGO"))
        .args([
            "build",
            "--lib",
            "--no-default-features",
            "--offline",
            "--quiet",
        ])
        .arg("--target-dir")
        .arg(&target)
        .current_dir(root));
    // Cargo's output folder (target/<profile>), where the README links from.
    let folder = target.join("debug");
    assert!(folder.join("libarbor.so").is_file(), "{}", folder.display());
    let soname = soname();
    assert_eq!(
        std::fs::read_link(folder.join(&soname)).unwrap(),
        Path::new("libarbor.so"),
        "{}",
        folder.display()
    );
    let exe = work.join("app_build_folder");
    run(Command::new("cc")
        .arg(work.join("app.c"))
        .arg(format!("-I{}", root.join("include").display()))
        .arg(format!("-L{}", folder.display()))
        .arg("-larbor")
        .arg(format!("-Wl,-rpath,{}", folder.display()))
        .arg("-o")
        .arg(&exe));
    let needed = run(Command::new("readelf").arg("-d").arg(&exe));
    assert!(needed.contains(&format!("[{soname}]")), "{needed}");
    let out = run(Command::new(&exe).env_remove("LD_LIBRARY_PATH"));
    assert!(out.contains(" 1023"), "{out}");
}

/// Installed libraries carry no debug info or bitcode: the archive is well under the
/// 36 MB it was with them (12.8 MB once serde, serde_json and base64 came in for glTF's
/// JSON, 14.8 MB with the png crate and its deflate for textures, 16.9 MB with its decoder
/// and inflate for height maps and species maps), and the shared library has no .debug
/// sections.
#[test]
fn installed_libraries_are_lean() {
    let (_, prefix) = setup_in("packaging_lean");
    let lib = prefix.join("lib");
    let archive = std::fs::metadata(lib.join("libarbor.a")).unwrap().len();
    assert!(archive < 18 << 20, "libarbor.a is {archive} bytes");
    let sections = run(Command::new("readelf")
        .arg("-S")
        .arg(lib.join("libarbor.a")));
    assert!(!sections.contains(".llvmbc"), "bitcode left in the archive");
    assert!(
        !sections.contains(".debug_info"),
        "debug info left in the archive"
    );
}

/// A C++14 CMake project that links arbor::arbor and includes arbor.hpp builds: the
/// target asks for C++17 itself.
#[test]
fn cmake_targets_carry_cxx17() {
    require("cmake");
    let (work, prefix) = setup_in("packaging_cxx17");
    let project = work.join("cxx");
    std::fs::create_dir_all(&project).unwrap();
    std::fs::write(
        project.join("app.cpp"),
        "#include <arbor.hpp>\n#include <cstdio>\nint main() { auto t = arbor::Tree::honda('a');\n\
         std::printf(\"%zu\\n\", t.branch_count()); return t.branch_count() == 1023 ? 0 : 1; }\n",
    )
    .unwrap();
    std::fs::write(
        project.join("CMakeLists.txt"),
        "cmake_minimum_required(VERSION 3.16)\nproject(app CXX)\nset(CMAKE_CXX_STANDARD 14)\n\
         find_package(arbor 0.2 CONFIG REQUIRED)\n\
         add_executable(app app.cpp)\ntarget_link_libraries(app PRIVATE arbor::arbor_static)\n",
    )
    .unwrap();
    let build = cmake_build(&project, &prefix);
    let out = run(&mut Command::new(build.join("app")));
    assert!(out.contains("1023"), "{out}");
}

/// Configures and builds the CMake project in `project` against the arbor installed in
/// `prefix`; returns its build folder.
fn cmake_build(project: &Path, prefix: &Path) -> PathBuf {
    let build = project.join("build");
    run(Command::new("cmake")
        .arg("-S")
        .arg(project)
        .arg("-B")
        .arg(&build)
        .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display())));
    run(Command::new("cmake").arg("--build").arg(&build));
    build
}

fn soname() -> String {
    let (major, minor) = (
        env!("CARGO_PKG_VERSION_MAJOR"),
        env!("CARGO_PKG_VERSION_MINOR"),
    );
    if major == "0" {
        format!("libarbor.so.0.{minor}")
    } else {
        format!("libarbor.so.{major}")
    }
}

/// The committed list of the static library's system libraries is what rustc prints for
/// this platform now: a new Rust or dependency that needs another library fails here.
#[test]
fn libs_private_match_rustc_native_static_libs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let committed = std::fs::read_to_string(root.join("packaging/native-static-libs.txt")).unwrap();
    let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("native-static-libs");
    let out = Command::new(env!("CARGO"))
        .current_dir(root)
        .args([
            "rustc",
            "--release",
            "--lib",
            "--crate-type",
            "staticlib",
            "--target-dir",
        ])
        .arg(&target)
        .args(["--", "--print", "native-static-libs"])
        .output()
        .unwrap();
    let text =
        String::from_utf8_lossy(&out.stderr).into_owned() + &String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find_map(|l| l.split("native-static-libs:").nth(1))
        .unwrap_or_else(|| panic!("rustc printed no native-static-libs: {text}"));
    assert_eq!(
        line.trim(),
        committed.trim(),
        "update packaging/native-static-libs.txt (Libs.private and the CMake static target)"
    );
    let pc = {
        let (_, prefix) = setup_in("packaging_libs");
        std::fs::read_to_string(prefix.join("lib/pkgconfig/arbor.pc")).unwrap()
    };
    assert!(
        pc.contains(&format!("Libs.private: {}", committed.trim())),
        "{pc}"
    );
}

/// The linking blocks of docs/hosts.md run as printed (their `cargo build` lines aside:
/// cargo already built this run's library, which stands in for `target/release`), in a
/// scratch folder that mirrors the checkout, with a scratch HOME, and the README's C quick
/// start as `app.c`. tools/fresh-clone runs them all, cargo included, on a fresh clone.
#[test]
fn the_documented_link_lines_work() {
    require("pkg-config");
    require("cmake");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("documented_links");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(work.join("target")).unwrap();
    std::fs::create_dir_all(work.join("home")).unwrap();
    for name in ["include", "packaging", "ffi-tests", "Cargo.toml"] {
        std::os::unix::fs::symlink(root.join(name), work.join(name)).unwrap();
    }
    // target/release: this run's libraries, with the SONAME link the build folder has.
    let release = work.join("target/release");
    std::fs::create_dir_all(&release).unwrap();
    for name in ["libarbor.a", "libarbor.so"] {
        std::fs::copy(lib_dir().join(name), release.join(name)).unwrap();
    }
    std::os::unix::fs::symlink("libarbor.so", release.join(soname())).unwrap();
    // The README's app.c.
    let readme = common::runnable_blocks("README.md", &work.join("readme-blocks"));
    let (_, app) = readme
        .iter()
        .find(|(path, _)| path.as_deref() == Some("app.c"))
        .expect("the README writes app.c");
    std::fs::write(work.join("app.c"), app).unwrap();
    let mut ran = 0;
    for (path, text) in common::runnable_blocks("docs/hosts.md", &work.join("hosts-blocks")) {
        if let Some(path) = path {
            let path = work.join(path);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, text).unwrap();
            continue;
        }
        let script: String = text
            .lines()
            .filter(|l| !l.starts_with("cargo "))
            .map(|l| format!("{l}\n"))
            .collect();
        let out = run(Command::new("bash")
            .args(["-euo", "pipefail", "-c", &script])
            .current_dir(&work)
            .env("HOME", work.join("home"))
            .env_remove("PKG_CONFIG_PATH")
            .env_remove("LD_LIBRARY_PATH"));
        assert!(out.contains("tree g: 1023 branches"), "{script}: {out}");
        ran += 1;
    }
    assert!(ran >= 3, "{ran} linking blocks in docs/hosts.md");
    // Shared from the build folder, shared and static installed, CMake both ways.
    for (exe, shared) in [
        ("app", true),
        ("app_shared", true),
        ("app_static", false),
        ("cmake-app/build/app_shared", true),
        ("cmake-app/build/app_static", false),
    ] {
        let dynamic = run(Command::new("readelf").arg("-d").arg(work.join(exe)));
        assert_eq!(dynamic.contains(&soname()), shared, "{exe}: {dynamic}");
    }
}

/// The library alone (`default-features = false`, as an engine embeds it) depends on no
/// command-line crates: clap, ctrlc, anyhow and indicatif come only with the `cli` feature. (serde_json is the
/// glTF writer's, so the library has it.)
#[test]
fn the_library_alone_has_no_cli_dependencies() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tree = |features: &[&str]| {
        run(Command::new(env!("CARGO"))
            .current_dir(root)
            .args(["tree", "--edges", "normal", "--prefix", "none", "--offline"])
            .args(features))
    };
    let lean = tree(&["--no-default-features"]);
    let cli_crates = ["clap ", "ctrlc ", "anyhow ", "indicatif "];
    for name in cli_crates {
        assert!(!lean.contains(name), "{name}in the library's tree:\n{lean}");
    }
    let cli = tree(&[]);
    for name in cli_crates {
        assert!(cli.contains(name), "the cli feature brings {name}:\n{cli}");
    }
}
