//! Layouts shared with the Rust types, and struct sizes for bindings.

use super::*;

/// Asserts at compile time that a C type and the Rust type it is cast to have the same
/// size, alignment and, field by field, the same offsets (C name => Rust name).
macro_rules! same_layout {
    ($c:ty, $rust:ty, [$($cf:ident => $rf:ident),* $(,)?]) => {
        const _: () = {
            use std::mem::{align_of, offset_of, size_of};
            assert!(size_of::<$c>() == size_of::<$rust>());
            assert!(align_of::<$c>() == align_of::<$rust>());
            $(assert!(offset_of!($c, $cf) == offset_of!($rust, $rf));)*
        };
    };
}

same_layout!(ArborBranch, Branch, [
    start => start, end => end, start_radius => start_radius, end_radius => end_radius,
    parent => parent, depth => birth, order => order, flags => flags,
]);
same_layout!(ArborVertex, Vertex, [position => position, normal => normal, uv => uv]);
same_layout!(ArborHondaParams, HondaParams, [
    trunk_length => trunk_length, trunk_width => trunk_width, r1 => r1, r2 => r2,
    alpha1 => alpha1, alpha2 => alpha2, phi1 => phi1, phi2 => phi2, q => q, e => e,
    min_length => min_length, steps => steps,
]);
same_layout!(ArborBranchRange, BranchRange, [
    first_vertex => first_vertex, vertex_count => vertex_count,
    first_index => first_index, index_count => index_count,
]);
same_layout!(ArborLeafInstance, LeafInstance, [
    position => position, rotation => rotation, scale => scale,
]);
same_layout!(ArborLeafSite, crate::skeleton::LeafSite, [
    position => position, heading => heading, up => up, branch => branch, depth => birth,
]);
same_layout!(ArborOrgan, crate::skeleton::Organ, [
    position => position, heading => heading, up => up, size => size, kind => kind,
    branch => branch, depth => birth, color => color,
]);
same_layout!(ArborCurveRecord, crate::mesh::CurveRecord, [
    p0 => p0, r0 => r0, p1 => p1, r1 => r1, p2 => p2, v0 => v0, p3 => p3, length => length,
    u_offset => u_offset, order => order, parent => parent, birth => birth,
]);
same_layout!(ArborCurveGrowthRecord, crate::mesh::CurveGrowthRecord, [
    curve => curve, grow_start => grow_start, grow_end => grow_end, reserved => reserved,
]);
same_layout!(ArborAnimationVertex, crate::mesh::AnimationVertex, [
    growth => growth, order => order, along => along, phase => phase,
]);

/// Identifies a struct of this header for arbor_struct_size().
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArborStructId {
    /// ArborHondaParams.
    HondaParams = 0,
    /// ArborBranch.
    Branch = 1,
    /// ArborVertex.
    Vertex = 2,
    /// ArborMeshOptions.
    MeshOptions = 3,
    /// ArborLsystemOptions.
    LsystemOptions = 4,
    /// ArborLeafOptions.
    LeafOptions = 5,
    /// ArborLeafInstance.
    LeafInstance = 6,
    /// ArborBranchRange.
    BranchRange = 7,
    /// ArborLeafSite.
    LeafSite = 8,
    /// ArborAnimationVertex.
    AnimationVertex = 9,
    /// ArborForestTree.
    ForestTree = 10,
    /// ArborWorldOptions.
    WorldOptions = 11,
    /// ArborGrowthParams.
    GrowthParams = 12,
    /// ArborCurve.
    Curve = 13,
    /// ArborCurveRecord.
    CurveRecord = 14,
    /// ArborCurveGrowthRecord.
    CurveGrowthRecord = 15,
    /// ArborOrgan.
    Organ = 16,
}

/// The size in bytes of the struct `id` (an ArborStructId) as this library was built, so a
/// binding in another language (C#, Python) can check its layouts at run time; 0 for an
/// unknown id.
#[unsafe(no_mangle)]
pub extern "C" fn arbor_struct_size(id: u32) -> usize {
    use std::mem::size_of;
    match id {
        0 => size_of::<ArborHondaParams>(),
        1 => size_of::<ArborBranch>(),
        2 => size_of::<ArborVertex>(),
        3 => size_of::<ArborMeshOptions>(),
        4 => size_of::<ArborLsystemOptions>(),
        5 => size_of::<ArborLeafOptions>(),
        6 => size_of::<ArborLeafInstance>(),
        7 => size_of::<ArborBranchRange>(),
        8 => size_of::<ArborLeafSite>(),
        9 => size_of::<ArborAnimationVertex>(),
        10 => size_of::<ArborForestTree>(),
        11 => size_of::<ArborWorldOptions>(),
        12 => size_of::<ArborGrowthParams>(),
        13 => size_of::<ArborCurve>(),
        14 => size_of::<ArborCurveRecord>(),
        15 => size_of::<ArborCurveGrowthRecord>(),
        16 => size_of::<ArborOrgan>(),
        _ => 0,
    }
}
