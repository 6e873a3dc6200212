//! Self-organizing growth: worlds of trees that grow toward light and space.

use super::*;
use crate::enums::Numbered;
use crate::models::growth::{GrowthParams, Obstacle, Species, World, WorldOptions};

/// sizeof(ArborWorldOptions) of its first layout: the smallest `struct_size` accepted.
pub const ARBOR_WORLD_OPTIONS_MIN_SIZE: usize = 88;

growing!(ArborWorldOptions as "ArborWorldOptions", ARBOR_WORLD_OPTIONS_MIN_SIZE,
    first_added: progress, defaults: Self::from_rust(&WorldOptions::default()));

/// sizeof(ArborGrowthParams) of its first layout: the smallest `struct_size` accepted.
pub const ARBOR_GROWTH_PARAMS_MIN_SIZE: usize = 76;

growing!(ArborGrowthParams as "ArborGrowthParams", ARBOR_GROWTH_PARAMS_MIN_SIZE,
    first_added: shed_light, defaults: Self::from_rust(&GrowthParams::default()));

/// A world of trees growing together (see arbor_world_create()). Opaque; free with
/// arbor_world_free(). A `const ArborWorld *` may be read from several threads at once;
/// stepping or planting needs it to yourself.
pub struct ArborWorld {
    pub(crate) world: World,
    /// `parallel` of the options it was made with: false grows on the calling thread only.
    parallel: bool,
    progress: ArborProgressFn,
    progress_user_data: *mut c_void,
}

impl ArborWorld {
    /// A copy of the world with the same settings (see arbor_world_clone()).
    pub(crate) fn copy(&self) -> ArborWorld {
        ArborWorld {
            world: self.world.clone(),
            parallel: self.parallel,
            progress: self.progress,
            progress_user_data: self.progress_user_data,
        }
    }
}

/// Writes the default world options into the first `struct_size` bytes at `options`
/// (pass `sizeof(ArborWorldOptions)`), with `options->struct_size = struct_size`, and
/// nothing beyond. NULL does nothing.
///
/// # Safety
/// `options` is NULL or writable for `struct_size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_options_init(
    options: *mut ArborWorldOptions,
    struct_size: usize,
) {
    // SAFETY: the caller promises `struct_size` writable bytes at `options`.
    unsafe { init_for_host(options, struct_size) }
}

/// Writes the default species parameters into the first `struct_size` bytes at `params`
/// (pass `sizeof(ArborGrowthParams)`), with `params->struct_size = struct_size`, and
/// nothing beyond. NULL does nothing.
///
/// # Safety
/// `params` is NULL or writable for `struct_size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_growth_params_init(
    params: *mut ArborGrowthParams,
    struct_size: usize,
) {
    // SAFETY: the caller promises `struct_size` writable bytes at `params`.
    unsafe { init_for_host(params, struct_size) }
}

/// Writes the parameters of species `species` (an ArborSpecies) into the first
/// `struct_size` bytes at `params`, as arbor_growth_params_init() does for the defaults.
/// An unknown species: ARBOR_STATUS_INVALID_ARGUMENT, nothing written.
///
/// # Safety
/// `params` is NULL or writable for `struct_size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_growth_params_preset(
    species: u32,
    params: *mut ArborGrowthParams,
    struct_size: usize,
) -> ArborStatus {
    guard(|| {
        let species = Species::from_field("species", species)?;
        if params.is_null() {
            return Err(FfiError::null("params"));
        }
        let value = ArborGrowthParams::from_rust(&GrowthParams::preset(species));
        // SAFETY: the caller promises `struct_size` writable bytes at `params`.
        unsafe { write_growing(params, struct_size, &value) };
        Ok(())
    })
}

/// The name of species `species` in lower case ("excurrent", "decurrent", "columnar",
/// "bush", "weeping": what the command-line tool's `--species` takes), as a static
/// NUL-terminated string; NULL for a number past the last species, so a host lists every
/// species by counting up from 0 until NULL.
#[unsafe(no_mangle)]
pub extern "C" fn arbor_species_name(species: u32) -> *const c_char {
    guard_value(std::ptr::null(), || {
        Species::from_u32(species).map_or(std::ptr::null(), |s| s.name_nul().as_ptr().cast())
    })
}

/// Makes an empty world. `options` NULL: the defaults. Writes the world to `*out` on
/// success (free it with arbor_world_free()). ARBOR_STATUS_LIMIT_EXCEEDED when the box at
/// `cell_size` would pass `max_cells` (nothing allocated); INVALID_ARGUMENT naming the
/// first bad option.
///
/// # Safety
/// `options` is NULL or readable for its struct_size; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_create(
    options: *const ArborWorldOptions,
    out: *mut *mut ArborWorld,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let raw = if options.is_null() {
            ArborWorldOptions::defaults()
        } else {
            // SAFETY: the caller promises `options` is readable for its struct_size.
            unsafe { read_growing(options, "options") }?
        };
        let options = raw.to_rust()?;
        let parallel: bool = CField::c_to_rust(raw.parallel, "parallel")?;
        let world = World::new(&options)?;
        *out = ArborWorld {
            world,
            parallel,
            progress: raw.progress,
            progress_user_data: raw.progress_user_data,
        }
        .into_handle();
        Ok(())
    })
}

/// Frees a world. NULL does nothing.
///
/// # Safety
/// `world` is NULL or a world from arbor_world_create() not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_free(world: *mut ArborWorld) {
    // SAFETY: the caller promises `world` is NULL or a live world of this library.
    unsafe { ArborWorld::free_handle(world) }
}

/// The mutable world behind a handle.
///
/// # Safety
/// `world` is NULL or live and not used by another thread for the call.
pub(crate) unsafe fn world_mut<'a>(world: *mut ArborWorld) -> Result<&'a mut World, FfiError> {
    if world.is_null() {
        return Err(FfiError::null("world"));
    }
    // SAFETY: non-null; the caller promises it is live and unshared for the call.
    Ok(&mut unsafe { &mut *world }.world)
}

/// Plants a tree of `species` (NULL: the default parameters) with its base at
/// `position` (inside the world's box); `seed` turns its first bud. Writes its index
/// (planting order) to `*tree_id` if `tree_id` is not NULL.
///
/// # Safety
/// `world` is NULL or live (and not used elsewhere meanwhile); `species` is NULL or
/// readable for its struct_size; `position` is NULL or readable for 3 floats;
/// `tree_id` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_plant(
    world: *mut ArborWorld,
    species: *const ArborGrowthParams,
    position: *const f32,
    seed: u64,
    tree_id: *mut u32,
) -> ArborStatus {
    guard(|| {
        // SAFETY: as the caller promises.
        let world = unsafe { world_mut(world) }?;
        let p = if species.is_null() {
            GrowthParams::default()
        } else {
            // SAFETY: the caller promises `species` is readable for its struct_size.
            unsafe { read_growing(species, "species") }?.to_rust()?
        };
        // SAFETY: the caller promises three readable floats.
        let at = unsafe { in_slice(position, 3, "position") }?;
        let id = world.plant(&p, [at[0], at[1], at[2]], seed)?;
        // SAFETY: the caller promises `tree_id` is NULL or writable.
        unsafe { write_if_given(tree_id, "tree_id", id) }?;
        Ok(())
    })
}

/// Adds an axis-aligned box obstacle (min <= max) that casts shadow or removes markers.
/// Its cost is in proportion to the cells it covers (and the columns below them), never to
/// the obstacles already there; the world's progress callback (ArborWorldOptions.progress,
/// ARBOR_STAGE_GROWTH) is called per layer and may cancel (ARBOR_STATUS_CANCELLED, the
/// world unchanged). A world holds at most 1,048,576 obstacles
/// (ARBOR_STATUS_LIMIT_EXCEEDED naming MAX_OBSTACLES).
///
/// # Safety
/// `world` is NULL or live (not used elsewhere meanwhile); `min` and `max` are NULL or
/// readable for 3 floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_add_box(
    world: *mut ArborWorld,
    min: *const f32,
    max: *const f32,
) -> ArborStatus {
    guard(|| {
        if world.is_null() {
            return Err(FfiError::null("world"));
        }
        // SAFETY: non-null; the caller promises it is live and unshared for the call.
        let world = unsafe { &mut *world };
        // SAFETY: the caller promises three readable floats each.
        let (a, b) = unsafe { (in_slice(min, 3, "min")?, in_slice(max, 3, "max")?) };
        add_obstacle(
            world,
            Obstacle::Box {
                min: [a[0], a[1], a[2]],
                max: [b[0], b[1], b[2]],
            },
        )?;
        Ok(())
    })
}

/// Adds an obstacle, reporting to the world's progress callback (which may cancel: then
/// the world is unchanged).
fn add_obstacle(w: &mut ArborWorld, o: Obstacle) -> crate::Result<()> {
    let mut progress = progress_closure(w.progress, w.progress_user_data);
    w.world.add_obstacle_in(o, &mut run_of(&mut progress))
}

/// Adds a sphere obstacle (radius > 0) that casts shadow or removes markers; cost,
/// progress and limit as arbor_world_add_box().
///
/// # Safety
/// `world` is NULL or live (not used elsewhere meanwhile); `center` is NULL or readable
/// for 3 floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_add_sphere(
    world: *mut ArborWorld,
    center: *const f32,
    radius: f32,
) -> ArborStatus {
    guard(|| {
        if world.is_null() {
            return Err(FfiError::null("world"));
        }
        // SAFETY: non-null; the caller promises it is live and unshared for the call.
        let world = unsafe { &mut *world };
        // SAFETY: the caller promises three readable floats.
        let c = unsafe { in_slice(center, 3, "center") }?;
        add_obstacle(
            world,
            Obstacle::Sphere {
                center: [c[0], c[1], c[2]],
                radius,
            },
        )?;
        Ok(())
    })
}

/// Runs `cycles` growth cycles for every tree. A cycle that would pass max_branches
/// returns ARBOR_STATUS_LIMIT_EXCEEDED naming it, before it grows anything (the world
/// stays as after the last whole cycle).
///
/// # Safety
/// `world` is NULL or live (not used elsewhere meanwhile).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_step(world: *mut ArborWorld, cycles: u32) -> ArborStatus {
    guard(|| {
        if world.is_null() {
            return Err(FfiError::null("world"));
        }
        // SAFETY: non-null; the caller promises it is live and unshared for the call.
        let w = unsafe { &mut *world };
        let mut progress = progress_closure(w.progress, w.progress_user_data);
        let mut run = run_of(&mut progress);
        if !w.parallel {
            run = run.threads(1);
        }
        w.world.step_in(cycles, &mut run)?;
        Ok(())
    })
}

/// Number of trees (planted and seeded); 0 for NULL.
///
/// # Safety
/// `world` is NULL or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_tree_count(world: *const ArborWorld) -> usize {
    guard_value(0, || {
        // SAFETY: the caller promises `world` is NULL or live.
        unsafe { arg_ref(world, "world") }.map_or(0, |w| w.world.tree_count())
    })
}

/// Living internodes of all trees; 0 for NULL.
///
/// # Safety
/// `world` is NULL or live.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_branch_count(world: *const ArborWorld) -> usize {
    guard_value(0, || {
        // SAFETY: the caller promises `world` is NULL or live.
        unsafe { arg_ref(world, "world") }.map_or(0, |w| w.world.branch_count())
    })
}

/// A snapshot of tree `index` (0..count, planting order) as an ordinary ArborTree, so
/// every mesh, leaf, export and curve function takes it: its branches' `depth` is the
/// growth cycle that made them, `order` the branching order, and every living bud is a
/// leaf site. Free it with arbor_tree_free(). An index past the end:
/// ARBOR_STATUS_INVALID_ARGUMENT.
///
/// # Safety
/// `world` is NULL or live; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn arbor_world_tree(
    world: *const ArborWorld,
    index: usize,
    out: *mut *mut ArborTree,
) -> ArborStatus {
    guard(|| {
        // SAFETY: the caller promises `world` is NULL or live.
        let world = unsafe { arg_ref(world, "world") }?;
        // SAFETY: the caller promises `out` is NULL or writable.
        let out = unsafe { out_ref(out, "out") }?;
        let skeleton = world.world.tree(index)?;
        *out = ArborTree::new(skeleton).into_handle();
        Ok(())
    })
}
