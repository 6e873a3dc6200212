//! Limits on what one call may produce. Every generator checks its limit before the memory
//! is spent and stops with [`Error::LimitExceeded`](crate::error::Error::LimitExceeded) naming it.

/// Most branches a generator makes by default (2^24).
pub const DEFAULT_MAX_BRANCHES: usize = 1 << 24;
/// Largest coordinate, radius or organ size a skeleton may hold (10^15 units): far past
/// any plant, and far enough inside the f32 range that squares and sums of them (lengths,
/// normals) stay finite.
pub const MAX_COORDINATE: f32 = 1e15;
/// Most modules a derived string may hold by default (2^24).
pub const DEFAULT_MAX_MODULES: usize = 1 << 24;
/// Most parameter values a derived string may hold by default (2^25).
pub const DEFAULT_MAX_PARAMS: usize = 1 << 25;
/// Most leaves (instances or baked copies) one call makes by default (2^24).
pub const DEFAULT_MAX_LEAVES: usize = 1 << 24;
/// Most vertices one mesh may have by default (2^32 − 1: 32-bit indices, the restart
/// index reserved).
pub const DEFAULT_MAX_VERTICES: usize = u32::MAX as usize;
/// The work budget of one derivation and its interpretation by default, in units (2^28;
/// the slowest units measured take 4.6 ns, so a default-limited load stops within about
/// 1.3 s on the machine it was measured on): a string that stays large for many steps, or
/// a loop that never ends, stops here instead of running for hours. See
/// [`LsystemOptions::max_work`](crate::lsystem::LsystemOptions::max_work).
pub const DEFAULT_MAX_WORK: usize = 1 << 28;

/// `n` zeroed values (calloc: pages are touched only when written), or
/// [`Error::OutOfMemory`](crate::error::Error::OutOfMemory) naming `what` when the allocation
/// fails, instead of aborting the process.
pub(crate) fn try_zeroed<T: bytemuck::Zeroable>(
    n: usize,
    what: &str,
) -> crate::error::Result<Vec<T>> {
    bytemuck::allocation::try_zeroed_slice_box::<T>(n)
        .map(Vec::from)
        .map_err(|()| out_of_memory::<T>(n, what))
}

/// [`Error::OutOfMemory`](crate::error::Error::OutOfMemory) for `n` values of `T` named `what`.
fn out_of_memory<T>(n: usize, what: &str) -> crate::error::Error {
    crate::error::Error::OutOfMemory {
        what: format!(
            "{what} ({n} × {} bytes = {} bytes)",
            std::mem::size_of::<T>(),
            n.saturating_mul(std::mem::size_of::<T>())
        ),
    }
}

/// An empty vector with room for `n` values, or
/// [`Error::OutOfMemory`](crate::error::Error::OutOfMemory) naming `what`: for buffers a
/// writer fills whole, which a zero fill first would only slow down.
pub(crate) fn try_with_capacity<T>(n: usize, what: &str) -> crate::error::Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n)
        .map_err(|_| out_of_memory::<T>(n, what))?;
    Ok(v)
}

/// Asks for `bytes` once, fallibly, and gives them back: work that then builds several
/// arrays of that total size (a mesh plan) finds the address space there, and a process
/// short of memory gets [`Error::OutOfMemory`](crate::error::Error::OutOfMemory) naming `what`
/// before any of it is built, instead of an abort halfway.
pub(crate) fn check_available(bytes: usize, what: &str) -> crate::error::Result<()> {
    let mut probe: Vec<u8> = Vec::new();
    probe
        .try_reserve_exact(bytes)
        .map_err(|_| crate::error::Error::OutOfMemory {
            what: format!("{what} ({bytes} bytes)"),
        })
}

/// A growable array whose room can be asked for fallibly (see [`try_room`]).
pub(crate) trait Room {
    /// Room for `n` more elements: exactly, or amortized as `push` grows; false when the
    /// memory cannot be had.
    fn room(&mut self, n: usize, exact: bool) -> bool;
}

impl<T> Room for Vec<T> {
    fn room(&mut self, n: usize, exact: bool) -> bool {
        if exact {
            self.try_reserve_exact(n).is_ok()
        } else {
            self.try_reserve(n).is_ok()
        }
    }
}

/// Room for `n` more elements in each of `arrays` (parallel arrays of one thing), or
/// [`Error::OutOfMemory`](crate::error::Error::OutOfMemory) naming `what()`.
pub(crate) fn try_room(
    arrays: &mut [&mut dyn Room],
    n: usize,
    exact: bool,
    what: impl FnOnce() -> String,
) -> crate::error::Result<()> {
    if arrays.iter_mut().all(|a| a.room(n, exact)) {
        Ok(())
    } else {
        Err(crate::error::Error::OutOfMemory { what: what() })
    }
}
