//! The Unity package (`bindings/unity/`): its binding (`Runtime/Arbor.cs`) compiled with
//! Mono's `mcs` and run with `mono` against the shared library cargo built for this test
//! run; its Unity-only helpers and sample compiled with `UNITY_5_3_OR_NEWER` against
//! stand-ins of the UnityEngine types they use, and run; the package's files checked.
//! Mono is required: without it the tests fail with its install line.

mod common;
use common::{lib_dir, require, run};

use std::path::Path;
use std::process::Command;

#[test]
fn unity_binding_runs_under_mono() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lib_dir = lib_dir();
    require("mcs");
    let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ArborTest.exe");
    run(Command::new("mcs")
        .arg(format!("-out:{}", exe.display()))
        .arg(root.join("bindings/unity/Runtime/Arbor.cs"))
        .arg(root.join("bindings/unity/Tests~/ArborTest.cs")));
    let text = run(Command::new("mono")
        .arg(&exe)
        .env("LD_LIBRARY_PATH", &lib_dir));
    assert!(text.contains(" 0 failed"), "{text}");
    println!("{text}");
}

#[test]
fn unity_helpers_compile_against_unityengine_and_fill_a_mesh() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lib_dir = lib_dir();
    require("mcs");
    let u = root.join("bindings/unity");
    let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join("UnityHelpersTest.exe");
    run(Command::new("mcs")
        .arg("-define:UNITY_5_3_OR_NEWER")
        .arg(format!("-out:{}", exe.display()))
        .arg(u.join("Runtime/Arbor.cs"))
        .arg(u.join("Tests~/UnityStubs.cs"))
        .arg(u.join("Tests~/UnityHelpersTest.cs"))
        .arg(u.join("Samples~/GrowATree/GrowATree.cs")));
    let text = run(Command::new("mono")
        .arg(&exe)
        .env("LD_LIBRARY_PATH", &lib_dir));
    assert!(text.contains("unity helpers: 0 failed"), "{text}");
}

/// The package has what Unity's package manager reads: package.json, an assembly
/// definition, a .meta (with a unique GUID) beside every file and folder Unity imports,
/// and plugin import settings per platform.
#[test]
fn the_unity_package_is_complete() {
    let u = Path::new(env!("CARGO_MANIFEST_DIR")).join("bindings/unity");
    let pkg = std::fs::read_to_string(u.join("package.json")).unwrap();
    assert!(
        pkg.contains(&format!("\"version\": \"{}\"", env!("CARGO_PKG_VERSION"))),
        "{pkg}"
    );
    assert!(u.join("Runtime/Arbor.Runtime.asmdef").is_file());
    let mut guids = std::collections::HashSet::new();
    let mut stack = vec![u.join("Runtime")];
    let mut imported = vec![u.join("package.json"), u.join("Runtime")];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "meta") {
                let text = std::fs::read_to_string(&p).unwrap();
                let guid = text
                    .lines()
                    .find_map(|l| l.strip_prefix("guid: "))
                    .unwrap()
                    .to_string();
                assert_eq!(guid.len(), 32, "{}", p.display());
                assert!(guids.insert(guid), "duplicate GUID in {}", p.display());
                continue;
            }
            if p.is_dir() {
                stack.push(p.clone());
            }
            imported.push(p);
        }
    }
    for p in &imported {
        let meta = p.with_file_name(format!("{}.meta", p.file_name().unwrap().to_string_lossy()));
        assert!(meta.is_file(), "{} has no .meta", p.display());
    }
    for plugin in [
        "Linux/x86_64/libarbor.so",
        "Windows/x86_64/arbor.dll",
        "macOS/libarbor.dylib",
    ] {
        let meta =
            std::fs::read_to_string(u.join(format!("Runtime/Plugins/{plugin}.meta"))).unwrap();
        assert!(meta.contains("PluginImporter:"), "{plugin}");
    }
}

/// How regular a GUID's hex digits are: neighbours equal or counting up, or every other
/// digit counting up (`1a2b3c4d…`). Random GUIDs score about 6; hand-typed patterns 20+.
fn regularity(guid: &str) -> usize {
    let d: Vec<u32> = guid.chars().map(|c| c.to_digit(16).unwrap()).collect();
    (0..d.len() - 1)
        .filter(|&i| {
            d[i + 1] == (d[i] + 1) % 16
                || d[i + 1] == d[i]
                || (i + 2 < d.len() && d[i + 2] == (d[i] + 1) % 16)
        })
        .count()
}

/// Every GUID in the package is random (Unity identifies assets by them across every
/// project: a hand-typed pattern invites collisions), hex, and lower case.
#[test]
fn unity_guids_are_random() {
    let u = Path::new(env!("CARGO_MANIFEST_DIR")).join("bindings/unity");
    let mut stack = vec![u];
    let mut seen = 0;
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "meta") {
                let text = std::fs::read_to_string(&p).unwrap();
                let guid = text.lines().find_map(|l| l.strip_prefix("guid: ")).unwrap();
                assert!(
                    guid.len() == 32
                        && guid
                            .chars()
                            .all(|c| c.is_ascii_hexdigit() && !c.is_ascii_uppercase()),
                    "{}: {guid}",
                    p.display()
                );
                assert!(
                    regularity(guid) < 14,
                    "{}: GUID {guid} looks hand-typed (regularity {})",
                    p.display(),
                    regularity(guid)
                );
                seen += 1;
            }
        }
    }
    assert!(seen >= 10, "{seen} .meta files");
    assert!(regularity("1a2b3c4d5e6f40718293a4b5c6d7e8f9") >= 14);
}

/// Plugin binaries copied into the package are ignored by git (only their .meta files
/// are committed).
#[test]
fn copied_plugins_are_ignored_by_git() {
    require("git");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    // A scratch repository with the project's .gitignore, so this holds in a tarball too.
    let scratch = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gitignore");
    let _ = std::fs::remove_dir_all(&scratch);
    std::fs::create_dir_all(&scratch).unwrap();
    std::fs::copy(root.join(".gitignore"), scratch.join(".gitignore")).unwrap();
    run(Command::new("git")
        .arg("init")
        .arg("-q")
        .current_dir(&scratch));
    for plugin in [
        "Linux/x86_64/libarbor.so",
        "Windows/x86_64/arbor.dll",
        "macOS/libarbor.dylib",
    ] {
        let path = format!("bindings/unity/Runtime/Plugins/{plugin}");
        run(Command::new("git")
            .args(["check-ignore", "-q", &path])
            .current_dir(&scratch));
        let meta = format!("{path}.meta");
        let kept = Command::new("git")
            .args(["check-ignore", "-q", &meta])
            .current_dir(&scratch)
            .status()
            .unwrap();
        assert!(!kept.success(), "{meta} must stay committed");
    }
}

/// The Windows plugin cross-builds from Linux with the package's script (mingw-w64), and
/// the DLL exports every function of arbor.h and needs only Windows' own DLLs.
#[test]
fn the_windows_plugin_cross_builds() {
    require("x86_64-w64-mingw32-gcc");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("unity-windows");
    run(Command::new("bash")
        .arg(root.join("bindings/unity/build-plugins.sh"))
        .arg("windows")
        .env("CARGO_TARGET_DIR", &target));
    let dll = root.join("bindings/unity/Runtime/Plugins/Windows/x86_64/arbor.dll");
    let dump = run(Command::new("x86_64-w64-mingw32-objdump")
        .arg("-p")
        .arg(&dll));
    let header = std::fs::read_to_string(root.join("include/arbor.h")).unwrap();
    let mut functions = 0;
    for line in header.lines() {
        // Declarations only: not comments, and not the header's own `static inline` helpers.
        if line.trim_start().starts_with('*') || line.contains("static inline") {
            continue;
        }
        let Some(i) = line.find(" arbor_") else {
            continue;
        };
        let name: String = line[i + 1..]
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        if line[i + 1 + name.len()..].starts_with('(') {
            functions += 1;
            assert!(
                dump.contains(&format!(" {name}\n")),
                "arbor.dll does not export {name}"
            );
        }
    }
    assert!(functions > 50, "{functions} functions found in arbor.h");
    for dep in dump
        .lines()
        .filter_map(|l| l.trim().strip_prefix("DLL Name: "))
    {
        let dep = dep.to_ascii_lowercase();
        assert!(
            [
                "kernel32",
                "ntdll",
                "msvcrt",
                "userenv",
                "ws2_32",
                "bcryptprimitives",
                "api-ms-win-"
            ]
            .iter()
            .any(|s| dep.starts_with(s)),
            "arbor.dll needs {dep}, which Windows does not have"
        );
    }
}

/// The C header's structs as members: (struct name without `Arbor`, member names).
fn header_structs(header: &str) -> Vec<(String, Vec<String>)> {
    // Comments out first.
    let mut text = String::new();
    let mut rest = header;
    while let Some(i) = rest.find("/*") {
        text.push_str(&rest[..i]);
        rest = rest[i..].find("*/").map_or("", |j| &rest[i + j + 2..]);
    }
    text.push_str(rest);
    let mut out = Vec::new();
    let mut at = 0;
    while let Some(i) = text[at..].find("typedef struct Arbor") {
        let start = at + i + "typedef struct ".len();
        let name_end = start
            + text[start..]
                .find(|c: char| !c.is_ascii_alphanumeric())
                .unwrap();
        let name = text[start..name_end].to_string();
        // `typedef struct ArborMesh ArborMesh;` is opaque: only definitions count.
        if !text[name_end..].trim_start().starts_with('{') {
            at = name_end;
            continue;
        }
        let open = name_end + text[name_end..].find('{').unwrap();
        let close = open + text[open..].find('}').unwrap();
        let members = text[open + 1..close]
            .split(';')
            .map(str::trim)
            .filter(|d| !d.is_empty())
            .map(|d| {
                let d = d.split('[').next().unwrap().trim();
                d.rsplit(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                    .next()
                    .unwrap()
                    .to_string()
            })
            .collect();
        out.push((name.trim_start_matches("Arbor").to_string(), members));
        at = close;
    }
    out
}

/// Every field of every struct the binding declares starts where the C compiler puts the
/// member of the same struct (a C array is several C# fields: its start must be one of
/// them), and the sizes agree.
#[test]
fn unity_struct_offsets_match_the_c_compiler() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    require("mcs");
    require("cc");
    let header = std::fs::read_to_string(root.join("include/arbor.h")).unwrap();
    let structs = header_structs(&header);
    assert!(
        structs.len() >= 15,
        "{} structs in the header",
        structs.len()
    );
    let mut c = String::from(
        "#include \"arbor.h\"\n#include <stdio.h>\n#include <stddef.h>\nint main(void) {\n",
    );
    for (name, members) in &structs {
        c += &format!("  printf(\"{name} SIZE %zu\\n\", sizeof(Arbor{name}));\n");
        for m in members {
            c += &format!("  printf(\"{name} {m} %zu\\n\", offsetof(Arbor{name}, {m}));\n");
        }
    }
    c += "  return 0;\n}\n";
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("unity_offsets");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("offsets.c"), c).unwrap();
    run(Command::new("cc")
        .arg("-I")
        .arg(root.join("include"))
        .arg(dir.join("offsets.c"))
        .arg("-o")
        .arg(dir.join("offsets")));
    let c_out = run(&mut Command::new(dir.join("offsets")));
    let exe = dir.join("ArborOffsets.exe");
    run(Command::new("mcs")
        .arg(format!("-out:{}", exe.display()))
        .arg(root.join("bindings/unity/Runtime/Arbor.cs"))
        .arg(root.join("bindings/unity/Tests~/ArborOffsets.cs")));
    let cs_out = run(Command::new("mono").arg(&exe));
    let table = |text: &str| {
        let mut t: std::collections::BTreeMap<String, (usize, Vec<usize>)> = Default::default();
        for line in text.lines() {
            let w: Vec<&str> = line.split_whitespace().collect();
            if w.len() != 3 {
                continue;
            }
            let e = t.entry(w[0].to_string()).or_default();
            let v: usize = w[2].parse().unwrap();
            if w[1] == "SIZE" { e.0 = v } else { e.1.push(v) }
        }
        t
    };
    let (c_t, cs_t) = (table(&c_out), table(&cs_out));
    let mut compared = 0;
    for (name, (cs_size, cs_offsets)) in &cs_t {
        let Some((c_size, c_offsets)) = c_t.get(name) else {
            continue;
        };
        assert_eq!(cs_size, c_size, "{name}: size");
        for o in c_offsets {
            assert!(
                cs_offsets.contains(o),
                "{name}: no C# field starts at the C member offset {o} ({cs_offsets:?})"
            );
        }
        assert!(cs_offsets.iter().all(|o| o < c_size), "{name}");
        compared += 1;
    }
    assert!(compared >= 12, "{compared} structs compared");
}

/// Every enum of the binding is the header's enum of that name (`Topology` is
/// `ArborTopology`): the same members, spelled as the C enumerators (`TriangleList` is
/// `ARBOR_TOPOLOGY_TRIANGLE_LIST`), with the same values, none missing. The header's enums
/// are generated from the Rust ones, so the binding is checked against the one definition.
#[test]
fn the_bindings_enums_are_the_headers() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(root.join("include/arbor.h")).unwrap();
    let cs = std::fs::read_to_string(root.join("bindings/unity/Runtime/Arbor.cs")).unwrap();
    let snake = |s: &str| {
        let mut out = String::new();
        for (i, c) in s.chars().enumerate() {
            if c.is_ascii_uppercase() && i > 0 {
                out.push('_');
            }
            out.push(c.to_ascii_uppercase());
        }
        out
    };
    // Members `NAME = value` between the braces that follow `at`.
    let members = |text: &str, at: usize| -> Vec<(String, u32)> {
        let open = at + text[at..].find('{').unwrap();
        let close = open + text[open..].find('}').unwrap();
        let mut body = text[open + 1..close].to_string();
        while let Some(a) = body.find("/*") {
            let b = a + body[a..].find("*/").unwrap() + 2;
            body.replace_range(a..b, "");
        }
        body.lines()
            .map(|l| l.split("//").next().unwrap())
            .collect::<String>()
            .split(',')
            .filter_map(|m| {
                let (name, value) = m.split_once('=')?;
                Some((name.trim().to_string(), value.trim().parse().ok()?))
            })
            .collect()
    };
    let mut checked = 0;
    let mut rest = 0;
    while let Some(i) = cs[rest..].find("public enum ") {
        let at = rest + i;
        rest = at + 12;
        let name = cs[rest..].split([' ', ':']).next().unwrap();
        let c_name = format!("Arbor{name}");
        let h = header
            .find(&format!("enum {c_name}\n"))
            .or_else(|| header.find(&format!("enum {c_name} {{")))
            .unwrap_or_else(|| panic!("the header has no enum {c_name}"));
        let mut want = members(&header, h);
        let mut have: Vec<(String, u32)> = members(&cs, at)
            .into_iter()
            .map(|(m, v)| (format!("{}_{}", snake(&c_name), snake(&m)), v))
            .collect();
        want.sort();
        have.sort();
        assert_eq!(
            have, want,
            "Arbor.cs enum {name} against the header's {c_name}"
        );
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} enums found in Arbor.cs");
}

/// The package's impostor shader: its HLSL programs compile (glslangValidator's HLSL front
/// end, both stages, against the few UnityCG names they read), the .shader wraps them and
/// declares every property the Unity helper sets on its material.
#[test]
fn the_impostor_shader_compiles_and_declares_what_the_helper_sets() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let shaders = root.join("bindings/unity/Runtime/Shaders");
    require("glslangValidator");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("impostor-hlsl");
    std::fs::create_dir_all(&dir).unwrap();
    let check = dir.join("check.hlsl");
    std::fs::write(
        &check,
        "// What ArborImpostor.hlsl reads of UnityCG.cginc.\n\
         float4x4 unity_ObjectToWorld;\n\
         float4x4 unity_WorldToObject;\n\
         float4x4 unity_MatrixVP;\n\
         float3 _WorldSpaceCameraPos;\n\
         float4 UnityObjectToClipPos(float4 p) { return mul(unity_MatrixVP, mul(unity_ObjectToWorld, p)); }\n\
         #include \"ArborImpostor.hlsl\"\n",
    )
    .unwrap();
    for (stage, entry) in [
        ("vert", "ArborImpostorVertex"),
        ("frag", "ArborImpostorFragment"),
    ] {
        run(Command::new("glslangValidator")
            .args(["-D", "-V", "-S", stage, "-e", entry])
            .arg(format!("-I{}", shaders.display()))
            .arg("-o")
            .arg(dir.join(format!("{stage}.spv")))
            .arg(&check));
    }
    let shader = std::fs::read_to_string(shaders.join("ArborImpostor.shader")).unwrap();
    for line in [
        "Shader \"Arbor/Impostor\"",
        "#pragma vertex ArborImpostorVertex",
        "#pragma fragment ArborImpostorFragment",
        "#include \"ArborImpostor.hlsl\"",
    ] {
        assert!(shader.contains(line), "ArborImpostor.shader lacks {line}");
    }
    let hlsl = std::fs::read_to_string(shaders.join("ArborImpostor.hlsl")).unwrap();
    let cs = std::fs::read_to_string(root.join("bindings/unity/Runtime/Arbor.cs")).unwrap();
    let mut set = Vec::new();
    for call in [
        "material.SetFloat(\"",
        "material.SetVector(\"",
        "material.SetTexture(\"",
    ] {
        for part in cs.split(call).skip(1) {
            set.push(part.split('"').next().unwrap().to_string());
        }
    }
    set.push("_MainTex".into());
    assert!(set.len() >= 8, "{set:?}");
    for name in &set {
        assert!(
            shader.contains(&format!("{name} (")),
            "the helper sets {name}, which ArborImpostor.shader does not declare"
        );
        assert!(
            hlsl.contains(&format!(" {name};")),
            "the helper sets {name}, which ArborImpostor.hlsl does not read"
        );
    }
}
