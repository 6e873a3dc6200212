//! Forests: many placed trees in one mesh.

use super::*;

/// One tree of a forest: the 1996 model's parameters, a variation seed (0: none) and its
/// placement (position of its root, turn about the up axis in degrees, uniform scale).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArborForestTree {
    /// The model's parameters.
    pub params: HondaParams,
    /// Variation seed, as arbor_tree_from_honda_varied(); 0 for none.
    pub seed: u64,
    /// Where the root stands, in the output space of the mesh options.
    pub position: [f32; 3],
    /// Turn about the up axis, degrees.
    pub rotation: f32,
    /// Uniform scale, > 0.
    pub scale: f32,
}

/// Grows `count` trees (on all cores when arbor is built with its `parallel` feature),
/// places them and merges them into one new mesh object written to `*out` (read it with
/// arbor_mesh_vertices() / arbor_mesh_indices(), free it with arbor_mesh_free()).
///
/// # Safety
/// `trees` is NULL (only with `count` 0) or readable for `count` elements; `options` is
/// NULL or readable; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_mesh_create(
    trees: *const ArborForestTree,
    count: usize,
    options: *const ArborMeshOptions,
    out: *mut *mut ArborMesh,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `trees` is readable for `count` elements.
        let placed = unsafe { read_forest(trees, count) }?;
        // SAFETY: passed on from the caller.
        unsafe { create_forest(&placed, options, out) }
    })
}

/// The placed forest of `trees` as Rust values.
///
/// # Safety
/// `trees` is NULL (only with `count` 0) or readable for `count` elements.
pub(crate) unsafe fn read_forest<'a>(
    trees: *const ArborForestTree,
    count: usize,
) -> Result<Vec<crate::forest::Placed<'a>>, FfiError> {
    // SAFETY: the caller promises `trees` is readable for `count` elements.
    let trees = unsafe { in_slice(trees, count, "trees") }?;
    Ok(trees
        .iter()
        .map(|t| crate::forest::Placed {
            item: crate::forest::Item {
                source: crate::forest::Source::Honda(t.params),
                seed: t.seed,
            },
            position: t.position,
            rotation: t.rotation,
            scale: t.scale,
        })
        .collect())
}

/// Exact vertex and index counts of the merged forest mesh arbor_forest_mesh_write()
/// writes (the trees are grown to count them; arbor_forest_mesh_create() grows them once).
///
/// # Safety
/// `trees` is NULL (only with `count` 0) or readable for `count` elements; `options` is
/// NULL or readable; the counts are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_mesh_size(
    trees: *const ArborForestTree,
    count: usize,
    options: *const ArborMeshOptions,
    vertex_count: *mut usize,
    index_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `trees` is readable for `count` elements.
        let placed = unsafe { read_forest(trees, count) }?;
        // SAFETY: passed on from the caller.
        unsafe { size_forest(&placed, options, vertex_count, index_count) }
    })
}

/// Writes the merged forest mesh into caller memory; the buffer rules of
/// arbor_mesh_write().
///
/// # Safety
/// As arbor_forest_mesh_size(), and `vertices` / `indices` are NULL or valid for writes
/// of their capacities and do not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_mesh_write(
    trees: *const ArborForestTree,
    count: usize,
    options: *const ArborMeshOptions,
    vertices: *mut Vertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `trees` is readable for `count` elements.
        let placed = unsafe { read_forest(trees, count) }?;
        // SAFETY: passed on from the caller.
        unsafe {
            write_forest(
                &placed,
                options,
                vertices,
                vertex_capacity,
                indices,
                index_capacity,
            )
        }
    })
}

/// The shell of arbor_forest_mesh_create() and arbor_forest_plants_mesh_create(): merges
/// `placed` with the host's options into a new mesh at `*out`.
///
/// # Safety
/// `options` is NULL or readable; `out` is NULL or writable.
unsafe fn create_forest(
    placed: &[crate::forest::Placed<'_>],
    options: *const ArborMeshOptions,
    out: *mut *mut ArborMesh,
) -> Result<(), FfiError> {
    // SAFETY: the caller promises `options` is NULL or readable.
    let (options, threads) = unsafe { read_mesh_options(options) }?;
    // SAFETY: the caller promises `out` is NULL or writable.
    let out = unsafe { out_ref(out, "out") }?;
    let mesh = crate::forest::merged_in(placed, &options, &on_threads(threads))?;
    *out = ArborMesh { mesh }.into_handle();
    Ok(())
}

/// The shell of the two forest sizes: the merged mesh's counts.
///
/// # Safety
/// `options` is NULL or readable; the counts are NULL or writable.
unsafe fn size_forest(
    placed: &[crate::forest::Placed<'_>],
    options: *const ArborMeshOptions,
    vertex_count: *mut usize,
    index_count: *mut usize,
) -> Result<(), FfiError> {
    // SAFETY: the caller promises `options` is NULL or readable.
    let (options, threads) = unsafe { read_mesh_options(options) }?;
    // SAFETY: the caller promises both counts are NULL or writable.
    let vc = unsafe { out_ref(vertex_count, "vertex_count") }?;
    // SAFETY: as above.
    let ic = unsafe { out_ref(index_count, "index_count") }?;
    let size = crate::forest::merged_size_in(placed, &options, &on_threads(threads))?;
    *vc = size.vertices;
    *ic = size.indices;
    Ok(())
}

/// The shell of the two forest writes: the merged mesh into the host's buffers.
///
/// # Safety
/// `options` is NULL or readable; `vertices` / `indices` are NULL or valid for writes of
/// their capacities and do not overlap.
unsafe fn write_forest(
    placed: &[crate::forest::Placed<'_>],
    options: *const ArborMeshOptions,
    vertices: *mut Vertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
) -> Result<(), FfiError> {
    // SAFETY: the caller promises `options` is NULL or readable.
    let (options, threads, progress, user) = unsafe { read_mesh_options_with_progress(options) }?;
    let whole = mesh::MeshSize {
        vertices: vertex_capacity,
        indices: index_capacity,
    };
    // SAFETY: the caller promises both hold their capacities, writable, apart.
    let (v, i) =
        unsafe { mesh_buffers(vertices, vertex_capacity, indices, index_capacity, whole) }?;
    // Grows and meshes every tree once; checks the capacities before writing.
    let mut f = progress_closure(progress, user);
    let mut run = run_of(&mut f).threads(threads);
    crate::forest::write_merged_uninit_in(placed, &options, v, i, &mut run)?;
    Ok(())
}

/// What an ArborForestPlant grows from.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArborPlantSource {
    /// The 1996 model with `honda` (seed: its variation, 0 for none).
    Honda = 0,
    /// A self-organizing tree of `species`, grown alone for `cycles` cycles in a default
    /// world (a shadow world 20 units wide and tall) seeded with `seed`.
    Growth = 1,
}

/// One tree of a forest of any source: a struct that grows (see "Structs that grow" in
/// docs/c-api.md), passed as an array read with the stride `plants[0].struct_size`. Start
/// each from arbor_forest_plant_init().
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct ArborForestPlant {
    /// sizeof(ArborForestPlant) as the host was compiled; set by arbor_forest_plant_init().
    pub struct_size: u32,
    /// An ArborPlantSource value. Default ARBOR_PLANT_SOURCE_HONDA.
    pub source: u32,
    /// ARBOR_PLANT_SOURCE_HONDA: the model's parameters. Default the paper's tree a.
    pub honda: HondaParams,
    /// ARBOR_PLANT_SOURCE_GROWTH: the species (read as arbor_world_plant() reads it); NULL
    /// (default): the default species.
    pub species: *const ArborGrowthParams,
    /// ARBOR_PLANT_SOURCE_GROWTH: growth cycles, 1..=1000. Default 30.
    pub cycles: u32,
    /// The 1996 model's variation seed (0: none) or the growth world's seed. Default 0.
    pub seed: u64,
    /// Where the root stands, in the output space of the mesh options. Default (0, 0, 0).
    pub position: [f32; 3],
    /// Turn about the up axis, degrees. Default 0.
    pub rotation: f32,
    /// Uniform scale, > 0. Default 1.
    pub scale: f32,
}

/// sizeof(ArborForestPlant) of its first layout (this one; it holds a pointer, so it
/// depends on the target): the smallest `struct_size` accepted.
const ARBOR_FOREST_PLANT_MIN_SIZE: usize = std::mem::size_of::<ArborForestPlant>();

/// The most cycles a plant of a forest grows alone.
const MAX_PLANT_CYCLES: u32 = 1000;

impl Growing for ArborForestPlant {
    const NAME: &'static str = "ArborForestPlant";
    const MIN_SIZE: usize = ARBOR_FOREST_PLANT_MIN_SIZE;
    fn defaults() -> Self {
        ArborForestPlant {
            struct_size: std::mem::size_of::<Self>() as u32,
            source: ArborPlantSource::Honda as u32,
            honda: HondaParams::preset('a').expect("tree a is a preset"),
            species: std::ptr::null(),
            cycles: 30,
            seed: 0,
            position: [0.0; 3],
            rotation: 0.0,
            scale: 1.0,
        }
    }
}

/// Writes the default plant into the first `struct_size` bytes at `plant` (pass
/// `sizeof(ArborForestPlant)`), with `plant->struct_size = struct_size`, and nothing
/// beyond. NULL does nothing.
///
/// # Safety
/// `plant` is NULL or writable for `struct_size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_plant_init(plant: *mut ArborForestPlant, struct_size: usize) {
    // SAFETY: the caller promises `struct_size` writable bytes at `plant`.
    unsafe { init_for_host(plant, struct_size) }
}

/// The forest of the host's `plants` as Rust values.
///
/// # Safety
/// `plants` is NULL (only with `count` 0) or readable for `count` elements of the host's
/// ArborForestPlant, each `species` NULL or readable.
unsafe fn read_plants(
    plants: *const ArborForestPlant,
    count: usize,
) -> Result<Vec<crate::forest::Placed<'static>>, FfiError> {
    // SAFETY: passed on from the caller.
    let plants = unsafe { read_growing_array(plants, count, "plants") }?;
    plants
        .iter()
        .enumerate()
        .map(|(k, plant)| {
            // SAFETY: the caller promises `species` is NULL or readable.
            let source = unsafe { plant_source(plant, k) }?;
            Ok(crate::forest::Placed {
                item: crate::forest::Item {
                    source,
                    seed: plant.seed,
                },
                position: plant.position,
                rotation: plant.rotation,
                scale: plant.scale,
            })
        })
        .collect()
}

/// What plant `k` grows from.
///
/// # Safety
/// `plant.species` is NULL or readable.
unsafe fn plant_source(
    plant: &ArborForestPlant,
    k: usize,
) -> Result<crate::forest::Source<'static>, FfiError> {
    match plant.source {
        0 => Ok(crate::forest::Source::Honda(plant.honda)),
        1 => {
            if !(1..=MAX_PLANT_CYCLES).contains(&plant.cycles) {
                return Err(FfiError::invalid(format!(
                    "`plants[{k}].cycles` is {}; expected 1..={MAX_PLANT_CYCLES}",
                    plant.cycles
                )));
            }
            let species = if plant.species.is_null() {
                crate::models::growth::GrowthParams::default()
            } else {
                // SAFETY: the caller promises a non-NULL `species` is readable.
                let c = unsafe { read_growing(plant.species, &format!("plants[{k}].species")) }?;
                c.to_rust()?
            };
            Ok(crate::forest::Source::Growth(species, plant.cycles))
        }
        other => Err(FfiError::invalid(format!(
            "`plants[{k}].source` is {other}; expected an ArborPlantSource (0 honda, 1 growth)"
        ))),
    }
}

/// arbor_forest_mesh_create() for plants of any source (ArborForestPlant): grows them (on
/// all cores when arbor is built with its `parallel` feature), places them and merges them
/// into one new mesh object written to `*out`.
///
/// # Safety
/// `plants` is NULL (only with `count` 0) or readable for `count` elements of the host's
/// ArborForestPlant (stride `plants[0].struct_size`), each `species` NULL or readable;
/// `options` is NULL or readable; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_plants_mesh_create(
    plants: *const ArborForestPlant,
    count: usize,
    options: *const ArborMeshOptions,
    out: *mut *mut ArborMesh,
) -> ArborStatus {
    guard(|| {
        // SAFETY: passed on from the caller.
        let placed = unsafe { read_plants(plants, count) }?;
        // SAFETY: passed on from the caller.
        unsafe { create_forest(&placed, options, out) }
    })
}

/// arbor_forest_mesh_size() for plants of any source (the plants are grown to count
/// them; arbor_forest_plants_mesh_create() grows them once).
///
/// # Safety
/// As arbor_forest_plants_mesh_create(); the counts are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_plants_mesh_size(
    plants: *const ArborForestPlant,
    count: usize,
    options: *const ArborMeshOptions,
    vertex_count: *mut usize,
    index_count: *mut usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: passed on from the caller.
        let placed = unsafe { read_plants(plants, count) }?;
        // SAFETY: passed on from the caller.
        unsafe { size_forest(&placed, options, vertex_count, index_count) }
    })
}

/// arbor_forest_mesh_write() for plants of any source; the buffer rules of
/// arbor_mesh_write().
///
/// # Safety
/// As arbor_forest_plants_mesh_size(), and `vertices` / `indices` are NULL or valid for
/// writes of their capacities and do not overlap.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_forest_plants_mesh_write(
    plants: *const ArborForestPlant,
    count: usize,
    options: *const ArborMeshOptions,
    vertices: *mut Vertex,
    vertex_capacity: usize,
    indices: *mut u32,
    index_capacity: usize,
) -> ArborStatus {
    guard(|| {
        // SAFETY: passed on from the caller.
        let placed = unsafe { read_plants(plants, count) }?;
        // SAFETY: passed on from the caller.
        unsafe {
            write_forest(
                &placed,
                options,
                vertices,
                vertex_capacity,
                indices,
                index_capacity,
            )
        }
    })
}
