//! Opaque handles: every object a C host holds by pointer (trees, worlds, meshes, leaf
//! prefabs) is boxed on the way out and freed once on the way back, here and nowhere else.

use super::guard::guard_value;

/// An object handed to C as an opaque pointer (rustls-ffi's `BoxCastPtr`).
pub(crate) trait Handle: Sized {
    /// `self` boxed, as the pointer a constructor writes to its `out` parameter.
    fn into_handle(self) -> *mut Self {
        Box::into_raw(Box::new(self))
    }

    /// Frees a pointer from [`into_handle`](Self::into_handle); NULL does nothing, and a
    /// panic while dropping is caught.
    ///
    /// # Safety
    /// `handle` is NULL or came from `into_handle` and is not yet freed.
    unsafe fn free_handle(handle: *mut Self) {
        if handle.is_null() {
            return;
        }
        guard_value((), || {
            // SAFETY: the caller promises `handle` came from `into_handle` (Box::into_raw)
            // and is freed once.
            drop(unsafe { Box::from_raw(handle) });
        })
    }
}

impl Handle for super::ArborTree {}
impl Handle for super::ArborWorld {}
impl Handle for super::ArborMesh {}
impl Handle for super::ArborLeafPrefab {}
