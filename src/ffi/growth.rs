//! Self-organizing growth: worlds of trees that grow toward light and space.

use super::*;
use crate::enums::Numbered;
use crate::models::growth::{GrowthParams, Obstacle, Species, World, WorldOptions};

/// Options of a world: a struct that grows (see "Structs that grow" in docs/c-api.md).
/// Start from arbor_world_options_default() (or arbor_world_options_init()).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct ArborWorldOptions {
    /// sizeof(ArborWorldOptions) as the host was compiled; set by arbor_world_options_init().
    pub struct_size: u32,
    /// An ArborEnvironment value. Default ARBOR_ENVIRONMENT_SHADOW.
    pub environment: u32,
    /// Lower corner of the box trees grow in (world units, Y up). Default (-10, 0, -10).
    pub min: [f32; 3],
    /// Upper corner. Default (10, 20, 10).
    pub max: [f32; 3],
    /// Voxel edge (shadow) or marker spacing (colonization), > 0. Default 0.25.
    pub cell_size: f32,
    /// Seeds the markers and the seeding of new trees. Default 0.
    pub seed: u64,
    /// Shadow a bud casts (a), > 0. Default 0.2.
    pub shadow_strength: f32,
    /// Falloff per layer below a bud (b > 1). Default 2.
    pub shadow_falloff: f32,
    /// Layers of the shadow pyramid (q_max), 0..=16. Default 5.
    pub shadow_depth: u32,
    /// Full exposure (C), > 0. Default 1.5.
    pub full_light: f32,
    /// Most grid cells (4 bytes each; never more than 2^31): a finer box is
    /// ARBOR_STATUS_LIMIT_EXCEEDED naming max_cells, and so is a step, plant or obstacle
    /// whose shadow would need more (the shadow grid grows with what is shaded). Default
    /// 33,554,432.
    pub max_cells: u64,
    /// Growth stops with ARBOR_STATUS_LIMIT_EXCEEDED before the world's internodes pass
    /// this. Default 16,777,216.
    pub max_branches: u64,
    /// Most trees (seeding stops there). Default 1,024.
    pub max_trees: u32,
    /// 1 (default): grow the trees of a cycle and update the shadow grid on all cores
    /// when arbor is built with its `parallel` feature (the result is identical; a world
    /// under 4,096 internodes stays on the calling thread); 0: the calling thread only.
    pub parallel: u32,
    /// Called by arbor_world_step() before every cycle and at the end
    /// (ARBOR_STAGE_GROWTH, the fraction of the cycles asked), on the calling thread;
    /// non-zero stops with ARBOR_STATUS_CANCELLED before the next cycle (the world as it
    /// was after the last whole cycle). NULL (default): none. (Added after the first
    /// layout.)
    pub progress: ArborProgressFn,
    /// Passed to `progress`. (Added after the first layout.)
    pub progress_user_data: *mut c_void,
}

/// sizeof(ArborWorldOptions) of its first layout: the smallest `struct_size` accepted.
pub const ARBOR_WORLD_OPTIONS_MIN_SIZE: usize = 88;

growing!(ArborWorldOptions as "ArborWorldOptions", ARBOR_WORLD_OPTIONS_MIN_SIZE,
    first_added: progress, defaults: Self::from_rust(&WorldOptions::default()));

mirror!(ArborWorldOptions => WorldOptions {
    same {
        environment, min, max, cell_size, seed, shadow_strength, shadow_falloff,
        shadow_depth, full_light, max_cells, max_branches, max_trees,
    }
    renamed {}
    c_only { parallel: 1, progress: None, progress_user_data: std::ptr::null_mut() }
    rust_only {}
});

/// sizeof(ArborGrowthParams) of its first layout: the smallest `struct_size` accepted.
pub const ARBOR_GROWTH_PARAMS_MIN_SIZE: usize = 76;

/// One species: how a tree grows. The defaults are the excurrent species' values with
/// neutral apical control. Lengths are world units, angles degrees.
///
/// A struct that grows (see "Structs that grow" in docs/c-api.md): start from
/// arbor_growth_params_default() or arbor_growth_params_preset().
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArborGrowthParams {
    /// sizeof(ArborGrowthParams) as the host was compiled; set by arbor_growth_params_init().
    pub struct_size: u32,
    /// lambda in [0, 1]: 0.5 neutral, above favours the main axis (excurrent), below the
    /// laterals (decurrent). Default 0.5.
    pub apical_control: f32,
    /// alpha > 0: vigour at the base = alpha * light gathered. Default 2.
    pub vigor_multiplier: f32,
    /// Length of an internode at vigour 1, in (0, 10000]. Default 0.25.
    pub internode_length: f32,
    /// Angle between a lateral bud and its internode's heading, 0..=180. Default 45.
    pub branch_angle: f32,
    /// Turn about the heading from one lateral bud to the next, finite. Default 137.5.
    pub phyllotaxis: f32,
    /// eta: weight of up (gravitropism) in a shoot's heading; negative bends down. Finite,
    /// -1..=1. Default 0.1.
    pub tropism: f32,
    /// xi >= 0: weight of the environment's optimal direction. Default 0.25.
    pub environment_weight: f32,
    /// n in [1, 4]: a parent's r^n is the sum of its children's. Default 2.5.
    pub pipe_exponent: f32,
    /// Radius of a branch tip, in (0, 10000]. Default 0.01.
    pub tip_radius: f32,
    /// A lateral branch is shed when its vigour < shed_multiplier * internodes^shed_exponent
    /// (its internodes counted with everything above it). >= 0 (0: never). Default 0.03.
    pub shed_multiplier: f32,
    /// 0..=8. Default 1.3.
    pub shed_exponent: f32,
    /// A branch younger than this many cycles is never shed. Default 4.
    pub shed_delay: u32,
    /// A tree older than this many cycles drops seeds each cycle; 0 (default): never.
    pub seed_age: u32,
    /// Seeds land within ln(root vigour) * seed_spread of the base, >= 0. Default 2.
    pub seed_spread: f32,
    /// Space colonization: half-angle of a bud's perception cone, degrees, in (0, 180].
    /// Default 90.
    pub perception_angle: f32,
    /// Space colonization: reach of the perception cone, in internode lengths, in
    /// (0, 64]. Default 4.
    pub perception_reach: f32,
    /// Space colonization: markers closer than this many internode lengths to a bud are
    /// removed (occupied), 0..=64. Default 2.
    pub occupancy_reach: f32,
    /// Most internodes one shoot grows in a cycle, 1..=64. Default 8.
    pub max_shoot: u32,
    /// Palubicki's shedding: a lateral branch older than `shed_delay` cycles is shed when
    /// the light its buds gather, per internode it carries, is below this (a tree whose
    /// whole light per internode falls below it dies). Light is Q as the environment gives
    /// it (at most `full_light` in a shadow world, 1 with markers). >= 0 (0: off).
    /// Default 0.1. (Added after the first layout.)
    pub shed_light: f32,
    /// Apical control (lambda) of a new tree, in [0, 1]: it moves linearly to
    /// `apical_control` over `maturity_age` cycles. Default 0.5. (Added after the first
    /// layout.)
    pub young_apical_control: f32,
    /// Vigour multiplier (alpha) of a new tree, > 0: it moves linearly to
    /// `vigor_multiplier` over `maturity_age` cycles. Default 2. (Added after the first
    /// layout.)
    pub young_vigor_multiplier: f32,
    /// Growth cycles from planting until a tree has its adult apical control and vigour
    /// multiplier, 0..=10000 (0: adult from the start). Default 0. (Added after the first
    /// layout.)
    pub maturity_age: u32,
    /// A tree this many cycles old grows no more shoots (it still sheds); 0: it never
    /// stops. Default 0. (Added after the first layout.)
    pub max_age: u32,
    /// No internode grows to end higher than this above the tree's base, world units,
    /// >= 0 (0: no limit). Default 0. (Added after the first layout.)
    pub max_height: f32,
    /// Weeping: a lateral axis's tropism falls by this for each internode of the axis
    /// before the new one, so a longer branch hangs more. 0..=1. Default 0. (Added after
    /// the first layout.)
    pub droop: f32,
    /// In a shadow world, a seed of this species grows into a tree only where the light on
    /// the ground is at least this: full light less `shadow_strength` per bud above the
    /// ground there, at any height (buds counted over the 5 x 5 columns of cells around
    /// it, per column; see `shed_light` for the unit). >= 0. Default 0. (Added after the
    /// first layout.)
    pub germination_light: f32,
}

growing!(ArborGrowthParams as "ArborGrowthParams", ARBOR_GROWTH_PARAMS_MIN_SIZE,
    first_added: shed_light, defaults: Self::from_rust(&GrowthParams::default()));

mirror!(ArborGrowthParams => GrowthParams {
    same {
        apical_control, vigor_multiplier, internode_length, branch_angle, phyllotaxis,
        tropism, environment_weight, pipe_exponent, tip_radius, shed_multiplier,
        shed_exponent, shed_delay, seed_age, seed_spread, perception_angle,
        perception_reach, occupancy_reach, max_shoot, shed_light, young_apical_control,
        young_vigor_multiplier, maturity_age, max_age, max_height, droop, germination_light,
    }
    renamed {}
    c_only {}
    rust_only {}
});

/// A world of trees growing together (see arbor_world_create()). Opaque; free with
/// arbor_world_free(). A `const ArborWorld *` may be read from several threads at once;
/// stepping or planting needs it to yourself.
pub struct ArborWorld {
    world: World,
    /// `parallel` of the options it was made with: false grows on the calling thread only.
    parallel: bool,
    progress: ArborProgressFn,
    progress_user_data: *mut c_void,
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
unsafe fn world_mut<'a>(world: *mut ArborWorld) -> Result<&'a mut World, FfiError> {
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
        if !tree_id.is_null() {
            // SAFETY: the caller promises a non-NULL `tree_id` is writable.
            *unsafe { out_ref(tree_id, "tree_id") }? = id;
        }
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
