//! The panic guard, the thread's last error message, and every pointer conversion of the
//! C ABI.

use super::ArborStatus;
use crate::error::Error;
use std::cell::RefCell;
use std::mem::MaybeUninit;
use std::panic::{AssertUnwindSafe, catch_unwind};

/// An error on its way to a C caller: a status and the message for
/// `arbor_last_error_message`.
pub(crate) struct FfiError {
    pub(crate) status: ArborStatus,
    pub(crate) message: String,
}

impl FfiError {
    pub(crate) fn null(argument: &str) -> Self {
        FfiError {
            status: ArborStatus::NullArgument,
            message: format!("argument `{argument}` is NULL"),
        }
    }

    /// Prefixes the message with the level of detail it concerns.
    pub(crate) fn at_level(mut self, k: usize) -> Self {
        self.message = format!("level {k}: {}", self.message);
        self
    }

    pub(crate) fn invalid(message: String) -> Self {
        FfiError {
            status: ArborStatus::InvalidArgument,
            message,
        }
    }
}

impl From<Error> for FfiError {
    fn from(e: Error) -> Self {
        let status = match &e {
            Error::InvalidArgument { .. } => ArborStatus::InvalidArgument,
            Error::LimitExceeded { .. } => ArborStatus::LimitExceeded,
            Error::BufferTooSmall { .. } => ArborStatus::BufferTooSmall,
            Error::Parse { .. } => ArborStatus::ParseError,
            Error::Eval { .. } => ArborStatus::InvalidArgument,
            Error::Io(_) => ArborStatus::IoError,
            Error::Cancelled { .. } => ArborStatus::Cancelled,
            Error::FileAccess { .. } => ArborStatus::IoError,
            Error::FileBudget { .. } => ArborStatus::LimitExceeded,
            Error::OutOfMemory { .. } => ArborStatus::OutOfMemory,
        };
        FfiError {
            status,
            message: e.to_string(),
        }
    }
}

thread_local! {
    static LAST_ERROR: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Stores the thread's last message with every control character (NUL included) escaped
/// (`\0`, `\n`, `\t`, `\x01` …), so a C host's `strlen` sees all of it and printing it
/// cannot move a terminal's cursor: messages quote input, and input may hold any byte.
fn set_last_error(message: &str) {
    LAST_ERROR.with(|m| {
        let mut m = m.borrow_mut();
        m.clear();
        for c in message.chars() {
            match c {
                '\0' => m.push_str("\\0"),
                '\n' => m.push_str("\\n"),
                '\r' => m.push_str("\\r"),
                '\t' => m.push_str("\\t"),
                c if c.is_control() => {
                    use std::fmt::Write;
                    let _ = write!(m, "\\x{:02x}", c as u32);
                }
                c => m.push(c),
            }
        }
    });
}

/// Calls `f` with the thread's last error message.
pub(crate) fn with_last_error<R>(f: impl FnOnce(&str) -> R) -> R {
    LAST_ERROR.with(|m| f(&m.borrow()))
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    let text = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown payload".to_string());
    format!("internal error (panic) in arbor: {text}")
}

/// Runs the body of a status-returning export: a returned error or a panic becomes its
/// status and the thread's last message; success clears the message.
pub(crate) fn guard(f: impl FnOnce() -> Result<(), FfiError>) -> ArborStatus {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => {
            set_last_error("");
            ArborStatus::Ok
        }
        Ok(Err(e)) => {
            set_last_error(&e.message);
            e.status
        }
        Err(payload) => {
            set_last_error(&panic_message(payload.as_ref()));
            ArborStatus::Panic
        }
    }
}

/// Runs the body of an export that returns a plain value; a panic gives `fallback`.
pub(crate) fn guard_value<T>(fallback: T, f: impl FnOnce() -> T) -> T {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(v) => v,
        Err(payload) => {
            set_last_error(&panic_message(payload.as_ref()));
            fallback
        }
    }
}

/// A shared reference from an argument pointer; NULL gives `ARBOR_STATUS_NULL_ARGUMENT`.
///
/// # Safety
/// `p` is NULL or points to a valid, initialised `T` that is not written for `'a`.
pub(crate) unsafe fn arg_ref<'a, T>(p: *const T, name: &str) -> Result<&'a T, FfiError> {
    check_aligned(p, name)?;
    // SAFETY: the caller promises `p` is NULL or valid for reads for 'a; it is aligned.
    unsafe { p.as_ref() }.ok_or_else(|| FfiError::null(name))
}

/// A mutable reference for an out-parameter; NULL gives `ARBOR_STATUS_NULL_ARGUMENT`.
///
/// # Safety
/// `p` is NULL or points to memory valid for writes of one `T`, not aliased for `'a`.
pub(crate) unsafe fn out_ref<'a, T>(p: *mut T, name: &str) -> Result<&'a mut T, FfiError> {
    check_aligned(p, name)?;
    // SAFETY: the caller promises `p` is NULL or valid for writes for 'a; it is aligned.
    // Only Copy types without drop glue are passed here, so the reference is only written.
    unsafe { p.as_mut() }.ok_or_else(|| FfiError::null(name))
}

/// Writes `value` to an optional out-parameter: nothing when `p` is NULL.
///
/// # Safety
/// `p` is NULL or points to memory valid for writes of one `T`.
pub(crate) unsafe fn write_if_given<T>(p: *mut T, name: &str, value: T) -> Result<(), FfiError> {
    if !p.is_null() {
        // SAFETY: non-NULL, and the caller promises it is writable.
        *unsafe { out_ref(p, name) }? = value;
    }
    Ok(())
}

/// Copies `src` into a caller buffer of `capacity` elements, with the checks of
/// [`out_slice`] (too small: `ARBOR_STATUS_BUFFER_TOO_SMALL`, nothing written).
///
/// # Safety
/// As [`out_slice`].
pub(crate) unsafe fn copy_out<T: Copy>(
    src: &[T],
    p: *mut T,
    capacity: usize,
    name: &'static str,
) -> Result<(), FfiError> {
    // SAFETY: passed on from the caller.
    let dst = unsafe { out_slice(p, capacity, src.len(), name) }?;
    for (d, s) in dst.iter_mut().zip(src) {
        d.write(*s);
    }
    Ok(())
}

/// The host's vertex and index buffers (`capacity` elements each), at least `size` of
/// each (else `BufferTooSmall` naming the buffer), as slots to write.
///
/// # Safety
/// Each pointer is NULL or valid for writes of its capacity, and they do not overlap.
pub(crate) unsafe fn mesh_buffers<'a>(
    vertices: *mut crate::mesh::Vertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
    size: crate::mesh::MeshSize,
) -> Result<MeshSlots<'a>, FfiError> {
    // SAFETY: the caller promises `vertices` holds `vertex_capacity` writable vertices.
    let v = unsafe { out_slice(vertices, vertex_capacity, size.vertices, "vertices") }?;
    // SAFETY: the caller promises `indices` holds `index_capacity` writable indices.
    let i = unsafe { out_slice(indices, index_capacity, size.indices, "indices") }?;
    Ok((v, i))
}

/// What [`mesh_buffers`] gives: vertex and index slots.
pub(crate) type MeshSlots<'a> = (
    &'a mut [MaybeUninit<crate::mesh::Vertex>],
    &'a mut [MaybeUninit<u32>],
);

/// The first `needed` elements of a caller buffer of `capacity` elements, as
/// possibly-uninitialised slots (a host's `malloc` or mapped GPU memory).
///
/// Checks the capacity first (`ARBOR_STATUS_BUFFER_TOO_SMALL`, the buffer untouched), then
/// the pointer: NULL is accepted only when nothing is needed.
///
/// # Safety
/// `p` is NULL or valid for writes of `capacity` elements of `T`, not aliased for `'a`.
pub(crate) unsafe fn out_slice<'a, T>(
    p: *mut T,
    capacity: usize,
    needed: usize,
    name: &'static str,
) -> Result<&'a mut [MaybeUninit<T>], FfiError> {
    if capacity < needed {
        return Err(Error::BufferTooSmall {
            buffer: name,
            required: needed,
            capacity,
        }
        .into());
    }
    if needed == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(FfiError::null(name));
    }
    check_aligned(p, name)?;
    // SAFETY: `p` is non-null and aligned, and the caller promises `capacity >= needed`
    // elements behind it are writable and unaliased. The slots are `MaybeUninit`, so the
    // memory need not be initialised, and arbor only writes them.
    Ok(unsafe { std::slice::from_raw_parts_mut(p.cast::<MaybeUninit<T>>(), needed) })
}

/// A slice of `len` elements the caller passes in; NULL only when `len` is 0.
///
/// # Safety
/// `p` is NULL or valid for reads of `len` initialised elements, not written for `'a`.
pub(crate) unsafe fn in_slice<'a, T>(
    p: *const T,
    len: usize,
    name: &str,
) -> Result<&'a [T], FfiError> {
    if len == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(FfiError::null(name));
    }
    check_aligned(p, name)?;
    if len
        .checked_mul(std::mem::size_of::<T>())
        .is_none_or(|b| b > isize::MAX as usize)
    {
        return Err(FfiError::invalid(format!(
            "argument `{name}`: {len} elements do not fit in memory"
        )));
    }
    // SAFETY: non-null, aligned, within isize::MAX bytes, and the caller promises `len`
    // readable initialised elements.
    Ok(unsafe { std::slice::from_raw_parts(p, len) })
}

fn check_aligned<T>(p: *const T, name: &str) -> Result<(), FfiError> {
    if p.is_aligned() {
        Ok(())
    } else {
        Err(FfiError::invalid(format!(
            "argument `{name}` is not aligned to {} bytes",
            std::mem::align_of::<T>()
        )))
    }
}
