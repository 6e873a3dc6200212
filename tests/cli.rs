//! The `arbor` command-line tool: export to glTF and OBJ from each kind of source, info
//! as text and JSON, and errors as one line with a non-zero exit.

use std::path::Path;
use std::process::Command;

fn arbor(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_arbor"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn export_writes_every_format_from_every_source() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli");
    std::fs::create_dir_all(&dir).unwrap();
    let grammar = dir.join("plant.l");
    std::fs::write(
        &grammar,
        "#define N 4\nderivation length: N\nAxiom: A\nA --> F[+A~][-A]\n",
    )
    .unwrap();
    std::fs::write(dir.join("plant.v"), "angle factor: 12\n").unwrap();
    let g = grammar.to_str().unwrap();
    for (source, out, extra) in [
        ("g", "g.glb", vec!["--leaves"]),
        (g, "plant.gltf", vec!["--radial-segments", "5"]),
        ("growth:bush", "bush.obj", vec!["--steps", "6", "--leaves"]),
        (
            "c",
            "c_curved.glb",
            vec!["--curve-rings", "2", "--seed", "9"],
        ),
        ("g", "g_instanced.glb", vec!["--instanced-leaves"]),
    ] {
        let path = dir.join(out);
        let _ = std::fs::remove_file(&path);
        let mut args = vec!["export", source, "-o", path.to_str().unwrap()];
        args.extend(extra);
        let (ok, _, err) = arbor(&args);
        assert!(ok, "{args:?}: {err}");
        let bytes = std::fs::read(&path).unwrap();
        match out.rsplit('.').next().unwrap() {
            "glb" => assert_eq!(&bytes[..4], b"glTF"),
            "gltf" => assert!(bytes.starts_with(b"{\"asset\":{\"version\":\"2.0\"")),
            _ => assert!(String::from_utf8_lossy(&bytes).contains("\nf ")),
        }
        assert!(err.contains("branches"), "{err}");
    }
}

#[test]
fn info_prints_counts_as_text_and_json() {
    let (ok, text, _) = arbor(&["info", "a"]);
    assert!(ok);
    assert!(text.contains("branches    1023"), "{text}");
    let (ok, json, _) = arbor(&["info", "a", "--steps", "6", "--json"]);
    assert!(ok);
    assert!(
        json.trim().starts_with('{') && json.trim().ends_with('}'),
        "{json}"
    );
    assert!(json.contains("\"branches\":63"), "{json}");
    let (ok, help, _) = arbor(&["--help"]);
    assert!(ok && help.contains("export") && help.contains("info"));
}

/// `--leaves` on a tree without leaf sites (the 1996 trees) puts leaves at the tips, and
/// says so; the file holds them (OBJ group, glTF primitive and `extras.leaves`).
#[test]
fn leaves_appear_when_asked() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_leaves");
    std::fs::create_dir_all(&dir).unwrap();
    let obj = dir.join("g.obj");
    let (ok, _, err) = arbor(&["export", "g", "-o", obj.to_str().unwrap(), "--leaves"]);
    assert!(ok, "{err}");
    assert!(err.contains("at the tips"), "{err}");
    let text = std::fs::read_to_string(&obj).unwrap();
    let leaves = text.split("\ng leaves\n").nth(1).expect("a leaves group");
    let faces = leaves.lines().filter(|l| l.starts_with("f ")).count();
    assert!(faces >= 1000, "{faces} leaf faces");

    let glb = dir.join("g.gltf");
    let (ok, _, err) = arbor(&["export", "g", "-o", glb.to_str().unwrap(), "--leaves"]);
    assert!(ok, "{err}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&glb).unwrap()).unwrap();
    assert_eq!(json["asset"]["extras"]["leaves"], true, "{}", json["asset"]);
    assert_eq!(json["meshes"][0]["primitives"].as_array().unwrap().len(), 2);
    // Without leaves the flag says false.
    let (ok, _, err) = arbor(&["export", "g", "-o", glb.to_str().unwrap()]);
    assert!(ok, "{err}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&glb).unwrap()).unwrap();
    assert_eq!(json["asset"]["extras"]["leaves"], false);

    // A grammar with leaf sites: auto keeps to its sites; tips may be asked for.
    let grammar = dir.join("plant.l");
    std::fs::write(
        &grammar,
        "derivation length: 3\nAxiom: A\nA --> F[+A~][-A]\n",
    )
    .unwrap();
    let (ok, _, err) = arbor(&[
        "export",
        grammar.to_str().unwrap(),
        "-o",
        obj.to_str().unwrap(),
        "--leaves",
    ]);
    assert!(ok && err.contains("at the model's leaf sites"), "{err}");
    let (ok, _, err) = arbor(&[
        "export",
        grammar.to_str().unwrap(),
        "-o",
        obj.to_str().unwrap(),
        "--leaves=tips",
    ]);
    assert!(ok && err.contains("at the tips"), "{err}");
    // Sites on a tree without any is an error that names the way out.
    let (ok, _, err) = arbor(&["export", "g", "-o", obj.to_str().unwrap(), "--leaves=sites"]);
    assert!(!ok && err.contains("--leaves=tips"), "{err}");
}

/// Options that cannot apply to the chosen output are errors, not silently dropped.
#[test]
fn options_that_do_nothing_are_errors() {
    let (ok, _, err) = arbor(&["export", "g", "-o", "x.obj", "--instanced-leaves"]);
    assert!(
        !ok && err.contains("--instanced-leaves is for glTF"),
        "{err}"
    );
    let (ok, _, err) = arbor(&["export", "g", "-o", "x.glb", "--leaf-size", "2"]);
    assert!(!ok && err.contains("--leaf-size needs --leaves"), "{err}");
    let (ok, _, err) = arbor(&["export", "g", "-o", "x.fbx"]);
    assert!(!ok && err.contains(".glb, .gltf or .obj"), "{err}");
    assert!(!Path::new("x.fbx").exists() && !Path::new("x.obj").exists());
}

/// `--help` names every species; `info --json` is JSON even for a path with control
/// characters and quotes.
#[test]
fn help_lists_species_and_json_is_json() {
    let (ok, help, _) = arbor(&["--help"]);
    assert!(ok);
    for s in arbor::models::growth::Species::ALL {
        assert!(
            help.contains(s.name()),
            "{} missing from --help:\n{help}",
            s.name()
        );
    }
    let (_, export_help, _) = arbor(&["export", "--help"]);
    assert!(export_help.contains("weeping"), "{export_help}");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_json");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("odd\t\u{1}\"name\\.l");
    std::fs::write(&path, "derivation length: 2\nAxiom: A\nA --> F[+A][-A]\n").unwrap();
    let source = path.to_str().unwrap();
    let (ok, json, err) = arbor(&["info", source, "--json"]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(json.trim()).expect("valid JSON");
    assert_eq!(v["source"], source);
    assert_eq!(v["branches"], 3);
}

#[test]
fn errors_are_one_line_and_a_failure_exit() {
    for args in [
        vec!["export", "z", "-o", "x.glb"],
        vec!["export", "a", "-o", "x.fbx"],
        vec!["info", "growth:palm"],
        vec!["info", "/no/such/file.l"],
    ] {
        let (ok, _, err) = arbor(&args);
        assert!(!ok, "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("arbor: "), "{err}");
    }
    let (ok, _, _) = arbor(&["export", "a"]);
    assert!(!ok, "a missing -o is a usage error");
    // Write errors name the file, for every format.
    for out in ["/no/such/dir/x.obj", "/no/such/dir/x.glb"] {
        let (ok, _, err) = arbor(&["export", "a", "-o", out]);
        assert!(!ok, "{out}");
        assert!(err.contains(&format!("cannot write {out}")), "{out}: {err}");
    }
    let (_, _, err) = arbor(&["export", "a", "-o", "x.fbx"]);
    assert!(err.contains(".glb, .gltf or .obj"), "{err}");
}

/// Files in `dir` other than `keep`.
fn others(dir: &Path, keep: &str) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != keep)
        .collect()
}

/// Starts a long OBJ export over an existing file and sends `signal` to it after a while;
/// returns the exit status.
#[cfg(unix)]
fn export_then_signal(dir: &Path, signal: &str) -> std::process::ExitStatus {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).unwrap();
    let target = dir.join("tree.obj");
    std::fs::write(&target, "old\n").unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_arbor"))
        .args([
            "export",
            "a",
            "--steps",
            "16",
            "--radial-segments",
            "16",
            "-o",
        ])
        .arg(&target)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the export ended before the signal; make it longer"
    );
    // The shell's own `kill` (no procps needed on a fresh machine).
    let sent = Command::new("sh")
        .arg("-c")
        .arg(format!("kill {signal} {}", child.id()))
        .status()
        .unwrap();
    assert!(sent.success());
    child.wait().unwrap()
}

/// Ctrl-C (SIGINT) during an export: exit 130, the old file as it was, no temporary file.
#[cfg(unix)]
#[test]
fn ctrl_c_leaves_the_old_file_and_nothing_else() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_interrupt");
    let status = export_then_signal(&dir, "-INT");
    assert_eq!(status.code(), Some(130), "{status:?}");
    assert_eq!(
        std::fs::read_to_string(dir.join("tree.obj")).unwrap(),
        "old\n"
    );
    assert!(
        others(&dir, "tree.obj").is_empty(),
        "{:?}",
        others(&dir, "tree.obj")
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A killed process (SIGKILL) can leave only its temporary file, named so a user
/// recognises it, and the old file as it was.
#[cfg(unix)]
#[test]
fn a_killed_export_leaves_the_old_file() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_killed");
    let status = export_then_signal(&dir, "-KILL");
    assert!(!status.success());
    assert_eq!(
        std::fs::read_to_string(dir.join("tree.obj")).unwrap(),
        "old\n"
    );
    for name in others(&dir, "tree.obj") {
        assert!(
            name.starts_with(".tree.obj.arbor-") && name.ends_with(".tmp"),
            "{name}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A vlab object's folder is a source: the grammar and view file its specifications names.
#[test]
fn a_vlab_object_folder_is_a_source() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_vlab_object");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("p.l"),
        "derivation length: 2\nAxiom: A\nA --> F[+A]A\n",
    )
    .unwrap();
    std::fs::write(dir.join("p.v"), "angle factor: 8\n").unwrap();
    std::fs::write(
        dir.join("specifications"),
        "p.l\np.v\nmodel:\n\tcpfg p.l p.v\n",
    )
    .unwrap();
    let (ok, out, err) = arbor(&["info", dir.to_str().unwrap(), "--json"]);
    assert!(ok, "{err}");
    assert!(out.contains("\"branches\":3"), "{out}");
}

#[test]
fn compact_vertices_are_quantized_gltf_and_refused_for_obj() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-compact");
    std::fs::create_dir_all(&dir).unwrap();
    let (full, compact) = (dir.join("a.gltf"), dir.join("a_compact.gltf"));
    let (ok, _, err) = arbor(&["export", "a", "-o", full.to_str().unwrap()]);
    assert!(ok, "{err}");
    let (ok, _, err) = arbor(&[
        "export",
        "a",
        "-o",
        compact.to_str().unwrap(),
        "--compact-vertices",
    ]);
    assert!(ok, "{err}");
    let (full, compact) = (
        std::fs::read_to_string(full).unwrap(),
        std::fs::read_to_string(compact).unwrap(),
    );
    assert!(!full.contains("KHR_mesh_quantization"));
    assert!(compact.contains("\"extensionsRequired\":[\"KHR_mesh_quantization\"]"));
    assert!(
        compact.len() < full.len(),
        "quantized normals take fewer bytes"
    );
    let obj = dir.join("a.obj");
    let (ok, _, err) = arbor(&[
        "export",
        "a",
        "-o",
        obj.to_str().unwrap(),
        "--compact-vertices",
    ]);
    assert!(
        !ok && err.contains("--compact-vertices is for glTF"),
        "{err}"
    );
    assert!(!obj.exists());
}
