//! `packaging/install.sh` into a scratch prefix, then a C host built the usual ways:
//! `pkg-config --cflags --libs arbor`, and CMake's `find_package(arbor)` with the
//! `arbor::arbor` and `arbor::arbor_static` targets. pkg-config and cmake are required when
//! `CI` is set.

mod common;
use common::{have, lib_dir, run};

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

fn setup() -> (PathBuf, PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lib_dir = lib_dir();
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("packaging");
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
    let (work, prefix) = setup();
    let pc = std::fs::read_to_string(prefix.join("lib/pkgconfig/arbor.pc")).unwrap();
    assert!(pc.contains(&format!("Version: {}", env!("CARGO_PKG_VERSION"))));
    if have("pkg-config") {
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
    }
    if have("cmake") {
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
        let build = project.join("build");
        run(Command::new("cmake")
            .arg("-S")
            .arg(&project)
            .arg("-B")
            .arg(&build)
            .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display())));
        run(Command::new("cmake").arg("--build").arg(&build));
        for exe in ["app_shared", "app_static"] {
            let out = run(&mut Command::new(build.join(exe)));
            assert!(out.contains(" 1023"), "{exe}: {out}");
        }
    }
}
