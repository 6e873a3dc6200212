//! cpfg files as written: the preprocessor over files, view files, statements, arrays,
//! multi-module predecessors, function files, and hostile preprocessor input.

use arbor::Error;
use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::progress::Run;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// A fresh folder under the target directory for this test's files.
fn folder(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("cpfg_files")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    if let Some(parent) = p.parent() {
        std::fs::create_dir_all(parent).unwrap();
    }
    std::fs::write(&p, text).unwrap();
    p
}

fn derive(ls: &LSystem) -> String {
    ls.format(&ls.derive(&LsystemOptions::default()).unwrap())
}

fn parse_error(result: arbor::Result<LSystem>) -> (u32, String) {
    match result {
        Err(Error::Parse { line, message, .. }) => (line, message),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn includes_are_relative_to_the_including_file() {
    let dir = folder("includes");
    write(&dir, "lib/inner.h", "#define STEP 3\n");
    write(
        &dir,
        "lib/outer.h",
        "#include \"inner.h\"\n#define SQ(x) ((x)*(x))\n",
    );
    let path = write(
        &dir,
        "plant.l",
        "#include \"lib/outer.h\"\n#ifdef STEP\nAxiom: F(SQ(STEP))\n#else\nAxiom: G\n#endif\n",
    );
    let ls = LSystem::from_file(&path, None).unwrap();
    assert_eq!(derive(&ls), "F(9)");
    // A missing include names the file and points at the line in the file with it.
    write(&dir, "lib/broken.h", "\n\n#include \"nowhere.h\"\n");
    let path = write(&dir, "broken.l", "#include \"lib/broken.h\"\nAxiom: F\n");
    let (line, message) = parse_error(LSystem::from_file(&path, None));
    assert_eq!(line, 3, "{message}");
    assert!(
        message.contains("broken.h") && message.contains("nowhere.h"),
        "{message}"
    );
    // An include cycle is named, in bounded time.
    write(&dir, "a.h", "#include \"b.h\"\n");
    write(&dir, "b.h", "#include \"a.h\"\n");
    let path = write(&dir, "cycle.l", "#include \"a.h\"\nAxiom: F\n");
    let (_, message) = parse_error(LSystem::from_file(&path, None));
    assert!(
        message.contains("#include cycle: a.h → b.h → a.h"),
        "{message}"
    );
    // Errors after the preprocessor point at the original line.
    let path = write(
        &dir,
        "late.l",
        "/* two\n lines */\n#define X 1\n\nAxiom: F(X +)\n",
    );
    let (line, message) = parse_error(LSystem::from_file(&path, None));
    assert_eq!(line, 5, "{message}");
}

#[test]
fn the_view_file_sets_the_angle_widths_and_tropism() {
    let dir = folder("view");
    let grammar =
        "#define N 1\nLsystem: 1\nderivation length: N\nAxiom: A\nA --> F+F\nendlsystem\n";
    let path = write(&dir, "plant.l", grammar);
    // No view file: the default angle.
    let plain = LSystem::from_file(&path, None).unwrap();
    assert_eq!(plain.view().angle_increment, 45.0);
    write(
        &dir,
        "plant.v",
        "angle factor: 40\ninitial line width: 2 pixels\nline width increment: .1\n\
         viewpoint: -1,0,30\nlight direction: 1.0,0.0,0.5\nsurface: l leaf.s 800 3 5\n\
         tropism direction: 0.0,1.0,0.0\ninitial elasticity: 0.02\n",
    );
    let ls = LSystem::from_file(&path, None).unwrap();
    assert_eq!(ls.view().angle_increment, 9.0);
    assert_eq!(ls.view().initial_width, 2.0);
    assert_eq!(ls.view().width_increment, 0.1);
    let t = ls.view().old_tropism.unwrap();
    assert_eq!((t.direction.y, t.elasticity), (1.0, 0.02));
    // The same text from memory, and an explicit view file.
    let mem = LSystem::parse_with_view(grammar, "angle increment: 30\n").unwrap();
    assert_eq!(mem.view().angle_increment, 30.0);
    let other = write(&dir, "other.v", "angle increment: 12.5\n");
    let ls = LSystem::from_file(&path, Some(&other)).unwrap();
    assert_eq!(ls.view().angle_increment, 12.5);
    // The older tropism bends every F toward its direction by asin(e·(T·U)) and
    // asin(e·(T·L)): a branch turned off the vertical bends back up.
    let g = "derivation length: 1\nAxiom: +(60)A\nA --> F(1)F(1)F(1)\n";
    let straight = LSystem::parse(g)
        .unwrap()
        .skeleton(&Default::default())
        .unwrap();
    let bent = LSystem::parse_with_view(g, "tropism direction: 0,1,0\ninitial elasticity: 0.3\n")
        .unwrap()
        .skeleton(&Default::default())
        .unwrap();
    let rise = |s: &arbor::skeleton::Skeleton| s.branches()[2].end[1] - s.branches()[2].start[1];
    assert!(
        rise(&bent) > rise(&straight) + 0.05,
        "{} vs {}",
        rise(&bent),
        rise(&straight)
    );
    // `_(e)` sets the elasticity: 0 keeps the branch straight.
    let unbent = LSystem::parse_with_view(
        "derivation length: 1\nAxiom: +(60)_(0)A\nA --> F(1)F(1)F(1)\n",
        "tropism direction: 0,1,0\ninitial elasticity: 0.3\n",
    )
    .unwrap()
    .skeleton(&Default::default())
    .unwrap();
    assert!((rise(&unbent) - rise(&straight)).abs() < 1e-5);
    // A value the view file gets wrong is named with its line.
    // A value cpfg cannot read: as cpfg, the setting keeps its value (the angle its
    // default), and the grammar's warnings name the file, line and key.
    let bad = write(&dir, "bad.v", "\n\nangle factor: none\n");
    let ls = LSystem::from_file(&path, Some(&bad)).unwrap();
    assert_eq!(ls.view().angle_increment, 45.0);
    let w = ls.warnings().join("\n");
    assert!(
        w.contains("bad.v") && w.contains("line 3") && w.contains("angle factor"),
        "{w}"
    );
}

#[test]
fn blocks_run_in_cpfg_order_and_statements_change_the_derivation() {
    // Start, axiom, then per step StartEach / step / EndEach, then End.
    let ls = LSystem::parse(
        "Lsystem: 1\nderivation length: 3\n\
         Start: { n = 10; printf(\"start %g\\n\", n); }\n\
         StartEach: { n = n + 1; }\n\
         EndEach: { printf(\"step %g\\n\", n); }\n\
         End: { printf(\"end\\n\"); }\n\
         Axiom: A(n)\n\
         A(x) --> A(n)\n\
         endlsystem\n",
    )
    .unwrap();
    let s = ls.derive(&LsystemOptions::default()).unwrap();
    assert_eq!(ls.format(&s), "A(13)");
    assert_eq!(s.log(), "start 10\nstep 11\nstep 12\nstep 13\nend\n");
    // Statements before the condition (which see and change the parameters) and after
    // it; a global counts the rewrites, left to right.
    let ls = LSystem::parse(
        "derivation length: 1\nAxiom: A(1)A(2)A(3)\n\
         A(x) : { y = x * 2; } y > 2 { k = k + 1; } --> B(y, k)\n",
    )
    .unwrap();
    assert_eq!(derive(&ls), "A(1)B(4,1)B(6,2)");
    // if/else, while, do-while, ?: and arrays.
    let ls = LSystem::parse(
        "define: { array a[4] = { 1, 2, 3, 4 }, m[2][2]; }\n\
         derivation length: 1\nAxiom: A(0)\n\
         A(x) : * { i = 0; s = 0; while (i < 4) { s = s + a[i]; i = i + 1; }\n\
                    m[1][0] = 7; do { i = i - 1; } while (i > 2);\n\
                    if (s == 10) t = 1; else t = 2; } --> B(s, m[1][0], i, t, s > 5 ? 1 : 0)\n",
    )
    .unwrap();
    assert_eq!(derive(&ls), "B(10,7,2,1,1)");
    // stop() ends the derivation after the step.
    let ls = LSystem::parse(
        "derivation length: 10\nAxiom: A(0)\nA(x) : * { if (x >= 2) stop(); } --> A(x + 1)\n",
    )
    .unwrap();
    assert_eq!(derive(&ls), "A(3)");
    // Run-time faults are errors with the production's line.
    let ls = LSystem::parse("define: { array a[2]; }\nderivation length: 1\nAxiom: A(5)\nA(x) : * { a[x] = 1; } --> A(x)\n").unwrap();
    match ls.derive(&LsystemOptions::default()) {
        Err(Error::Eval { message, .. }) => {
            assert!(
                message.contains("line 4") && message.contains("outside 0..2"),
                "{message}"
            )
        }
        other => panic!("{other:?}"),
    }
    // A loop that never ends stops at max_work.
    let ls = LSystem::parse(
        "derivation length: 1\nAxiom: A\nA : * { while (1) { x = x + 1; } } --> A\n",
    )
    .unwrap();
    let options = LsystemOptions::default().max_work(100_000);
    assert!(matches!(
        ls.derive(&options),
        Err(Error::LimitExceeded {
            limit_name: "max_work",
            ..
        })
    ));
}

#[test]
fn predecessors_of_several_modules_replace_them_all() {
    let ls = LSystem::parse("derivation length: 1\nAxiom: XAB(2)C\nAB(x) --> D(x + 1)\n").unwrap();
    assert_eq!(derive(&ls), "XD(3)C");
    // Bracketed predecessors match brackets literally.
    let ls = LSystem::parse("derivation length: 1\nAxiom: F[A(1)B]G[A(2)C]\n[A(x)B] --> [E(x)]\n")
        .unwrap();
    assert_eq!(derive(&ls), "F[E(1)]G[A(2)C]");
    // In interpretation rules too: the turtle reads what they make.
    let ls = LSystem::parse("Axiom: AB\nhomomorphism\nAB --> FFF\n").unwrap();
    assert_eq!(ls.skeleton(&Default::default()).unwrap().len(), 3);
}

#[test]
fn function_files_are_read_from_the_view_file() {
    let dir = folder("functions");
    write(
        &dir,
        "ramp.func",
        "fver 1 1\nname: ramp\nsamples: 10\nflip: off\npoints: 4\n0 0 1\n0.333333 0.666667 1\n0.666667 1.333333 1\n1 2 1\n",
    );
    write(
        &dir,
        "plant.v",
        "angle factor: 8\nfunction: ramp.func 100\n",
    );
    let path = write(
        &dir,
        "plant.l",
        "derivation length: 1\nAxiom: A\nA --> F(func(1, 0.5))F(func(ramp, 1))\n",
    );
    let ls = LSystem::from_file(&path, None).unwrap();
    let s = ls.skeleton(&Default::default()).unwrap();
    let len = |i: usize| s.branches()[i].end[1] - s.branches()[i].start[1];
    // cpfg's values: each found where the curve's x is within 0.001 of the one asked for
    // (y rises twice as fast as x here).
    assert!((len(0) - 1.0).abs() < 2e-3, "{}", len(0));
    assert!((len(1) - 2.0).abs() < 2e-3, "{}", len(1));
    // A function the view file does not list is an error naming how many it lists.
    let path = write(
        &dir,
        "more.l",
        "derivation length: 1\nAxiom: A\nA --> F(func(3, 0.5))\n",
    );
    let e = LSystem::from_file(&path, Some(&dir.join("plant.v")))
        .unwrap()
        .derive(&Default::default())
        .unwrap_err();
    assert!(e.to_string().contains("lists 1 function"), "{e}");
}

/// Hostile preprocessor input: a clear error in bounded time.
#[test]
fn malformed_preprocessor_input_is_refused_quickly() {
    let bounded = |text: &str, expect: &str| {
        let t = Instant::now();
        let (_, message) = parse_error(LSystem::parse(text));
        assert!(message.contains(expect), "{message}");
        println!("{expect}: {:?}", t.elapsed());
        assert!(
            t.elapsed() < Duration::from_secs(20),
            "{expect}: {:?}",
            t.elapsed()
        );
    };
    bounded(
        "#define M(a, b) a b\nAxiom: M(F, \n",
        "unterminated macro call",
    );
    bounded("#define M(a\nAxiom: F\n", "unterminated #define");
    bounded(
        "#define A B\n#define B A\nAxiom: A\n",
        "recursive #define: A → B → A",
    );
    let mut exp = String::new();
    for i in 1..64 {
        exp += &format!("#define M{i} M{} M{}\n", i - 1, i - 1);
    }
    exp += "#define M0 F\nAxiom: M63\n";
    bounded(&exp, "macro expansion produces more than");
    bounded(&"#if 1\n".repeat(100_000), "nested deeper than");
    bounded(
        &format!("{}Axiom: F\n", "#ifdef X\n".repeat(3000)),
        "never closed",
    );
    bounded("#else\nAxiom: F\n", "without an `#if`");
    bounded("#error no model here\nAxiom: F\n", "no model here");
    bounded("#include \"x.h\"\nAxiom: F\n", "needs the grammar's folder");
}

#[test]
fn surface_files_are_drawn_at_their_sites() {
    let dir = folder("surfaces");
    write(
        &dir,
        "flat.s",
        "0 1 0 1 0 0\nCONTACT POINT  X: 0.0 Y: 0.0 Z: 0.0\nEND POINT X: 0 Y: 1 Z: 0\n\
         HEADING  X: 0.00 Y: 1.00 Z: 0.00\nUP  X: 0.00 Y: 0.00 Z: -1.00\nSIZE: 2.00\npatch\n\
         TOP COLOR: 0 DIFFUSE: 0.00 BOTTOM COLOR: 0 DIFFUSE: 0.00\nAL: ~ A: ~ AR: ~\nL: ~ R: ~\nBL: ~ B: ~ BR: ~\n\
         0 0 0  1 0 0  2 0 0  3 0 0\n0 1 0  1 1 0  2 1 0  3 1 0\n0 2 0  1 2 0  2 2 0  3 2 0\n0 3 0  1 3 0  2 3 0  3 3 0\n",
    );
    write(
        &dir,
        "plant.v",
        "angle factor: 4\nsurface: l flat.s 2 2 3\nsurface: m missing.s 1\n",
    );
    let path = write(&dir, "plant.l", "Axiom: F(1)~l(1.5)+~m F(1)~k\n");
    let ls = LSystem::from_file(&path, None).unwrap();
    // The missing surface is a warning; its `~m` stays a leaf site, as does `~k`.
    assert_eq!(ls.warnings().len(), 1, "{:?}", ls.warnings());
    assert!(ls.warnings()[0].contains("missing.s"));
    let s = ls.skeleton(&Default::default()).unwrap();
    assert_eq!(s.leaves().len(), 2);
    // 2 x 3 cells of 2 triangles, scaled by 2 x 1.5: the area grows by 3^2.
    assert_eq!(s.polygons().len(), 12);
    let area: f32 = s
        .polygons()
        .iter()
        .map(|p| {
            let q = s.polygon(p);
            let (a, b, c) = (
                glam::Vec3::from(q[0]),
                glam::Vec3::from(q[1]),
                glam::Vec3::from(q[2]),
            );
            0.5 * (b - a).cross(c - a).length()
        })
        .sum();
    assert!((area - 2.25 * 9.0).abs() < 1e-3, "{area}");
    // The surface stands on the turtle at the end of the first branch, along its heading.
    for p in s.polygons() {
        for q in s.polygon(p) {
            assert!(q[1] >= 1.0 - 1e-5, "{q:?}");
            assert!(q[2].abs() < 1e-5, "{q:?}");
        }
        assert_eq!(p.branch, 0);
    }
    // A copy scaled past the f32 range is an error that names the surface, not a
    // skeleton of infinite points; one that stays inside is drawn.
    let view = dir.join("plant.v");
    let path = write(&dir, "far.l", "Axiom: F(1)~l(1e16)\n");
    let err = LSystem::from_file(&path, Some(view.as_path()))
        .unwrap()
        .skeleton(&Default::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("surface `~l`") && err.contains("f32 range"),
        "{err}"
    );
    let path = write(&dir, "near.l", "Axiom: F(1)~l(1e12)\n");
    let s = LSystem::from_file(&path, Some(view.as_path()))
        .unwrap()
        .skeleton(&Default::default())
        .unwrap();
    assert_eq!(s.polygons().len(), 12);
    assert!(s.polygon_points().iter().flatten().all(|v| v.is_finite()));
}

#[test]
fn a_ring_lsystem_closes_its_string_for_context() {
    let text = "derivation length: 1\nAxiom: BCA\nA < B --> X\nA > B --> Z\n";
    let open = LSystem::parse(text).unwrap();
    assert_eq!(derive(&open), "BCA");
    let ring = LSystem::parse(&format!("ring lsystem\n{text}")).unwrap();
    assert_eq!(derive(&ring), "XCZ");
}

#[test]
fn query_modules_learn_where_the_turtle_is() {
    // After every step the turtle reads the string and ?P gets its position (?H its
    // heading), so the next step's productions see them.
    let ls = LSystem::parse(
        "angle increment: 90\nderivation length: 1\nAxiom: F(2)+F(3)?P(0,0)?H(0,0,0)\n\
         ?P(x,y) --> A(x,y)\n?H(x,y,z) --> B(x,y,z)\n",
    )
    .unwrap();
    let s = ls.derive(&LsystemOptions::default()).unwrap();
    assert_eq!(ls.format(&s).split('B').next(), Some("F(2)+F(3)A(-3,2)"));
    let heading = s.params(s.len() - 1);
    assert!((heading[0] + 1.0).abs() < 1e-6 && heading[1].abs() < 1e-6 && heading[2].abs() < 1e-6);
    // An environment query runs without an environment program, with a warning.
    let ls = LSystem::parse("Axiom: A?E(1)\n").unwrap();
    assert!(ls.warnings()[0].contains("environment program"));
    // A growing shoot that stops where the query says it left a region.
    let ls =
        LSystem::parse("derivation length: 10\nAxiom: A?P(0,0)\nA > ?P(x,y) : y < 4 --> F(1)A\n")
            .unwrap();
    let s = ls.skeleton(&Default::default()).unwrap();
    assert_eq!(s.len(), 4);
}

/// The file policies from Rust: Bundle refuses what leaves the folder (naming it, never
/// quoting it), None reads only the file named, Any opts in, Host serves every file from
/// the host's reader (here a map in memory) and reports loading progress.
#[test]
fn file_policies_from_rust() {
    use arbor::files::{FileAccess, FileOptions};
    use arbor::progress::Stage;
    let dir = folder("policies");
    write(&dir, "secret.txt", "TOKEN=hunter2\n");
    let up = write(
        &dir,
        "model/up.l",
        "#include \"../secret.txt\"\nderivation length: 1\nAxiom: F\n",
    );
    let with = |access: FileAccess| FileOptions::default().access(access);
    match LSystem::from_file_with(&up, None, &with(FileAccess::Bundle), &mut Run::default()) {
        Err(Error::FileAccess { path, reason }) => {
            assert_eq!(path, "../secret.txt");
            assert!(reason.contains("leaves the model's folder"), "{reason}");
            assert!(!reason.contains("hunter2"), "{reason}");
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
    let e = LSystem::from_file_with(&up, None, &with(FileAccess::None), &mut Run::default())
        .unwrap_err();
    assert!(e.to_string().contains("`none`"), "{e}");
    // Any reads it (and it is not a grammar).
    let e = LSystem::from_file_with(&up, None, &with(FileAccess::Any), &mut Run::default())
        .unwrap_err();
    assert!(matches!(e, Error::Parse { .. }), "{e}");

    let files: std::collections::HashMap<String, Vec<u8>> = [
        (
            "m/tree.l",
            "#include \"defs.h\"\nderivation length: N\nAxiom: A\nA --> F[+A][-A]\n",
        ),
        ("m/defs.h", "#define N 3\n"),
        ("m/tree.v", "angle factor: 8\n"),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.as_bytes().to_vec()))
    .collect();
    let mut stages = Vec::new();
    let mut progress = |s: Stage, f: f32| {
        stages.push((s, f));
        true
    };
    let ls = LSystem::from_file_with(
        "m/tree.l",
        None,
        &with(FileAccess::from_map(files)),
        &mut Run::reporting(&mut progress),
    )
    .unwrap();
    assert_eq!(ls.view().angle_increment, 45.0);
    let s = ls.skeleton(&LsystemOptions::default()).unwrap();
    assert_eq!(s.len(), 7);
    assert!(stages.iter().all(|&(s, _)| s == Stage::Load));
    assert_eq!(stages.last().map(|&(_, f)| f), Some(1.0));
    // A budget smaller than the model.
    let tiny = (with(FileAccess::Any)).max_bytes(16);
    let e = LSystem::from_file_with(&up, None, &tiny, &mut Run::default()).unwrap_err();
    assert!(matches!(e, Error::FileBudget { .. }), "{e}");
}

/// A vlab object opens by its folder: `specifications` names the grammar and view file
/// (the `cpfg` command of its `model:` section, else the first `.l` and `.v` it lists).
#[test]
fn a_vlab_object_opens_by_its_folder() {
    let dir = folder("vlab_object");
    write(
        &dir,
        "tree.l",
        "derivation length: 1\nAxiom: A\nA --> F+F\n",
    );
    write(&dir, "plant.l", "derivation length: 1\nAxiom: A\nA --> F\n");
    write(&dir, "turn.v", "angle factor: 4\n");
    write(
        &dir,
        "specifications",
        "plant.l\ntree.l\nturn.v\nignore:\n*\nmodel:\n\tgenerate:\n\t\tcpfg -M a.mat tree.l turn.v\n",
    );
    let ls = LSystem::from_file(&dir, None).unwrap();
    assert_eq!(ls.view().angle_increment, 90.0);
    assert_eq!(derive(&ls), "F+F");
    // Without a cpfg command: the first .l listed.
    write(&dir, "specifications", "plant.l\nturn.v\nignore:\n*\n");
    assert_eq!(derive(&LSystem::from_file(&dir, None).unwrap()), "F");
    // A folder without specifications, or naming no grammar, is refused by name.
    std::fs::remove_file(dir.join("specifications")).unwrap();
    let e = LSystem::from_file(&dir, None).unwrap_err().to_string();
    assert!(e.contains("specifications"), "{e}");
    write(&dir, "specifications", "turn.v\n");
    let e = LSystem::from_file(&dir, None).unwrap_err().to_string();
    assert!(e.contains("names no `.l` file"), "{e}");
}

/// DATA: a data file the model opens for reading and that is not there is what cpfg goes
/// on without (its fscanf reads nothing): a warning, the model runs. One that is there is
/// refused, since arbor does not read data files' values; text has no folder to look in.
#[test]
fn a_missing_data_file_is_a_warning() {
    let dir = folder("data_files");
    let text = "Define: {array len[3];}\nStart: {fp = fopen(\"lengths.p\", \"r\"); i = 0;\n\
                while (i < 3) {fscanf(fp, \"%lf\", &len[i]); i = i + 1;} fclose(fp);}\n\
                derivation length: 1\nAxiom: A\nA --> F(len[0] + 1)\n";
    let path = write(&dir, "plant.l", text);
    let ls = LSystem::from_file(&path, None).unwrap();
    assert!(
        ls.warnings().iter().any(|w| w.contains("lengths.p")),
        "{:?}",
        ls.warnings()
    );
    assert_eq!(derive(&ls), "F(1)");
    write(&dir, "lengths.p", "2 3 4\n");
    let e = LSystem::from_file(&path, None).unwrap_err().to_string();
    assert!(e.contains("lengths.p") && e.contains("data file"), "{e}");
    let e = LSystem::parse(text).unwrap_err().to_string();
    assert!(e.contains("no folder"), "{e}");
}
