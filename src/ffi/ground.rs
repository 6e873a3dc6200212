//! Worlds on a terrain: a height field under a world, trees planted on it or from a
//! species map, each tree's species slot, a world's copy, and a world as one glTF file.

use super::growth::{ArborWorld, world_mut};
use super::*;
use crate::models::growth::{GrowthParams, HeightField, MAX_GROUND_SAMPLES, SpeciesMap};

/// The samples a host's lattice of `columns x rows` claims, checked against
/// MAX_GROUND_SAMPLES before any is read.
fn samples(columns: u32, rows: u32) -> Result<usize, FfiError> {
    let n = columns as u64 * rows as u64;
    if n > MAX_GROUND_SAMPLES as u64 {
        return Err(crate::Error::LimitExceeded {
            limit_name: "MAX_GROUND_SAMPLES",
            what: "samples of a ground map",
            limit: MAX_GROUND_SAMPLES as u64,
            requested: n,
            step: None,
        }
        .into());
    }
    Ok(n as usize)
}

/// Lays a height field under an empty world (no tree and no obstacle yet; else
/// ARBOR_STATUS_INVALID_ARGUMENT): `columns x rows` heights, row by row with x fastest,
/// sample (i, j) at (origin_x + i*cell_size, origin_z + j*cell_size), bilinear between
/// samples and the edge's height beyond them. Trees planted with
/// arbor_world_plant_on_ground() and seedlings stand on it, and no bud below it gets
/// light. Every height must lie inside the world's box in y. At most 4,096 x 4,096
/// samples (ARBOR_STATUS_LIMIT_EXCEEDED, checked before a height is read); fewer than
/// 2 x 2, a non-finite height, cell or origin: INVALID_ARGUMENT naming it.
///
/// # Safety
/// `world` is NULL or live (not used elsewhere meanwhile); `heights` is NULL or readable
/// for `columns * rows` floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_set_ground(
    world: *mut ArborWorld,
    heights: *const f32,
    columns: u32,
    rows: u32,
    cell_size: f32,
    origin_x: f32,
    origin_z: f32,
) -> ArborStatus {
    guard(|| {
        // SAFETY: as the caller promises.
        let world = unsafe { world_mut(world) }?;
        let n = samples(columns, rows)?;
        // SAFETY: the caller promises `columns * rows` readable floats.
        let h = unsafe { in_slice(heights, n, "heights") }?;
        let ground = HeightField::new(columns, rows, cell_size, [origin_x, origin_z], h.to_vec())?;
        world.set_ground(ground)?;
        Ok(())
    })
}

/// arbor_world_set_ground() from a PNG height map (`png`, `png_len` bytes): a pixel a
/// sample, the top row at the lowest z, its grey level (8 or 16 bits; colour: the mean
/// of red, green and blue) from black at `base` to white at `base + height_scale`. The
/// image's size is read from its header and checked (at most 4,096 x 4,096:
/// ARBOR_STATUS_LIMIT_EXCEEDED) before a pixel is decoded; bytes that are not a PNG:
/// INVALID_ARGUMENT naming `height map`.
///
/// # Safety
/// `world` is NULL or live (not used elsewhere meanwhile); `png` is NULL or readable for
/// `png_len` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_set_ground_png(
    world: *mut ArborWorld,
    png: *const u8,
    png_len: usize,
    height_scale: f32,
    base: f32,
    cell_size: f32,
    origin_x: f32,
    origin_z: f32,
) -> ArborStatus {
    guard(|| {
        // SAFETY: as the caller promises.
        let world = unsafe { world_mut(world) }?;
        // SAFETY: the caller promises `png_len` readable bytes.
        let bytes = unsafe { in_slice(png, png_len, "png") }?;
        let ground =
            HeightField::from_png(bytes, height_scale, base, cell_size, [origin_x, origin_z])?;
        world.set_ground(ground)?;
        Ok(())
    })
}

/// Writes the ground's height at (x, z) to `*height`: the height field's, or the floor of
/// the world's box where it has none.
///
/// # Safety
/// `world` is NULL or live; `height` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_ground_height(
    world: *const ArborWorld,
    x: f32,
    z: f32,
    height: *mut f32,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `world` is NULL or live.
        let world = unsafe { arg_ref(world, "world") }?;
        // SAFETY: the caller promises `height` is NULL or writable.
        let out = unsafe { out_ref(height, "height") }?;
        *out = world.world.ground_height(x, z);
        Ok(())
    })
}

/// Reads a species pointer: NULL is the default parameters.
///
/// # Safety
/// `p` is NULL or readable for its struct_size.
unsafe fn species_of(
    p: *const ArborGrowthParams,
    name: &'static str,
) -> Result<GrowthParams, FfiError> {
    if p.is_null() {
        return Ok(GrowthParams::default());
    }
    // SAFETY: the caller promises `p` is readable for its struct_size.
    Ok(unsafe { read_growing(p, name) }?.to_rust()?)
}

/// Plants a tree of `species` (NULL: the defaults) standing on the ground at (x, z) (see
/// arbor_world_plant()), in species slot `slot` (a number of the host's that the tree and
/// its seedlings carry: arbor_world_tree_slot(), arbor_world_set_species()). Writes its
/// index to `*tree_id` if not NULL.
///
/// # Safety
/// `world` is NULL or live (not used elsewhere meanwhile); `species` is NULL or readable
/// for its struct_size; `tree_id` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_plant_on_ground(
    world: *mut ArborWorld,
    species: *const ArborGrowthParams,
    x: f32,
    z: f32,
    slot: u32,
    seed: u64,
    tree_id: *mut u32,
) -> ArborStatus {
    guard(|| {
        // SAFETY: as the caller promises.
        let world = unsafe { world_mut(world) }?;
        // SAFETY: as the caller promises.
        let p = unsafe { species_of(species, "species") }?;
        let id = world.plant_on_ground(&p, [x, z], slot, seed)?;
        // SAFETY: the caller promises `tree_id` is NULL or writable.
        unsafe { write_if_given(tree_id, "tree_id", id) }?;
        Ok(())
    })
}

/// Reads the host's species list: `count` pointers, none NULL.
///
/// # Safety
/// `species` is NULL or readable for `count` pointers, each readable for its struct_size.
unsafe fn species_list(
    species: *const *const ArborGrowthParams,
    count: usize,
) -> Result<Vec<GrowthParams>, FfiError> {
    if count > 1 << 16 {
        return Err(crate::Error::invalid(
            "species_count",
            format!("{count}; expected at most 65,536 species"),
        )
        .into());
    }
    // SAFETY: the caller promises `count` readable pointers.
    let list = unsafe { in_slice(species, count, "species") }?;
    list.iter()
        .map(|&p| {
            if p.is_null() {
                return Err(FfiError::null("species[k]"));
            }
            // SAFETY: the caller promises each pointer readable for its struct_size.
            unsafe { species_of(p, "species[k]") }
        })
        .collect()
}

/// Plants a world from a species map: `columns x rows` cells (row by row, x fastest),
/// cell (i, j) covering x from origin_x + i*cell_size and z from origin_z + j*cell_size;
/// `slots[k]` the species slot of cell k (an index into `species`, `count` of them;
/// UINT32_MAX: nothing grows), `density[k]` its trees per square unit. Each cell gets
/// density x area trees (the fraction by chance) at random points, seeded by `seed`
/// (the same map and seed give the same forest), standing on the ground, each in its
/// slot; points outside the world's box are left out. Writes the trees planted to
/// `*planted` if not NULL. All or nothing: a slot past `count`, a bad density, a map past
/// 4,096 x 4,096 cells or more trees than the world's max_trees leave the world as it was.
///
/// # Safety
/// `world` is NULL or live (not used elsewhere meanwhile); `slots` and `density` are
/// NULL or readable for `columns * rows` elements; `species` is NULL or readable for
/// `count` pointers, each readable for its struct_size; `planted` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_plant_map(
    world: *mut ArborWorld,
    slots: *const u32,
    density: *const f32,
    columns: u32,
    rows: u32,
    cell_size: f32,
    origin_x: f32,
    origin_z: f32,
    species: *const *const ArborGrowthParams,
    count: usize,
    seed: u64,
    planted: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: as the caller promises.
        let world = unsafe { world_mut(world) }?;
        let n = samples(columns, rows)?;
        // SAFETY: the caller promises `columns * rows` readable elements each.
        let (s, d) = unsafe {
            (
                in_slice(slots, n, "slots")?,
                in_slice(density, n, "density")?,
            )
        };
        let map = SpeciesMap::new(
            columns,
            rows,
            cell_size,
            [origin_x, origin_z],
            s.to_vec(),
            d.to_vec(),
        )?;
        // SAFETY: as the caller promises.
        let list = unsafe { species_list(species, count) }?;
        let ids = world.plant_map(&map, &list, seed)?;
        // SAFETY: the caller promises `planted` is NULL or writable.
        unsafe { write_if_given(planted, "planted", ids.len()) }?;
        Ok(())
    })
}

/// arbor_world_plant_map() from a PNG picture (`png`, `png_len` bytes): a pixel a cell,
/// the top row at the lowest z; a pixel of colour `colours[k]` (0xRRGGBB) grows
/// `species[k]` at `density` trees per square unit, any other colour nothing. The size is
/// checked from the header before a pixel is decoded.
///
/// # Safety
/// `world` is NULL or live (not used elsewhere meanwhile); `png` is NULL or readable for
/// `png_len` bytes; `colours` is NULL or readable for `count` values and `species` for
/// `count` pointers, each readable for its struct_size; `planted` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_plant_map_png(
    world: *mut ArborWorld,
    png: *const u8,
    png_len: usize,
    colours: *const u32,
    species: *const *const ArborGrowthParams,
    count: usize,
    density: f32,
    cell_size: f32,
    origin_x: f32,
    origin_z: f32,
    seed: u64,
    planted: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: as the caller promises.
        let world = unsafe { world_mut(world) }?;
        // SAFETY: as the caller promises.
        let list = unsafe { species_list(species, count) }?;
        // SAFETY: the caller promises `count` readable colours.
        let colours = unsafe { in_slice(colours, count, "colours") }?;
        let legend: Vec<([u8; 3], u32)> = colours
            .iter()
            .enumerate()
            .map(|(k, &c)| ([(c >> 16) as u8, (c >> 8) as u8, c as u8], k as u32))
            .collect();
        // SAFETY: the caller promises `png_len` readable bytes.
        let bytes = unsafe { in_slice(png, png_len, "png") }?;
        let map = SpeciesMap::from_png(bytes, &legend, density, cell_size, [origin_x, origin_z])?;
        let ids = world.plant_map(&map, &list, seed)?;
        // SAFETY: the caller promises `planted` is NULL or writable.
        unsafe { write_if_given(planted, "planted", ids.len()) }?;
        Ok(())
    })
}

/// Writes the species slot of tree `index` (what it was planted with; a seedling: its
/// parent's) to `*slot`. An index past the end: ARBOR_STATUS_INVALID_ARGUMENT.
///
/// # Safety
/// `world` is NULL or live; `slot` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_tree_slot(
    world: *const ArborWorld,
    index: usize,
    slot: *mut u32,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `world` is NULL or live.
        let world = unsafe { arg_ref(world, "world") }?;
        // SAFETY: the caller promises `slot` is NULL or writable.
        let out = unsafe { out_ref(slot, "slot") }?;
        *out = world.world.tree_slot(index)?;
        Ok(())
    })
}

/// Gives every tree in species slot `slot` (and the seedlings they drop from now on) the
/// parameters `species` (NULL: the defaults): what a host's slider changes. Writes how
/// many trees changed to `*changed` if not NULL.
///
/// # Safety
/// `world` is NULL or live (not used elsewhere meanwhile); `species` is NULL or readable
/// for its struct_size; `changed` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_set_species(
    world: *mut ArborWorld,
    slot: u32,
    species: *const ArborGrowthParams,
    changed: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: as the caller promises.
        let world = unsafe { world_mut(world) }?;
        // SAFETY: as the caller promises.
        let p = unsafe { species_of(species, "species") }?;
        let n = world.set_species(slot, &p)?;
        // SAFETY: the caller promises `changed` is NULL or writable.
        unsafe { write_if_given(changed, "changed", n) }?;
        Ok(())
    })
}

/// A copy of `world` (its trees, ground, shadow, options and progress callback) that
/// grows on by itself: a preview to step ahead of the original. Free it with
/// arbor_world_free(). It takes as much memory as the world.
///
/// # Safety
/// `world` is NULL or live; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_clone(
    world: *const ArborWorld,
    out: *mut *mut ArborWorld,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `world` is NULL or live.
        let world = unsafe { arg_ref(world, "world") }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        *out = world.copy().into_handle();
        Ok(())
    })
}

/// Writes a world's trees as one glTF 2.0 file at `path` (`.glb` or `.gltf`, whole or not
/// at all): a node a tree named `NAME_k`, `k` its index and NAME `names[slot]` of its
/// species slot ("tree" past `name_count`), in world space (metres; the mesh options'
/// scale stands). Each tree's mesh is its bark and, unless `leaf_options` is NULL, its
/// baked leaves; a name that is a species with a look of its own ("oak", "pine", ...: see
/// arbor_species_name()) gets that species' bark and leaf textures, `texture_size` pixels
/// square (0: untextured; else 16..=4096). With `ground` (non-zero), the world's height
/// field is a node "ground". Passes the Khronos glTF validator.
///
/// # Safety
/// `world` is NULL or live; `names` is NULL or readable for `name_count` pointers, each
/// NUL-terminated; the options are NULL or readable; `path` is NULL or NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_export_gltf(
    world: *const ArborWorld,
    names: *const *const c_char,
    name_count: usize,
    mesh_options: *const ArborMeshOptions,
    leaf_options: *const ArborLeafOptions,
    texture_size: u32,
    ground: u32,
    path: *const c_char,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `world` is NULL or live.
        let world = unsafe { arg_ref(world, "world") }?;
        // SAFETY: the caller promises `name_count` readable pointers.
        let raw = unsafe { in_slice(names, name_count, "names") }?;
        let mut list = Vec::with_capacity(raw.len());
        for &p in raw {
            if p.is_null() {
                return Err(FfiError::null("names[k]"));
            }
            // SAFETY: the caller promises each name NUL-terminated.
            let name = unsafe { CStr::from_ptr(p) }
                .to_str()
                .map_err(|_| crate::Error::invalid("names", "a name is not UTF-8"))?;
            list.push(name);
        }
        // SAFETY: the caller promises `mesh_options` is NULL or readable.
        let (mo, _, _, _) = unsafe { read_mesh_options_with_progress(mesh_options) }?;
        let leaves = if leaf_options.is_null() {
            None
        } else {
            // SAFETY: the caller promises a non-NULL `leaf_options` is readable.
            Some(unsafe { read_leaf_options(leaf_options, true) }?)
        };
        if path.is_null() {
            return Err(FfiError::null("path"));
        }
        // SAFETY: the caller promises a non-NULL `path` is NUL-terminated.
        let path = unsafe { CStr::from_ptr(path) }
            .to_str()
            .map_err(|_| crate::Error::invalid("path", "the path is not UTF-8"))?;
        crate::export::save_gltf_world(
            &world.world,
            &list,
            &mo,
            leaves.as_ref(),
            texture_size,
            ground != 0,
            path,
        )?;
        Ok(())
    })
}
