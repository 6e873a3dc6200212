//! Statuses, the thread's last error message, and versions.

use super::*;

/// Major version of the library this header belongs to.
pub const ARBOR_VERSION_MAJOR: u32 = 0;
/// Minor version of the library this header belongs to.
pub const ARBOR_VERSION_MINOR: u32 = 2;
/// Patch version of the library this header belongs to.
pub const ARBOR_VERSION_PATCH: u32 = 0;
/// ABI version of this header: MAJOR * 10000 + MINOR * 100 + PATCH. It only grows; a host
/// built against ABI version N (N >= 200) runs with a library whose
/// `arbor_abi_version()` >= N. 200 is the one break: option structs gained `struct_size`
/// first (hosts built against 100 must be rebuilt).
pub const ARBOR_ABI_VERSION: u32 = 200;
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
    /// A progress callback asked to stop; no out-parameter was written.
    Cancelled = 8,
    /// An allocation in proportion to the input failed (the message names what was being
    /// allocated); nothing was built and the host keeps running.
    OutOfMemory = 9,
}

/// A progress callback (see "Progress and cancellation" in docs/c-api.md): called on the
/// calling thread only, with `user_data`, an ARBOR_STAGE_* and a fraction in [0, 1]; a
/// non-zero return stops the work, which returns ARBOR_STATUS_CANCELLED, writes no
/// out-parameter and leaks nothing.
pub type ArborProgressFn =
    Option<unsafe extern "C" fn(user_data: *mut c_void, stage: u32, fraction: f32) -> i32>;

/// The Rust closure that calls a host's progress callback (None when it is NULL).
pub(crate) fn progress_closure(
    f: ArborProgressFn,
    user_data: *mut c_void,
) -> Option<impl FnMut(crate::progress::Stage, f32) -> bool> {
    let f = f?;
    Some(move |stage: crate::progress::Stage, fraction: f32| {
        // SAFETY: the host gave this function and its user data for the call's duration
        // and promises it may be called on this thread (C-API.md).
        unsafe { f(user_data, stage as u32, fraction) == 0 }
    })
}

/// The run of a call: reporting to the closure from [`progress_closure`], if any, on
/// `threads` threads when given (the mesh options' own otherwise).
pub(crate) fn run_of<F: FnMut(crate::progress::Stage, f32) -> bool>(
    f: &mut Option<F>,
) -> crate::progress::Run<'_> {
    crate::progress::Run::new(f.as_mut().map(|f| f as crate::progress::ProgressFn<'_>))
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
        8 => c"cancelled",
        9 => c"out of memory",
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

/// The library version, e.g. "0.2.0": static, NUL-terminated; do not free.
#[unsafe(no_mangle)]
pub extern "C" fn arbor_version() -> *const c_char {
    VERSION.as_ptr()
}

/// The library's ABI version (see ARBOR_ABI_VERSION).
#[unsafe(no_mangle)]
pub extern "C" fn arbor_abi_version() -> u32 {
    ARBOR_ABI_VERSION
}
