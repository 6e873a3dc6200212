//! Rust-side checks of the C ABI shell; the C programs in `ffi-tests/` test it from C.

use super::guard::{guard, guard_value};
use super::*;
use std::ffi::CStr;

fn last_error() -> String {
    // SAFETY: NULL with capacity 0 asks for the length only.
    let n = unsafe { arbor_last_error_message(std::ptr::null_mut(), 0) };
    let mut buf = vec![0 as c_char; n + 1];
    // SAFETY: `buf` holds n + 1 writable bytes.
    let m = unsafe { arbor_last_error_message(buf.as_mut_ptr(), buf.len()) };
    assert_eq!(m, n);
    // SAFETY: the function NUL-terminated the buffer.
    unsafe { CStr::from_ptr(buf.as_ptr()) }
        .to_str()
        .unwrap()
        .to_owned()
}

#[test]
fn versions_match_cargo_toml() {
    let major: u32 = env!("CARGO_PKG_VERSION_MAJOR").parse().unwrap();
    let minor: u32 = env!("CARGO_PKG_VERSION_MINOR").parse().unwrap();
    let patch: u32 = env!("CARGO_PKG_VERSION_PATCH").parse().unwrap();
    assert_eq!(
        (
            ARBOR_VERSION_MAJOR,
            ARBOR_VERSION_MINOR,
            ARBOR_VERSION_PATCH
        ),
        (major, minor, patch)
    );
    assert_eq!(ARBOR_ABI_VERSION, major * 10000 + minor * 100 + patch);
    assert_eq!(arbor_abi_version(), ARBOR_ABI_VERSION);
    // SAFETY: arbor_version returns a static NUL-terminated string.
    let v = unsafe { CStr::from_ptr(arbor_version()) };
    assert_eq!(v.to_str().unwrap(), env!("CARGO_PKG_VERSION"));
}

#[test]
fn enums_match_the_rust_api() {
    for t in Topology::ALL {
        let c = match t {
            Topology::TriangleList => ArborTopology::TriangleList,
            Topology::TriangleStripRestart => ArborTopology::TriangleStripRestart,
            Topology::TriangleStripDegenerate => ArborTopology::TriangleStripDegenerate,
        };
        assert_eq!(c as u32, t as u32);
    }
    assert_eq!(ARBOR_RESTART_INDEX, mesh::RESTART_INDEX);
    assert_eq!(ARBOR_NO_PARENT, crate::skeleton::NO_PARENT);
}

#[test]
fn status_strings_are_distinct_and_static() {
    let mut seen = std::collections::HashSet::new();
    for s in 0..=8u32 {
        // SAFETY: arbor_status_str never returns NULL and its strings are static.
        let text = unsafe { CStr::from_ptr(arbor_status_str(s)) };
        assert!(seen.insert(text.to_owned()), "duplicate text for {s}");
    }
    // SAFETY: as above.
    let unknown = unsafe { CStr::from_ptr(arbor_status_str(12345)) };
    assert_eq!(unknown.to_str().unwrap(), "unknown status");
}

#[test]
fn a_panic_becomes_a_status_and_a_message() {
    let status = guard(|| panic!("boom in a test"));
    assert_eq!(status, ArborStatus::Panic);
    let message = last_error();
    assert!(message.contains("boom in a test"), "{message}");
    assert_eq!(guard_value(7u32, || panic!("again")), 7);
    assert_eq!(guard(|| Ok(())), ArborStatus::Ok);
    assert_eq!(last_error(), "");
}

#[test]
fn last_error_message_is_cut_at_capacity() {
    // SAFETY: `out` is NULL; the function reports NULL_ARGUMENT.
    let status = unsafe { arbor_honda_preset('a' as u32, std::ptr::null_mut()) };
    assert_eq!(status, ArborStatus::NullArgument);
    let full = last_error();
    assert!(full.contains("`out`"), "{full}");
    let mut buf = [0x55 as c_char; 8];
    // SAFETY: the capacity given is 5 of the 8 bytes.
    let n = unsafe { arbor_last_error_message(buf.as_mut_ptr(), 5) };
    assert_eq!(n, full.len());
    // SAFETY: NUL-terminated within the 5 bytes.
    let cut = unsafe { CStr::from_ptr(buf.as_ptr()) };
    assert_eq!(cut.to_bytes(), &full.as_bytes()[..4]);
    assert_eq!(buf[5], 0x55, "wrote past the capacity");
}

#[test]
fn options_round_trip_and_unknown_topology_is_rejected() {
    let d = arbor_mesh_options_default();
    assert_eq!(MeshOptions::try_from(&d).ok(), Some(MeshOptions::default()));
    let bad = ArborMeshOptions { topology: 3, ..d };
    let err = MeshOptions::try_from(&bad).unwrap_err();
    assert!(matches!(
        err,
        crate::Error::InvalidArgument {
            field: "topology",
            ..
        }
    ));
    assert!(err.to_string().contains("expected 0"), "{err}");
}
