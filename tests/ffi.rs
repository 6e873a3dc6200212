//! Builds the C programs in `ffi-tests/` against `include/arbor.h` and the static library
//! cargo built for this test run, and runs each twice: built with gcc under valgrind, and
//! built with clang under AddressSanitizer + UndefinedBehaviorSanitizer. Both tools are
//! required: a missing one fails with its install line (`ARBOR_FFI_VALGRIND=0` turns
//! valgrind off on purpose, for a quicker run by hand).

mod common;
use common::{lib_dir, missing, require, run};

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn out_dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ffi-tests");
    std::fs::create_dir_all(&d).unwrap();
    d
}

const WARNINGS: [&str; 4] = ["-Wall", "-Wextra", "-Werror", "-pedantic"];

/// Compiles `source` (C or C++ by its extension) and links it with the static library;
/// `sanitize`: with clang, AddressSanitizer and UndefinedBehaviorSanitizer.
fn build_with(source: &str, std: &str, sanitize: bool) -> PathBuf {
    let src = root().join("ffi-tests").join(source);
    let suffix = if sanitize { "_asan" } else { "" };
    let exe = out_dir().join(format!("{}{suffix}", source.replace('.', "_")));
    let cpp = source.ends_with(".cpp");
    let compiler = match (cpp, sanitize) {
        (false, false) => "cc",
        (true, false) => "c++",
        (false, true) => "clang",
        (true, true) => "clang++",
    };
    require(compiler);
    let mut cmd = Command::new(compiler);
    cmd.arg(format!("-std={std}"))
        .args(WARNINGS)
        .arg("-g")
        .arg("-I")
        .arg(root().join("include"));
    if sanitize {
        cmd.args([
            "-fsanitize=address,undefined",
            "-fno-sanitize-recover=all",
            "-fno-omit-frame-pointer",
        ]);
    }
    run(cmd
        .arg(&src)
        .arg(lib_dir().join("libarbor.a"))
        .args(["-lpthread", "-ldl", "-lm"])
        .arg("-o")
        .arg(&exe));
    exe
}

fn build(source: &str, std: &str) -> PathBuf {
    build_with(source, std, false)
}

/// Builds and runs `source` under valgrind (gcc build) and under ASan + UBSan (clang).
fn check_program(source: &str, std: &str) {
    run_test_program(&build(source, std));
    let clang = if source.ends_with(".cpp") {
        "clang++"
    } else {
        "clang"
    };
    require(clang);
    let exe = build_with(source, std, true);
    let text = run(Command::new(&exe)
        .arg(out_dir())
        .env("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=1")
        .env("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1"));
    assert!(text.contains(" 0 failed"), "{text}");
}

fn valgrind() -> Option<PathBuf> {
    if std::env::var("ARBOR_FFI_VALGRIND").as_deref() == Ok("0") {
        return None;
    }
    let found = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|p| p.join("valgrind"))
            .find(|p| p.is_file())
    });
    if found.is_none() {
        missing("valgrind");
    }
    found
}

fn run_test_program(exe: &Path) {
    let text = match valgrind() {
        Some(vg) => run(Command::new(vg)
            .args([
                "--error-exitcode=99",
                "--leak-check=full",
                "--show-leak-kinds=definite,indirect,possible",
                "--errors-for-leak-kinds=definite,indirect,possible",
                "--quiet",
            ])
            // With `parallel`, the worker pool's threads outlive main (the file says why;
            // hosts use it too).
            .arg(format!(
                "--suppressions={}",
                Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("ffi-tests/valgrind.supp")
                    .display()
            ))
            .arg(exe)
            .arg(out_dir())),
        None => run(Command::new(exe).arg(out_dir())),
    };
    assert!(text.contains(" 0 failed"), "{text}");
    println!("{text}");
}

#[test]
fn c_generate_then_upload_all_presets() {
    check_program("generate_upload.c", "c11");
}

#[test]
fn c_bad_input_and_every_buffer_capacity() {
    check_program("errors.c", "c11");
}

/// The round-4 findings of the outside fuzzer (`ffi-tests/hostile/`), with every option
/// each names. Built with gcc and run as it is, and under ASan + UBSan; not under
/// valgrind, whose fifty-fold slowdown would make the default-limited derivation the
/// finding is about (seconds in a debug build) take minutes.
#[test]
fn c_hostile_inputs_of_round_four() {
    let text = run(Command::new(build("hostile.c", "c11")).arg(out_dir()));
    assert!(text.contains(" 0 failed"), "{text}");
    require("clang");
    let exe = build_with("hostile.c", "c11", true);
    let text = run(Command::new(&exe)
        .arg(out_dir())
        .env("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=1")
        .env("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1"));
    assert!(text.contains(" 0 failed"), "{text}");
}

#[test]
fn c_trees_from_grammar_text() {
    check_program("lsystem.c", "c11");
}

#[test]
fn c_mesh_options_ranges_lods_leaves_and_obj() {
    check_program("mesh_leaves.c", "c11");
}

#[test]
fn c_owned_meshes_threads_and_every_bad_field() {
    check_program("handles_threads.c", "c11");
}

#[test]
fn cpp_wrapper_raii_exceptions_and_unreal_fill() {
    check_program("wrapper.cpp", "c++17");
}

#[test]
fn c_species_trees_options_and_textures() {
    check_program("species.c", "c11");
}

#[test]
fn c_levels_of_detail_and_impostors() {
    check_program("lod.c", "c11");
}

#[test]
fn c_forests_variation_pruning_animation() {
    check_program("forest.c", "c11");
}

#[test]
fn c_structs_that_grow_older_newer_and_bad_sizes() {
    check_program("growing.c", "c11");
}

#[test]
fn c_trees_from_a_hosts_own_branches() {
    check_program("skeleton.c", "c11");
}

#[test]
fn c_self_organizing_worlds() {
    check_program("growth.c", "c11");
}

#[test]
fn c_curves_smoothing_edits_and_records() {
    check_program("curves.c", "c11");
}

#[test]
fn c_untrusted_model_files() {
    check_program("files.c", "c11");
}

/// Run natively under `ulimit -v` (1 GiB of address space): valgrind and the sanitizers
/// reserve more than that themselves.
#[test]
fn c_allocation_failures_are_statuses() {
    let exe = build("out_of_memory.c", "c11");
    let text = run(Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v 1048576 && exec '{}'", exe.display())));
    assert!(text.contains(" 0 failed"), "{text}");
    println!("{text}");
}

#[test]
fn header_compiles_as_cpp17() {
    check_program("header_cpp.cpp", "c++17");
}

#[test]
fn header_compiles_as_strict_c99() {
    let exe = build("header_c99.c", "c99");
    // It only has to compile and link; it exits with the default topology number (0).
    run(&mut Command::new(exe));
}
