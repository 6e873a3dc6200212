//! Option structs declared once: each field with its documentation, its default and, where
//! it has one, its bound, from which come the struct (`#[non_exhaustive]`, so a field
//! added in a later version breaks no Rust user), its `Default`, the checks of single
//! fields ([`Bound`]) and a setter per field for building one in an expression:
//!
//! ```
//! use arbor::mesh::{MeshOptions, Topology};
//!
//! let o = MeshOptions::default()
//!     .topology(Topology::TriangleList)
//!     .radial_segments(6);
//! assert_eq!(o.radial_segments, 6);
//! // Or start from `Default` (or a preset) and set fields.
//! let mut p = MeshOptions::default();
//! p.radial_segments = 6;
//! assert_eq!(o, p);
//! assert!(o.validate().is_ok());
//! // Out of range: refused, naming the field.
//! let e = o.radial_segments(1).validate().unwrap_err();
//! assert!(e.to_string().contains("radial_segments"));
//! ```
//!
//! Each struct's `validate()` runs these checks in the order the fields are declared,
//! then what ties fields together (a box's corners, a range of segments).

use crate::error::{Error, Result};

/// The range a field must lie in; a floating-point field must also be finite.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Bound<T> {
    /// Any (finite) value.
    Any,
    /// `lo..=hi`.
    In(T, T),
    /// `lo..hi`.
    InBelow(T, T),
    /// `> lo`.
    Above(T),
    /// `>= lo`.
    AtLeast(T),
    /// `<= hi`.
    AtMost(T),
    /// `(lo, hi]`.
    AboveTo(T, T),
}

/// A value a [`Bound`] can hold: ordered and shown in messages; finite unless a float
/// says otherwise.
pub(crate) trait Bounded: PartialOrd + Copy + std::fmt::Display {
    /// Whether the value is a finite number (always, for an integer).
    fn finite(self) -> bool {
        true
    }
    /// `v` as this type (an integer saturates; a negative value is 0).
    fn from_f64(v: f64) -> Self;
}

impl Bounded for f32 {
    fn finite(self) -> bool {
        self.is_finite()
    }
    fn from_f64(v: f64) -> Self {
        v as f32
    }
}
impl Bounded for f64 {
    fn finite(self) -> bool {
        self.is_finite()
    }
    fn from_f64(v: f64) -> Self {
        v
    }
}
impl Bounded for u32 {
    fn from_f64(v: f64) -> Self {
        v as u32
    }
}
impl Bounded for u64 {
    fn from_f64(v: f64) -> Self {
        v as u64
    }
}
impl Bounded for usize {
    fn from_f64(v: f64) -> Self {
        v as usize
    }
}

impl<T: Bounded> Bound<T> {
    /// Whether `v` lies in the bound (and is finite).
    pub(crate) fn holds(self, v: T) -> bool {
        v.finite()
            && match self {
                Bound::Any => true,
                Bound::In(lo, hi) => lo <= v && v <= hi,
                Bound::InBelow(lo, hi) => lo <= v && v < hi,
                Bound::Above(lo) => v > lo,
                Bound::AtLeast(lo) => v >= lo,
                Bound::AtMost(hi) => v <= hi,
                Bound::AboveTo(lo, hi) => v > lo && v <= hi,
            }
    }

    /// `Ok`, or [`Error::InvalidArgument`] naming `field`: "`v`; expected `expected`".
    pub(crate) fn check(
        self,
        field: &'static str,
        v: T,
        expected: impl FnOnce() -> String,
    ) -> Result<()> {
        if self.holds(v) {
            Ok(())
        } else {
            Err(Error::invalid(
                field,
                format!("{v}; expected {}", expected()),
            ))
        }
    }
}

/// One field of an option struct as its `options!` declaration wrote it.
#[cfg_attr(not(test), allow(dead_code))]
#[derive(Clone, Copy, Debug)]
pub(crate) struct FieldInfo {
    /// The field's name.
    pub name: &'static str,
    /// Its Rust type, as written (`f32`, `Topology`, `Option<u32>`).
    pub ty: &'static str,
    /// Its documentation, one entry per `///` line (each starting with the space after
    /// the slashes).
    pub doc: &'static [&'static str],
}

/// Declares an option struct once. Each field is written with its documentation, its
/// default and, optionally, its bound and what a message says was expected:
///
/// ```text
/// /// Documentation.
/// pub apical_control: f32 = 0.5, checked In(0.0, 1.0), "0..=1",
/// pub topology: Topology = Topology::TriangleList,
/// ```
///
/// From it come the struct (with `#[non_exhaustive]`), `Default`, `check_fields()` (the
/// bounds in declaration order, naming the first field out of its bound) and one setter
/// per field: `field(self, value) -> Self`. The message of a bound may be any expression
/// that gives a `&str` or a `String`; it is built only when the check fails.
macro_rules! options {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $(
                $(#[doc = $doc:literal])*
                pub $field:ident : $ty:ty = $default:expr
                $(, checked $bound:expr, $expected:expr)? ,
            )*
        }
    ) => {
        $(#[$meta])*
        #[non_exhaustive]
        pub struct $name {
            $(
                $(#[doc = $doc])*
                pub $field: $ty,
            )*
        }

        impl Default for $name {
            fn default() -> Self {
                $name {
                    $($field: $default,)*
                }
            }
        }

        impl $name {
            /// Every field as declared, in order: for generators (the C ABI's mirror
            /// structs) and tools that walk the options.
            #[allow(dead_code)]
            pub(crate) const FIELDS: &'static [$crate::options::FieldInfo] = &[
                $($crate::options::FieldInfo {
                    name: stringify!($field),
                    ty: stringify!($ty),
                    doc: &[$($doc),*],
                },)*
            ];

            /// Each field's own bound, in declaration order: `Ok`, or
            /// [`Error::InvalidArgument`](crate::error::Error::InvalidArgument) naming
            /// the first field out of its bound.
            #[allow(unused_imports, dead_code)]
            pub(crate) fn check_fields(&self) -> crate::error::Result<()> {
                use $crate::options::Bound::*;
                $($(
                    $crate::options::Bound::<$ty>::check(
                        $bound,
                        stringify!($field),
                        self.$field,
                        || ($expected).to_string(),
                    )?;
                )?)*
                Ok(())
            }

            /// Sets the field named `field`, if it is one with a bound, to `v` converted
            /// to its type (an integer saturates), and says whether it was: for tools and
            /// tests that walk every bound (sliders, the documented-range checks) without
            /// a list of their own.
            #[doc(hidden)]
            pub fn set_bounded(&mut self, field: &str, v: f64) -> bool {
                $($(
                    if field == stringify!($field) {
                        let _ = stringify!($bound);
                        self.$field = <$ty as $crate::options::Bounded>::from_f64(v);
                        return true;
                    }
                )?)*
                let _ = (field, v);
                false
            }

            $(
                #[doc = concat!(
                    "These options with [`", stringify!($field), "`](Self::",
                    stringify!($field), ") set to `value`."
                )]
                #[must_use]
                #[inline]
                pub fn $field(mut self, value: $ty) -> Self {
                    self.$field = value;
                    self
                }
            )*
        }
    };
}

pub(crate) use options;
