//! Named species: their adult trees, the options that draw them at their height, and
//! their textures into the host's memory.

use super::*;
use crate::enums::Numbered;
use crate::models::growth::Species;
use crate::species::Look;
use crate::texture::{BarkMap, bark_map, leaf_atlas_in};

/// Which texture of a species arbor_species_texture_write() draws.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArborTexture {
    /// The leaf atlas: sprays of the species' blades (or needles) in a grid of cells (see
    /// arbor_leaf_atlas_rect()), alpha 0 around them; sRGB.
    LeafAtlas = 0,
    /// The bark's colour, tiling; sRGB.
    BarkColor = 1,
    /// The bark's tangent-space normal map (+X right, +Y up the image, +Z out), tiling;
    /// linear.
    BarkNormal = 2,
    /// The bark's roughness in glTF's metallic-roughness layout (green roughness, blue
    /// metalness 0, red and alpha 255), tiling; linear.
    BarkRoughness = 3,
}

/// The look of a named species, or an error naming `species`.
fn look_of(species: u32) -> Result<Look, FfiError> {
    let s = Species::from_field("species", species)?;
    Look::of(s).ok_or_else(|| {
        crate::Error::invalid(
            "species",
            format!(
                "{species} ({}) is a crown archetype without leaves or bark; expected a named \
                 species, ARBOR_SPECIES_OAK ({}) or after",
                s.c_enumerator(),
                Species::Oak as u32
            ),
        )
        .into()
    })
}

/// Grows the adult tree of a named species (ARBOR_SPECIES_OAK and after: its cycles, its
/// trunk cleared below its crown) seeded with `seed`, and writes it to `*out` (free it
/// with arbor_tree_free()). Its model units are the growth model's: draw it with
/// arbor_species_options() for metres. A crown archetype (excurrent ... weeping) or an
/// unknown number: ARBOR_STATUS_INVALID_ARGUMENT naming `species`.
///
/// # Safety
/// `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_from_species(
    species: u32,
    seed: u64,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    // SAFETY: the caller promises `out` is NULL or writable.
    unsafe { grow_species(species, seed, out, Look::grow) }
}

/// Grows a named species with `grow` (with or without its twigs) into `*out`.
///
/// # Safety
/// `out` is NULL or writable.
unsafe fn grow_species(
    species: u32,
    seed: u64,
    out: *mut *mut ArborTree,
    grow: fn(&Look, u64) -> crate::Result<crate::skeleton::Skeleton>,
) -> ArborStatus {
    guard(|| {
        let look = look_of(species)?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        *out = ArborTree::new(grow(&look, seed)?).into_handle();
        Ok(())
    })
}

/// The options that draw `tree` as species `species` does: `*mesh_options` (read, then
/// written back at the host's struct_size) gets a scale that makes the tree the species'
/// height in metres, `texture_scale` one bark tile and `even_texels` 1; `*leaf_options`
/// (written at its struct_size, over the defaults) places the species' leaf cards on the
/// buds and young tips, in metres, on the atlas' cells. Either may be NULL to skip it.
///
/// # Safety
/// `tree` is NULL or live; each options pointer is NULL or readable and writable for its
/// `struct_size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_species_options(
    species: u32,
    tree: *const ArborTree,
    mesh_options: *mut ArborMeshOptions,
    leaf_options: *mut ArborLeafOptions,
) -> ArborStatus {
    guard(|| {
        let look = look_of(species)?;
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises each options pointer as this function does.
        unsafe {
            rewrite_options(mesh_options, leaf_options, |base| {
                crate::species::options(&look, tree.skeleton(), &base)
            })
        }
    })
}

/// Reads the host's mesh options (NULL: defaults), lets `make` turn them into the options
/// to write back, and writes them: the mesh options at the host's struct_size (what only
/// C has stays the host's), the leaf options at theirs (read first, so their struct_size
/// is checked as every call checks it). Either pointer may be NULL to skip it.
///
/// # Safety
/// Each options pointer is NULL or readable and writable for its `struct_size` bytes.
unsafe fn rewrite_options(
    mesh_options: *mut ArborMeshOptions,
    leaf_options: *mut ArborLeafOptions,
    make: impl FnOnce(MeshOptions) -> crate::Result<(MeshOptions, crate::mesh::LeafOptions)>,
) -> Result<(), FfiError> {
    let host = if mesh_options.is_null() {
        None
    } else {
        // SAFETY: the caller promises a readable struct of its struct_size.
        Some(unsafe { read_growing(mesh_options.cast_const(), "mesh_options") }?)
    };
    let base = match &host {
        Some(c) => c.to_rust()?,
        None => MeshOptions::default(),
    };
    let (mesh, leaves) = make(base)?;
    let host_leaves = if leaf_options.is_null() {
        None
    } else {
        // SAFETY: the caller promises a readable struct of its struct_size.
        Some(unsafe { read_growing(leaf_options.cast_const(), "leaf_options") }?)
    };
    if let Some(c) = host {
        let size = c.struct_size as usize;
        let mut out = ArborMeshOptions::from_rust(&mesh);
        (out.threads, out.progress, out.progress_user_data) =
            (c.threads, c.progress, c.progress_user_data);
        // SAFETY: the caller promises `struct_size` writable bytes (read above).
        unsafe { write_growing(mesh_options, size, &out) };
    }
    if let Some(host) = host_leaves {
        let out = ArborLeafOptions::from_rust(&leaves);
        // SAFETY: the caller promises `struct_size` writable bytes (read above).
        unsafe { write_growing(leaf_options, host.struct_size as usize, &out) };
    }
    Ok(())
}

/// Grows the adult tree of a named species as arbor_tree_from_species() does, without
/// its twigs: the tree a host draws instanced twigs on (arbor_species_twig_create(),
/// arbor_species_twig_instances_write()). Its bark and leaf options are still
/// arbor_species_options()'s; its leaves there sit on the young tips the twigs leave.
///
/// # Safety
/// `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_tree_from_species_bare(
    species: u32,
    seed: u64,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    // SAFETY: the caller promises `out` is NULL or writable.
    unsafe { grow_species(species, seed, out, Look::grow_bare) }
}

/// Writes twig `variant` (taken modulo ARBOR_TWIG_VARIANTS) of a named species to `*out`
/// as a tree of its own (free it with arbor_tree_free()): its stems in metres (+Y along
/// the twig, +Z the side its spray faces) and leaf sites at their tips. Mesh it once
/// with the options of arbor_species_twig_options() (bark and leaves) and draw it at each
/// transform of arbor_species_twig_instances_write(): the twigs
/// arbor_tree_from_species() bakes in.
///
/// # Safety
/// `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_species_twig_create(
    species: u32,
    variant: u32,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    guard(|| {
        let look = look_of(species)?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let twig = crate::species::twig_prototype(&look, variant as usize)?;
        *out = ArborTree::new(twig).into_handle();
        Ok(())
    })
}

/// The options that draw a species' twig (arbor_species_twig_create()) in the host's
/// conventions: `*mesh_options` (read, then written back at the host's struct_size)
/// keeps its up axis, scale, winding and layout and gets the bark's texture scale and
/// even texels, 3 or 4 sides; `*leaf_options` (written at its struct_size) puts the
/// species' leaf cards on the twig's sites, in metres, on the atlas' cells. Either may
/// be NULL to skip it.
///
/// # Safety
/// Each options pointer is NULL or readable and writable for its `struct_size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_species_twig_options(
    species: u32,
    mesh_options: *mut ArborMeshOptions,
    leaf_options: *mut ArborLeafOptions,
) -> ArborStatus {
    guard(|| {
        let look = look_of(species)?;
        // SAFETY: the caller promises each options pointer as this function does.
        unsafe {
            rewrite_options(mesh_options, leaf_options, |base| {
                Ok(crate::species::twig_options(&look, &base))
            })
        }
    })
}

/// Writes where `tree` (from arbor_tree_from_species_bare() for this species) carries its
/// twigs: one ArborLeafInstance each (position, rotation x y z w, scale) that places the
/// twig meshed with arbor_species_twig_options(`mesh_options`) into the tree meshed with
/// arbor_species_options(`mesh_options`); instance k is twig variant k %
/// ARBOR_TWIG_VARIANTS. `*count` (when not NULL) gets the number of twigs; `out` (NULL:
/// count only) holds `capacity` instances: at least that many, else
/// ARBOR_STATUS_BUFFER_TOO_SMALL and nothing written. `mesh_options` NULL: the defaults.
///
/// # Safety
/// `tree` is NULL or live; `mesh_options` is NULL or readable; `out` is NULL or writable
/// for `capacity` instances; `count` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_species_twig_instances_write(
    species: u32,
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    out: *mut LeafInstance,
    capacity: usize,
    count: *mut usize,
) -> ArborStatus {
    guard(|| {
        let look = look_of(species)?;
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `mesh_options` is NULL or readable.
        let (mo, _) = unsafe { read_mesh_options(mesh_options) }?;
        let twigs = crate::species::twig_instances(&look, tree.skeleton(), &mo)?;
        if !out.is_null() {
            // SAFETY: the caller promises `out` holds `capacity` writable instances.
            let dst = unsafe { out_slice(out, capacity, twigs.len(), "out") }?;
            for (d, t) in dst.iter_mut().zip(&twigs) {
                d.write(*t);
            }
        }
        if !count.is_null() {
            // SAFETY: the caller promises a non-NULL `count` is writable.
            *unsafe { out_ref(count, "count") }? = twigs.len();
        }
        Ok(())
    })
}

/// Draws texture `which` (an ArborTexture) of a named species as `size` x `size` RGBA8
/// pixels (16..=4096; rows from the top, glTF's uv origin) into `rgba`, which holds
/// `capacity` bytes: at least `size * size * 4`, else ARBOR_STATUS_BUFFER_TOO_SMALL and
/// nothing written. `threads`: 0 all cores (at most 8), 1 the calling thread only (an
/// image under 256 x 256 is drawn on it whatever this asks). The same species, size and
/// seed give the same bytes on every platform and any thread count; the textures of
/// arbor's own glTF export of the species are these.
///
/// # Safety
/// `rgba` is NULL or writable for `capacity` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_species_texture_write(
    species: u32,
    which: u32,
    size: u32,
    seed: u64,
    threads: u32,
    rgba: *mut u8,
    capacity: usize,
) -> ArborStatus {
    guard(|| {
        let look = look_of(species)?;
        if which > ArborTexture::BarkRoughness as u32 {
            return Err(FfiError::invalid(format!(
                "`which` is {which}; expected an ArborTexture (0 leaf atlas, 1 bark colour, 2 \
                 bark normal, 3 bark roughness)"
            )));
        }
        crate::texture::check_size("size", size)?;
        let needed = size as usize * size as usize * 4;
        // SAFETY: the caller promises `capacity` writable bytes at `rgba`.
        let out = unsafe { out_slice(rgba, capacity, needed, "rgba") }?;
        let run = on_threads(threads);
        let image = match which {
            0 => leaf_atlas_in(&look.leaf, size, seed, &run)?.image,
            1 => bark_map(&look.bark, size, seed, BarkMap::Color, &run)?,
            2 => bark_map(&look.bark, size, seed, BarkMap::Normal, &run)?,
            _ => bark_map(&look.bark, size, seed, BarkMap::Roughness, &run)?,
        };
        for (slot, &b) in out.iter_mut().zip(&image.pixels) {
            slot.write(b);
        }
        Ok(())
    })
}

/// Writes cell `cell`'s rectangle of a species' leaf atlas as (u0, v0, u1, v1) into
/// `rect` (4 floats; v0 is the stem's end), and the atlas' cell count to `*cells` when it
/// is not NULL. Every species' atlas has the same grid (4 by 2); `cell` is taken modulo
/// the count. A baked leaf mesh already samples its cells; an instanced leaf `k` samples
/// cell arbor_leaf_cell(leaf_options, k).
///
/// # Safety
/// `rect` is NULL or writable for 4 floats; `cells` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_atlas_rect(
    cell: u32,
    rect: *mut f32,
    cells: *mut u32,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises 4 writable floats.
        let r = unsafe { out_slice(rect, 4, 4, "rect") }?;
        let (columns, rows) = (crate::texture::ATLAS_COLUMNS, crate::texture::ATLAS_ROWS);
        for (slot, v) in r
            .iter_mut()
            .zip(crate::texture::atlas_rect(columns, rows, cell as usize))
        {
            slot.write(v);
        }
        if !cells.is_null() {
            // SAFETY: the caller promises a non-NULL `cells` is writable.
            *unsafe { out_ref(cells, "cells") }? = columns * rows;
        }
        Ok(())
    })
}

/// The atlas cell that leaf `k` (in the order of arbor_leaf_instances_write()) samples
/// with these leaf options (NULL: the defaults, one cell: 0); 0 for unreadable options.
///
/// # Safety
/// `leaf_options` is NULL or readable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_leaf_cell(leaf_options: *const ArborLeafOptions, k: usize) -> u32 {
    guard_value(0, || {
        // SAFETY: the caller promises NULL or readable options.
        unsafe { super::leaves::read_leaf_options(leaf_options, false) }
            .map_or(0, |o| crate::mesh::leaf_cell(&o, k))
    })
}

/// A grown tree of a named species (such as a snapshot of a world's tree from
/// arbor_world_tree()) shaped as the species is after it grows: its trunk cleared below
/// its crown, bare limbs shed, a conifer's crown drawn into its cone, a weeping crown into
/// its dome, its foot flared with roots, and its twigs grafted on the young shoots (what
/// arbor_tree_from_species() does to the tree it grows), in the same units. Writes the new
/// tree to `*out` (free it with arbor_tree_free()). A crown archetype or an unknown
/// number: ARBOR_STATUS_INVALID_ARGUMENT naming `species`; a tree without branches:
/// INVALID_ARGUMENT.
///
/// # Safety
/// `grown` is NULL or live; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_species_finish(
    species: u32,
    grown: *const ArborTree,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    guard(|| {
        let look = look_of(species)?;
        // SAFETY: the caller promises `grown` is NULL or live.
        let grown = unsafe { arg_ref(grown, "grown") }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        if grown.skeleton().is_empty() {
            return Err(crate::Error::invalid(
                "grown",
                "a tree without branches; expected a grown tree",
            )
            .into());
        }
        *out = ArborTree::new(look.finish(grown.skeleton())?).into_handle();
        Ok(())
    })
}
