//! Mesh writes in the vertex format the options name (`vertex_format`): ArborVertex or
//! ArborVertexCompact into a byte buffer, their rewrites after an edit, the scale of a
//! compact mesh's v, and the animation stream packed to match.

use super::meshes::{MeshWrite, rewrite_branch};
use super::*;

/// The size of one vertex of `format`, once `vertices` is known to be 4-byte aligned (the
/// positions are f32).
fn stride_of(format: VertexFormat, vertices: *const c_void) -> Result<usize, FfiError> {
    if !vertices.is_null() && (vertices as usize) % 4 != 0 {
        return Err(crate::Error::invalid(
            "vertices",
            "the buffer is not aligned to 4 bytes (f32 positions)",
        )
        .into());
    }
    Ok(match format {
        VertexFormat::F32 => std::mem::size_of::<Vertex>(),
        VertexFormat::Compact => std::mem::size_of::<VertexCompact>(),
    })
}

/// Writes the mesh of `tree` into a byte buffer of `vertex_bytes` bytes, in the vertex
/// format `options->vertex_format` names: ArborVertex (32 bytes each) or
/// ArborVertexCompact (20 bytes each; decode v with arbor_mesh_v_scale()). Indices as
/// arbor_mesh_write(). The counts are arbor_mesh_size()'s, so a host allocates (or maps)
/// vertex count x the format's size bytes. `vertices` must be 4-byte aligned (malloc'd
/// and mapped GPU memory are). Too few bytes give ARBOR_STATUS_BUFFER_TOO_SMALL naming
/// `vertex_bytes` (required and capacity in bytes) and nothing is written.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `vertices` is NULL or valid for
/// writes of `vertex_bytes` bytes, `indices` NULL or valid for writes of `index_count`
/// indices, and they do not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_write_bytes(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    vertices: *mut c_void,
    vertex_bytes: usize,
    indices: *mut u32,
    index_count: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live and `options` NULL or readable.
        let w = unsafe { MeshWrite::read(tree, options) }?;
        let (size, format) = (w.size(), w.options.vertex_format);
        let stride = stride_of(format, vertices)?;
        let needed = size.vertices.saturating_mul(stride);
        if vertex_bytes < needed {
            return Err(crate::Error::BufferTooSmall {
                buffer: "vertex_bytes",
                required: needed,
                capacity: vertex_bytes,
            }
            .into());
        }
        let count = vertex_bytes / stride;
        // SAFETY: the caller promises `indices` holds `index_count` writable indices.
        let i = unsafe { out_slice(indices, index_count, size.indices, "indices") }?;
        match format {
            VertexFormat::F32 => {
                // SAFETY: the caller promises `vertex_bytes` writable bytes apart from
                // `indices`; `count` ArborVertex fit in them, at a 4-byte aligned address.
                let v = unsafe {
                    out_slice(vertices.cast::<Vertex>(), count, size.vertices, "vertices")
                }?;
                w.write(v, i)
            }
            VertexFormat::Compact => {
                // SAFETY: as above, for `count` ArborVertexCompact.
                let v = unsafe {
                    out_slice(
                        vertices.cast::<VertexCompact>(),
                        count,
                        size.vertices,
                        "vertices",
                    )
                }?;
                w.write(v, i)
            }
        }
    })
}

/// What the v of `tree`'s compact mesh with `options` is stored over: an
/// ArborVertexCompact's v is `uv[1] / 65535 * v_scale`. A power of two at or above the
/// mesh's largest v (at least 1); 1 when `options->vertex_format` is
/// ARBOR_VERTEX_FORMAT_F32. It can change after an edit that lengthens the tree (then
/// arbor_mesh_rewrite_branch_bytes() rewrites every vertex): read it again after edits.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `v_scale` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_v_scale(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    v_scale: *mut f32,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let (options, threads) = unsafe { read_mesh_options(options) }?;
        // SAFETY: the caller promises `v_scale` is NULL or writable.
        let out = unsafe { out_ref(v_scale, "v_scale") }?;
        *out = tree.plan_in(&options, &on_threads(threads))?.v_scale();
        Ok(())
    })
}

/// arbor_mesh_rewrite_branch() for buffers in the format `options->vertex_format` names
/// (as arbor_mesh_write_bytes() writes them): `vertex_bytes` must be the mesh's vertex
/// count times the format's size, and `vertices` 4-byte aligned. Compact vertices whose
/// v_scale an edit changed are all rewritten.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `vertices` is NULL or valid for
/// reads and writes of `vertex_bytes` bytes and `indices` of `index_count` indices, and
/// they hold the mesh.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_rewrite_branch_bytes(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    branch: usize,
    vertices: *mut c_void,
    vertex_bytes: usize,
    indices: *mut u32,
    index_count: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `options` is NULL or readable.
        let format = unsafe { read_mesh_options(options) }?.0.vertex_format;
        let stride = stride_of(format, vertices)?;
        if vertex_bytes % stride != 0 {
            return Err(crate::Error::invalid(
                "vertex_bytes",
                format!("{vertex_bytes} bytes is not a whole number of {stride}-byte vertices"),
            )
            .into());
        }
        let count = vertex_bytes / stride;
        // SAFETY: the caller promises the tree, options and buffers; `count` vertices of
        // the format fill `vertex_bytes` aligned bytes.
        unsafe {
            match format {
                VertexFormat::F32 => rewrite_branch(
                    tree,
                    options,
                    branch,
                    vertices.cast::<Vertex>(),
                    count,
                    indices,
                    index_count,
                ),
                VertexFormat::Compact => rewrite_branch(
                    tree,
                    options,
                    branch,
                    vertices.cast::<VertexCompact>(),
                    count,
                    indices,
                    index_count,
                ),
            }
        }
    })
}

/// Writes the animation stream of `tree`'s mesh with `options` into a byte buffer of
/// `bytes` bytes, in the format `options->vertex_format` names: ArborAnimationVertex (16
/// bytes each) or, for compact vertices, ArborAnimationVertexCompact (8 bytes each). One
/// element per vertex of arbor_mesh_size(); too few bytes give
/// ARBOR_STATUS_BUFFER_TOO_SMALL naming `bytes` and nothing is written. `out` must be
/// 4-byte aligned.
///
/// # Safety
/// `tree` is NULL or live; `options` is NULL or readable; `out` is NULL or valid for
/// writes of `bytes` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_mesh_animation_write_bytes(
    tree: *const ArborTree,
    options: *const ArborMeshOptions,
    out: *mut c_void,
    bytes: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `options` is NULL or readable.
        let (options, threads) = unsafe { read_mesh_options(options) }?;
        let plan = tree.plan_in(&options, &on_threads(threads))?;
        let data: Vec<u8> = match options.vertex_format {
            VertexFormat::F32 => bytemuck::cast_slice(&plan.animation(tree.skeleton())?).to_vec(),
            VertexFormat::Compact => {
                bytemuck::cast_slice(&plan.animation_compact(tree.skeleton())?).to_vec()
            }
        };
        if !out.is_null() && (out as usize) % 4 != 0 {
            return Err(
                crate::Error::invalid("out", "the buffer is not aligned to 4 bytes").into(),
            );
        }
        // SAFETY: the caller promises `out` holds `bytes` writable bytes.
        unsafe { copy_out(&data, out.cast::<u8>(), bytes, "bytes") }?;
        Ok(())
    })
}
