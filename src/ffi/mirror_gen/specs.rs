//! What each C mirror has beyond its Rust struct: its documentation, the fields only C has
//! (`struct_size` aside), renamed fields, and C documentation where the Rust one, translated,
//! is not what a C user reads.

use super::{COnly, RustOnly, Spec};

/// Every growing option struct's C mirror, in the order of `mirrors.rs`.
pub(super) const SPECS: &[Spec] = &[
    Spec {
        c: "ArborMeshOptions",
        rust: "crate::mesh::MeshOptions",
        fields: crate::mesh::MeshOptions::FIELDS,
        doc: "Options of the tube mesher: a struct that grows (see \"Structs that grow\" in docs/c-api.md). Start from arbor_mesh_options_default() (or arbor_mesh_options_init()) and change what you need. Enum-like fields are validated (unknown values give ARBOR_STATUS_INVALID_ARGUMENT naming the field).",
        derive: "Clone, Copy, Debug",
        c_only: &[
            COnly {
                name: "threads",
                ty: "u32",
                doc: "Threads a large write may use: 0 (default) all cores (at most 8), 1 only the calling thread. Trees under 16,384 branches per thread use fewer. Sizing a tree of 32,768 branches or more takes two when this allows more than one. The output is the same whatever the count. (Added after the first layout.)",
                value: "0",
                computed: false,
            },
            COnly {
                name: "progress",
                ty: "ArborProgressFn",
                doc: "Called while a mesh is written (arbor_mesh_write, arbor_mesh_create, arbor_forest_mesh_write, arbor_export_obj, arbor_export_gltf): ARBOR_STAGE_MESH with the fraction of branches written, after every 65,536 branches and at the end, on the calling thread; non-zero stops with ARBOR_STATUS_CANCELLED (the buffers then hold a partial mesh; an export writes no file). NULL (default): none. (Added after the first layout.)",
                value: "None",
                computed: false,
            },
            COnly {
                name: "progress_user_data",
                ty: "*mut c_void",
                doc: "Passed to `progress`. (Added after the first layout.)",
                value: "std::ptr::null_mut()",
                computed: false,
            },
        ],
        renamed: &[],
        rust_only: &[],
        c_types: &[],
        c_docs: &[
            (
                "struct_size",
                "sizeof(ArborMeshOptions) as the host was compiled; set by arbor_mesh_options_init().",
            ),
            (
                "radial_segments",
                "Sides of each truncated cone, 3..=64 (the most, with LOD). Default 8.",
            ),
            (
                "topology",
                "An ArborTopology value. Default ARBOR_TOPOLOGY_TRIANGLE_LIST.",
            ),
            (
                "min_radial_segments",
                "0 (default): no LOD. Else a branch gets ceil(radial_segments * r / r_max) sides, clamped to min_radial_segments..=radial_segments (r: its larger radius, r_max: the tree's largest).",
            ),
            (
                "cull_radius",
                "Branches whose larger radius is below this are dropped with their subtree. Default 0.",
            ),
            (
                "joints",
                "An ArborJoints value. Default ARBOR_JOINTS_MITRED.",
            ),
            (
                "smooth_taper",
                "1: a branch's end radius becomes its continuation's start radius. Default 0.",
            ),
            (
                "base_cap",
                "1: a disc closes the base of each root. Default 0.",
            ),
            ("tip", "An ArborTip value. Default ARBOR_TIP_OPEN."),
            (
                "texture_scale",
                "v = arc length from the root / texture_scale; finite, > 0. Default 1.",
            ),
            (
                "winding",
                "An ArborWinding value. Default ARBOR_WINDING_COUNTER_CLOCKWISE.",
            ),
            ("up_axis", "An ArborUpAxis value. Default ARBOR_UP_AXIS_Y."),
            (
                "scale",
                "Uniform scale of positions; finite, > 0. Default 1.",
            ),
            (
                "max_vertices",
                "Sizing or writing a mesh of more vertices than this stops with ARBOR_STATUS_LIMIT_EXCEEDED naming max_vertices, before any memory is spent. Default 4,294,967,295 (what 32-bit indices address). (Added after the first layout.)",
            ),
            (
                "curve_rings",
                "Extra rings inside every branch along its curve, 0..=64: 0 (default) one cone per branch, exactly as without curves; k >= 1 a sweep with k inner rings, rotation-minimising frames, interpolated radii and v by arc length. (Added after the first layout.)",
            ),
            (
                "axes",
                "An ArborAxes value: ARBOR_AXES_UNITY or ARBOR_AXES_UNREAL set the axes, units and winding of that engine (then up_axis and winding must stay at their defaults, and scale applies first). Default ARBOR_AXES_ARBOR. (Added after the first layout.)",
            ),
            (
                "vertex_format",
                "An ArborVertexFormat value: ARBOR_VERTEX_FORMAT_F32 (ArborVertex, 32 bytes; the default) or ARBOR_VERTEX_FORMAT_COMPACT (ArborVertexCompact, 20 bytes), which only arbor_mesh_write_bytes() writes. (Added after the first layout.)",
            ),
        ],
    },
    Spec {
        c: "ArborLsystemOptions",
        rust: "crate::lsystem::LsystemOptions",
        fields: crate::lsystem::LsystemOptions::FIELDS,
        doc: "Options of arbor_tree_from_lsystem(): a struct that grows (see \"Structs that grow\" in docs/c-api.md). Start from arbor_lsystem_options_default() (or arbor_lsystem_options_init()) and change what you need.",
        derive: "Clone, Copy, Debug",
        c_only: &[
            COnly {
                name: "override_flags",
                ty: "u32",
                doc: "ARBOR_OVERRIDE_* bits saying which of the three settings below replace the grammar's directives. Default 0 (none).",
                value: "ArborLsystemOptions::override_flags_of(r)",
                computed: true,
            },
            COnly {
                name: "angle_increment",
                ty: "f32",
                doc: "Degrees turned by + - & ^ / \\ without a parameter (`angle increment:`).",
                value: "ArborLsystemOptions::setting_of(r.angle_increment, |v| v.angle_increment)",
                computed: true,
            },
            COnly {
                name: "initial_width",
                ty: "f32",
                doc: "The turtle's starting width (`initial line width:`), a diameter.",
                value: "ArborLsystemOptions::setting_of(r.initial_width, |v| v.initial_width)",
                computed: true,
            },
            COnly {
                name: "width_increment",
                ty: "f32",
                doc: "What ! and # without a parameter subtract and add (`line width increment:`).",
                value: "ArborLsystemOptions::setting_of(r.width_increment, |v| v.width_increment)",
                computed: true,
            },
            COnly {
                name: "view_path",
                ty: "*const c_char",
                doc: "arbor_tree_from_lsystem_file(): the view file to read (NUL-terminated UTF-8 path); NULL (default): the `.v` file beside the grammar with the same stem, if any. (Added after the first layout.)",
                value: "std::ptr::null()",
                computed: false,
            },
            COnly {
                name: "view_text",
                ty: "*const c_char",
                doc: "arbor_tree_from_lsystem(): the text of the grammar's view file (NUL-terminated UTF-8), applied as cpfg applies a `.v` file; NULL (default): none. (Added after the first layout.)",
                value: "std::ptr::null()",
                computed: false,
            },
            COnly {
                name: "progress",
                ty: "ArborProgressFn",
                doc: "Called during derivation and interpretation (ARBOR_STAGE_DERIVATION at every step and every 65,536 modules, ARBOR_STAGE_INTERPRETATION every 65,536 modules) on the calling thread; non-zero stops with ARBOR_STATUS_CANCELLED. NULL (default): none. (Added after the first layout.)",
                value: "None",
                computed: false,
            },
            COnly {
                name: "progress_user_data",
                ty: "*mut c_void",
                doc: "Passed to `progress`. (Added after the first layout.)",
                value: "std::ptr::null_mut()",
                computed: false,
            },
            COnly {
                name: "file_access",
                ty: "u32",
                doc: "Which files the model may read (ArborFileAccess): arbor_tree_from_lsystem_file()'s `#include`s, the `.v` beside the grammar and the view file's `function:`, `function set:`, `curve:` and `surface:` files. Default ARBOR_FILE_ACCESS_BUNDLE (the model's folder). (Added after the first layout.)",
                value: "ArborFileAccess::Bundle as u32",
                computed: false,
            },
            COnly {
                name: "read_file",
                ty: "ArborReadFileFn",
                doc: "The host's reader for ARBOR_FILE_ACCESS_HOST (then it also reads the model file and `view_path`); NULL (default) otherwise. (Added after the first layout.)",
                value: "None",
                computed: false,
            },
            COnly {
                name: "read_file_user_data",
                ty: "*mut c_void",
                doc: "Passed to `read_file`. (Added after the first layout.)",
                value: "std::ptr::null_mut()",
                computed: false,
            },
            COnly {
                name: "max_file_bytes",
                ty: "u64",
                doc: "Bytes read over all files of one load; past it the load stops with ARBOR_STATUS_LIMIT_EXCEEDED naming max_file_bytes. Default 67,108,864 (64 MiB). (Added after the first layout.)",
                value: "crate::files::DEFAULT_MAX_FILE_BYTES",
                computed: false,
            },
        ],
        renamed: &[],
        rust_only: &[
            RustOnly {
                name: "angle_increment",
                value: "c.overridden(ARBOR_OVERRIDE_ANGLE_INCREMENT, c.angle_increment)?",
                computed: true,
            },
            RustOnly {
                name: "initial_width",
                value: "c.overridden(ARBOR_OVERRIDE_INITIAL_WIDTH, c.initial_width)?",
                computed: true,
            },
            RustOnly {
                name: "width_increment",
                value: "c.overridden(ARBOR_OVERRIDE_WIDTH_INCREMENT, c.width_increment)?",
                computed: true,
            },
        ],
        c_types: &[],
        c_docs: &[
            (
                "struct_size",
                "sizeof(ArborLsystemOptions) as the host was compiled; set by arbor_lsystem_options_init().",
            ),
            (
                "steps",
                "Rewriting steps; < 0 (default -1): the grammar's own `derivation length:`.",
            ),
            (
                "seed",
                "Seed of stochastic productions, ran() and nran(), used when the grammar has no `seed:`. Default 0.",
            ),
            (
                "max_modules",
                "Derivation stops with ARBOR_STATUS_LIMIT_EXCEEDED before a string would pass this many modules (also bounds what the turtle reads after interpretation rules). Default 16,777,216.",
            ),
            (
                "max_params",
                "Same for the parameter values of a string. Default 33,554,432.",
            ),
            (
                "max_branches",
                "Same for the branches of the tree. Default 16,777,216.",
            ),
            (
                "turn_jitter",
                "Each turn is off by a random amount up to +- this many degrees (seeded). Default 0.",
            ),
            (
                "variation_seed",
                "0 (default): the grammar's `seed:` (else `seed`) as written. Otherwise mixed into that seed, so each value grows a distinct plant even from a file that fixes its `seed:` (a forest of one grammar). (Added after the first layout.)",
            ),
            (
                "max_work",
                "One work budget, in units, for everything a derivation and its interpretation do (rewriting, decomposition, interpretation rules, statements, queries; see docs/c-api.md, \"Robustness\"): past it the load stops with ARBOR_STATUS_LIMIT_EXCEEDED naming max_work, and `progress` hears the work every 2^20 units. Default 268,435,456 (at most about 1.3 s on a 2-core x86-64 machine). (Added after the first layout.)",
            ),
        ],
    },
    Spec {
        c: "ArborLeafOptions",
        rust: "crate::mesh::LeafOptions",
        fields: crate::mesh::LeafOptions::FIELDS,
        doc: "Where leaves go and how they vary: a struct that grows (see \"Structs that grow\" in docs/c-api.md). Start from arbor_leaf_options_default() (or arbor_leaf_options_init()).",
        derive: "Clone, Copy, Debug",
        c_only: &[
            COnly {
                name: "prefab_obj_path",
                ty: "*const c_char",
                doc: "NUL-terminated UTF-8 path of an OBJ file whose triangles are the baked leaf shape (+Y along the blade, +Z its face); NULL (default) for a 0.5 x 1 quad. Read by each leaf-mesh call (to read it once, load it into `prefab` instead); ARBOR_STATUS_IO_ERROR if it cannot be loaded.",
                value: "std::ptr::null()",
                computed: false,
            },
            COnly {
                name: "file_access",
                ty: "u32",
                doc: "How `prefab_obj_path` is read (ArborFileAccess): ARBOR_FILE_ACCESS_HOST reads it through `read_file`; every other policy reads it from disk as a regular file (never a device or FIFO), its `mtllib` never. Default ARBOR_FILE_ACCESS_BUNDLE. (Added after the first layout.)",
                value: "ArborFileAccess::Bundle as u32",
                computed: false,
            },
            COnly {
                name: "read_file",
                ty: "ArborReadFileFn",
                doc: "The host's reader for ARBOR_FILE_ACCESS_HOST; NULL (default) otherwise. (Added after the first layout.)",
                value: "None",
                computed: false,
            },
            COnly {
                name: "read_file_user_data",
                ty: "*mut c_void",
                doc: "Passed to `read_file`. (Added after the first layout.)",
                value: "std::ptr::null_mut()",
                computed: false,
            },
            COnly {
                name: "max_file_bytes",
                ty: "u64",
                doc: "Most bytes of the prefab read; past it ARBOR_STATUS_LIMIT_EXCEEDED naming max_file_bytes. Default 67,108,864 (64 MiB). (Added after the first layout.)",
                value: "crate::files::DEFAULT_MAX_FILE_BYTES",
                computed: false,
            },
            COnly {
                name: "prefab",
                ty: "*const ArborLeafPrefab",
                doc: "A leaf shape loaded once with arbor_leaf_prefab_load(), used by every call without reading its file again (set this or `prefab_obj_path`, not both); it must outlive the calls. NULL (default): none. (Added after the first layout.)",
                value: "std::ptr::null()",
                computed: false,
            },
        ],
        renamed: &[("min_depth", "min_birth")],
        rust_only: &[RustOnly {
            name: "prefab",
            value: "None",
            computed: false,
        }],
        c_types: &[],
        c_docs: &[
            (
                "struct_size",
                "sizeof(ArborLeafOptions) as the host was compiled; set by arbor_leaf_options_init().",
            ),
            (
                "sites",
                "1: a leaf at every `~` site of the grammar. Default 1.",
            ),
            (
                "polygons",
                "1: the grammar's `{ . }` polygons go into the baked leaf mesh. Default 1.",
            ),
            (
                "tips",
                "1: leaves at the tips of terminal branches. Default 0.",
            ),
            (
                "min_depth",
                "Only tips of branches made at this rewriting step or later (their `depth`, the birth step) get leaves. Default 0.",
            ),
            (
                "density",
                "Expected leaves per tip (whole part always, fraction by chance), 0..=64. Default 1.",
            ),
            ("size", "Leaf size in model units; > 0. Default 1."),
            (
                "size_jitter",
                "Size varies by up to +- this fraction, in [0, 1). Default 0.2.",
            ),
            (
                "rotation_jitter",
                "Each leaf turns about its stem by up to +- this many degrees. Default 180.",
            ),
            (
                "tilt",
                "Tip leaves lean out from the branch by this many degrees. Default 30.",
            ),
            (
                "max_leaves",
                "Making more leaves than this (instances, or copies in the baked mesh) stops with ARBOR_STATUS_LIMIT_EXCEEDED naming max_leaves before their memory is spent. Default 16,777,216. (Added after the first layout.)",
            ),
        ],
    },
    Spec {
        c: "ArborWorldOptions",
        rust: "crate::models::growth::WorldOptions",
        fields: crate::models::growth::WorldOptions::FIELDS,
        doc: "Options of a world: a struct that grows (see \"Structs that grow\" in docs/c-api.md). Start from arbor_world_options_default() (or arbor_world_options_init()).",
        derive: "Clone, Copy, Debug",
        c_only: &[
            COnly {
                name: "parallel",
                ty: "u32",
                doc: "1 (default): grow the trees of a cycle and update the shadow grid on all cores when arbor is built with its `parallel` feature (the result is identical; a world under 4,096 internodes stays on the calling thread); 0: the calling thread only.",
                value: "1",
                computed: false,
            },
            COnly {
                name: "progress",
                ty: "ArborProgressFn",
                doc: "Called by arbor_world_step() before every cycle and at the end (ARBOR_STAGE_GROWTH, the fraction of the cycles asked), on the calling thread; non-zero stops with ARBOR_STATUS_CANCELLED before the next cycle (the world as it was after the last whole cycle). NULL (default): none. (Added after the first layout.)",
                value: "None",
                computed: false,
            },
            COnly {
                name: "progress_user_data",
                ty: "*mut c_void",
                doc: "Passed to `progress`. (Added after the first layout.)",
                value: "std::ptr::null_mut()",
                computed: false,
            },
        ],
        renamed: &[],
        rust_only: &[],
        c_types: &[("max_trees", "u32")],
        c_docs: &[
            (
                "struct_size",
                "sizeof(ArborWorldOptions) as the host was compiled; set by arbor_world_options_init().",
            ),
            (
                "environment",
                "An ArborEnvironment value. Default ARBOR_ENVIRONMENT_SHADOW.",
            ),
            (
                "cell_size",
                "Voxel edge (shadow) or marker spacing (colonization), > 0. Default 0.25.",
            ),
            (
                "shadow_strength",
                "Shadow a bud casts (a), > 0. Default 0.2.",
            ),
            (
                "shadow_falloff",
                "Falloff per layer below a bud (b > 1). Default 2.",
            ),
            (
                "shadow_depth",
                "Layers of the shadow pyramid (q_max), 0..=16. Default 5.",
            ),
            ("full_light", "Full exposure (C), > 0. Default 1.5."),
            (
                "max_cells",
                "Most grid cells (4 bytes each; never more than 2^31): a finer box is ARBOR_STATUS_LIMIT_EXCEEDED naming max_cells, and so is a step, plant or obstacle whose shadow would need more (the shadow grid grows with what is shaded). Default 33,554,432.",
            ),
            (
                "max_branches",
                "Growth stops with ARBOR_STATUS_LIMIT_EXCEEDED before the world's internodes pass this. Default 16,777,216.",
            ),
            (
                "max_trees",
                "Most trees (seeding stops there). Default 1,024.",
            ),
        ],
    },
    Spec {
        c: "ArborLodOptions",
        rust: "crate::lod::LodOptions",
        fields: crate::lod::LodOptions::FIELDS,
        doc: "How a chain of levels of detail is made (arbor_tree_lods_create()): a struct that grows (see \"Structs that grow\" in docs/c-api.md). Start from arbor_lod_options_default() (or arbor_lod_options_init()).",
        derive: "Clone, Copy, Debug",
        c_only: &[],
        renamed: &[],
        rust_only: &[],
        c_types: &[],
        c_docs: &[(
            "struct_size",
            "sizeof(ArborLodOptions) as the host was compiled; set by arbor_lod_options_init().",
        )],
    },
    Spec {
        c: "ArborGrowthParams",
        rust: "crate::models::growth::GrowthParams",
        fields: crate::models::growth::GrowthParams::FIELDS,
        doc: "One species: how a tree grows. The defaults are the excurrent species' values with neutral apical control. Lengths are world units, angles degrees.  A struct that grows (see \"Structs that grow\" in docs/c-api.md): start from arbor_growth_params_default() or arbor_growth_params_preset().",
        derive: "Clone, Copy, Debug, PartialEq",
        c_only: &[],
        renamed: &[],
        rust_only: &[],
        c_types: &[],
        c_docs: &[(
            "struct_size",
            "sizeof(ArborGrowthParams) as the host was compiled; set by arbor_growth_params_init().",
        )],
    },
];
