//! Option structs that can grow: each is `#[non_exhaustive]`, so a field added in a later
//! version breaks no Rust user, and has a setter per field for building one in an
//! expression:
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

/// Declares an option struct as written (its attributes, documentation and public fields)
/// with `#[non_exhaustive]` and one setter per field: `field(self, value) -> Self`.
macro_rules! options {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $(
                $(#[$field_meta:meta])*
                pub $field:ident : $ty:ty,
            )*
        }
    ) => {
        $(#[$meta])*
        #[non_exhaustive]
        pub struct $name {
            $(
                $(#[$field_meta])*
                pub $field: $ty,
            )*
        }

        impl $name {
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
