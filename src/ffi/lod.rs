//! Levels of detail and impostors for a host's own assets: the chain of levels (each
//! level's bark and leaves, size then fill), and an octahedral impostor's atlases into
//! host memory.

use super::*;
use crate::lod::{Level, LodOptions};

/// sizeof(ArborLodOptions) of its first layout (this one): the smallest `struct_size`
/// accepted.
const ARBOR_LOD_OPTIONS_MIN_SIZE: usize = std::mem::size_of::<ArborLodOptions>();

impl Growing for ArborLodOptions {
    const NAME: &'static str = "ArborLodOptions";
    const MIN_SIZE: usize = ARBOR_LOD_OPTIONS_MIN_SIZE;
    fn defaults() -> Self {
        Self::from_rust(&LodOptions::default())
    }
}

impl Default for ArborLodOptions {
    /// What arbor_lod_options_init() writes for this library's size.
    fn default() -> Self {
        Self::defaults()
    }
}

/// Writes the default chain options into the first `struct_size` bytes at `options`
/// (pass `sizeof(ArborLodOptions)`), with `options->struct_size = struct_size`, and
/// nothing beyond. NULL does nothing.
///
/// # Safety
/// `options` is NULL or writable for `struct_size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_lod_options_init(options: *mut ArborLodOptions, struct_size: usize) {
    // SAFETY: the caller promises `struct_size` writable bytes at `options`.
    unsafe { init_for_host(options, struct_size) }
}

/// The levels of detail of a tree (see arbor_tree_lods_create()). Opaque; free with
/// arbor_lods_free(). A `const ArborLods *` may be read from several threads at once.
pub struct ArborLods {
    levels: Vec<Level>,
    /// The threads it was made on (0: the machine's cores), for its impostors too.
    threads: u32,
    /// The tree's skeleton and the mesh options the chain was made from: its skin's rig.
    pub(super) skeleton: crate::skeleton::Skeleton,
    pub(super) mesh_options: crate::mesh::MeshOptions,
}

/// An octahedral impostor's atlases and frame (see arbor_lods_impostor_create()). Opaque;
/// free with arbor_impostor_free().
pub struct ArborImpostor {
    impostor: crate::impostor::Impostor,
}

/// A billboard's crossed quads and atlases (see arbor_lods_billboard_create()). Opaque;
/// free with arbor_billboard_free().
pub struct ArborBillboard {
    billboard: crate::impostor::Billboard,
    /// Its level's meshes wind clockwise (the quads follow them).
    clockwise: bool,
}

/// The most pixels a side of an atlas a host passes in.
const MAX_ATLAS: u32 = crate::texture::MAX_TEXTURE_SIZE;

/// The leaf atlas a host passes (RGBA8, rows from the top), checked before it is read.
///
/// # Safety
/// `rgba` is NULL or readable for `width * height * 4` bytes.
unsafe fn host_atlas(
    rgba: *const u8,
    width: u32,
    height: u32,
) -> Result<Option<crate::texture::Image>, FfiError> {
    if rgba.is_null() {
        return Ok(None);
    }
    if !(1..=MAX_ATLAS).contains(&width) || !(1..=MAX_ATLAS).contains(&height) {
        return Err(crate::Error::invalid(
            "atlas",
            format!("{width} x {height} pixels; expected 1..={MAX_ATLAS} a side"),
        )
        .into());
    }
    let n = width as usize * height as usize * 4;
    // SAFETY: the caller promises `n` readable bytes at a non-NULL `rgba`.
    let bytes = unsafe { std::slice::from_raw_parts(rgba, n) };
    Ok(Some(crate::texture::Image {
        width,
        height,
        pixels: bytes.to_vec(),
    }))
}

/// Makes the levels of detail of `tree` (`lod::chain`): the full tree meshed with
/// `mesh_options` (NULL: the defaults), its leaves baked with `leaf_options` (NULL: no
/// leaves), and `lod_options->levels - 1` thinner levels within their budgets, each
/// switch fitted to the silhouette (the leaves alpha-tested against `atlas_rgba`, the leaf
/// atlas they sample, `atlas_width` x `atlas_height` RGBA8 pixels, rows from the top;
/// NULL: opaque cards). `lod_options` NULL: the defaults. `*out` gets the chain (free
/// with arbor_lods_free()), NULL on failure.
///
/// # Safety
/// `tree` is NULL or live; the options NULL or readable; `atlas_rgba` NULL or readable for
/// `atlas_width * atlas_height * 4` bytes; `out` writable.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn arbor_tree_lods_create(
    tree: *const ArborTree,
    mesh_options: *const ArborMeshOptions,
    leaf_options: *const ArborLeafOptions,
    atlas_rgba: *const u8,
    atlas_width: u32,
    atlas_height: u32,
    lod_options: *const ArborLodOptions,
    out: *mut *mut ArborLods,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `out` is writable.
        let out = unsafe { out_ref(out, "out") }?;
        *out = std::ptr::null_mut();
        // SAFETY: the caller promises `tree` is NULL or live.
        let tree = unsafe { arg_ref(tree, "tree") }?;
        // SAFETY: the caller promises `mesh_options` is NULL or readable.
        let (mo, threads) = unsafe { read_mesh_options(mesh_options) }?;
        let leaves = if leaf_options.is_null() {
            None
        } else {
            // SAFETY: the caller promises readable leaf options.
            Some(unsafe { super::leaves::read_leaf_options(leaf_options, true) }?)
        };
        let lod = if lod_options.is_null() {
            LodOptions::default()
        } else {
            // SAFETY: the caller promises readable options of their struct_size.
            unsafe { read_growing(lod_options, "lod_options") }?.to_rust()?
        };
        // The mesh options' threads when the chain's leave it to them.
        let lod = if lod.threads == 0 {
            lod.threads(threads)
        } else {
            lod
        };
        // SAFETY: the caller promises the atlas' bytes.
        let atlas = unsafe { host_atlas(atlas_rgba, atlas_width, atlas_height) }?;
        let levels =
            crate::lod::chain(tree.skeleton(), &mo, leaves.as_ref(), atlas.as_ref(), &lod)?;
        *out = Box::into_raw(Box::new(ArborLods {
            levels,
            threads: lod.threads,
            skeleton: tree.skeleton().clone(),
            mesh_options: mo,
        }));
        Ok(())
    })
}

/// Frees a chain; NULL does nothing.
///
/// # Safety
/// `lods` is NULL or from arbor_tree_lods_create(), not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_lods_free(lods: *mut ArborLods) {
    if !lods.is_null() {
        // SAFETY: the caller promises a live chain from arbor_tree_lods_create().
        drop(unsafe { Box::from_raw(lods) });
    }
}

/// The number of levels (0 for NULL).
///
/// # Safety
/// `lods` is NULL or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_lods_count(lods: *const ArborLods) -> usize {
    // SAFETY: the caller promises NULL or live.
    unsafe { lods.as_ref() }.map_or(0, |l| l.levels.len())
}

/// The level an impostor of views `cell` pixels across is best baked from
/// (arbor_lods_impostor_create()): the last first drawn with the tree's bounding square at
/// least `cell` pixels across (a level made for a smaller size shows its straightened and
/// pruned twigs in larger views), 0 (the full tree) when none is, and for NULL.
///
/// # Safety
/// `lods` is NULL or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_lods_impostor_level(lods: *const ArborLods, cell: u32) -> usize {
    // SAFETY: the caller promises NULL or live.
    unsafe { lods.as_ref() }.map_or(0, |l| crate::lod::impostor_source(&l.levels, cell))
}

/// Level `level`'s figures: `*screen_coverage` (drawn while the tree covers at least this
/// share of the screen's height), `*silhouette` (the IoU it keeps with the full tree where
/// it is first drawn), `*triangles`; each pointer may be NULL.
///
/// # Safety
/// `lods` is NULL or live; each pointer NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_lods_level_info(
    lods: *const ArborLods,
    level: usize,
    screen_coverage: *mut f32,
    silhouette: *mut f32,
    triangles: *mut usize,
) -> ArborStatus {
    guard(|| {
        let l = level_of(lods, level)?;
        if !screen_coverage.is_null() {
            // SAFETY: the caller promises a non-NULL pointer is writable.
            *unsafe { out_ref(screen_coverage, "screen_coverage") }? = l.screen_coverage;
        }
        if !silhouette.is_null() {
            // SAFETY: as above.
            *unsafe { out_ref(silhouette, "silhouette") }? = l.silhouette;
        }
        if !triangles.is_null() {
            // SAFETY: as above.
            *unsafe { out_ref(triangles, "triangles") }? = l.triangles;
        }
        Ok(())
    })
}

impl ArborLods {
    /// Level `level`, or the error naming the levels there are.
    pub(super) fn level(&self, level: usize) -> Result<&Level, FfiError> {
        self.levels.get(level).ok_or_else(|| {
            crate::Error::invalid(
                "level",
                format!("{level}; expected 0..{}", self.levels.len()),
            )
            .into()
        })
    }
}

fn level_of<'a>(lods: *const ArborLods, level: usize) -> Result<&'a Level, FfiError> {
    // SAFETY: every caller's caller promises `lods` is NULL or live.
    unsafe { arg_ref(lods, "lods") }?.level(level)
}

/// Part `part` of `level` (0: the bark, 1: the baked leaves, none without leaves), or the
/// error naming the parts there are.
pub(super) fn part_of(level: &Level, part: u32) -> Result<Option<&crate::mesh::Mesh>, FfiError> {
    match part {
        0 => Ok(Some(&level.bark)),
        1 => Ok(level.leaves.as_ref()),
        p => Err(
            crate::Error::invalid("part", format!("{p}; expected 0 (bark) or 1 (leaves)")).into(),
        ),
    }
}

/// Writes part `part` (0: the bark, 1: the baked leaves, empty without leaves) of level
/// `level` into host memory: `*vertex_count` and `*index_count` (when not NULL) get its
/// sizes; `vertices` (ArborVertex, NULL: sizes only) holds `vertex_capacity` and
/// `indices` `index_capacity`: at least the sizes, else ARBOR_STATUS_BUFFER_TOO_SMALL and
/// nothing written. The indices are laid out as the mesh options' topology.
///
/// # Safety
/// `lods` is NULL or live; `vertices` NULL or writable for `vertex_capacity` vertices,
/// `indices` for `index_capacity` indices; the counts NULL or writable.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn arbor_lods_mesh_write(
    lods: *const ArborLods,
    level: usize,
    part: u32,
    vertices: *mut crate::mesh::Vertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
    vertex_count: *mut usize,
    index_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        let l = level_of(lods, level)?;
        let empty = crate::mesh::Mesh {
            vertices: Vec::new(),
            indices: Vec::new(),
            topology: l.mesh_options.topology,
            ranges: Vec::new(),
        };
        let m = part_of(l, part)?.unwrap_or(&empty);
        if !vertices.is_null() || !indices.is_null() {
            // SAFETY: the caller promises the capacities at non-NULL pointers.
            let v = unsafe { out_slice(vertices, vertex_capacity, m.vertices.len(), "vertices") }?;
            // SAFETY: as above.
            let i = unsafe { out_slice(indices, index_capacity, m.indices.len(), "indices") }?;
            for (d, s) in v.iter_mut().zip(&m.vertices) {
                d.write(*s);
            }
            for (d, s) in i.iter_mut().zip(&m.indices) {
                d.write(*s);
            }
        }
        if !vertex_count.is_null() {
            // SAFETY: the caller promises a non-NULL count is writable.
            *unsafe { out_ref(vertex_count, "vertex_count") }? = m.vertices.len();
        }
        if !index_count.is_null() {
            // SAFETY: as above.
            *unsafe { out_ref(index_count, "index_count") }? = m.indices.len();
        }
        Ok(())
    })
}

/// Bakes the octahedral impostor of level `level` (arbor's rasterizer, on every core):
/// `frames` x `frames` views (1..=32) of `cell` pixels (8..=1024, the atlas at most 4096
/// a side), hemi-octahedral when `hemi` is 1, whole-sphere when 0; the leaves sample
/// `atlas_rgba` as in arbor_tree_lods_create() (NULL: opaque cards). `*out` gets it (free
/// with arbor_impostor_free()), NULL on failure. The layout is docs/meshes.md's
/// "Impostors".
///
/// # Safety
/// `lods` NULL or live; `atlas_rgba` NULL or readable for `atlas_width * atlas_height * 4`
/// bytes; `out` writable.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn arbor_lods_impostor_create(
    lods: *const ArborLods,
    level: usize,
    frames: u32,
    cell: u32,
    hemi: u32,
    atlas_rgba: *const u8,
    atlas_width: u32,
    atlas_height: u32,
    out: *mut *mut ArborImpostor,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `out` is writable.
        let out = unsafe { out_ref(out, "out") }?;
        *out = std::ptr::null_mut();
        // SAFETY: the caller promises `lods` is NULL or live.
        let lods = unsafe { arg_ref(lods, "lods") }?;
        let (l, threads) = (lods.level(level)?, lods.threads);
        // SAFETY: the caller promises the atlas' bytes.
        let atlas = unsafe { host_atlas(atlas_rgba, atlas_width, atlas_height) }?
            .map(|a| a.downsampled(crate::lod::SILHOUETTE_ATLAS));
        let sphere = if hemi != 0 {
            crate::impostor::Sphere::Hemi
        } else {
            crate::impostor::Sphere::Full
        };
        let impostor = crate::impostor::octahedral_on(
            &crate::lod::surfaces(l, atlas.as_ref()),
            l.mesh_options.up(),
            frames,
            cell,
            sphere,
            threads,
        )?;
        *out = Box::into_raw(Box::new(ArborImpostor { impostor }));
        Ok(())
    })
}

/// Frees an impostor; NULL does nothing.
///
/// # Safety
/// `impostor` is NULL or from arbor_lods_impostor_create(), not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_impostor_free(impostor: *mut ArborImpostor) {
    if !impostor.is_null() {
        // SAFETY: the caller promises a live impostor.
        drop(unsafe { Box::from_raw(impostor) });
    }
}

/// The impostor's frame: `*atlas_size` (pixels a side of each atlas), `centre` (3 floats)
/// and `*radius` (its bounding sphere), `up` (3 floats); each pointer may be NULL.
///
/// # Safety
/// `impostor` NULL or live; each pointer NULL or writable (3 floats for `centre`, `up`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_impostor_info(
    impostor: *const ArborImpostor,
    atlas_size: *mut u32,
    centre: *mut f32,
    radius: *mut f32,
    up: *mut f32,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises NULL or live.
        let i = &unsafe { arg_ref(impostor, "impostor") }?.impostor;
        if !atlas_size.is_null() {
            // SAFETY: the caller promises a non-NULL pointer is writable.
            *unsafe { out_ref(atlas_size, "atlas_size") }? = i.albedo.width;
        }
        if !radius.is_null() {
            // SAFETY: as above.
            *unsafe { out_ref(radius, "radius") }? = i.radius;
        }
        for (p, v, name) in [(centre, i.centre, "centre"), (up, i.up, "up")] {
            if !p.is_null() {
                // SAFETY: the caller promises 3 writable floats.
                let d = unsafe { out_slice(p, 3, 3, name) }?;
                for (d, s) in d.iter_mut().zip(v) {
                    d.write(s);
                }
            }
        }
        Ok(())
    })
}

/// Writes atlas `which` (0: albedo, sRGB colour and coverage; 1: normal and depth) as
/// RGBA8, rows from the top, into `out` (NULL: size only) of `capacity` bytes: at least
/// `*size` (when not NULL: atlas_size * atlas_size * 4), else ARBOR_STATUS_BUFFER_TOO_SMALL and
/// nothing written.
///
/// # Safety
/// `impostor` NULL or live; `out` NULL or writable for `capacity` bytes; `size` NULL or
/// writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_impostor_atlas_write(
    impostor: *const ArborImpostor,
    which: u32,
    out: *mut u8,
    capacity: usize,
    size: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises NULL or live.
        let i = &unsafe { arg_ref(impostor, "impostor") }?.impostor;
        let image = match which {
            0 => &i.albedo,
            1 => &i.normal,
            w => {
                return Err(crate::Error::invalid(
                    "which",
                    format!("{w}; expected 0 (albedo) or 1 (normal)"),
                )
                .into());
            }
        };
        if !out.is_null() {
            // SAFETY: the caller promises `capacity` writable bytes.
            let d = unsafe { out_slice(out, capacity, image.pixels.len(), "out") }?;
            for (d, s) in d.iter_mut().zip(&image.pixels) {
                d.write(*s);
            }
        }
        if !size.is_null() {
            // SAFETY: the caller promises a non-NULL `size` is writable.
            *unsafe { out_ref(size, "size") }? = image.pixels.len();
        }
        Ok(())
    })
}

/// Bakes the billboard of level `level` (arbor's rasterizer, on every core): `planes`
/// (2..=4) upright quads crossed about the up axis through the level's bounding sphere,
/// each drawn from its view into a cell of `cell` pixels (8..=1024) of an atlas `planes`
/// cells wide and one high; the leaves sample `atlas_rgba` as in arbor_tree_lods_create()
/// (NULL: opaque cards). For hosts without an impostor shader: the quads draw with any
/// alpha-tested material. `*out` gets it (free with arbor_billboard_free()), NULL on
/// failure.
///
/// # Safety
/// `lods` NULL or live; `atlas_rgba` NULL or readable for `atlas_width * atlas_height * 4`
/// bytes; `out` writable.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn arbor_lods_billboard_create(
    lods: *const ArborLods,
    level: usize,
    planes: u32,
    cell: u32,
    atlas_rgba: *const u8,
    atlas_width: u32,
    atlas_height: u32,
    out: *mut *mut ArborBillboard,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `out` is writable.
        let out = unsafe { out_ref(out, "out") }?;
        *out = std::ptr::null_mut();
        let l = level_of(lods, level)?;
        // SAFETY: the caller promises the atlas' bytes.
        let atlas = unsafe { host_atlas(atlas_rgba, atlas_width, atlas_height) }?
            .map(|a| a.downsampled(crate::lod::SILHOUETTE_ATLAS));
        let billboard = crate::impostor::billboard(
            &crate::lod::surfaces(l, atlas.as_ref()),
            l.mesh_options.up(),
            planes,
            cell,
        )?;
        *out = Box::into_raw(Box::new(ArborBillboard {
            billboard,
            clockwise: l.mesh_options.reversed(),
        }));
        Ok(())
    })
}

/// Frees a billboard; NULL does nothing.
///
/// # Safety
/// `billboard` is NULL or from arbor_lods_billboard_create(), not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_billboard_free(billboard: *mut ArborBillboard) {
    if !billboard.is_null() {
        // SAFETY: the caller promises a live billboard.
        drop(unsafe { Box::from_raw(billboard) });
    }
}

/// Writes the billboard's quads (a triangle list of ArborVertex, in the level's axes and
/// winding; uv into the atlas, v 0 at its top row): four vertices and two triangles a
/// plane, and with `two_sided` 1 each plane again wound the other way with its normal
/// turned (for materials that cull back faces). `*vertex_count` and `*index_count` (when
/// not NULL) get the sizes; `vertices` and `indices` (NULL: sizes only) hold
/// `vertex_capacity` and `index_capacity`: at least the sizes, else
/// ARBOR_STATUS_BUFFER_TOO_SMALL and nothing written.
///
/// # Safety
/// `billboard` NULL or live; `vertices` and `indices` NULL or writable for their
/// capacities; the counts NULL or writable.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn arbor_billboard_mesh_write(
    billboard: *const ArborBillboard,
    two_sided: u32,
    vertices: *mut crate::mesh::Vertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
    vertex_count: *mut usize,
    index_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises NULL or live.
        let b = unsafe { arg_ref(billboard, "billboard") }?;
        let m = match two_sided {
            0 => b.billboard.mesh(b.clockwise),
            1 => b.billboard.two_sided_mesh(b.clockwise),
            t => {
                return Err(
                    crate::Error::invalid("two_sided", format!("{t}; expected 0 or 1")).into(),
                );
            }
        };
        if !vertices.is_null() || !indices.is_null() {
            // SAFETY: the caller promises the capacities at non-NULL pointers.
            let v = unsafe { out_slice(vertices, vertex_capacity, m.vertices.len(), "vertices") }?;
            // SAFETY: as above.
            let i = unsafe { out_slice(indices, index_capacity, m.indices.len(), "indices") }?;
            for (d, s) in v.iter_mut().zip(&m.vertices) {
                d.write(*s);
            }
            for (d, s) in i.iter_mut().zip(&m.indices) {
                d.write(*s);
            }
        }
        if !vertex_count.is_null() {
            // SAFETY: the caller promises a non-NULL count is writable.
            *unsafe { out_ref(vertex_count, "vertex_count") }? = m.vertices.len();
        }
        if !index_count.is_null() {
            // SAFETY: as above.
            *unsafe { out_ref(index_count, "index_count") }? = m.indices.len();
        }
        Ok(())
    })
}

/// Writes the billboard's atlas `which` (0: albedo, sRGB colour and coverage; 1: normal
/// and depth) as RGBA8, rows from the top, `*width` by `*height` pixels (when not NULL:
/// `planes * cell` by `cell`), into `out` (NULL: size only) of `capacity` bytes: at least
/// `width * height * 4`, else ARBOR_STATUS_BUFFER_TOO_SMALL and nothing written.
///
/// # Safety
/// `billboard` NULL or live; `out` NULL or writable for `capacity` bytes; `width` and
/// `height` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_billboard_atlas_write(
    billboard: *const ArborBillboard,
    which: u32,
    out: *mut u8,
    capacity: usize,
    width: *mut u32,
    height: *mut u32,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises NULL or live.
        let b = &unsafe { arg_ref(billboard, "billboard") }?.billboard;
        let image = match which {
            0 => &b.albedo,
            1 => &b.normal,
            w => {
                return Err(crate::Error::invalid(
                    "which",
                    format!("{w}; expected 0 (albedo) or 1 (normal)"),
                )
                .into());
            }
        };
        if !out.is_null() {
            // SAFETY: the caller promises `capacity` writable bytes.
            let d = unsafe { out_slice(out, capacity, image.pixels.len(), "out") }?;
            for (d, s) in d.iter_mut().zip(&image.pixels) {
                d.write(*s);
            }
        }
        for (p, v, name) in [
            (width, image.width, "width"),
            (height, image.height, "height"),
        ] {
            if !p.is_null() {
                // SAFETY: the caller promises a non-NULL pointer is writable.
                *unsafe { out_ref(p, name) }? = v;
            }
        }
        Ok(())
    })
}
