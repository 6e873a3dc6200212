//! The README and the chapters in `docs/` keep their word: every repository path they
//! name exists, every link resolves, the README's quick starts are there for
//! `tools/fresh-clone` to run (which CI does, verbatim, on a fresh clone), and the parts
//! that can run inside `cargo test` run here: the C quick start's program against this
//! test run's library, the CLI quick start's commands, the documented `--help`, and the
//! cpfg model the docs show with and without its view file.

mod common;
use common::{lib_dir, run};

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// README.md, BENCHMARKS.md and every chapter in docs/.
fn documents() -> Vec<PathBuf> {
    let mut docs = vec![root().join("README.md"), root().join("BENCHMARKS.md")];
    for e in std::fs::read_dir(root().join("docs")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "md") {
            docs.push(p);
        }
    }
    docs.sort();
    docs
}

/// Top-level folders of the repository: a word that starts with one names a path in it.
const TOP: [&str; 12] = [
    "models/",
    "src/",
    "include/",
    "examples/",
    "tests/",
    "tools/",
    "packaging/",
    "bindings/",
    "ffi-tests/",
    "benches/",
    "docs/",
    ".ci/",
];

#[test]
fn every_path_and_link_in_the_docs_exists() {
    let mut checked = 0;
    let mut broken = Vec::new();
    for doc in documents() {
        let text = std::fs::read_to_string(&doc).unwrap();
        let name = doc.strip_prefix(root()).unwrap().display().to_string();
        for word in text.split(|c: char| c.is_whitespace() || "`\"'()[]|,;".contains(c)) {
            let word = word.split('#').next().unwrap();
            let word = word.trim_end_matches(['.', ':', '*']);
            if word.starts_with("../shared") {
                broken.push(format!("{name}: {word} is outside the repository"));
                continue;
            }
            if !TOP.iter().any(|t| word.starts_with(t))
                || word.contains(['<', '>', '*', '{', '}', '…', '$', '='])
                || word.contains("NAME")
                || word.contains("FILE")
            {
                continue;
            }
            // `src/foo.rs:12` names a line.
            let path = word.split(':').next().unwrap();
            checked += 1;
            // A build output the docs' commands make (git ignores it) need not exist yet.
            if !root().join(path).exists() && !git_ignores(path) {
                broken.push(format!("{name}: {path} does not exist"));
            }
        }
        // Markdown links and images, relative to the document.
        let mut rest = text.as_str();
        while let Some(i) = rest.find("](") {
            rest = &rest[i + 2..];
            let target = &rest[..rest.find(')').unwrap()];
            let target = target.split('#').next().unwrap();
            if target.is_empty() || target.starts_with("http") {
                continue;
            }
            checked += 1;
            if !doc.parent().unwrap().join(target).exists() {
                broken.push(format!("{name}: link ({target}) does not resolve"));
            }
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
    assert!(checked > 100, "only {checked} paths checked");
}

/// Whether git ignores `path` (a build output such as `examples/gallery/gallery`).
fn git_ignores(path: &str) -> bool {
    std::process::Command::new("git")
        .args(["check-ignore", "-q", path])
        .current_dir(root())
        .status()
        .is_ok_and(|s| s.success())
}

/// The README starts where users start: short, with the two commands, three quick starts
/// and every chapter linked.
#[test]
fn the_readme_is_short_and_links_every_chapter() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    assert!(
        readme.lines().count() <= 220,
        "{} lines",
        readme.lines().count()
    );
    let intro: Vec<&str> = readme
        .lines()
        .skip(1)
        .take_while(|l| !l.starts_with('!'))
        .filter(|l| !l.trim().is_empty())
        .collect();
    assert!(intro.len() <= 5, "intro of {} lines", intro.len());
    for needle in [
        "examples/gallery/run.sh",
        "tools/test",
        "## Quick start: a tree into Blender",
        "## Quick start: a C host",
        "## Quick start: Rust",
        "Rust 1.85",
    ] {
        assert!(readme.contains(needle), "README lacks {needle}");
    }
    for doc in documents() {
        let name = doc.strip_prefix(root()).unwrap().display().to_string();
        if name.starts_with("docs/") {
            assert!(
                readme.contains(&format!("]({name})")),
                "README does not link {name}"
            );
        }
    }
}

fn blocks(doc: &str) -> Vec<(Option<String>, String)> {
    let out =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("blocks-{}", doc.replace('/', "_")));
    common::runnable_blocks(doc, &out)
}

/// The C quick start: its program, compiled as printed against this run's library, runs
/// and prints tree g's counts.
#[test]
fn the_c_quick_start_runs() {
    let b = blocks("README.md");
    assert!(b.len() >= 6, "{} runnable blocks in the README", b.len());
    let (_, app) = b
        .iter()
        .find(|(p, _)| p.as_deref() == Some("app.c"))
        .expect("the README writes app.c");
    assert!(
        b.iter()
            .any(|(p, t)| p.is_none() && t.contains("cc app.c -Iinclude")),
        "the README builds app.c"
    );
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("readme_c");
    std::fs::create_dir_all(&work).unwrap();
    std::fs::write(work.join("app.c"), app).unwrap();
    let libs = std::fs::read_to_string(root().join("packaging/native-static-libs.txt")).unwrap();
    let exe = work.join("app");
    run(Command::new("cc")
        .arg(work.join("app.c"))
        .arg(format!("-I{}", root().join("include").display()))
        .arg(lib_dir().join("libarbor.a"))
        .args(libs.split_whitespace())
        .args(["-Wall", "-Wextra", "-Werror", "-o"])
        .arg(&exe));
    let out = run(&mut Command::new(&exe));
    assert!(out.contains("tree g: 1023 branches"), "{out}");
}

/// The CLI quick start's `arbor` commands, as printed, with the `arbor` of this test run.
#[test]
fn the_cli_quick_start_runs() {
    let b = blocks("README.md");
    let (_, cli) = b
        .iter()
        .find(|(p, t)| p.is_none() && t.contains("cargo install --locked --path ."))
        .expect("the README installs the CLI with --locked");
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("readme_cli");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(root().join("examples"), work.join("examples")).unwrap();
    let bin = Path::new(env!("CARGO_BIN_EXE_arbor")).parent().unwrap();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap());
    let mut ran = 0;
    for line in cli.lines().filter(|l| l.starts_with("arbor ")) {
        let out = Command::new("sh")
            .arg("-c")
            .arg(line)
            .current_dir(&work)
            .env("PATH", &path)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{line}: {err}");
        assert!(err.contains("leaves: "), "{line}: no leaves placed: {err}");
        let file = line
            .split_whitespace()
            .skip_while(|w| *w != "-o")
            .nth(1)
            .unwrap();
        let bytes = std::fs::read(work.join(file)).unwrap();
        assert_eq!(&bytes[..4], b"glTF", "{file}");
        ran += 1;
    }
    assert!(ran >= 2, "{ran} arbor commands in the CLI quick start");
}

/// docs/hosts.md prints `arbor export --help` as it is.
#[test]
fn the_documented_help_is_the_help() {
    let hosts = std::fs::read_to_string(root().join("docs/hosts.md")).unwrap();
    let start = hosts
        .find("$ arbor export --help\n")
        .expect("the help in docs/hosts.md");
    let shown = &hosts[start + "$ arbor export --help\n".len()..];
    let shown = &shown[..shown.find("```").unwrap()];
    let out = Command::new(env!("CARGO_BIN_EXE_arbor"))
        .args(["export", "--help"])
        .output()
        .unwrap();
    let actual = String::from_utf8_lossy(&out.stdout);
    assert_eq!(shown.trim_end(), actual.trim_end());
}

/// The cpfg model the docs show grows with its view file's angle (22.5°), and without it
/// is another plant (cpfg's default of 45°).
#[test]
fn the_documented_model_reads_its_view_file() {
    use arbor::lsystem::{LSystem, LsystemOptions};
    let path = root().join("examples/models/meadow/plant.l");
    let with = LSystem::from_file(&path, None).unwrap();
    let s = with.skeleton(&LsystemOptions::default()).unwrap();
    assert!(s.polygons().len() >= 10 && s.organs().len() >= 9);
    // The same text, its include resolved by hand, with plant.v's text: the same plant.
    let text = std::fs::read_to_string(&path).unwrap();
    let params = std::fs::read_to_string(root().join("examples/models/meadow/params.h")).unwrap();
    let view = std::fs::read_to_string(root().join("examples/models/meadow/plant.v")).unwrap();
    let inline = text.replace("#include \"params.h\"", &params);
    let grow = |view: &str| {
        LSystem::parse_with_view(&inline, view)
            .unwrap()
            .skeleton(&LsystemOptions::default())
            .unwrap()
    };
    let same = grow(&view);
    assert_eq!(
        same.branches(),
        s.branches(),
        "plant.l with plant.v, read either way"
    );
    // Without the view file's angle line: cpfg's default angle, another plant.
    assert!(view.contains("angle factor: 16"), "{view}");
    let no_angle: String = view
        .lines()
        .filter(|l| !l.starts_with("angle factor"))
        .map(|l| format!("{l}\n"))
        .collect();
    let other = grow(&no_angle);
    assert_eq!(other.len(), s.len(), "the same topology");
    let moved = other
        .branches()
        .iter()
        .zip(s.branches())
        .map(|(a, b)| {
            (0..3)
                .map(|c| (a.end[c] - b.end[c]).abs())
                .fold(0.0f32, f32::max)
        })
        .fold(0.0f32, f32::max);
    assert!(
        moved > 0.1,
        "the view file's angle changes the plant: {moved}"
    );
}

/// A suite whose tool is missing fails with the line that installs it (never a silent
/// skip), and that line comes from `tools/deps.txt`, the one list the scripts share.
#[test]
fn a_missing_tool_fails_with_its_install_line() {
    let e = std::panic::catch_unwind(|| common::require("arbor-no-such-tool")).unwrap_err();
    let msg = e.downcast_ref::<String>().cloned().unwrap_or_default();
    assert!(msg.contains("arbor-no-such-tool is not installed"), "{msg}");
    for package in [
        "sudo apt-get install -y",
        "valgrind",
        "mono-mcs",
        "g++",
        "libglfw3-dev",
    ] {
        assert!(msg.contains(package), "{package} missing from: {msg}");
    }
    // The scripts install from tools/deps.txt through tools/deps, and list no packages of
    // their own.
    for script in [".ci/run", "examples/gallery/run.sh", "tools/test"] {
        let text = std::fs::read_to_string(root().join(script)).unwrap();
        assert!(
            text.contains("tools/deps"),
            "{script} does not use tools/deps"
        );
        assert!(
            !text.contains("libglfw3-dev"),
            "{script} keeps its own package list"
        );
    }
    let ci = std::fs::read_to_string(root().join(".ci/run")).unwrap();
    assert!(
        ci.contains("tools/fresh-clone"),
        "CI follows the README on a fresh clone"
    );
    let fresh = std::fs::read_to_string(root().join("tools/fresh-clone")).unwrap();
    assert!(fresh.contains("tools/test") && fresh.contains("examples/gallery/run.sh"));
}

/// CI runs the README's test command as the README prints it: the block after
/// `<!-- test -->` is `tools/test`, the command that runs every suite, and `.ci/run` runs
/// that line, right after installing what it needs, with nothing that could end the run
/// before it.
#[test]
fn ci_runs_the_readmes_test_command() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let after = readme
        .split_once("<!-- test -->\n")
        .expect("README.md marks its test command with <!-- test -->")
        .1;
    let block = after
        .strip_prefix("```sh\n")
        .expect("a sh block after the marker");
    let command = &block[..block.find("```").unwrap()];
    assert_eq!(command.trim(), "tools/test");
    let ci = std::fs::read_to_string(root().join(".ci/run")).unwrap();
    let lines: Vec<&str> = ci.lines().map(str::trim).collect();
    let at = lines
        .iter()
        .position(|l| *l == command.trim())
        .expect(".ci/run runs the README's test command as a line of its own");
    assert!(
        lines[..at].contains(&"tools/deps test"),
        ".ci/run installs what the tests need first"
    );
    assert!(
        !lines[..at].iter().any(|l| l.contains("exit")),
        "nothing in .ci/run exits before the test command"
    );
    assert!(root().join("tools/test").exists());
}
