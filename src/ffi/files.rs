//! What files a model may read: the policy and the host's reader.

use super::*;
use crate::files::{FileAccess, FileOptions};
use std::sync::Arc;

/// Which files a model (its `#include`s, its view file's `function:`, `curve:` and
/// `surface:` files, a leaf prefab) may read: the `file_access` field of
/// ArborLsystemOptions and ArborLeafOptions. Files the host names itself (the model's
/// path, `view_path`, `prefab_obj_path`) are read under every policy.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArborFileAccess {
    /// The default: the model's own folder and below, canonicalised, regular files only,
    /// no symbolic link leaving it; absolute paths and `..` leaving it are refused by name.
    Bundle = 0,
    /// Nothing beyond the one file named (or the text given); not even the `.v` beside it.
    None = 1,
    /// Explicit opt-in: any regular file the process can read.
    Any = 2,
    /// Every read goes through `read_file`; arbor opens nothing.
    Host = 3,
}

/// The host's reader (ARBOR_FILE_ACCESS_HOST). Asked for `path` (as the model names it,
/// resolved against the model's folder, NUL-terminated UTF-8, `/`-separated on Unix):
/// write at most `capacity` bytes to `buffer` and the file's full size to `*size`; return
/// 0, or non-zero for "no such file" (arbor reports the path, never content). Called again
/// with a larger buffer when `*size > capacity` (`buffer` may be NULL when `capacity` is 0:
/// a question whether the file exists). Called on the calling thread only.
pub type ArborReadFileFn = Option<
    unsafe extern "C" fn(
        user_data: *mut c_void,
        path: *const c_char,
        buffer: *mut u8,
        capacity: usize,
        size: *mut usize,
    ) -> i32,
>;

/// The host's reader with its user data, as a Rust reader.
struct HostReader {
    f: unsafe extern "C" fn(*mut c_void, *const c_char, *mut u8, usize, *mut usize) -> i32,
    user: *mut c_void,
}

// SAFETY: the reader is used only inside the call that received it, on the calling thread
// (a load never spawns threads); Send and Sync are needed only because the Rust policy type
// can be shared, which this one never is beyond the call.
unsafe impl Send for HostReader {}
// SAFETY: as for Send above.
unsafe impl Sync for HostReader {}

impl HostReader {
    fn read(&self, path: &str, buffer: &mut [u8]) -> Option<u64> {
        let path = std::ffi::CString::new(path).ok()?;
        let mut size = 0usize;
        let ptr = if buffer.is_empty() {
            std::ptr::null_mut()
        } else {
            buffer.as_mut_ptr()
        };
        // SAFETY: the host gave this function and its user data for the duration of the
        // call that is running; `path` is NUL-terminated, `ptr` is NULL or holds
        // `buffer.len()` writable bytes, and `size` is a local.
        let r = unsafe { (self.f)(self.user, path.as_ptr(), ptr, buffer.len(), &mut size) };
        (r == 0).then_some(size as u64)
    }
}

/// The Rust file options of the four growing-struct fields.
pub(crate) fn file_options(
    access: u32,
    read_file: ArborReadFileFn,
    user: *mut c_void,
    max_file_bytes: u64,
) -> Result<FileOptions, FfiError> {
    if max_file_bytes == 0 {
        return Err(crate::Error::invalid(
            "max_file_bytes",
            "0; expected the byte budget of one load (> 0, default 67,108,864)",
        )
        .into());
    }
    let access = match access {
        0 => FileAccess::Bundle,
        1 => FileAccess::None,
        2 => FileAccess::Any,
        3 => {
            let Some(f) = read_file else {
                return Err(crate::Error::invalid(
                    "read_file",
                    "NULL with file_access ARBOR_FILE_ACCESS_HOST; expected the host's reader",
                )
                .into());
            };
            let reader = HostReader { f, user };
            FileAccess::Host(Arc::new(move |path: &str, buffer: &mut [u8]| {
                reader.read(path, buffer)
            }))
        }
        v => {
            return Err(crate::Error::invalid(
                "file_access",
                format!("{v}; expected an ArborFileAccess (0 bundle, 1 none, 2 any, 3 host)"),
            )
            .into());
        }
    };
    Ok(FileOptions {
        access,
        max_bytes: max_file_bytes,
    })
}
