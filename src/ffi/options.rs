//! Option structs that grow, by the rule of Linux's `copy_struct_from_user` (C-API.md,
//! "Structs that grow"), and the conversion of enum-like fields.
//!
//! A growing struct starts with `uint32_t struct_size`, the size the host was compiled
//! with. The library reads exactly that many bytes: a smaller (older) struct gets the
//! defaults for the fields it lacks; a larger (newer) one is accepted when every byte past
//! the library's size is zero; a size below the first published layout is refused.
//! `arbor_<name>_init(p, size)` writes the defaults into the first `size` bytes only.

use super::guard::FfiError;

/// Largest `struct_size` accepted: far above any layout, low enough that a garbage size
/// is refused before it is read.
pub(crate) const MAX_STRUCT_SIZE: usize = 4096;

/// A `#[repr(C)]` struct that grows at its end and starts with `struct_size: u32`.
pub(crate) trait Growing: Copy {
    /// Its C name, for messages.
    const NAME: &'static str;
    /// `sizeof` of its first published layout: smaller sizes are refused.
    const MIN_SIZE: usize;
    /// The defaults, with `struct_size` set to the library's size.
    fn defaults() -> Self;
}

/// Reads a host's growing struct at `p` (any alignment: an older layout may be less
/// aligned than this one) into a full-size value: the host's `struct_size` bytes over the
/// defaults. `name` is the argument's name for messages.
///
/// # Safety
/// `p` is non-NULL and readable for the `struct_size` bytes its first four bytes say.
pub(crate) unsafe fn read_growing<T: Growing>(p: *const T, name: &str) -> Result<T, FfiError> {
    let full = std::mem::size_of::<T>();
    // SAFETY: every published layout starts with a u32 struct_size, which the caller
    // promises is readable; read unaligned, since an older layout may be less aligned.
    let size = unsafe { p.cast::<u32>().read_unaligned() } as usize;
    if size < T::MIN_SIZE {
        return Err(FfiError::invalid(format!(
            "`{name}.struct_size` is {size}; expected the sizeof({}) of a header (at least {}, \
             this library's is {full}): set it with {}",
            T::NAME,
            T::MIN_SIZE,
            init_name::<T>()
        )));
    }
    if size > MAX_STRUCT_SIZE {
        return Err(FfiError::invalid(format!(
            "`{name}.struct_size` is {size}; expected at most {MAX_STRUCT_SIZE} (this \
             library's sizeof({}) is {full})",
            T::NAME
        )));
    }
    let bytes = p.cast::<u8>();
    if size > full {
        // SAFETY: the caller promises `size` readable bytes at `p`.
        let tail = unsafe { std::slice::from_raw_parts(bytes.add(full), size - full) };
        if let Some(k) = tail.iter().position(|&b| b != 0) {
            return Err(FfiError::invalid(format!(
                "`{name}` is a newer {} of {size} bytes with a non-zero byte at offset {}, \
                 past the {full} bytes this library knows: a field this library does not \
                 have is set",
                T::NAME,
                full + k
            )));
        }
    }
    let mut out = T::defaults();
    // SAFETY: `out` is a plain-old-data #[repr(C)] value of `full` bytes whose every bit
    // pattern is valid (integers, floats and raw pointers); the host's first
    // min(size, full) bytes are readable and do not overlap it.
    unsafe {
        std::ptr::copy_nonoverlapping(bytes, (&mut out as *mut T).cast::<u8>(), size.min(full))
    };
    Ok(out)
}

/// Reads an array of a host's growing structs, `count` elements with the stride of the
/// first one's `struct_size` (a host built against another header has another size), each
/// as [`read_growing`] reads one; messages name `name[k]`.
///
/// # Safety
/// `p` is NULL (only with `count` 0) or points to `count` elements of the host's layout,
/// each readable for the first one's `struct_size` bytes.
pub(crate) unsafe fn read_growing_array<T: Growing>(
    p: *const T,
    count: usize,
    name: &str,
) -> Result<Vec<T>, FfiError> {
    if count == 0 {
        return Ok(Vec::new());
    }
    if p.is_null() {
        return Err(FfiError::null(name));
    }
    // SAFETY: the caller promises the first element is readable.
    unsafe { read_growing(p, &format!("{name}[0]")) }?;
    // SAFETY: as above; read_growing accepted the size, so it is at least the first
    // layout's and at most MAX_STRUCT_SIZE.
    let stride = unsafe { p.cast::<u32>().read_unaligned() } as usize;
    (0..count)
        .map(|k| {
            // SAFETY: element k starts k strides in, inside the caller's array.
            let e = unsafe { p.cast::<u8>().add(k * stride) }.cast::<T>();
            // SAFETY: the caller promises element k is readable.
            unsafe { read_growing(e, &format!("{name}[{k}]")) }
        })
        .collect()
}

/// What every `arbor_*_init` does: [`init_growing`], with no panic crossing into C.
///
/// # Safety
/// `p` is NULL or writable for `size` bytes.
pub(crate) unsafe fn init_for_host<T: Growing>(p: *mut T, size: usize) {
    super::guard::guard_value((), || {
        // SAFETY: passed on from the caller.
        unsafe { init_growing(p, size) }
    })
}

/// Writes the defaults of `T` into the first `size` bytes at `p` (zeros past the
/// library's size), with `struct_size` = `size`; writes nothing when `p` is NULL or `size`
/// is below 4.
///
/// # Safety
/// `p` is NULL or writable for `size` bytes.
pub(crate) unsafe fn init_growing<T: Growing>(p: *mut T, size: usize) {
    if p.is_null() || size < 4 {
        return;
    }
    let full = std::mem::size_of::<T>();
    let defaults = T::defaults();
    let bytes = p.cast::<u8>();
    // SAFETY: `defaults` is `full` bytes; the caller promises `size` writable bytes at
    // `p`, which cannot overlap a local. Padding bytes of `defaults` are copied as they
    // are: the library never reads them.
    unsafe {
        std::ptr::copy_nonoverlapping((&defaults as *const T).cast::<u8>(), bytes, size.min(full));
        if size > full {
            std::ptr::write_bytes(bytes.add(full), 0, size - full);
        }
        p.cast::<u32>()
            .write_unaligned(u32::try_from(size).unwrap_or(u32::MAX));
    }
}

/// Writes `value` (a full-size struct) into the first `size` bytes at `p` as
/// [`init_growing`] writes the defaults: zeros past the library's size, `struct_size` =
/// `size`; nothing when `size` is below 4.
///
/// # Safety
/// `p` is non-NULL and writable for `size` bytes.
pub(crate) unsafe fn write_growing<T: Growing>(p: *mut T, size: usize, value: &T) {
    if size < 4 {
        return;
    }
    let full = std::mem::size_of::<T>();
    let bytes = p.cast::<u8>();
    // SAFETY: `value` is `full` bytes; the caller promises `size` writable bytes at `p`,
    // which cannot overlap a reference the caller holds.
    unsafe {
        std::ptr::copy_nonoverlapping((value as *const T).cast::<u8>(), bytes, size.min(full));
        if size > full {
            std::ptr::write_bytes(bytes.add(full), 0, size - full);
        }
        p.cast::<u32>()
            .write_unaligned(u32::try_from(size).unwrap_or(u32::MAX));
    }
}

pub(super) fn init_name<T: Growing>() -> String {
    // ArborMeshOptions -> arbor_mesh_options_init()
    heck::ToSnakeCase::to_snake_case(T::NAME) + "_init()"
}

/// How a field of a C struct carries a field of the Rust struct it mirrors: the same type
/// as it is, a [`Numbered`](crate::enums::Numbered) enum or a flag as `uint32_t`, a count
/// as a fixed-width integer.
pub(crate) trait CField<R>: Sized {
    /// The Rust value, or an error naming `field` when the C value has no meaning.
    fn c_to_rust(self, field: &'static str) -> crate::Result<R>;
    /// The C value of a Rust value.
    fn c_from_rust(value: R) -> Self;
}

impl<T> CField<T> for T {
    fn c_to_rust(self, _: &'static str) -> crate::Result<T> {
        Ok(self)
    }
    fn c_from_rust(value: T) -> Self {
        value
    }
}

impl<E: crate::enums::Numbered> CField<E> for u32 {
    fn c_to_rust(self, field: &'static str) -> crate::Result<E> {
        E::from_field(field, self)
    }
    fn c_from_rust(value: E) -> Self {
        E::ALL
            .iter()
            .position(|&v| v.variant() == value.variant())
            .unwrap_or(0) as u32
    }
}

impl CField<bool> for u32 {
    fn c_to_rust(self, field: &'static str) -> crate::Result<bool> {
        match self {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(crate::Error::invalid(
                field,
                format!("{self}; expected 0 (false) or 1 (true)"),
            )),
        }
    }
    fn c_from_rust(value: bool) -> Self {
        value as u32
    }
}

/// A count: saturates on a platform whose `size_t` is narrower.
impl CField<usize> for u64 {
    fn c_to_rust(self, _: &'static str) -> crate::Result<usize> {
        Ok(usize::try_from(self).unwrap_or(usize::MAX))
    }
    fn c_from_rust(value: usize) -> Self {
        value as u64
    }
}

/// A step count, or none: negative in C.
impl CField<Option<u32>> for i32 {
    fn c_to_rust(self, _: &'static str) -> crate::Result<Option<u32>> {
        Ok(u32::try_from(self).ok())
    }
    fn c_from_rust(value: Option<u32>) -> Self {
        value.map_or(-1, |v| i32::try_from(v).unwrap_or(i32::MAX))
    }
}

/// A number C keeps in single precision.
impl CField<f64> for f32 {
    fn c_to_rust(self, _: &'static str) -> crate::Result<f64> {
        Ok(self as f64)
    }
    fn c_from_rust(value: f64) -> Self {
        value as f32
    }
}

/// A count kept in 32 bits.
impl CField<usize> for u32 {
    fn c_to_rust(self, _: &'static str) -> crate::Result<usize> {
        Ok(self as usize)
    }
    fn c_from_rust(value: usize) -> Self {
        u32::try_from(value).unwrap_or(u32::MAX)
    }
}

/// The one field list of a growing C struct and the Rust struct it mirrors, from which
/// both conversions come: `to_rust` (validating, naming the C field in errors) and
/// `from_rust` (with `struct_size` this library's size). Both are struct literals, so a
/// field added to either struct and not listed here does not compile. Every C struct of
/// options is converted by it.
///
/// - `same { a, b }`: fields of one name (the types convert by [`CField`]);
/// - `renamed { c_name = rust_name }`: fields whose names differ;
/// - `c_only { field: value }`: C fields the Rust struct lacks, and what `from_rust` writes;
/// - `rust_only { field: value }`: Rust fields the C struct lacks, and what `to_rust` gives
///   (the caller fills them in);
/// - optionally `to_rust(c) { field: expr }` and `to_c(r) { field: expr }`: fields whose
///   value is computed from the whole other struct (`c` the C value, `r` the Rust one),
///   such as an `Option` carried by a flag bit; `to_rust`'s expressions may use `?`.
macro_rules! mirror {
    ($c:ident => $rust:ident {
        same { $($f:ident),* $(,)? }
        renamed { $($cf:ident = $rf:ident),* $(,)? }
        c_only { $($co:ident: $cov:expr),* $(,)? }
        rust_only { $($ro:ident: $rov:expr),* $(,)? }
        $(to_rust($cv:ident) { $($tf:ident: $te:expr),* $(,)? })?
        $(to_c($rv:ident) { $($uf:ident: $ue:expr),* $(,)? })?
    }) => {
        impl $c {
            /// The Rust value this means; an error names the first field out of range.
            pub(crate) fn to_rust(self) -> crate::Result<$rust> {
                use $crate::ffi::options::CField;
                $(let $cv = &self;)?
                // Every field named: a Rust field the mirror lacks does not compile, until
                // the generator (src/ffi/mirror_gen) writes the mirror again. While it
                // does (the `regen-mirrors` feature), a missing field is its default.
                #[cfg(not(feature = "regen-mirrors"))]
                let r = $rust {
                    $($f: CField::c_to_rust(self.$f, stringify!($f))?,)*
                    $($rf: CField::c_to_rust(self.$cf, stringify!($cf))?,)*
                    $($ro: $rov,)*
                    $($($tf: $te,)*)?
                };
                #[cfg(feature = "regen-mirrors")]
                #[allow(clippy::needless_update)]
                let r = $rust {
                    $($f: CField::c_to_rust(self.$f, stringify!($f))?,)*
                    $($rf: CField::c_to_rust(self.$cf, stringify!($cf))?,)*
                    $($ro: $rov,)*
                    $($($tf: $te,)*)?
                    ..Default::default()
                };
                Ok(r)
            }

            /// The C value of `r`, with `struct_size` this library's size.
            pub(crate) fn from_rust(r: &$rust) -> Self {
                use $crate::ffi::options::CField;
                $(let $rv = r;)?
                $c {
                    struct_size: std::mem::size_of::<$c>() as u32,
                    $($f: CField::c_from_rust(r.$f),)*
                    $($cf: CField::c_from_rust(r.$rf),)*
                    $($co: $cov,)*
                    $($($uf: $ue,)*)?
                }
            }
        }
    };
}
pub(crate) use mirror;

/// A growing struct's [`Growing`] impl: its C name, the `sizeof` of its first layout
/// (checked at compile time to be where the first field added after it starts) and its
/// defaults.
macro_rules! growing {
    (
        $ty:ident as $name:literal, $min:ident,
        first_added: $field:ident, defaults: $defaults:expr
    ) => {
        const _: () = assert!(std::mem::offset_of!($ty, $field) == $min);

        impl Growing for $ty {
            const NAME: &'static str = $name;
            const MIN_SIZE: usize = $min;
            fn defaults() -> Self {
                $defaults
            }
        }
    };
}

pub(crate) use growing;
