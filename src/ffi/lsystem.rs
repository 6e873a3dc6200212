//! Trees from L-system text.

use super::*;

/// ArborLsystemOptions.override_flags bit: use `angle_increment` instead of the grammar's.
pub const ARBOR_OVERRIDE_ANGLE_INCREMENT: u32 = 1;
/// ArborLsystemOptions.override_flags bit: use `initial_width` instead of the grammar's.
pub const ARBOR_OVERRIDE_INITIAL_WIDTH: u32 = 2;
/// ArborLsystemOptions.override_flags bit: use `width_increment` instead of the grammar's.
pub const ARBOR_OVERRIDE_WIDTH_INCREMENT: u32 = 4;

impl ArborLsystemOptions {
    /// The ARBOR_OVERRIDE_* bits of the settings `r` overrides.
    pub(super) fn override_flags_of(r: &LsystemOptions) -> u32 {
        [
            (r.angle_increment, ARBOR_OVERRIDE_ANGLE_INCREMENT),
            (r.initial_width, ARBOR_OVERRIDE_INITIAL_WIDTH),
            (r.width_increment, ARBOR_OVERRIDE_WIDTH_INCREMENT),
        ]
        .iter()
        .filter(|(v, _)| v.is_some())
        .fold(0, |flags, (_, bit)| flags | bit)
    }

    /// The C value of an overridable setting: the override, else the view's default.
    pub(super) fn setting_of(
        value: Option<f64>,
        default: impl FnOnce(crate::lsystem::ViewSettings) -> f64,
    ) -> f32 {
        value.unwrap_or_else(|| default(crate::lsystem::ViewSettings::default())) as f32
    }

    /// `value` when `override_flags` has `bit`, else none (the grammar's own); an error
    /// when `override_flags` has a bit no ARBOR_OVERRIDE_* names.
    pub(super) fn overridden(&self, bit: u32, value: f32) -> crate::Result<Option<f64>> {
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
        Ok((self.override_flags & bit != 0).then_some(value as f64))
    }
}

/// sizeof(ArborLsystemOptions) of its first layout (up to `turn_jitter`, padded): the
/// smallest `struct_size` accepted.
pub const ARBOR_LSYSTEM_OPTIONS_MIN_SIZE: usize = 64;

growing!(ArborLsystemOptions as "ArborLsystemOptions", ARBOR_LSYSTEM_OPTIONS_MIN_SIZE,
    first_added: variation_seed, defaults: Self::from_rust(&LsystemOptions::default()));

/// Derives and interprets, with the host's progress callback if it gave one.
fn grow(
    grammar: &LSystem,
    options: &LsystemOptions,
    raw: &ArborLsystemOptions,
) -> crate::Result<Skeleton> {
    let mut progress = progress_closure(raw.progress, raw.progress_user_data);
    crate::source::Source::Grammar(grammar, *options)
        .grow_in(options.variation_seed, &mut run_of(&mut progress))
}

/// The host's options as given (NULL: the defaults) and as the Rust options they mean.
///
/// # Safety
/// `options` is NULL or readable for its `struct_size` bytes.
unsafe fn read_options(
    options: *const ArborLsystemOptions,
) -> Result<(ArborLsystemOptions, LsystemOptions), FfiError> {
    if options.is_null() {
        return Ok((ArborLsystemOptions::default(), LsystemOptions::default()));
    }
    // SAFETY: the caller promises `options` is readable for its struct_size bytes.
    let o = unsafe { read_growing(options, "options") }?;
    Ok((o, o.to_rust()?))
}

/// A NUL-terminated UTF-8 string argument, or `None` for NULL.
///
/// # Safety
/// `p` is NULL or points to a NUL-terminated string.
unsafe fn c_string<'a>(p: *const c_char, name: &'static str) -> Result<Option<&'a str>, FfiError> {
    if p.is_null() {
        return Ok(None);
    }
    // SAFETY: the caller promises a non-NULL `p` is NUL-terminated.
    let s = unsafe { CStr::from_ptr(p) };
    if s.to_bytes().len() > MAX_SOURCE_BYTES {
        return Err(
            crate::Error::invalid(name, format!("longer than {MAX_SOURCE_BYTES} bytes")).into(),
        );
    }
    s.to_str()
        .map(Some)
        .map_err(|_| crate::Error::invalid(name, "not UTF-8 text").into())
}

/// Grows a tree from an L-system file read as cpfg reads it (GRAMMAR.md): the C
/// preprocessor over the text (`#include` relative to the file's folder), then its view
/// file: `options->view_path` when set, else the `.v` file beside it with the same stem,
/// else none (the view file's angle, line widths, tropism and functions apply). `path`
/// is a NUL-terminated UTF-8 path; `options` may be NULL for the defaults. Writes a new
/// tree to `*out` on success. `path` may also name a vlab object's folder: its
/// `specifications` names the grammar and view file (the `cpfg` command of its `model:`
/// section, else the first `.l` and `.v` listed).
///
/// Statuses: as arbor_tree_from_lsystem() (parse errors name the file and line, an
/// included file's name first); ARBOR_STATUS_INVALID_ARGUMENT for a file that cannot be
/// opened or read (the message has the path and why).
///
/// # Safety
/// `path` is NULL or NUL-terminated; `options` is NULL or readable (its `view_path` NULL
/// or NUL-terminated); `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_from_lsystem_file(
    path: *const c_char,
    options: *const ArborLsystemOptions,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let (raw, options) = unsafe { read_options(options) }?;
        // SAFETY: the caller promises `view_path` is NULL or NUL-terminated.
        let view = unsafe { c_string(raw.view_path, "view_path") }?.map(std::path::PathBuf::from);
        // SAFETY: the caller promises `path` is NULL or NUL-terminated.
        let Some(path) = (unsafe { c_string(path, "path") })? else {
            return Err(FfiError::null("path"));
        };
        let files = file_options(
            raw.file_access,
            raw.read_file,
            raw.read_file_user_data,
            raw.max_file_bytes,
        )?;
        let mut progress = progress_closure(raw.progress, raw.progress_user_data);
        let grammar =
            LSystem::from_file_with(path, view.as_deref(), &files, &mut run_of(&mut progress))?;
        let skeleton = grow(&grammar, &options, &raw)?;
        *out = ArborTree::new(skeleton).into_handle();
        Ok(())
    })
}

impl Default for ArborLsystemOptions {
    /// What arbor_lsystem_options_init() writes for this library's size.
    fn default() -> Self {
        Self::defaults()
    }
}

/// Writes the default L-system options into the first `struct_size` bytes at `options`
/// (pass `sizeof(ArborLsystemOptions)`), with `options->struct_size = struct_size`, and
/// nothing beyond. The header's static inline arbor_lsystem_options_default() does this
/// for you. NULL does nothing.
///
/// # Safety
/// `options` is NULL or writable for `struct_size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_lsystem_options_init(
    options: *mut ArborLsystemOptions,
    struct_size: usize,
) {
    // SAFETY: the caller promises `struct_size` writable bytes at `options`.
    unsafe { init_for_host(options, struct_size) }
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
        // SAFETY: the caller promises `options` is NULL or readable.
        let (raw, options) = unsafe { read_options(options) }?;
        // SAFETY: the caller promises `view_text` is NULL or NUL-terminated.
        let view = unsafe { c_string(raw.view_text, "view_text") }?;
        // Text has no folder: its `#include`s and companions are refused under every
        // policy; the fields are still checked.
        file_options(
            raw.file_access,
            raw.read_file,
            raw.read_file_user_data,
            raw.max_file_bytes,
        )?;
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
        let grammar = match view {
            Some(v) => LSystem::parse_with_view(text, v)?,
            None => LSystem::parse(text)?,
        };
        let skeleton = grow(&grammar, &options, &raw)?;
        *out = ArborTree::new(skeleton).into_handle();
        Ok(())
    })
}
