//! Struct sizes for bindings.

use super::*;

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
    /// ArborVertexCompact.
    VertexCompact = 17,
    /// ArborAnimationVertexCompact.
    AnimationVertexCompact = 18,
    /// ArborForestPlant.
    ForestPlant = 19,
    /// ArborCapsule.
    Capsule = 20,
    /// ArborLodOptions.
    LodOptions = 21,
    /// ArborBone.
    Bone = 22,
}

/// The size in bytes of the struct `id` (an ArborStructId) as this library was built, so a
/// binding in another language (C#, Python) can check its layouts at run time; 0 for an
/// unknown id.
#[unsafe(no_mangle)]
pub extern "C" fn arbor_struct_size(id: u32) -> usize {
    use std::mem::size_of;
    match id {
        0 => size_of::<HondaParams>(),
        1 => size_of::<Branch>(),
        2 => size_of::<Vertex>(),
        3 => size_of::<ArborMeshOptions>(),
        4 => size_of::<ArborLsystemOptions>(),
        5 => size_of::<ArborLeafOptions>(),
        6 => size_of::<LeafInstance>(),
        7 => size_of::<BranchRange>(),
        8 => size_of::<LeafSite>(),
        9 => size_of::<AnimationVertex>(),
        10 => size_of::<ArborForestTree>(),
        11 => size_of::<ArborWorldOptions>(),
        12 => size_of::<super::ArborGrowthParams>(),
        13 => size_of::<ArborCurve>(),
        14 => size_of::<CurveRecord>(),
        15 => size_of::<CurveGrowthRecord>(),
        16 => size_of::<Organ>(),
        17 => size_of::<VertexCompact>(),
        18 => size_of::<mesh::AnimationVertexCompact>(),
        19 => size_of::<ArborForestPlant>(),
        20 => size_of::<crate::collision::Capsule>(),
        21 => size_of::<super::ArborLodOptions>(),
        22 => size_of::<crate::wind::Bone>(),
        _ => 0,
    }
}
