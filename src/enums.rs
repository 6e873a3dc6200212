//! Enums whose values cross into C, and everything derived from their one declaration.
//!
//! Each such enum is written once, as a plain `#[repr(u32)]` Rust enum numbered 0, 1, 2…
//! (the C header's enum is generated from it, under its C name). A macro then
//! derives, from one list of its variants and their names, what messages, the command-line
//! tool, validation and the bindings read: the list of values in numeric order, the count,
//! the conversion from a C `uint32_t`, the name in lower case (as the command-line tool and
//! the documentation spell it) and the C enumerator's name. The list is tied to the enum
//! at compile time: a variant missing from it does not compile (the name `match` is
//! exhaustive), and a list out of numeric order fails a compile-time assertion.

use crate::error::{Error, Result};

/// What every numbered enum offers (implemented by the crate's `numbered!` macro).
pub trait Numbered: Copy + 'static {
    /// The C enum's name, for example `ArborTopology`.
    const C_NAME: &'static str;
    /// Every value, in numeric order (value `i` at index `i`).
    const ALL: &'static [Self];
    /// The value's name in lower case with hyphens, as the command-line tool and the
    /// documentation spell it, for example `triangle-list`.
    fn name(self) -> &'static str;
    /// The value's Rust variant name, for example `TriangleList`.
    fn variant(self) -> &'static str;
    /// [`name`](Numbered::name) with a NUL byte at its end, for C.
    fn name_nul(self) -> &'static str;

    /// The value numbered `value` in C, `None` for an unknown number.
    fn from_u32(value: u32) -> Option<Self> {
        Self::ALL.get(value as usize).copied()
    }

    /// The value of that name (any case, `_` or `-` alike), if there is one.
    fn from_name(name: &str) -> Option<Self> {
        let wanted = name.replace('_', "-");
        Self::ALL
            .iter()
            .copied()
            .find(|v| v.name().eq_ignore_ascii_case(&wanted))
    }

    /// The C enumerator, for example `ARBOR_TOPOLOGY_TRIANGLE_LIST`.
    fn c_enumerator(self) -> String {
        format!(
            "{}_{}",
            screaming_snake(Self::C_NAME),
            screaming_snake(self.variant())
        )
    }

    /// Every name, joined by `, ` (for messages and help texts).
    fn names() -> String {
        Self::ALL
            .iter()
            .map(|v| v.name())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The value of a C struct's `uint32_t` field `field`, or an error that names the field
    /// and lists every accepted number with its C enumerator.
    fn from_field(field: &'static str, value: u32) -> Result<Self> {
        Self::from_u32(value).ok_or_else(|| {
            let accepted: Vec<String> = Self::ALL
                .iter()
                .enumerate()
                .map(|(i, v)| format!("{i} ({})", v.c_enumerator()))
                .collect();
            Error::invalid(
                field,
                format!(
                    "{value}; expected {} (an {})",
                    accepted.join(", "),
                    Self::C_NAME
                ),
            )
        })
    }
}

/// `TriangleList` → `TRIANGLE_LIST`, `ArborUpAxis` → `ARBOR_UP_AXIS` (cbindgen's rule for
/// enumerators; the test below holds it to the header's spelling).
fn screaming_snake(name: &str) -> String {
    heck::ToShoutySnakeCase::to_shouty_snake_case(name)
}

/// Implements [`Numbered`] (and `Display`, `FromStr`) for a `#[repr(u32)]` enum from one
/// list of its variants with their lower-case names, in numeric order:
///
/// ```ignore
/// numbered!(Topology as "ArborTopology" {
///     TriangleList = "triangle-list",
///     TriangleStripRestart = "triangle-strip-restart",
/// });
/// ```
macro_rules! numbered {
    ($ty:ident as $c:literal { $($variant:ident = $name:literal),+ $(,)? }) => {
        impl $ty {
            /// Every value, in numeric order (value `i` at index `i`).
            pub const ALL: [$ty; [$(stringify!($variant)),+].len()] = [$($ty::$variant),+];

            /// The value's name in lower case with hyphens, as the command-line tool and
            /// the documentation spell it.
            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),+
                }
            }

            /// The value numbered `value` in C, `None` for an unknown number.
            pub fn from_u32(value: u32) -> Option<Self> {
                Self::ALL.get(value as usize).copied()
            }

            /// The value of that name (any case, `_` or `-` alike), if there is one.
            pub fn from_name(name: &str) -> Option<Self> {
                <Self as $crate::enums::Numbered>::from_name(name)
            }
        }

        impl $crate::enums::Numbered for $ty {
            const C_NAME: &'static str = $c;
            const ALL: &'static [Self] = &$ty::ALL;
            fn name(self) -> &'static str {
                $ty::name(self)
            }
            fn variant(self) -> &'static str {
                match self {
                    $($ty::$variant => stringify!($variant)),+
                }
            }
            fn name_nul(self) -> &'static str {
                match self {
                    $($ty::$variant => concat!($name, "\0")),+
                }
            }
        }

        const _: () = {
            let all = $ty::ALL;
            let mut i = 0;
            while i < all.len() {
                assert!(all[i] as usize == i, "numbered! lists the variants in numeric order");
                i += 1;
            }
        };

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str($ty::name(*self))
            }
        }

        impl std::str::FromStr for $ty {
            type Err = $crate::error::Error;
            fn from_str(s: &str) -> $crate::error::Result<Self> {
                $ty::from_name(s).ok_or_else(|| {
                    $crate::error::Error::invalid(
                        stringify!($ty),
                        format!(
                            "`{s}`; expected one of {}",
                            <$ty as $crate::enums::Numbered>::names()
                        ),
                    )
                })
            }
        }
    };
}
pub(crate) use numbered;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Axes, Topology, UpAxis};

    #[test]
    fn values_names_and_enumerators_come_from_one_list() {
        assert_eq!(Topology::ALL.len(), 3);
        assert_eq!(
            Topology::from_u32(2),
            Some(Topology::TriangleStripDegenerate)
        );
        assert_eq!(Topology::from_u32(3), None);
        assert_eq!(Topology::TriangleList.name(), "triangle-list");
        assert_eq!(
            Topology::TriangleStripRestart.c_enumerator(),
            "ARBOR_TOPOLOGY_TRIANGLE_STRIP_RESTART"
        );
        assert_eq!(UpAxis::Z.c_enumerator(), "ARBOR_UP_AXIS_Z");
        assert_eq!(Axes::from_name("UNREAL"), Some(Axes::Unreal));
        assert_eq!(
            "triangle_list".parse::<Topology>().unwrap(),
            Topology::TriangleList
        );
        let e = Topology::from_field("topology", 9).unwrap_err().to_string();
        assert!(
            e.contains("topology")
                && e.contains("9")
                && e.contains("2 (ARBOR_TOPOLOGY_TRIANGLE_STRIP_DEGENERATE)"),
            "{e}"
        );
        assert!("strip".parse::<Topology>().is_err());
    }
}
