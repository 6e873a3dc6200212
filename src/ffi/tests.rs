//! Rust-side checks of the C ABI shell; the C programs in `ffi-tests/` test it from C.

use super::guard::{FfiError, guard, guard_value};
use super::*;
use crate::lsystem::{LSystem, LsystemOptions};
use std::ffi::CStr;

fn last_error() -> String {
    // SAFETY: NULL with capacity 0 asks for the length only.
    let n = unsafe { arbor_last_error_message(std::ptr::null_mut(), 0) };
    let mut buf = vec![0 as c_char; n + 1];
    // SAFETY: `buf` holds n + 1 writable bytes.
    let m = unsafe { arbor_last_error_message(buf.as_mut_ptr(), buf.len()) };
    assert_eq!(m, n);
    // SAFETY: the function NUL-terminated the buffer.
    let text = unsafe { CStr::from_ptr(buf.as_ptr()) }
        .to_str()
        .unwrap()
        .to_owned();
    // What a C host reads with strlen is the whole message, with no control character.
    assert_eq!(text.len(), n, "a NUL inside the message: {text:?}");
    assert!(
        !text.chars().any(char::is_control),
        "a control character: {text:?}"
    );
    text
}

/// nul_in_message.l: a NUL (or any control byte) in the grammar is escaped in the message.
#[test]
fn messages_escape_nul_and_control_bytes() {
    for bytes in [
        &b"Axiom: F\0"[..],
        b"Axiom: F\x01\x1b[2J",
        b"Axiom: F(\n\0\x7f",
    ] {
        let (status, message) = grow_c(bytes, None);
        assert_eq!(status, ArborStatus::ParseError, "{message}");
        assert!(message.contains("\\"), "escaped: {message}");
    }
}

#[test]
fn versions_match_cargo_toml() {
    let major: u32 = env!("CARGO_PKG_VERSION_MAJOR").parse().unwrap();
    let minor: u32 = env!("CARGO_PKG_VERSION_MINOR").parse().unwrap();
    let patch: u32 = env!("CARGO_PKG_VERSION_PATCH").parse().unwrap();
    assert_eq!(
        (
            ARBOR_VERSION_MAJOR,
            ARBOR_VERSION_MINOR,
            ARBOR_VERSION_PATCH
        ),
        (major, minor, patch)
    );
    assert_eq!(ARBOR_ABI_VERSION, major * 10000 + minor * 100 + patch);
    assert_eq!(arbor_abi_version(), ARBOR_ABI_VERSION);
    // SAFETY: arbor_version returns a static NUL-terminated string.
    let v = unsafe { CStr::from_ptr(arbor_version()) };
    assert_eq!(v.to_str().unwrap(), env!("CARGO_PKG_VERSION"));
}

#[test]
fn status_strings_are_distinct_and_static() {
    let mut seen = std::collections::HashSet::new();
    for s in 0..=8u32 {
        // SAFETY: arbor_status_str never returns NULL and its strings are static.
        let text = unsafe { CStr::from_ptr(arbor_status_str(s)) };
        assert!(seen.insert(text.to_owned()), "duplicate text for {s}");
    }
    // SAFETY: as above.
    let unknown = unsafe { CStr::from_ptr(arbor_status_str(12345)) };
    assert_eq!(unknown.to_str().unwrap(), "unknown status");
}

#[test]
fn a_panic_becomes_a_status_and_a_message() {
    let status = guard(|| panic!("boom in a test"));
    assert_eq!(status, ArborStatus::Panic);
    let message = last_error();
    assert!(message.contains("boom in a test"), "{message}");
    assert_eq!(guard_value(7u32, || panic!("again")), 7);
    assert_eq!(guard(|| Ok(())), ArborStatus::Ok);
    assert_eq!(last_error(), "");
}

#[test]
fn last_error_message_is_cut_at_capacity() {
    // SAFETY: `out` is NULL; the function reports NULL_ARGUMENT.
    let status = unsafe { arbor_honda_preset('a' as u32, std::ptr::null_mut()) };
    assert_eq!(status, ArborStatus::NullArgument);
    let full = last_error();
    assert!(full.contains("`out`"), "{full}");
    let mut buf = [0x55 as c_char; 8];
    // SAFETY: the capacity given is 5 of the 8 bytes.
    let n = unsafe { arbor_last_error_message(buf.as_mut_ptr(), 5) };
    assert_eq!(n, full.len());
    // SAFETY: NUL-terminated within the 5 bytes.
    let cut = unsafe { CStr::from_ptr(buf.as_ptr()) };
    assert_eq!(cut.to_bytes(), &full.as_bytes()[..4]);
    assert_eq!(buf[5], 0x55, "wrote past the capacity");
}

#[test]
fn options_round_trip_and_unknown_topology_is_rejected() {
    let d = ArborMeshOptions::default();
    assert_eq!(d.to_rust().ok(), Some(MeshOptions::default()));
    let bad = ArborMeshOptions { topology: 3, ..d };
    let err = bad.to_rust().unwrap_err();
    assert!(matches!(
        err,
        crate::Error::InvalidArgument {
            field: "topology",
            ..
        }
    ));
    assert!(
        err.to_string().contains(
            "expected 0 (ARBOR_TOPOLOGY_TRIANGLE_LIST), 1 (ARBOR_TOPOLOGY_TRIANGLE_STRIP_RESTART)"
        ),
        "{err}"
    );
}

/// Runs `arbor_tree_from_lsystem` on raw bytes and returns the status and message.
fn grow_c(bytes: &[u8], options: Option<&ArborLsystemOptions>) -> (ArborStatus, String) {
    let mut tree: *mut ArborTree = std::ptr::null_mut();
    let opts = options.map_or(std::ptr::null(), |o| o as *const _);
    // SAFETY: `bytes` is a live slice of `bytes.len()` bytes, `opts` is NULL or points to a
    // live struct, and `tree` is a local out-pointer.
    let status =
        unsafe { arbor_tree_from_lsystem(bytes.as_ptr().cast(), bytes.len(), opts, &mut tree) };
    let message = last_error();
    // SAFETY: the tree was made by this library (or is NULL) and is freed once.
    unsafe { arbor_tree_free(tree) };
    (status, message)
}

#[test]
fn errors_read_the_same_through_rust_and_c() {
    let cases: [&str; 6] = [
        "Axiom: F(",
        "Axiom: F\nF(x) --> F(a[1])",
        "#include \"missing.h\"\nAxiom: F",
        "derivation length: 1\nAxiom: A(0)\nA(x) --> F(log(x))",
        "derivation length: 30\nAxiom: F\nF --> FF",
        "",
    ];
    let small = LsystemOptions {
        max_modules: 1000,
        ..Default::default()
    };
    let c_small = ArborLsystemOptions {
        max_modules: 1000,
        ..Default::default()
    };
    for text in cases {
        let rust = LSystem::parse(text).and_then(|ls| ls.skeleton(&small));
        let rust = rust.expect_err(text);
        let (status, message) = grow_c(text.as_bytes(), Some(&c_small));
        assert_eq!(message, rust.to_string(), "{text:?}");
        assert_eq!(status, FfiError::from(rust).status, "{text:?}");
    }
}

mod fuzz {
    use super::*;
    use crate::ffi::options::Growing;
    use crate::mesh::{Axes, Topology, UpAxis, Winding};

    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig {
            cases: std::env::var("ARBOR_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(256),
            ..ProptestConfig::default()
        })]

        /// Random bytes (not always UTF-8) through the C entry point: a status, a message,
        /// never a panic.
        #[test]
        fn c_grammar_entry_point_takes_any_bytes(
            bytes in prop::collection::vec(any::<u8>(), 0..300),
            steps in -3i32..8,
            max_modules in 0u64..5000,
            flags in 0u32..16,
            angle in any::<f32>(),
        ) {
            let o = ArborLsystemOptions {
                steps,
                max_modules,
                override_flags: flags,
                angle_increment: angle,
                ..Default::default()
            };
            let (status, message) = grow_c(&bytes, Some(&o));
            prop_assert!(status != ArborStatus::Panic, "{message}");
            prop_assert!(status == ArborStatus::Ok || !message.is_empty());
        }

        /// Every field of ArborLsystemOptions random (sizes, seeds, limits, overrides,
        /// jitter, view text, progress) with a real grammar: a status, never a panic, and
        /// a tree whose numbers are finite.
        #[test]
        fn c_lsystem_options_take_any_values(
            floats in prop::collection::vec(prop_oneof![8 => -400.0f32..400.0, 1 => any::<f32>()], 4),
            ints in prop::collection::vec(any::<u64>(), 8),
            view in prop::sample::select(vec!["", "angle factor: 7\n", "angle factor: 0\n",
                "initial line width: 1e30\ntropism direction: 0,1,0\ninitial elasticity: 3\n",
                "interpretation past %: off\n", "#define X\nangle increment: X\n"]),
            grammar in prop::sample::select(vec![
                "derivation length: 6\nAxiom: A(1)\nA(x) --> F(x)[+A(x*0.7)][-A(x*0.6)]%\n",
                "derivation length: 9\nAxiom: F\nF --> F[+F]F[-F]F\n",
                "Start: {n=0;}\nderivation length: 5\nAxiom: A(0)\nA(x) : * {n=n+1;} --> F(n)@O(x)A(x+1)\n",
            ]),
        ) {
            let view_c = std::ffi::CString::new(view).unwrap();
            let o = ArborLsystemOptions {
                steps: (ints[0] % 14) as i32 - 2,
                seed: ints[1],
                max_modules: ints[2] % 200_000,
                max_params: ints[3] % 400_000,
                max_branches: ints[4] % 200_000,
                override_flags: (ints[5] % 16) as u32,
                angle_increment: floats[0],
                initial_width: floats[1],
                width_increment: floats[2],
                turn_jitter: floats[3],
                variation_seed: ints[6],
                max_work: ints[7] % 2_000_000,
                view_text: if view.is_empty() { std::ptr::null() } else { view_c.as_ptr() },
                ..Default::default()
            };
            let mut tree: *mut ArborTree = std::ptr::null_mut();
            // SAFETY: the grammar, options and view text outlive the call.
            let status = unsafe { arbor_tree_from_lsystem(grammar.as_ptr().cast(), grammar.len(), &o, &mut tree) };
            prop_assert!(status != ArborStatus::Panic, "{}", last_error());
            if status != ArborStatus::Ok {
                prop_assert!(!last_error().is_empty() && tree.is_null());
                return Ok(());
            }
            // SAFETY: `tree` is live.
            let n = unsafe { arbor_tree_branch_count(tree) };
            let mut b = vec![Branch::default(); n];
            // SAFETY: `b` holds `n` branches.
            prop_assert_eq!(unsafe { arbor_tree_copy_branches(tree, b.as_mut_ptr(), n) }, ArborStatus::Ok);
            for x in &b {
                prop_assert!(x.start.iter().chain(&x.end).all(|v| v.is_finite()));
                prop_assert!(x.start_radius.is_finite() && x.end_radius.is_finite());
            }
            // SAFETY: made above, freed once.
            unsafe { arbor_tree_free(tree) };
        }

        /// Random option structs (every field any value) through the mesh entry points.
        #[test]
        fn c_mesh_entry_points_take_any_options(
            fields in prop::collection::vec(any::<u32>(), 12),
            floats in prop::collection::vec(any::<f32>(), 3),
        ) {
            let o = ArborMeshOptions {
                radial_segments: fields[0] % 80,
                topology: fields[1] % 5,
                min_radial_segments: fields[2] % 80,
                cull_radius: floats[0],
                joints: fields[4] % 4,
                smooth_taper: fields[5] % 3,
                base_cap: fields[6] % 3,
                tip: fields[7] % 5,
                texture_scale: floats[1],
                winding: fields[9] % 3,
                up_axis: fields[10] % 3,
                scale: floats[2],
                // Sizes from below the first layout up to this one (never past the Rust value).
                struct_size: [52, 56, 64, 72, 96, fields[3] % 97][fields[8] as usize % 6],
                threads: fields[11] % 4,
                max_vertices: u64::from(fields[3]) * 64,
                curve_rings: fields[11] % 3,
                progress: None,
                progress_user_data: std::ptr::null_mut(),
                axes: (fields[1] / 5) % 4,
                vertex_format: (fields[2] / 80) % 3,
                even_texels: (fields[4] / 4) % 3,
            };
            let mut p = HondaParams::zeroed();
            // SAFETY: `p` is a local struct.
            prop_assert_eq!(unsafe { arbor_honda_preset('c' as u32, &mut p) }, ArborStatus::Ok);
            p.steps = 5;
            let mut tree: *mut ArborTree = std::ptr::null_mut();
            // SAFETY: local pointers.
            prop_assert_eq!(unsafe { arbor_tree_from_honda(&p, &mut tree) }, ArborStatus::Ok);
            let (mut nv, mut ni) = (0usize, 0usize);
            // SAFETY: `tree` is live; the options and counts are locals.
            let status = unsafe { arbor_mesh_size(tree, &o, &mut nv, &mut ni) };
            let size_error = last_error();
            prop_assert!(
                status == ArborStatus::Ok
                    || status == ArborStatus::InvalidArgument
                    || status == ArborStatus::LimitExceeded,
                "{status:?} {size_error}"
            );
            // Fields past `struct_size` are read as their defaults.
            let reads = |end: usize| o.struct_size as usize >= end;
            let reads_max = reads(std::mem::offset_of!(ArborMeshOptions, max_vertices) + 8);
            if status == ArborStatus::LimitExceeded {
                // Only the vertex limit the options set, and only when the mesh is
                // larger: the same options without it size the mesh past it.
                prop_assert!(reads_max && size_error.contains("`max_vertices`"), "{size_error}");
                let unlimited = ArborMeshOptions { max_vertices: u64::MAX, ..o };
                // SAFETY: as above.
                let s = unsafe { arbor_mesh_size(tree, &unlimited, &mut nv, &mut ni) };
                prop_assert_eq!(s, ArborStatus::Ok, "{}", last_error());
                prop_assert!(nv as u64 > o.max_vertices);
            }
            let compact = reads(std::mem::offset_of!(ArborMeshOptions, vertex_format) + 4)
                && o.vertex_format == VertexFormat::Compact as u32;
            // glTF writes lists, counter-clockwise, Y up, in arbor's axes: it succeeds
            // exactly when those options do and the given ones hold no error but the f32
            // range of positions in the given space (a contradiction or a bad field is
            // refused whatever the space).
            let as_gltf = ArborMeshOptions {
                topology: Topology::TriangleList as u32,
                winding: Winding::CounterClockwise as u32,
                up_axis: UpAxis::Y as u32,
                axes: Axes::Arbor as u32,
                ..o
            };
            let (mut gv, mut gi) = (0usize, 0usize);
            // SAFETY: as above.
            let gltf_space = unsafe { arbor_mesh_size(tree, &as_gltf, &mut gv, &mut gi) };
            let gltf_expected = gltf_space == ArborStatus::Ok
                && (status == ArborStatus::Ok || size_error.starts_with("invalid argument `scale`"));
            if status == ArborStatus::Ok && compact {
                // Compact vertices go through the byte writer; the f32 writer refuses them.
                let mut v = vec![VertexCompact::default(); nv];
                let mut i = vec![0u32; ni];
                let mut f = vec![Vertex::default(); nv];
                // SAFETY: the buffers hold exactly the sizes asked for.
                let w = unsafe { arbor_mesh_write(tree, &o, f.as_mut_ptr(), nv, i.as_mut_ptr(), ni) };
                prop_assert_eq!(w, ArborStatus::InvalidArgument);
                prop_assert!(last_error().contains("`vertex_format`"), "{}", last_error());
                let bytes = std::mem::size_of_val(v.as_slice());
                // SAFETY: `v` holds `bytes` bytes, 4-byte aligned; `i` holds `ni` indices.
                let w = unsafe { arbor_mesh_write_bytes(tree, &o, v.as_mut_ptr().cast(), bytes, i.as_mut_ptr(), ni) };
                prop_assert_eq!(w, ArborStatus::Ok, "{}", last_error());
                let mut v_scale = 0.0f32;
                // SAFETY: `tree` is live; the options and the scale are locals.
                prop_assert_eq!(unsafe { arbor_mesh_v_scale(tree, &o, &mut v_scale) }, ArborStatus::Ok);
                for x in v.iter().map(|x| x.decode(v_scale)) {
                    prop_assert!(x.position.iter().chain(&x.normal).chain(&x.uv).all(|f| f.is_finite()));
                }
            } else if status == ArborStatus::Ok {
                let mut v = vec![Vertex::default(); nv];
                let mut i = vec![0u32; ni];
                // SAFETY: the buffers hold exactly the sizes asked for.
                let w = unsafe { arbor_mesh_write(tree, &o, v.as_mut_ptr(), nv, i.as_mut_ptr(), ni) };
                prop_assert_eq!(w, ArborStatus::Ok);
                for x in &v {
                    prop_assert!(x.position.iter().chain(&x.normal).chain(&x.uv).all(|f| f.is_finite()));
                }
            } else {
                prop_assert!(!size_error.is_empty());
            }
            // The same options through the glTF writer: a status, and a file whose
            // numbers are finite when it is OK.
            let dir = std::env::temp_dir().join(format!("arbor-fuzz-gltf-{}", std::process::id()));
            let _ = std::fs::create_dir_all(&dir);
            let path = dir.join(if fields[2] % 2 == 0 { "t.glb" } else { "t.gltf" });
            let c_path = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
            let leaves = ArborLeafOptions::default();
            let leaf_ptr = if fields[5] % 2 == 0 { std::ptr::null() } else { &leaves as *const _ };
            // SAFETY: `tree` is live; the options, leaf options and path are locals.
            let g = unsafe { arbor_export_gltf(tree, &o, leaf_ptr, c_path.as_ptr()) };
            prop_assert!(g != ArborStatus::Panic, "{}", last_error());
            prop_assert_eq!(g == ArborStatus::Ok, gltf_expected, "{} / {}", size_error, last_error());
            if g == ArborStatus::Ok {
                let bytes = std::fs::read(&path).unwrap();
                // The JSON only (not the buffer, whose bytes or base64 may spell anything).
                let json = if bytes.starts_with(b"glTF") {
                    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
                    String::from_utf8_lossy(&bytes[20..20 + len]).into_owned()
                } else {
                    let text = String::from_utf8_lossy(&bytes).into_owned();
                    text.split("data:application").next().unwrap_or("").to_string()
                };
                prop_assert!(json.starts_with("{\"asset\""), "{json}");
                prop_assert!(!json.contains("NaN") && !json.contains("inf"), "{json}");
            }
            // SAFETY: made above, freed once.
            unsafe { arbor_tree_free(tree) };
        }

        /// Random world options and species through create, plant, step and the
        /// snapshot. Each float is mostly in a plausible range (so most cases grow) and
        /// otherwise any bit pattern (NaN, ±∞, huge, negative, zero): a status with a
        /// message, never a panic, and a snapshot that meshes to finite vertices. Grids
        /// and growth are capped so a case stays small.
        #[test]
        fn c_growth_entry_points_take_any_parameters(
            u in prop::collection::vec(prop_oneof![15 => 0.0f32..1.0, 1 => any::<f32>()], 28),
            ints in prop::collection::vec(any::<u32>(), 7),
            cycles in 0u32..6,
        ) {
            // Field k in [lo, hi) when u[k] is in [0, 1); wild values stay wild.
            let r = |k: usize, lo: f32, hi: f32| lo + u[k] * (hi - lo);
            let o = ArborWorldOptions {
                environment: [0, 0, 0, 0, 1, 1, 1, 2][ints[0] as usize % 8],
                min: [r(0, -30.0, -5.0), r(1, -2.0, 0.0), r(2, -30.0, -5.0)],
                max: [r(3, 5.0, 30.0), r(4, 5.0, 20.0), r(5, 5.0, 30.0)],
                cell_size: r(6, 0.2, 2.0),
                seed: u64::from(ints[1]),
                shadow_strength: r(7, 0.5, 3.0),
                shadow_falloff: r(8, 1.1, 4.0),
                shadow_depth: ints[2] % 20,
                full_light: r(9, 1.0, 20.0),
                max_cells: 1 << 18,
                max_branches: 20_000,
                max_trees: 1 + ints[3] % 16,
                parallel: ints[3] % 2,
                ..<ArborWorldOptions as Growing>::defaults()
            };
            let mut world: *mut ArborWorld = std::ptr::null_mut();
            // SAFETY: local struct and out-pointer.
            let status = unsafe { arbor_world_create(&o, &mut world) };
            prop_assert!(status != ArborStatus::Panic);
            if status != ArborStatus::Ok {
                prop_assert!(!last_error().is_empty());
                prop_assert!(world.is_null());
                return Ok(());
            }
            let species = ArborGrowthParams {
                apical_control: r(10, 0.0, 1.0),
                vigor_multiplier: r(11, 0.5, 4.0),
                internode_length: r(12, 0.05, 1.0),
                branch_angle: r(13, 0.0, 90.0),
                phyllotaxis: r(14, 0.0, 360.0),
                tropism: r(15, -0.5, 0.5),
                environment_weight: r(16, 0.0, 1.0),
                pipe_exponent: r(17, 1.5, 3.5),
                tip_radius: r(18, 0.001, 0.05),
                shed_multiplier: r(19, 0.0, 0.5),
                shed_exponent: r(20, 1.0, 2.0),
                shed_delay: ints[4] % 8,
                seed_age: ints[5] % 8,
                seed_spread: r(21, 0.0, 5.0),
                perception_angle: r(22, 10.0, 180.0),
                perception_reach: r(23, 1.0, 10.0),
                occupancy_reach: r(24, 0.5, 3.0),
                max_shoot: ints[6] % 6,
                ..<ArborGrowthParams as Growing>::defaults()
            };
            let at = [r(25, -5.0, 5.0), r(26, 0.0, 0.5), r(27, -5.0, 5.0)];
            // SAFETY: `world` is live; the species and position are locals.
            let planted = unsafe {
                arbor_world_plant(world, &species, at.as_ptr(), 7, std::ptr::null_mut())
            };
            prop_assert!(planted != ArborStatus::Panic);
            prop_assert!(planted == ArborStatus::Ok || !last_error().is_empty());
            // SAFETY: `world` is live.
            let stepped = unsafe { arbor_world_step(world, cycles) };
            prop_assert!(
                stepped == ArborStatus::Ok || stepped == ArborStatus::LimitExceeded,
                "{stepped:?}: {}", last_error()
            );
            // SAFETY: `world` is live.
            let trees = unsafe { arbor_world_tree_count(world) };
            if planted == ArborStatus::Ok {
                prop_assert!(trees >= 1);
            }
            for index in 0..trees.min(2) {
                let mut tree: *mut ArborTree = std::ptr::null_mut();
                // SAFETY: `world` is live; `tree` is a local out-pointer.
                prop_assert_eq!(unsafe { arbor_world_tree(world, index, &mut tree) }, ArborStatus::Ok);
                let (mut nv, mut ni) = (0usize, 0usize);
                // SAFETY: `tree` is live; NULL options are the defaults.
                let sized = unsafe { arbor_mesh_size(tree, std::ptr::null(), &mut nv, &mut ni) };
                prop_assert_eq!(sized, ArborStatus::Ok, "{}", last_error());
                let mut v = vec![Vertex::default(); nv];
                let mut i = vec![0u32; ni];
                // SAFETY: the buffers hold exactly the sizes asked for.
                let w = unsafe {
                    arbor_mesh_write(tree, std::ptr::null(), v.as_mut_ptr(), nv, i.as_mut_ptr(), ni)
                };
                prop_assert_eq!(w, ArborStatus::Ok);
                for x in &v {
                    prop_assert!(x.position.iter().chain(&x.normal).chain(&x.uv).all(|f| f.is_finite()), "{x:?}");
                }
                // SAFETY: made above, freed once.
                unsafe { arbor_tree_free(tree) };
            }
            // SAFETY: made above, freed once.
            unsafe { arbor_world_free(world) };
        }

        /// Random leaf options (floats mostly plausible, otherwise any bit pattern; enums
        /// and sizes random, struct_size of either layout) through the instance and baked
        /// leaf entry points: a status with a message, never a panic; what is written is
        /// finite, with unit rotations.
        #[test]
        fn c_leaf_entry_points_take_any_options(
            u in prop::collection::vec(prop_oneof![15 => 0.0f32..1.0, 1 => any::<f32>()], 5),
            ints in prop::collection::vec(any::<u32>(), 6),
        ) {
            let r = |k: usize, lo: f32, hi: f32| lo + u[k] * (hi - lo);
            let o = ArborLeafOptions {
                // Sizes of either layout or below (never past the Rust value: the
                // library reads struct_size bytes of this local).
                struct_size: {
                    let size = std::mem::size_of::<ArborLeafOptions>() as u32;
                    [ARBOR_LEAF_OPTIONS_MIN_SIZE as u32, size, size, ints[5] % (size + 1)][ints[5] as usize % 4]
                },
                sites: [0, 1, 1, 1, 1, 1, 1, 2][ints[0] as usize % 8],
                polygons: [0, 1, 1, 1, 1, 1, 1, 3][ints[1] as usize % 8],
                tips: [0, 0, 0, 1, 1, 1, 1, 2][ints[2] as usize % 8],
                min_depth: ints[3] % 8,
                density: r(0, 0.0, 2.0),
                size: r(1, 0.01, 1.0),
                size_jitter: r(2, 0.0, 1.0),
                rotation_jitter: r(3, 0.0, 180.0),
                tilt: r(4, -90.0, 90.0),
                seed: u64::from(ints[4]),
                max_leaves: 100_000,
                ..<ArborLeafOptions as Growing>::defaults()
            };
            let mut p = HondaParams::zeroed();
            // SAFETY: `p` is a local struct.
            prop_assert_eq!(unsafe { arbor_honda_preset('c' as u32, &mut p) }, ArborStatus::Ok);
            p.steps = 5;
            let mut tree: *mut ArborTree = std::ptr::null_mut();
            // SAFETY: local pointers.
            prop_assert_eq!(unsafe { arbor_tree_from_honda(&p, &mut tree) }, ArborStatus::Ok);
            let refused = |status: ArborStatus| {
                status == ArborStatus::InvalidArgument || status == ArborStatus::LimitExceeded
            };
            let mut count = 0usize;
            // SAFETY: `tree` is live; the options and count are locals; NULL mesh options
            // are the defaults.
            let status = unsafe { arbor_leaf_instance_count(tree, &o, std::ptr::null(), &mut count) };
            prop_assert!(status == ArborStatus::Ok || (refused(status) && !last_error().is_empty()), "{status:?}");
            if status == ArborStatus::Ok {
                let mut out = vec![LeafInstance::default(); count];
                // SAFETY: `out` holds exactly `count` instances.
                let w = unsafe { arbor_leaf_instances_write(tree, &o, std::ptr::null(), out.as_mut_ptr(), count) };
                prop_assert_eq!(w, ArborStatus::Ok);
                for l in &out {
                    prop_assert!(l.position.iter().chain(&l.rotation).all(|f| f.is_finite()) && l.scale.is_finite(), "{l:?}");
                    let norm: f32 = l.rotation.iter().map(|x| x * x).sum();
                    prop_assert!((norm - 1.0).abs() < 1e-3, "{l:?}");
                }
            }
            let (mut nv, mut ni) = (0usize, 0usize);
            // SAFETY: as above.
            let status = unsafe { arbor_leaf_mesh_size(tree, &o, std::ptr::null(), &mut nv, &mut ni) };
            prop_assert!(status == ArborStatus::Ok || (refused(status) && !last_error().is_empty()), "{status:?}");
            if status == ArborStatus::Ok {
                let mut v = vec![Vertex::default(); nv];
                let mut i = vec![0u32; ni];
                // SAFETY: the buffers hold exactly the sizes asked for.
                let w = unsafe { arbor_leaf_mesh_write(tree, &o, std::ptr::null(), v.as_mut_ptr(), nv, i.as_mut_ptr(), ni) };
                prop_assert_eq!(w, ArborStatus::Ok);
                for x in &v {
                    prop_assert!(x.position.iter().chain(&x.normal).chain(&x.uv).all(|f| f.is_finite()), "{x:?}");
                }
                prop_assert!(i.iter().all(|&k| (k as usize) < nv));
            }
            // SAFETY: made above, freed once.
            unsafe { arbor_tree_free(tree) };
        }

        #[test]
        fn c_forest_entry_points_take_any_placements(
            u in prop::collection::vec(prop_oneof![15 => 0.0f32..1.0, 1 => any::<f32>()], 5 * 6),
            ints in prop::collection::vec(any::<u32>(), 5 * 3),
            count in 0usize..5,
        ) {
            let r = |k: usize, lo: f32, hi: f32| lo + u[k] * (hi - lo);
            let trees: Vec<ArborForestTree> = (0..count)
                .map(|t| {
                    let mut params = HondaParams::zeroed();
                    let name = b"abcdefghiz"[ints[3 * t] as usize % 10] as u32;
                    // SAFETY: `params` is a local struct; an unknown name leaves it zeroed.
                    let _ = unsafe { arbor_honda_preset(name, &mut params) };
                    params.steps = ints[3 * t + 1] % 7;
                    params.r1 = r(6 * t + 5, 0.3, 0.95);
                    ArborForestTree {
                        params,
                        seed: u64::from(ints[3 * t + 2]),
                        position: [r(6 * t, -50.0, 50.0), r(6 * t + 1, -1.0, 1.0), r(6 * t + 2, -50.0, 50.0)],
                        rotation: r(6 * t + 3, -720.0, 720.0),
                        scale: r(6 * t + 4, -0.5, 3.0),
                    }
                })
                .collect();
            let o = ArborMeshOptions {
                radial_segments: 4 + ints[0] % 4,
                ..<ArborMeshOptions as Growing>::defaults()
            };
            let (mut nv, mut ni) = (0usize, 0usize);
            // SAFETY: `trees` holds `count` placements; the counts are locals.
            let status = unsafe { arbor_forest_mesh_size(trees.as_ptr(), trees.len(), &o, &mut nv, &mut ni) };
            prop_assert!(status != ArborStatus::Panic);
            if status != ArborStatus::Ok {
                prop_assert!(!last_error().is_empty());
                return Ok(());
            }
            let mut v = vec![Vertex::default(); nv];
            let mut i = vec![0u32; ni];
            // SAFETY: the buffers hold exactly the sizes asked for.
            let w = unsafe {
                arbor_forest_mesh_write(trees.as_ptr(), trees.len(), &o, v.as_mut_ptr(), nv, i.as_mut_ptr(), ni)
            };
            prop_assert_eq!(w, ArborStatus::Ok);
            for x in &v {
                prop_assert!(x.position.iter().chain(&x.normal).chain(&x.uv).all(|f| f.is_finite()), "{x:?}");
            }
            prop_assert!(i.iter().all(|&k| k == u32::MAX || (k as usize) < nv));
        }

        #[test]
        fn c_curve_entry_points_take_any_edits(
            u in prop::collection::vec(prop_oneof![12 => -1.0f32..1.0, 1 => any::<f32>()], 16),
            ints in prop::collection::vec(any::<u32>(), 4),
        ) {
            let mut p = HondaParams::zeroed();
            // SAFETY: `p` is a local struct.
            prop_assert_eq!(unsafe { arbor_honda_preset('a' as u32, &mut p) }, ArborStatus::Ok);
            p.steps = 4;
            let mut tree: *mut ArborTree = std::ptr::null_mut();
            // SAFETY: local pointers.
            prop_assert_eq!(unsafe { arbor_tree_from_honda(&p, &mut tree) }, ArborStatus::Ok);
            // SAFETY: `tree` is live.
            let n = unsafe { arbor_tree_branch_count(tree) };
            // SAFETY: `tree` is live; a wild tension is refused, not a panic.
            let smooth = unsafe { arbor_tree_smooth(tree, u[15] * 3.0) };
            prop_assert!(smooth != ArborStatus::Panic);
            let mut curves = vec![ArborCurve::default(); n];
            // SAFETY: `curves` holds `n` curves.
            prop_assert_eq!(unsafe { arbor_tree_copy_curves(tree, curves.as_mut_ptr(), n) }, ArborStatus::Ok);
            // An edit of a branch (or one past the end): p0 kept or moved, the rest wild.
            let branch = ints[0] as usize % (n + 2);
            let mut c = curves.get(branch).copied().unwrap_or_default();
            let scale = 50.0;
            for (k, q) in [&mut c.p1, &mut c.p2, &mut c.p3].into_iter().enumerate() {
                for (j, x) in q.iter_mut().enumerate() {
                    *x += u[3 * k + j] * scale;
                }
            }
            if ints[1] % 4 == 0 {
                c.p0[0] += u[9];
            }
            c.r0 = u[10] * 5.0;
            c.r1 = u[11] * 5.0;
            // SAFETY: `tree` is live; `c` is a local.
            let set = unsafe { arbor_tree_set_curve(tree, branch, &c) };
            prop_assert!(set != ArborStatus::Panic);
            prop_assert!(set == ArborStatus::Ok || !last_error().is_empty());
            // Whatever happened, the tree meshes with finite values, and a rewrite of the
            // edited branch equals a full write.
            let o = ArborMeshOptions {
                curve_rings: ints[2] % 4,
                radial_segments: 3 + ints[3] % 6,
                ..<ArborMeshOptions as Growing>::defaults()
            };
            let (mut nv, mut ni) = (0usize, 0usize);
            // SAFETY: `tree` is live; the counts are locals.
            let size = unsafe { arbor_mesh_size(tree, &o, &mut nv, &mut ni) };
            prop_assert!(size == ArborStatus::Ok || !last_error().is_empty(), "{size:?}");
            if size == ArborStatus::Ok {
                let mut v = vec![Vertex::default(); nv];
                let mut i = vec![0u32; ni];
                // SAFETY: the buffers hold exactly the sizes asked for.
                prop_assert_eq!(unsafe { arbor_mesh_write(tree, &o, v.as_mut_ptr(), nv, i.as_mut_ptr(), ni) }, ArborStatus::Ok);
                for x in &v {
                    prop_assert!(x.position.iter().chain(&x.normal).chain(&x.uv).all(|f| f.is_finite()), "{x:?}");
                }
                if branch < n {
                    let (mut v2, mut i2) = (v.clone(), i.clone());
                    // SAFETY: the buffers hold the whole mesh of `tree` with `o`.
                    let rw = unsafe {
                        arbor_mesh_rewrite_branch(tree, &o, branch, v2.as_mut_ptr(), nv, i2.as_mut_ptr(), ni)
                    };
                    prop_assert_eq!(rw, ArborStatus::Ok);
                    prop_assert!(v2 == v && i2 == i, "a rewrite equals the full write");
                }
            }
            // SAFETY: made above, freed once.
            unsafe { arbor_tree_free(tree) };
        }
    }
}

/// The init function a struct-size error names is the header's.
#[test]
fn struct_size_errors_name_the_headers_init_function() {
    let header = include_str!("../../include/arbor.h");
    for name in [
        super::options::init_name::<ArborMeshOptions>(),
        super::options::init_name::<ArborLsystemOptions>(),
        super::options::init_name::<ArborLeafOptions>(),
        super::options::init_name::<ArborWorldOptions>(),
        super::options::init_name::<ArborGrowthParams>(),
    ] {
        let function = name.trim_end_matches("()");
        assert!(
            header.contains(&format!("void {function}(")),
            "{name} is not in the header"
        );
    }
}

/// `ArborWorldOptions.parallel` is a flag: 0 and 1 make a world, anything else is refused
/// by name (the same rule and message as every flag of a C struct).
#[test]
fn world_parallel_is_a_flag() {
    for (parallel, ok) in [(0, true), (1, true), (2, false), (u32::MAX, false)] {
        let o = ArborWorldOptions {
            parallel,
            ..<ArborWorldOptions as Growing>::defaults()
        };
        let mut world: *mut ArborWorld = std::ptr::null_mut();
        // SAFETY: local struct and out-pointer.
        let status = unsafe { arbor_world_create(&o, &mut world) };
        assert_eq!(status == ArborStatus::Ok, ok, "parallel = {parallel}");
        if ok {
            // SAFETY: made above, freed once.
            unsafe { arbor_world_free(world) };
        } else {
            assert_eq!(status, ArborStatus::InvalidArgument);
            assert!(world.is_null());
            let e = last_error();
            assert!(
                e.contains("parallel") && e.contains("expected 0 (false) or 1 (true)"),
                "{e}"
            );
        }
    }
}
