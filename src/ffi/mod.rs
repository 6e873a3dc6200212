//! The C ABI: the only module with `unsafe` code.
//!
//! `include/arbor.h` is generated from this module by cbindgen (see `cbindgen.toml`) and
//! committed; a test regenerates it and fails on any difference. Each export is a thin
//! shell: argument checks, a panic guard, conversion, then a call into the Rust API.
//!
//! Rust users do not need this module; it is public so that its documentation and the
//! layouts it fixes can be read here too.

mod guard;

use crate::lsystem::{LSystem, LsystemOptions, MAX_SOURCE_BYTES};
use crate::mesh::{
    self, BranchRange, LeafInstance, LeafOptions, LeafPrefab, MeshOptions, Topology, Vertex,
};
use crate::models::honda::{self, HondaParams};
use crate::skeleton::{Branch, Skeleton};
use bytemuck::{Pod, Zeroable};
use guard::{FfiError, arg_ref, guard, guard_value, in_slice, out_ref, out_slice, with_last_error};
use std::ffi::{CStr, c_char};

/// Major version of the library this header belongs to.
pub const ARBOR_VERSION_MAJOR: u32 = 0;
/// Minor version of the library this header belongs to.
pub const ARBOR_VERSION_MINOR: u32 = 1;
/// Patch version of the library this header belongs to.
pub const ARBOR_VERSION_PATCH: u32 = 0;
/// ABI version of this header: MAJOR * 10000 + MINOR * 100 + PATCH. It only grows; a host
/// built against ABI version N runs with a library whose `arbor_abi_version()` >= N.
pub const ARBOR_ABI_VERSION: u32 = 100;
/// Index that separates strips in ARBOR_TOPOLOGY_TRIANGLE_STRIP_RESTART output (OpenGL's
/// GL_PRIMITIVE_RESTART_FIXED_INDEX for 32-bit indices).
pub const ARBOR_RESTART_INDEX: u32 = u32::MAX;
/// `ArborBranch.parent` of a root branch.
pub const ARBOR_NO_PARENT: u32 = u32::MAX;

/// Result of every fallible function. The numbers are fixed forever and never reused.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArborStatus {
    /// Success; out-parameters were written.
    Ok = 0,
    /// A required pointer argument was NULL.
    NullArgument = 1,
    /// An argument is out of range: NaN, infinity, negative size, unknown enum value or
    /// preset name, misaligned pointer.
    InvalidArgument = 2,
    /// Grammar text could not be parsed (the message has line, column and what was
    /// expected).
    ParseError = 3,
    /// The output would pass a limit (branches, modules, vertices); nothing was built.
    LimitExceeded = 4,
    /// A caller buffer is smaller than the size query said; nothing was written.
    BufferTooSmall = 5,
    /// A file could not be read or written.
    IoError = 6,
    /// An internal error (a Rust panic) was caught; please report it with the message.
    Panic = 7,
}

/// How indices string triangles together; passed as `uint32_t` in ArborMeshOptions.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArborTopology {
    /// Three indices per triangle (Unity, Unreal, glDrawElements(GL_TRIANGLES)).
    TriangleList = 0,
    /// One strip per branch, strips separated by ARBOR_RESTART_INDEX; draw with
    /// GL_TRIANGLE_STRIP and glEnable(GL_PRIMITIVE_RESTART_FIXED_INDEX).
    TriangleStripRestart = 1,
    /// One strip for the whole mesh, branches joined by degenerate triangles.
    TriangleStripDegenerate = 2,
}

/// A generated tree (its branch skeleton). Opaque; create with arbor_tree_from_honda() or
/// arbor_tree_from_lsystem(), free with arbor_tree_free(). A `const ArborTree *` may be
/// read from several threads at once.
pub struct ArborTree {
    skeleton: Skeleton,
}

/// Parameters of the 1996 Prusinkiewicz, Hammel, Hanan & Mech branching model (trees a-i).
/// Lengths in model units, widths are diameters, angles in degrees.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ArborHondaParams {
    /// s0: trunk length (100 in the paper); finite, > 0.
    pub trunk_length: f32,
    /// w0: trunk width, a diameter; finite, > 0.
    pub trunk_width: f32,
    /// Length ratio of the first child; finite, > 0.
    pub r1: f32,
    /// Length ratio of the second child; finite, > 0.
    pub r2: f32,
    /// Branching angle of the first child (turtle `+`), degrees; finite.
    pub alpha1: f32,
    /// Branching angle of the second child (turtle `+`), degrees; finite.
    pub alpha2: f32,
    /// Divergence angle of the first child (turtle `/`), degrees; finite.
    pub phi1: f32,
    /// Divergence angle of the second child (turtle `/`), degrees; finite.
    pub phi2: f32,
    /// Width share of the first child, 0 <= q <= 1.
    pub q: f32,
    /// Width exponent, finite, >= 0: children widths are w*q^e and w*(1-q)^e.
    pub e: f32,
    /// An apex grows only while its length s >= min_length; finite, >= 0.
    pub min_length: f32,
    /// Derivation length n (the axiom is step 0), at most 1024.
    pub steps: u32,
}

// The two structs share one layout (asserted below), so they convert by a plain cast.
impl From<ArborHondaParams> for HondaParams {
    fn from(p: ArborHondaParams) -> Self {
        bytemuck::cast(p)
    }
}

impl From<HondaParams> for ArborHondaParams {
    fn from(p: HondaParams) -> Self {
        bytemuck::cast(p)
    }
}

/// One internode (one turtle F), 48 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ArborBranch {
    /// Start point (x, y, z), Y up; equal to the parent's `end`.
    pub start: [f32; 3],
    /// End point (x, y, z).
    pub end: [f32; 3],
    /// Radius at `start` (half the turtle width).
    pub start_radius: f32,
    /// Radius at `end`.
    pub end_radius: f32,
    /// Index of the branch it grows from (always smaller than its own index);
    /// ARBOR_NO_PARENT for a root.
    pub parent: u32,
    /// The rewriting step that produced it; axiom modules are 0, so the 1996 trunk has 1.
    pub depth: u32,
    /// Branching order: 0 on the trunk axis, +1 per lateral branch.
    pub order: u32,
    /// Reserved, 0.
    pub flags: u32,
}

/// One mesh vertex, 32 bytes, interleaved: position at offset 0, normal at 12, uv at 24.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ArborVertex {
    /// Position in model units.
    pub position: [f32; 3],
    /// Unit outward normal.
    pub normal: [f32; 3],
    /// u around the branch (0..1, seam vertex duplicated), v along it (0 at start, 1 at end).
    pub uv: [f32; 2],
}

/// ArborLsystemOptions.override_flags bit: use `angle_increment` instead of the grammar's.
pub const ARBOR_OVERRIDE_ANGLE_INCREMENT: u32 = 1;
/// ArborLsystemOptions.override_flags bit: use `initial_width` instead of the grammar's.
pub const ARBOR_OVERRIDE_INITIAL_WIDTH: u32 = 2;
/// ArborLsystemOptions.override_flags bit: use `width_increment` instead of the grammar's.
pub const ARBOR_OVERRIDE_WIDTH_INCREMENT: u32 = 4;

/// Options of arbor_tree_from_lsystem(). Get defaults from arbor_lsystem_options_default()
/// and change what you need: fields may be added at the end in later versions.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArborLsystemOptions {
    /// Rewriting steps; < 0 (default -1): the grammar's own `derivation length:`.
    pub steps: i32,
    /// Seed of stochastic productions, ran() and nran(), used when the grammar has no
    /// `seed:`. Default 0.
    pub seed: u64,
    /// Derivation stops with ARBOR_STATUS_LIMIT_EXCEEDED before a string would pass this
    /// many modules (also bounds what the turtle reads after interpretation rules).
    /// Default 16,777,216.
    pub max_modules: u64,
    /// Same for the parameter values of a string. Default 33,554,432.
    pub max_params: u64,
    /// Same for the branches of the tree. Default 16,777,216.
    pub max_branches: u64,
    /// ARBOR_OVERRIDE_* bits saying which of the three settings below replace the
    /// grammar's directives. Default 0 (none).
    pub override_flags: u32,
    /// Degrees turned by + - & ^ / \ without a parameter (`angle increment:`).
    pub angle_increment: f32,
    /// The turtle's starting width (`initial line width:`), a diameter.
    pub initial_width: f32,
    /// What ! and # without a parameter subtract and add (`line width increment:`).
    pub width_increment: f32,
    /// Each turn is off by a random amount up to +- this many degrees (seeded). Default 0.
    pub turn_jitter: f32,
}

impl ArborLsystemOptions {
    fn to_rust(self) -> crate::Result<LsystemOptions> {
        let known = ARBOR_OVERRIDE_ANGLE_INCREMENT
            | ARBOR_OVERRIDE_INITIAL_WIDTH
            | ARBOR_OVERRIDE_WIDTH_INCREMENT;
        if self.override_flags & !known != 0 {
            return Err(crate::Error::invalid(
                "override_flags",
                format!(
                    "{:#x} has unknown bits; expected a combination of ARBOR_OVERRIDE_*",
                    self.override_flags
                ),
            ));
        }
        let flag = |bit: u32, v: f32| (self.override_flags & bit != 0).then_some(v as f64);
        let size = |v: u64| usize::try_from(v).unwrap_or(usize::MAX);
        Ok(LsystemOptions {
            steps: u32::try_from(self.steps).ok(),
            seed: self.seed,
            max_modules: size(self.max_modules),
            max_params: size(self.max_params),
            max_branches: size(self.max_branches),
            angle_increment: flag(ARBOR_OVERRIDE_ANGLE_INCREMENT, self.angle_increment),
            initial_width: flag(ARBOR_OVERRIDE_INITIAL_WIDTH, self.initial_width),
            width_increment: flag(ARBOR_OVERRIDE_WIDTH_INCREMENT, self.width_increment),
            turn_jitter: self.turn_jitter as f64,
        })
    }
}

/// Joints between a branch and the one it continues; ArborMeshOptions.joints.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArborJoints {
    /// Every branch has its own two rings.
    Separate = 0,
    /// A continuing branch shares its parent's end ring, in the bisecting plane
    /// (watertight axes). The default.
    Mitred = 1,
}

/// How the last branch of an axis ends; ArborMeshOptions.tip.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArborTip {
    /// Open tube (default).
    Open = 0,
    /// A flat disc.
    Cap = 1,
    /// A cone closing to a point one radius beyond the end.
    Point = 2,
}

/// Front-face winding seen from outside; ArborMeshOptions.winding.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArborWinding {
    /// Counter-clockwise (OpenGL; the default).
    CounterClockwise = 0,
    /// Clockwise (Unity, Direct3D).
    Clockwise = 1,
}

/// Up axis of the output; ArborMeshOptions.up_axis.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArborUpAxis {
    /// Y up (default).
    Y = 0,
    /// Z up (Unreal): (x, y, z) becomes (x, -z, y), a rotation that keeps the winding.
    Z = 1,
}

/// Options of the tube mesher. Get defaults from arbor_mesh_options_default() and change
/// what you need: fields may be added at the end in later versions. Enum-like fields are
/// validated (unknown values give ARBOR_STATUS_INVALID_ARGUMENT naming the field).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArborMeshOptions {
    /// Sides of each truncated cone, 3..=64 (the most, with LOD). Default 8.
    pub radial_segments: u32,
    /// An ArborTopology value. Default ARBOR_TOPOLOGY_TRIANGLE_LIST.
    pub topology: u32,
    /// 0 (default): no LOD. Else a branch gets ceil(radial_segments * r / r_max) sides,
    /// clamped to min_radial_segments..=radial_segments (r: its larger radius, r_max: the
    /// tree's largest).
    pub min_radial_segments: u32,
    /// Branches whose larger radius is below this are dropped with their subtree. Default 0.
    pub cull_radius: f32,
    /// An ArborJoints value. Default ARBOR_JOINTS_MITRED.
    pub joints: u32,
    /// 1: a branch's end radius becomes its continuation's start radius. Default 0.
    pub smooth_taper: u32,
    /// 1: a disc closes the base of each root. Default 0.
    pub base_cap: u32,
    /// An ArborTip value. Default ARBOR_TIP_OPEN.
    pub tip: u32,
    /// v = arc length from the root / texture_scale; finite, > 0. Default 1.
    pub texture_scale: f32,
    /// An ArborWinding value. Default ARBOR_WINDING_COUNTER_CLOCKWISE.
    pub winding: u32,
    /// An ArborUpAxis value. Default ARBOR_UP_AXIS_Y.
    pub up_axis: u32,
    /// Uniform scale of positions; finite, > 0. Default 1.
    pub scale: f32,
}

/// The vertices and indices one branch owns in a mesh (see arbor_mesh_branch_ranges()).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct ArborBranchRange {
    /// First vertex the branch owns.
    pub first_vertex: u32,
    /// Number of vertices it owns (0 for a culled branch).
    pub vertex_count: u32,
    /// First index it owns (restart or join indices before its strips included).
    pub first_index: u32,
    /// Number of indices it owns.
    pub index_count: u32,
}

const _: () = {
    assert!(std::mem::size_of::<ArborBranch>() == std::mem::size_of::<Branch>());
    assert!(std::mem::align_of::<ArborBranch>() == std::mem::align_of::<Branch>());
    assert!(std::mem::size_of::<ArborVertex>() == std::mem::size_of::<Vertex>());
    assert!(std::mem::align_of::<ArborVertex>() == std::mem::align_of::<Vertex>());
    assert!(std::mem::size_of::<ArborHondaParams>() == std::mem::size_of::<HondaParams>());
    assert!(std::mem::size_of::<ArborBranchRange>() == std::mem::size_of::<BranchRange>());
    assert!(std::mem::size_of::<ArborLeafInstance>() == std::mem::size_of::<LeafInstance>());
};

fn enum_field<T: Copy>(field: &'static str, value: u32, all: &[(T, &str)]) -> crate::Result<T> {
    all.get(value as usize).map(|&(v, _)| v).ok_or_else(|| {
        let names: Vec<String> = all
            .iter()
            .enumerate()
            .map(|(i, (_, n))| format!("{i} ({n})"))
            .collect();
        crate::Error::invalid(field, format!("{value}; expected {}", names.join(", ")))
    })
}

impl TryFrom<&ArborMeshOptions> for MeshOptions {
    type Error = crate::Error;
    fn try_from(o: &ArborMeshOptions) -> crate::Result<Self> {
        use crate::mesh::{Joints, Tip, UpAxis, Winding};
        let boolean = [(false, "false"), (true, "true")];
        Ok(MeshOptions {
            radial_segments: o.radial_segments,
            topology: enum_field(
                "topology",
                o.topology,
                &[
                    (Topology::TriangleList, "TRIANGLE_LIST"),
                    (Topology::TriangleStripRestart, "TRIANGLE_STRIP_RESTART"),
                    (
                        Topology::TriangleStripDegenerate,
                        "TRIANGLE_STRIP_DEGENERATE",
                    ),
                ],
            )?,
            min_radial_segments: o.min_radial_segments,
            cull_radius: o.cull_radius,
            joints: enum_field(
                "joints",
                o.joints,
                &[(Joints::Separate, "SEPARATE"), (Joints::Mitred, "MITRED")],
            )?,
            smooth_taper: enum_field("smooth_taper", o.smooth_taper, &boolean)?,
            base_cap: enum_field("base_cap", o.base_cap, &boolean)?,
            tip: enum_field(
                "tip",
                o.tip,
                &[
                    (Tip::Open, "OPEN"),
                    (Tip::Cap, "CAP"),
                    (Tip::Point, "POINT"),
                ],
            )?,
            texture_scale: o.texture_scale,
            winding: enum_field(
                "winding",
                o.winding,
                &[
                    (Winding::CounterClockwise, "COUNTER_CLOCKWISE"),
                    (Winding::Clockwise, "CLOCKWISE"),
                ],
            )?,
            up_axis: enum_field("up_axis", o.up_axis, &[(UpAxis::Y, "Y"), (UpAxis::Z, "Z")])?,
            scale: o.scale,
            threads: 0,
        })
    }
}

impl From<MeshOptions> for ArborMeshOptions {
    fn from(o: MeshOptions) -> Self {
        ArborMeshOptions {
            radial_segments: o.radial_segments,
            topology: o.topology as u32,
            min_radial_segments: o.min_radial_segments,
            cull_radius: o.cull_radius,
            joints: o.joints as u32,
            smooth_taper: o.smooth_taper as u32,
            base_cap: o.base_cap as u32,
            tip: o.tip as u32,
            texture_scale: o.texture_scale,
            winding: o.winding as u32,
            up_axis: o.up_axis as u32,
            scale: o.scale,
        }
    }
}

const VERSION: &CStr =
    match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
        Ok(v) => v,
        Err(_) => panic!("the package version has no NUL"),
    };

/// A static, NUL-terminated description of `status` ("ok", "null argument", ...);
/// "unknown status" for a number that is not an ArborStatus. Never NULL; do not free.
#[unsafe(no_mangle)]
pub extern "C" fn arbor_status_str(status: u32) -> *const c_char {
    let s: &'static CStr = match status {
        0 => c"ok",
        1 => c"null argument",
        2 => c"invalid argument",
        3 => c"parse error",
        4 => c"limit exceeded",
        5 => c"buffer too small",
        6 => c"I/O error",
        7 => c"internal error (panic)",
        _ => c"unknown status",
    };
    s.as_ptr()
}

/// Copies the calling thread's last error message into `buf` (NUL-terminated, cut to
/// `capacity - 1` bytes) and returns the message's full length in bytes, without the NUL.
/// Every status-returning function replaces the message; success leaves it empty.
/// `buf` may be NULL when `capacity` is 0, to ask for the length.
///
/// # Safety
/// `buf` is NULL or valid for writes of `capacity` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_last_error_message(buf: *mut c_char, capacity: usize) -> usize {
    guard_value(0, || {
        with_last_error(|message| {
            if capacity > 0 && !buf.is_null() {
                let mut n = message.len().min(capacity - 1);
                while !message.is_char_boundary(n) {
                    n -= 1;
                }
                // SAFETY: the caller promises `buf` holds `capacity` writable bytes, and
                // n + 1 <= capacity; the message is a separate Rust allocation.
                unsafe {
                    std::ptr::copy_nonoverlapping(message.as_ptr(), buf.cast::<u8>(), n);
                    buf.add(n).write(0);
                }
            }
            message.len()
        })
    })
}

/// The library version, e.g. "0.1.0": static, NUL-terminated; do not free.
#[unsafe(no_mangle)]
pub extern "C" fn arbor_version() -> *const c_char {
    VERSION.as_ptr()
}

/// The library's ABI version (see ARBOR_ABI_VERSION).
#[unsafe(no_mangle)]
pub extern "C" fn arbor_abi_version() -> u32 {
    ARBOR_ABI_VERSION
}

/// Writes the parameters of the paper's tree `name` ('a'..'i', upper case accepted) to
/// `*out`. Unknown name: ARBOR_STATUS_INVALID_ARGUMENT; `out` NULL:
/// ARBOR_STATUS_NULL_ARGUMENT.
///
/// # Safety
/// `out` is NULL or valid for writes of one ArborHondaParams.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_honda_preset(name: u32, out: *mut ArborHondaParams) -> ArborStatus {
    guard(|| {
        let params = char::from_u32(name)
            .and_then(HondaParams::preset)
            .ok_or_else(|| {
                FfiError::invalid(format!(
                    "invalid argument `name`: unknown preset {name:#x}; expected 'a'..'i'"
                ))
            })?;
        // SAFETY: the caller promises `out` is NULL or writable.
        *unsafe { out_ref(out, "out") }? = params.into();
        Ok(())
    })
}

/// Grows the 1996 model with `params` and writes a new tree to `*out` (free it with
/// arbor_tree_free). Every field is validated (ARBOR_STATUS_INVALID_ARGUMENT names the
/// field); a model that would make more than 16,777,216 branches returns
/// ARBOR_STATUS_LIMIT_EXCEEDED at once. `*out` is written only on success.
///
/// # Safety
/// `params` is NULL or points to an ArborHondaParams; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_from_honda(
    params: *const ArborHondaParams,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `params` is NULL or readable.
        let params: HondaParams = (*unsafe { arg_ref(params, "params") }?).into();
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let skeleton = honda::build(&params)?;
        *out = Box::into_raw(Box::new(ArborTree { skeleton }));
        Ok(())
    })
}

/// The default L-system options (see ArborLsystemOptions for each default).
#[unsafe(no_mangle)]
pub extern "C" fn arbor_lsystem_options_default() -> ArborLsystemOptions {
    let d = LsystemOptions::default();
    let view = crate::lsystem::ViewSettings::default();
    ArborLsystemOptions {
        steps: -1,
        seed: d.seed,
        max_modules: d.max_modules as u64,
        max_params: d.max_params as u64,
        max_branches: d.max_branches as u64,
        override_flags: 0,
        angle_increment: view.angle_increment as f32,
        initial_width: view.initial_width as f32,
        width_increment: view.width_increment as f32,
        turn_jitter: d.turn_jitter as f32,
    }
}

/// Grows a tree from L-system text in the cpfg language (see GRAMMAR.md): parse, derive,
/// then interpret with the turtle. `source` holds `source_len` bytes of UTF-8 (no NUL
/// needed; at most 16 MiB); `options` may be NULL for the defaults. Writes a new tree to
/// `*out` on success (free it with arbor_tree_free).
///
/// Statuses: ARBOR_STATUS_PARSE_ERROR (the message has line, column, what was found and
/// what was expected; also for bytes that are not UTF-8), ARBOR_STATUS_LIMIT_EXCEEDED
/// (the message names the limit and the step), ARBOR_STATUS_INVALID_ARGUMENT (options out
/// of range, or a parameter that evaluated to NaN or infinity), ARBOR_STATUS_NULL_ARGUMENT.
///
/// # Safety
/// `source` is NULL (only with `source_len` 0) or readable for `source_len` bytes;
/// `options` is NULL or readable; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_from_lsystem(
    source: *const c_char,
    source_len: usize,
    options: *const ArborLsystemOptions,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let options = if options.is_null() {
            LsystemOptions::default()
        } else {
            // SAFETY: the caller promises `options` is readable.
            unsafe { arg_ref(options, "options") }?.to_rust()?
        };
        if source_len > MAX_SOURCE_BYTES {
            return Err(crate::Error::invalid(
                "source_len",
                format!("{source_len} bytes; expected at most {MAX_SOURCE_BYTES}"),
            )
            .into());
        }
        let bytes: &[u8] = if source_len == 0 {
            &[]
        } else if source.is_null() {
            return Err(FfiError::null("source"));
        } else {
            // SAFETY: the caller promises `source_len` readable bytes at `source`, and
            // source_len <= 16 MiB fits isize.
            unsafe { std::slice::from_raw_parts(source.cast::<u8>(), source_len) }
        };
        let text = std::str::from_utf8(bytes).map_err(|e| {
            let valid = &bytes[..e.valid_up_to()];
            let line = valid.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
            let line_start = valid.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
            // The valid prefix is UTF-8 by definition.
            let column = String::from_utf8_lossy(&valid[line_start..])
                .chars()
                .count() as u32
                + 1;
            crate::Error::Parse {
                line,
                column,
                message: format!(
                    "found the byte {:#04x}, expected UTF-8 text",
                    bytes[e.valid_up_to()]
                ),
            }
        })?;
        let skeleton = LSystem::parse(text)?.skeleton(&options)?;
        *out = Box::into_raw(Box::new(ArborTree { skeleton }));
        Ok(())
    })
}

/// Frees a tree. NULL does nothing. The tree must not be used afterwards.
///
/// # Safety
/// `tree` is NULL or a tree from this library not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_free(tree: *mut ArborTree) {
    if tree.is_null() {
        return;
    }
    guard_value((), || {
        // SAFETY: the caller promises `tree` came from Box::into_raw in this library and is
        // freed once.
        drop(unsafe { Box::from_raw(tree) });
    })
}

/// Number of branches of `tree`; 0 for NULL.
///
/// # Safety
/// `tree` is NULL or a live tree.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_branch_count(tree: *const ArborTree) -> usize {
    guard_value(0, || {
        // SAFETY: the caller promises `tree` is NULL or live.
        unsafe { arg_ref(tree, "tree") }.map_or(0, |t| t.skeleton.len())
    })
}

/// Copies all branches of `tree` into `out`, parents before children. `capacity` is the
/// number of ArborBranch elements `out` holds; less than arbor_tree_branch_count() gives
/// ARBOR_STATUS_BUFFER_TOO_SMALL and writes nothing.
///
/// # Safety
/// `tree` is NULL or live; `out` is NULL or valid for writes of `capacity` branches.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_copy_branches(
    tree: *const ArborTree,
    out: *mut ArborBranch,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        let src = tree.skeleton.branches();
        // SAFETY: the caller promises `out` holds `capacity` writable branches.
        let dst = unsafe { out_slice(out.cast::<Branch>(), capacity, src.len(), "out") }?;
        for (d, s) in dst.iter_mut().zip(src) {
            d.write(*s);
        }
        Ok(())
    })
}

/// The default mesh options (see ArborMeshOptions for each default).
#[unsafe(no_mangle)]
pub extern "C" fn arbor_mesh_options_default() -> ArborMeshOptions {
    MeshOptions::default().into()
}

/// The options behind `options`, or the defaults for NULL.
///
/// # Safety
/// `options` is NULL or points to a readable ArborMeshOptions.
unsafe fn read_mesh_options(options: *const ArborMeshOptions) -> Result<MeshOptions, FfiError> {
    if options.is_null() {
        return Ok(MeshOptions::default());
    }
    // SAFETY: the caller promises `options` is readable; NULL was handled above.
    Ok(MeshOptions::try_from(unsafe {
        arg_ref(options, "options")
    }?)?)
}

/// Writes the exact number of vertices and indices arbor_mesh_write() needs for `tree`
/// with `options` (NULL: the defaults). Both out-pointers are required and written only
/// on success. More than 2^32 - 1 vertices: ARBOR_STATUS_LIMIT_EXCEEDED.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; the counts are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_size(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    vertex_count: *mut usize,
    index_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let options = unsafe { read_mesh_options(options) }?;
        // SAFETY: the caller promises both are NULL or writable.
        let vc = unsafe { out_ref(vertex_count, "vertex_count") }?;
        // SAFETY: as above.
        let ic = unsafe { out_ref(index_count, "index_count") }?;
        let size = mesh::mesh_size(&tree.skeleton, &options)?;
        *vc = size.vertices;
        *ic = size.indices;
        Ok(())
    })
}

/// Writes the mesh of `tree` into caller memory (a malloc'd array or a mapped GPU buffer):
/// `vertex_capacity` ArborVertex elements and `index_capacity` uint32_t indices. Capacities
/// below arbor_mesh_size()'s counts give ARBOR_STATUS_BUFFER_TOO_SMALL and nothing is
/// written; larger buffers are fine and only their first elements are written. A buffer
/// may be NULL only when its count is 0.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `vertices` and `indices` are
/// NULL or valid for writes of their capacities and do not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_write(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    vertices: *mut ArborVertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let options = unsafe { read_mesh_options(options) }?;
        let size = mesh::mesh_size(&tree.skeleton, &options)?;
        // SAFETY: the caller promises `vertices` holds `vertex_capacity` writable vertices
        // (ArborVertex and Vertex share one layout, asserted above).
        let v = unsafe {
            out_slice(
                vertices.cast::<Vertex>(),
                vertex_capacity,
                size.vertices,
                "vertices",
            )
        }?;
        // SAFETY: the caller promises `indices` holds `index_capacity` writable indices.
        let i = unsafe { out_slice(indices, index_capacity, size.indices, "indices") }?;
        mesh::write_mesh_uninit(&tree.skeleton, &options, v, i)?;
        Ok(())
    })
}

/// Copies, for each branch of `tree`, the vertices and indices it owns in the mesh that
/// arbor_mesh_write() writes with `options` (NULL: the defaults): `capacity` elements,
/// at least arbor_tree_branch_count(), else ARBOR_STATUS_BUFFER_TOO_SMALL. The ranges are
/// consecutive and tile both buffers; a culled branch has empty ranges.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `out` is NULL or valid for
/// writes of `capacity` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_branch_ranges(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    out: *mut ArborBranchRange,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let options = unsafe { read_mesh_options(options) }?;
        let n = tree.skeleton.len();
        // SAFETY: the caller promises `out` holds `capacity` writable elements.
        let dst = unsafe { out_slice(out.cast::<BranchRange>(), capacity, n, "out") }?;
        let ranges = mesh::branch_ranges(&tree.skeleton, &options)?;
        for (d, r) in dst.iter_mut().zip(ranges) {
            d.write(r);
        }
        Ok(())
    })
}

/// Where leaves go and how they vary (see arbor_leaf_options_default() for the defaults).
/// Fields may be added at the end in later versions.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArborLeafOptions {
    /// 1: a leaf at every `~` site of the grammar. Default 1.
    pub sites: u32,
    /// 1: the grammar's `{ . }` polygons go into the baked leaf mesh. Default 1.
    pub polygons: u32,
    /// 1: leaves at the tips of terminal branches. Default 0.
    pub tips: u32,
    /// Only tips of branches at least this deep get leaves. Default 0.
    pub min_depth: u32,
    /// Expected leaves per tip (whole part always, fraction by chance), 0..=64. Default 1.
    pub density: f32,
    /// Leaf size in model units; > 0. Default 1.
    pub size: f32,
    /// Size varies by up to +- this fraction, 0 <= x < 1. Default 0.2.
    pub size_jitter: f32,
    /// Each leaf turns about its stem by up to +- this many degrees. Default 180.
    pub rotation_jitter: f32,
    /// Tip leaves lean out from the branch by this many degrees. Default 30.
    pub tilt: f32,
    /// Seed of the variation. Default 0.
    pub seed: u64,
    /// NUL-terminated UTF-8 path of an OBJ file whose triangles are the baked leaf shape
    /// (+Y along the blade, +Z its face); NULL (default) for a 0.5 x 1 quad. Read by the
    /// leaf-mesh functions; ARBOR_STATUS_IO_ERROR if it cannot be loaded.
    pub prefab_obj_path: *const c_char,
}

/// One leaf for instanced drawing (glDrawElementsInstanced), 32 bytes: the leaf shape's
/// space (+Y along the blade, +Z its face) is rotated by `rotation`, scaled by `scale` and
/// moved to `position`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ArborLeafInstance {
    /// Where the stem attaches.
    pub position: [f32; 3],
    /// Unit quaternion (x, y, z, w).
    pub rotation: [f32; 4],
    /// Uniform scale.
    pub scale: f32,
}

const _: () = assert!(std::mem::size_of::<ArborLeafInstance>() == 32);

/// The default leaf options (see ArborLeafOptions for each default).
#[unsafe(no_mangle)]
pub extern "C" fn arbor_leaf_options_default() -> ArborLeafOptions {
    let d = LeafOptions::default();
    ArborLeafOptions {
        sites: d.sites as u32,
        polygons: d.polygons as u32,
        tips: d.tips as u32,
        min_depth: d.min_depth,
        density: d.density,
        size: d.size,
        size_jitter: d.size_jitter,
        rotation_jitter: d.rotation_jitter,
        tilt: d.tilt,
        seed: d.seed,
        prefab_obj_path: std::ptr::null(),
    }
}

/// The leaf options behind `options` (NULL: the defaults); `load_prefab` reads the OBJ.
///
/// # Safety
/// `options` is NULL or readable, and its `prefab_obj_path` NULL or NUL-terminated.
unsafe fn read_leaf_options(
    options: *const ArborLeafOptions,
    load_prefab: bool,
) -> Result<LeafOptions, FfiError> {
    if options.is_null() {
        return Ok(LeafOptions::default());
    }
    // SAFETY: the caller promises `options` is readable; NULL was handled above.
    let o = unsafe { arg_ref(options, "leaf_options") }?;
    let boolean = [(false, "false"), (true, "true")];
    let prefab = if load_prefab && !o.prefab_obj_path.is_null() {
        // SAFETY: the caller promises a non-NULL path is NUL-terminated.
        let path = unsafe { CStr::from_ptr(o.prefab_obj_path) };
        let path = path
            .to_str()
            .map_err(|_| crate::Error::invalid("prefab_obj_path", "the path is not UTF-8"))?;
        Some(LeafPrefab::from_obj(path)?)
    } else {
        None
    };
    Ok(LeafOptions {
        sites: enum_field("sites", o.sites, &boolean)?,
        polygons: enum_field("polygons", o.polygons, &boolean)?,
        tips: enum_field("tips", o.tips, &boolean)?,
        min_depth: o.min_depth,
        density: o.density,
        size: o.size,
        size_jitter: o.size_jitter,
        rotation_jitter: o.rotation_jitter,
        tilt: o.tilt,
        seed: o.seed,
        prefab,
    })
}

/// Writes the number of leaf instances of `tree` with `leaf_options` (NULL: defaults) to
/// `*count`; `mesh_options` (NULL: defaults) supplies the up axis and scale.
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_instance_count(
    tree: *const ArborTree,
    leaf_options: *const ArborLeafOptions,
    mesh_options: *const ArborMeshOptions,
    count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `leaf_options` is NULL or readable.
        let lo = unsafe { read_leaf_options(leaf_options, false) }?;
        // SAFETY: the caller promises `mesh_options` is NULL or readable.
        let mo = unsafe { read_mesh_options(mesh_options) }?;
        // SAFETY: the caller promises `count` is NULL or writable.
        let count = unsafe { out_ref(count, "count") }?;
        *count = mesh::leaf_instances(&tree.skeleton, &lo, &mo)?.len();
        Ok(())
    })
}

/// Writes the leaf instances of `tree` into `out` (`capacity` elements, at least
/// arbor_leaf_instance_count()'s, else ARBOR_STATUS_BUFFER_TOO_SMALL and nothing written).
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `out` is NULL or valid for
/// writes of `capacity` instances.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_instances_write(
    tree: *const ArborTree,
    leaf_options: *const ArborLeafOptions,
    mesh_options: *const ArborMeshOptions,
    out: *mut ArborLeafInstance,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `leaf_options` is NULL or readable.
        let lo = unsafe { read_leaf_options(leaf_options, false) }?;
        // SAFETY: the caller promises `mesh_options` is NULL or readable.
        let mo = unsafe { read_mesh_options(mesh_options) }?;
        let leaves = mesh::leaf_instances(&tree.skeleton, &lo, &mo)?;
        // SAFETY: the caller promises `out` holds `capacity` writable instances.
        let dst = unsafe { out_slice(out.cast::<LeafInstance>(), capacity, leaves.len(), "out") }?;
        for (d, l) in dst.iter_mut().zip(leaves) {
            d.write(l);
        }
        Ok(())
    })
}

/// Exact vertex and index counts of the baked leaf mesh (every leaf a copy of the leaf
/// shape, then the grammar's polygons), in the topology and conventions of
/// `mesh_options` (NULL: defaults).
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; the counts NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_mesh_size(
    tree: *const ArborTree,
    leaf_options: *const ArborLeafOptions,
    mesh_options: *const ArborMeshOptions,
    vertex_count: *mut usize,
    index_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `leaf_options` is NULL or readable.
        let lo = unsafe { read_leaf_options(leaf_options, true) }?;
        // SAFETY: the caller promises `mesh_options` is NULL or readable.
        let mo = unsafe { read_mesh_options(mesh_options) }?;
        // SAFETY: the caller promises both are NULL or writable.
        let vc = unsafe { out_ref(vertex_count, "vertex_count") }?;
        // SAFETY: as above.
        let ic = unsafe { out_ref(index_count, "index_count") }?;
        let size = mesh::leaf_mesh_size(&tree.skeleton, &lo, &mo)?;
        *vc = size.vertices;
        *ic = size.indices;
        Ok(())
    })
}

/// Writes the baked leaf mesh into caller memory; the same buffer rules as
/// arbor_mesh_write().
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `vertices` and `indices` are
/// NULL or valid for writes of their capacities and do not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_mesh_write(
    tree: *const ArborTree,
    leaf_options: *const ArborLeafOptions,
    mesh_options: *const ArborMeshOptions,
    vertices: *mut ArborVertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `leaf_options` is NULL or readable.
        let lo = unsafe { read_leaf_options(leaf_options, true) }?;
        // SAFETY: the caller promises `mesh_options` is NULL or readable.
        let mo = unsafe { read_mesh_options(mesh_options) }?;
        let size = mesh::leaf_mesh_size(&tree.skeleton, &lo, &mo)?;
        // SAFETY: the caller promises `vertices` holds `vertex_capacity` writable vertices.
        let v = unsafe {
            out_slice(
                vertices.cast::<Vertex>(),
                vertex_capacity,
                size.vertices,
                "vertices",
            )
        }?;
        // SAFETY: the caller promises `indices` holds `index_capacity` writable indices.
        let i = unsafe { out_slice(indices, index_capacity, size.indices, "indices") }?;
        mesh::write_leaf_mesh(&tree.skeleton, &lo, &mo, v, i)?;
        Ok(())
    })
}

/// Writes the bark mesh of `tree` (group `bark`) and, unless `leaf_options` is NULL, its
/// baked leaves (group `leaves`) as a Wavefront OBJ file at `path` (NUL-terminated UTF-8),
/// creating or truncating it. ARBOR_STATUS_IO_ERROR names the path on failure.
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `path` is NULL or
/// NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_export_obj(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    leaf_options: *const ArborLeafOptions,
    path: *const c_char,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `mesh_options` is NULL or readable.
        let mo = unsafe { read_mesh_options(mesh_options) }?;
        if path.is_null() {
            return Err(FfiError::null("path"));
        }
        // SAFETY: the caller promises a non-NULL `path` is NUL-terminated.
        let path = unsafe { CStr::from_ptr(path) }
            .to_str()
            .map_err(|_| crate::Error::invalid("path", "the path is not UTF-8"))?;
        let bark = mesh::tubes(&tree.skeleton, &mo)?;
        let result = if leaf_options.is_null() {
            crate::export::save_obj_parts(&[("bark", &bark)], path)
        } else {
            // SAFETY: the caller promises `leaf_options` is readable.
            let lo = unsafe { read_leaf_options(leaf_options, true) }?;
            let leaves = mesh::leaf_mesh(&tree.skeleton, &lo, &mo)?;
            crate::export::save_obj_parts(&[("bark", &bark), ("leaves", &leaves)], path)
        };
        result.map_err(|e| match e {
            crate::Error::Io(io) => crate::Error::Io(std::io::Error::new(
                io.kind(),
                format!("cannot write {path}: {io}"),
            )),
            other => other,
        })?;
        Ok(())
    })
}

/// Sizes of several levels of detail in one call: `levels` holds `level_count` mesh
/// options (for example growing cull_radius, fewer radial_segments); the counts of level
/// k go to `vertex_counts[k]` and `index_counts[k]`.
///
/// # Safety
/// `tree` is NULL or live; `levels` is NULL (only with `level_count` 0) or readable for
/// `level_count` options; the count arrays are NULL or writable for `level_count` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_lod_size(
    tree: *const ArborTree,
    levels: *const ArborMeshOptions,
    level_count: usize,
    vertex_counts: *mut usize,
    index_counts: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `levels` is readable for `level_count` options.
        let levels = unsafe { in_slice(levels, level_count, "levels") }?;
        let sizes = levels
            .iter()
            .map(|l| Ok(mesh::mesh_size(&tree.skeleton, &MeshOptions::try_from(l)?)?))
            .collect::<Result<Vec<_>, FfiError>>()?;
        // SAFETY: the caller promises both arrays hold `level_count` writable elements.
        let vc = unsafe { out_slice(vertex_counts, level_count, level_count, "vertex_counts") }?;
        // SAFETY: as above.
        let ic = unsafe { out_slice(index_counts, level_count, level_count, "index_counts") }?;
        for ((v, i), s) in vc.iter_mut().zip(ic.iter_mut()).zip(sizes) {
            v.write(s.vertices);
            i.write(s.indices);
        }
        Ok(())
    })
}

/// Writes several levels of detail in one call: level k into `vertices[k]` (capacity
/// `vertex_capacities[k]`) and `indices[k]` (capacity `index_capacities[k]`). Every
/// capacity is checked before anything is written.
///
/// # Safety
/// `tree` is NULL or live; `levels`, `vertices`, `vertex_capacities`, `indices` and
/// `index_capacities` are NULL (only with `level_count` 0) or readable for `level_count`
/// elements; each buffer pointer is NULL or valid for writes of its capacity, and no two
/// buffers overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_lod_write(
    tree: *const ArborTree,
    levels: *const ArborMeshOptions,
    level_count: usize,
    vertices: *const *mut ArborVertex,
    vertex_capacities: *const usize,
    indices: *const *mut u32,
    index_capacities: *const usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises each array is readable for `level_count` elements.
        let (levels, vs, vcaps, is, icaps) = unsafe {
            (
                in_slice(levels, level_count, "levels")?,
                in_slice(vertices, level_count, "vertices")?,
                in_slice(vertex_capacities, level_count, "vertex_capacities")?,
                in_slice(indices, level_count, "indices")?,
                in_slice(index_capacities, level_count, "index_capacities")?,
            )
        };
        let mut plans = Vec::with_capacity(level_count);
        for (k, l) in levels.iter().enumerate() {
            let o = MeshOptions::try_from(l)?;
            let size = mesh::mesh_size(&tree.skeleton, &o)?;
            size.check_capacity(vcaps[k], icaps[k])
                .map_err(|e| FfiError::from(e).at_level(k))?;
            plans.push((o, size));
        }
        for (k, (o, size)) in plans.into_iter().enumerate() {
            // SAFETY: the caller promises the level's buffers hold their capacities.
            let v =
                unsafe { out_slice(vs[k].cast::<Vertex>(), vcaps[k], size.vertices, "vertices") }
                    .map_err(|e| e.at_level(k))?;
            // SAFETY: as above.
            let i = unsafe { out_slice(is[k], icaps[k], size.indices, "indices") }
                .map_err(|e| e.at_level(k))?;
            mesh::write_mesh_uninit(&tree.skeleton, &o, v, i)?;
        }
        Ok(())
    })
}

/// A mesh arbor owns (made by arbor_mesh_create(), arbor_leaf_mesh_create() or
/// arbor_forest_mesh_create()): for hosts that prefer to read buffers in place and copy
/// them where they like. Opaque; free with arbor_mesh_free(). A
/// `const ArborMesh *` may be read from several threads at once.
pub struct ArborMesh {
    mesh: crate::Mesh,
}

/// Builds the bark mesh of `tree` with `options` (NULL: the defaults) into a new mesh
/// object written to `*out` (free it with arbor_mesh_free()); read it with
/// arbor_mesh_vertices() and arbor_mesh_indices(). `*out` is written only on success.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_create(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    out: *mut *mut ArborMesh,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let options = unsafe { read_mesh_options(options) }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let mesh = mesh::tubes(&tree.skeleton, &options)?;
        *out = Box::into_raw(Box::new(ArborMesh { mesh }));
        Ok(())
    })
}

/// Like arbor_mesh_create() for the baked leaf mesh (see arbor_leaf_mesh_write()).
///
/// # Safety
/// `tree` is NULL or live; the options are NULL or readable; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_mesh_create(
    tree: *const ArborTree,
    leaf_options: *const ArborLeafOptions,
    mesh_options: *const ArborMeshOptions,
    out: *mut *mut ArborMesh,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `leaf_options` is NULL or readable.
        let lo = unsafe { read_leaf_options(leaf_options, true) }?;
        // SAFETY: the caller promises `mesh_options` is NULL or readable.
        let mo = unsafe { read_mesh_options(mesh_options) }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let mesh = mesh::leaf_mesh(&tree.skeleton, &lo, &mo)?;
        *out = Box::into_raw(Box::new(ArborMesh { mesh }));
        Ok(())
    })
}

/// The vertices of `mesh`, valid until arbor_mesh_free(); their number goes to `*count`
/// (if `count` is not NULL). NULL mesh: returns NULL and a count of 0.
///
/// # Safety
/// `mesh` is NULL or live; `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_vertices(
    mesh: *const ArborMesh,
    count: *mut usize,
) -> *const ArborVertex {
    guard_value(std::ptr::null(), || {
        // SAFETY: the caller promises `mesh` is NULL or live.
        let m = unsafe { arg_ref(mesh, "mesh") }.ok();
        let v = m.map_or(&[][..], |m| &m.mesh.vertices[..]);
        // SAFETY: the caller promises `count` is NULL or writable.
        if let Ok(c) = unsafe { out_ref(count, "count") } {
            *c = v.len();
        }
        if m.is_some() {
            v.as_ptr().cast()
        } else {
            std::ptr::null()
        }
    })
}

/// The indices of `mesh` (laid out as arbor_mesh_topology() says), valid until
/// arbor_mesh_free(); their number goes to `*count` (if `count` is not NULL). NULL mesh:
/// returns NULL and a count of 0.
///
/// # Safety
/// `mesh` is NULL or live; `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_indices(
    mesh: *const ArborMesh,
    count: *mut usize,
) -> *const u32 {
    guard_value(std::ptr::null(), || {
        // SAFETY: the caller promises `mesh` is NULL or live.
        let m = unsafe { arg_ref(mesh, "mesh") }.ok();
        let i = m.map_or(&[][..], |m| &m.mesh.indices[..]);
        // SAFETY: the caller promises `count` is NULL or writable.
        if let Ok(c) = unsafe { out_ref(count, "count") } {
            *c = i.len();
        }
        if m.is_some() {
            i.as_ptr()
        } else {
            std::ptr::null()
        }
    })
}

/// The ArborTopology of `mesh`'s indices (ARBOR_TOPOLOGY_TRIANGLE_LIST for NULL).
///
/// # Safety
/// `mesh` is NULL or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_topology(mesh: *const ArborMesh) -> u32 {
    guard_value(0, || {
        // SAFETY: the caller promises `mesh` is NULL or live.
        unsafe { arg_ref(mesh, "mesh") }.map_or(0, |m| m.mesh.topology as u32)
    })
}

/// Frees a mesh. NULL does nothing. Pointers from arbor_mesh_vertices() and
/// arbor_mesh_indices() become invalid.
///
/// # Safety
/// `mesh` is NULL or a mesh from this library not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_free(mesh: *mut ArborMesh) {
    if mesh.is_null() {
        return;
    }
    guard_value((), || {
        // SAFETY: the caller promises `mesh` came from Box::into_raw here and is freed once.
        drop(unsafe { Box::from_raw(mesh) });
    })
}

/// A place where the turtle met `~` in a grammar (44 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ArborLeafSite {
    /// Where the turtle stood.
    pub position: [f32; 3],
    /// Its heading (unit).
    pub heading: [f32; 3],
    /// Its up vector (unit).
    pub up: [f32; 3],
    /// The branch the site sits on, or ARBOR_NO_PARENT.
    pub branch: u32,
    /// The rewriting step that produced the `~`.
    pub depth: u32,
}

const _: () = assert!(
    std::mem::size_of::<ArborLeafSite>() == std::mem::size_of::<crate::skeleton::LeafSite>()
);

/// Number of `~` leaf sites of `tree`; 0 for NULL.
///
/// # Safety
/// `tree` is NULL or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_leaf_site_count(tree: *const ArborTree) -> usize {
    guard_value(0, || {
        // SAFETY: the caller promises `tree` is NULL or live.
        unsafe { arg_ref(tree, "tree") }.map_or(0, |t| t.skeleton.leaves().len())
    })
}

/// Copies the leaf sites of `tree` into `out` (`capacity` elements, at least
/// arbor_tree_leaf_site_count(), else ARBOR_STATUS_BUFFER_TOO_SMALL).
///
/// # Safety
/// `tree` is NULL or live; `out` is NULL or valid for writes of `capacity` sites.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_copy_leaf_sites(
    tree: *const ArborTree,
    out: *mut ArborLeafSite,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        let src = tree.skeleton.leaves();
        // SAFETY: the caller promises `out` holds `capacity` writable sites.
        let dst = unsafe {
            out_slice(
                out.cast::<crate::skeleton::LeafSite>(),
                capacity,
                src.len(),
                "out",
            )
        }?;
        for (d, s) in dst.iter_mut().zip(src) {
            d.write(*s);
        }
        Ok(())
    })
}

/// Grows the 1996 model with seeded variation of every branch's angles (up to +-4 degrees
/// branching, +-10 divergence), length and width (up to +-6%), so trees from the same
/// parameters differ; `seed` 0 gives exactly arbor_tree_from_honda(). Same seed, same tree.
///
/// # Safety
/// `params` is NULL or readable; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_from_honda_varied(
    params: *const ArborHondaParams,
    seed: u64,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `params` is NULL or readable.
        let params: HondaParams = (*unsafe { arg_ref(params, "params") }?).into();
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let variation = honda::Variation {
            seed,
            ..Default::default()
        };
        let skeleton = honda::build_varied(&params, &variation)?;
        *out = Box::into_raw(Box::new(ArborTree { skeleton }));
        Ok(())
    })
}

/// Makes a new tree from `tree` without its colliding branches: where two branches'
/// volumes intersect and they do not meet at a joint, the deeper one goes with its
/// subtree (a parent left with no children gets a closed tip). Writes the new tree to
/// `*out` and, if `removed` is not NULL, how many branches went.
///
/// # Safety
/// `tree` is NULL or live; `out` is NULL or writable; `removed` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_prune_collisions(
    tree: *const ArborTree,
    out: *mut *mut ArborTree,
    removed: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let pruned = crate::skeleton::prune::prune_collisions(&tree.skeleton);
        if !removed.is_null() {
            // SAFETY: the caller promises a non-NULL `removed` is writable.
            *unsafe { out_ref(removed, "removed") }? = pruned.removed;
        }
        *out = Box::into_raw(Box::new(ArborTree {
            skeleton: pruned.skeleton,
        }));
        Ok(())
    })
}

/// Per-vertex animation data (16 bytes), one per vertex of the mesh of the same tree and
/// options: for growth and wind shaders, as a second vertex stream.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ArborAnimationVertex {
    /// When the vertex appears as the tree grows, 0..1: draw vertices with growth <= t.
    pub growth: f32,
    /// Branching order of its branch (0 on the trunk axis).
    pub order: f32,
    /// 0 at its branch's base, 1 at the tip.
    pub along: f32,
    /// Per-branch phase in [0, 1).
    pub phase: f32,
}

/// Writes the animation stream of the mesh arbor_mesh_write() makes with `options` (NULL:
/// defaults): `capacity` elements, at least the vertex count of arbor_mesh_size().
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `out` is NULL or valid for
/// writes of `capacity` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_animation_write(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    out: *mut ArborAnimationVertex,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let options = unsafe { read_mesh_options(options) }?;
        let data = mesh::animation(&tree.skeleton, &options)?;
        // SAFETY: the caller promises `out` holds `capacity` writable elements.
        let dst = unsafe {
            out_slice(
                out.cast::<mesh::AnimationVertex>(),
                capacity,
                data.len(),
                "out",
            )
        }?;
        for (d, v) in dst.iter_mut().zip(data) {
            d.write(v);
        }
        Ok(())
    })
}

/// One tree of a forest: the 1996 model's parameters, a variation seed (0: none) and its
/// placement (position of its root, turn about the up axis in degrees, uniform scale).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ArborForestTree {
    /// The model's parameters.
    pub params: ArborHondaParams,
    /// Variation seed, as arbor_tree_from_honda_varied(); 0 for none.
    pub seed: u64,
    /// Where the root stands, in the output space of the mesh options.
    pub position: [f32; 3],
    /// Turn about the up axis, degrees.
    pub rotation: f32,
    /// Uniform scale, > 0.
    pub scale: f32,
}

/// Grows `count` trees (on all cores when arbor is built with its `parallel` feature),
/// places them and merges them into one new mesh object written to `*out` (read it with
/// arbor_mesh_vertices() / arbor_mesh_indices(), free it with arbor_mesh_free()).
///
/// # Safety
/// `trees` is NULL (only with `count` 0) or readable for `count` elements; `options` is
/// NULL or readable; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_mesh_create(
    trees: *const ArborForestTree,
    count: usize,
    options: *const ArborMeshOptions,
    out: *mut *mut ArborMesh,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `trees` is readable for `count` elements.
        let trees = unsafe { read_forest(trees, count) }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let options = unsafe { read_mesh_options(options) }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let mesh = crate::forest::merged(&trees, &options)?;
        *out = Box::into_raw(Box::new(ArborMesh { mesh }));
        Ok(())
    })
}

/// The placed forest of `trees` as Rust values.
///
/// # Safety
/// `trees` is NULL (only with `count` 0) or readable for `count` elements.
unsafe fn read_forest<'a>(
    trees: *const ArborForestTree,
    count: usize,
) -> Result<Vec<crate::forest::Placed<'a>>, FfiError> {
    // SAFETY: the caller promises `trees` is readable for `count` elements.
    let trees = unsafe { in_slice(trees, count, "trees") }?;
    Ok(trees
        .iter()
        .map(|t| crate::forest::Placed {
            item: crate::forest::Item {
                source: crate::forest::Source::Honda(t.params.into()),
                seed: t.seed,
            },
            position: t.position,
            rotation: t.rotation,
            scale: t.scale,
        })
        .collect())
}

/// Exact vertex and index counts of the merged forest mesh arbor_forest_mesh_write()
/// writes (the trees are grown to count them; arbor_forest_mesh_create() grows them once).
///
/// # Safety
/// `trees` is NULL (only with `count` 0) or readable for `count` elements; `options` is
/// NULL or readable; the counts are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_mesh_size(
    trees: *const ArborForestTree,
    count: usize,
    options: *const ArborMeshOptions,
    vertex_count: *mut usize,
    index_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `trees` is readable for `count` elements.
        let placed = unsafe { read_forest(trees, count) }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let options = unsafe { read_mesh_options(options) }?;
        // SAFETY: the caller promises both counts are NULL or writable.
        let vc = unsafe { out_ref(vertex_count, "vertex_count") }?;
        // SAFETY: as above.
        let ic = unsafe { out_ref(index_count, "index_count") }?;
        let size = crate::forest::merged_size(&placed, &options)?;
        *vc = size.vertices;
        *ic = size.indices;
        Ok(())
    })
}

/// Writes the merged forest mesh into caller memory; the buffer rules of
/// arbor_mesh_write().
///
/// # Safety
/// As arbor_forest_mesh_size(), and `vertices` / `indices` are NULL or valid for writes
/// of their capacities and do not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_mesh_write(
    trees: *const ArborForestTree,
    count: usize,
    options: *const ArborMeshOptions,
    vertices: *mut ArborVertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `trees` is readable for `count` elements.
        let placed = unsafe { read_forest(trees, count) }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let options = unsafe { read_mesh_options(options) }?;
        let size = crate::forest::merged_size(&placed, &options)?;
        // SAFETY: the caller promises `vertices` holds `vertex_capacity` writable vertices.
        let v = unsafe {
            out_slice(
                vertices.cast::<Vertex>(),
                vertex_capacity,
                size.vertices,
                "vertices",
            )
        }?;
        // SAFETY: the caller promises `indices` holds `index_capacity` writable indices.
        let i = unsafe { out_slice(indices, index_capacity, size.indices, "indices") }?;
        let mesh = crate::forest::merged(&placed, &options)?;
        for (d, s) in v.iter_mut().zip(&mesh.vertices) {
            d.write(*s);
        }
        for (d, s) in i.iter_mut().zip(&mesh.indices) {
            d.write(*s);
        }
        Ok(())
    })
}

/// Identifies a struct of this header for arbor_struct_size().
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArborStructId {
    /// ArborHondaParams.
    HondaParams = 0,
    /// ArborBranch.
    Branch = 1,
    /// ArborVertex.
    Vertex = 2,
    /// ArborMeshOptions.
    MeshOptions = 3,
    /// ArborLsystemOptions.
    LsystemOptions = 4,
    /// ArborLeafOptions.
    LeafOptions = 5,
    /// ArborLeafInstance.
    LeafInstance = 6,
    /// ArborBranchRange.
    BranchRange = 7,
    /// ArborLeafSite.
    LeafSite = 8,
    /// ArborAnimationVertex.
    AnimationVertex = 9,
    /// ArborForestTree.
    ForestTree = 10,
}

/// The size in bytes of the struct `id` (an ArborStructId) as this library was built, so a
/// binding in another language (C#, Python) can check its layouts at run time; 0 for an
/// unknown id.
#[unsafe(no_mangle)]
pub extern "C" fn arbor_struct_size(id: u32) -> usize {
    use std::mem::size_of;
    match id {
        0 => size_of::<ArborHondaParams>(),
        1 => size_of::<ArborBranch>(),
        2 => size_of::<ArborVertex>(),
        3 => size_of::<ArborMeshOptions>(),
        4 => size_of::<ArborLsystemOptions>(),
        5 => size_of::<ArborLeafOptions>(),
        6 => size_of::<ArborLeafInstance>(),
        7 => size_of::<ArborBranchRange>(),
        8 => size_of::<ArborLeafSite>(),
        9 => size_of::<ArborAnimationVertex>(),
        10 => size_of::<ArborForestTree>(),
        _ => 0,
    }
}

#[cfg(test)]
mod tests;
