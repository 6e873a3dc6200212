//! Many trees at once: a forest from a list of tree sources and seeds, each grown and
//! meshed independently. With the `parallel` feature the trees are built on all cores
//! (rayon); the result is identical to [`build_serial`], tree by tree and byte by byte.
//!
//! [`merged`] places trees (position, turn about the up axis, scale) into one mesh;
//! [`instanced`] makes one mesh per distinct tree and a transform per placement, for
//! instanced drawing. Each tree grows from a [`Source`] with its seed: the 1996 model,
//! a grammar or a self-organizing species.

use crate::error::Result;
use crate::mesh::Slot;
use crate::mesh::{self, Mesh, MeshOptions, MeshPlan, MeshSize, RESTART_INDEX, Topology, Vertex};
use crate::progress::Run;
use crate::skeleton::Skeleton;

pub use crate::source::Source;

/// One tree of a forest.
#[derive(Clone, Copy, Debug)]
pub struct Item<'a> {
    /// What it grows from.
    pub source: Source<'a>,
    /// Its seed (for stochastic grammars; the 1996 model has no randomness).
    pub seed: u64,
}

fn grow(item: &Item<'_>) -> Result<Skeleton> {
    item.source.grow(item.seed)
}

fn build_one(item: &Item<'_>, options: &MeshOptions) -> Result<Mesh> {
    mesh::tubes(&grow(item)?, options)
}

/// Grows and meshes every item one after another.
pub fn build_serial(items: &[Item<'_>], options: &MeshOptions) -> Result<Vec<Mesh>> {
    items.iter().map(|i| build_one(i, options)).collect()
}

/// Grows and meshes every item; on all cores with the `parallel` feature, else serially.
/// The first error (in item order) is returned.
pub fn build(items: &[Item<'_>], options: &MeshOptions) -> Result<Vec<Mesh>> {
    each(items, |i| build_one(i, options))
}

/// `f` of every element, on all cores with the `parallel` feature; the first error in
/// order is returned.
fn each<T: Sync, R: Send>(
    items: &[T],
    f: impl Fn(&T) -> Result<R> + Sync + Send,
) -> Result<Vec<R>> {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        items.par_iter().map(f).collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        items.iter().map(f).collect()
    }
}

/// Every placed tree grown and planned (not meshed), with the merged mesh's counts
/// checked against the limits before any mesh memory is spent.
fn grow_and_plan(
    placed: &[Placed<'_>],
    options: &MeshOptions,
    threads: u32,
) -> Result<(Vec<(Skeleton, MeshPlan)>, MeshSize)> {
    check_placed(placed)?;
    let planned = each(placed, |p| {
        let s = grow(&p.item)?;
        let plan = MeshPlan::new_in(&s, options, &Run::default().threads(threads))?;
        Ok((s, plan))
    })?;
    let size = total(planned.iter().map(|(_, plan)| plan.size()), options)?;
    Ok((planned, size))
}

/// A tree placed in a scene.
#[derive(Clone, Copy, Debug)]
pub struct Placed<'a> {
    /// The tree.
    pub item: Item<'a>,
    /// Where its root stands (in the mesh's output space).
    pub position: [f32; 3],
    /// Turn about the up axis, degrees.
    pub rotation: f32,
    /// Uniform scale.
    pub scale: f32,
}

/// A placement as a column-major 4 × 4 matrix (rotation about the up axis, then scale,
/// then translation), for instanced drawing.
pub fn transform(p: &Placed<'_>, options: &MeshOptions) -> [f32; 16] {
    let up = options.up();
    glam::Mat4::from_scale_rotation_translation(
        glam::Vec3::splat(p.scale),
        crate::geom::rotation::axis_angle(up, p.rotation.to_radians()),
        glam::Vec3::from(p.position),
    )
    .to_cols_array()
}

/// Largest placement scale, and largest coordinate of a placement's position: a tree
/// placed within them stays far inside the f32 range.
pub const MAX_PLACEMENT_SCALE: f32 = 1e6;
/// See [`MAX_PLACEMENT_SCALE`].
pub const MAX_PLACEMENT_POSITION: f32 = 1e12;

fn check_placed(placed: &[Placed<'_>]) -> Result<()> {
    for (i, p) in placed.iter().enumerate() {
        let finite = p
            .position
            .iter()
            .all(|v| v.is_finite() && v.abs() <= MAX_PLACEMENT_POSITION)
            && p.rotation.is_finite();
        if !(finite && p.scale.is_finite() && p.scale > 0.0 && p.scale <= MAX_PLACEMENT_SCALE) {
            return Err(crate::error::Error::invalid(
                "placement",
                format!(
                    "tree {i}: position {:?}, rotation {}, scale {}; expected finite values, \
                     |position| <= 1e12 and scale in (0, 1e6]",
                    p.position, p.rotation, p.scale
                ),
            ));
        }
    }
    Ok(())
}

/// Index entries a join between two trees' strips takes.
fn per_join(topology: Topology) -> usize {
    match topology {
        Topology::TriangleList => 0,
        Topology::TriangleStripRestart => 1,
        Topology::TriangleStripDegenerate => 2,
    }
}

/// The merged mesh's counts from each tree's counts, or `LimitExceeded` when they pass
/// 32-bit indices or `max_vertices`.
fn total(sizes: impl Iterator<Item = MeshSize>, options: &MeshOptions) -> Result<MeshSize> {
    let (mut vertices, mut indices, mut non_empty) = (0u64, 0u64, 0u64);
    for s in sizes {
        vertices += s.vertices as u64;
        indices += s.indices as u64;
        non_empty += u64::from(s.indices > 0);
    }
    indices += non_empty.saturating_sub(1) * per_join(options.topology) as u64;
    let limit = (options.max_vertices as u64).min(RESTART_INDEX as u64);
    if vertices > limit || indices > u32::MAX as u64 {
        let (limit_name, what, limit, requested) = if vertices > limit {
            let name = if limit == options.max_vertices as u64 {
                "max_vertices"
            } else {
                "u32 index range"
            };
            (name, "forest vertices", limit, vertices)
        } else {
            (
                "u32 index range",
                "forest indices",
                u32::MAX as u64,
                indices,
            )
        };
        return Err(crate::error::Error::LimitExceeded {
            limit_name,
            what,
            limit,
            requested,
            step: None,
        });
    }
    Ok(MeshSize {
        vertices: vertices as usize,
        indices: indices as usize,
    })
}

/// Exact counts of [`merged`]'s mesh: every tree is grown and planned, none is meshed.
/// Fails with `LimitExceeded` when the forest would pass 32-bit indices or
/// [`MeshOptions::max_vertices`].
pub fn merged_size(placed: &[Placed<'_>], options: &MeshOptions) -> Result<MeshSize> {
    merged_size_in(placed, options, &Run::default())
}

/// [`merged_size`], each tree planned on `run`'s threads.
pub fn merged_size_in(
    placed: &[Placed<'_>],
    options: &MeshOptions,
    run: &Run<'_>,
) -> Result<MeshSize> {
    Ok(grow_and_plan(placed, options, run.threads_or(0))?.1)
}

/// Every placed tree in one mesh (one draw call): each tree's vertices are moved by its
/// placement (normals turned with it) and its indices offset, joined as the topology asks.
/// The counts are checked against the limits before any tree is meshed.
pub fn merged(placed: &[Placed<'_>], options: &MeshOptions) -> Result<Mesh> {
    merged_in(placed, options, &Run::default())
}

/// [`merged`] on `run`'s threads: each tree planned and meshed on them.
pub fn merged_in(placed: &[Placed<'_>], options: &MeshOptions, run: &Run<'_>) -> Result<Mesh> {
    let threads = run.threads_or(0);
    let (planned, size) = grow_and_plan(placed, options, threads)?;
    let meshes = each(&planned, |(s, plan)| {
        plan.mesh_in(s, &mut Run::default().threads(threads))
    })?;
    let mut vertices = crate::limits::try_zeroed::<Vertex>(size.vertices, "the forest's vertices")?;
    let mut indices = crate::limits::try_zeroed::<u32>(size.indices, "the forest's indices")?;
    place(placed, &meshes, options, &mut vertices, &mut indices);
    Ok(Mesh {
        vertices,
        indices,
        topology: options.topology,
        ranges: Vec::new(),
    })
}

/// [`merged`] into caller memory: every tree is grown once, the counts checked against
/// the limits and the buffers' capacities (`BufferTooSmall`, nothing written), then each
/// tree is meshed and placed into the buffers.
pub fn write_merged(
    placed: &[Placed<'_>],
    options: &MeshOptions,
    vertices: &mut [Vertex],
    indices: &mut [u32],
) -> Result<MeshSize> {
    write_merged_into(placed, options, vertices, indices, &mut Run::default())
}

/// [`write_merged`] into uninitialised memory (a mapped GPU buffer).
pub fn write_merged_uninit(
    placed: &[Placed<'_>],
    options: &MeshOptions,
    vertices: &mut [std::mem::MaybeUninit<Vertex>],
    indices: &mut [std::mem::MaybeUninit<u32>],
) -> Result<MeshSize> {
    write_merged_into(placed, options, vertices, indices, &mut Run::default())
}

/// [`write_merged_uninit`] in `run`: each tree meshed on the run's threads, reporting [`Stage::Mesh`](crate::progress::Stage::Mesh) (the fraction of the
/// trees meshed) on the calling thread after each tree; `false` stops with
/// [`Error::Cancelled`](crate::error::Error::Cancelled) before anything is written into the
/// buffers.
pub fn write_merged_uninit_in(
    placed: &[Placed<'_>],
    options: &MeshOptions,
    vertices: &mut [std::mem::MaybeUninit<Vertex>],
    indices: &mut [std::mem::MaybeUninit<u32>],
    run: &mut Run<'_>,
) -> Result<MeshSize> {
    write_merged_into(placed, options, vertices, indices, run)
}

fn write_merged_into<V: Slot<Vertex>, I: Slot<u32>>(
    placed: &[Placed<'_>],
    options: &MeshOptions,
    vertices: &mut [V],
    indices: &mut [I],
    run: &mut Run<'_>,
) -> Result<MeshSize> {
    let threads = run.threads_or(0);
    let (planned, size) = grow_and_plan(placed, options, threads)?;
    let mesh =
        |(s, plan): &(Skeleton, MeshPlan)| plan.mesh_in(s, &mut Run::default().threads(threads));
    size.check_capacity(vertices.len(), indices.len())?;
    let meshes = if run.active() {
        // One tree at a time, so the calling thread can report between them.
        let mut meshes = Vec::with_capacity(planned.len());
        for (k, item) in planned.iter().enumerate() {
            meshes.push(mesh(item)?);
            run.report(
                crate::progress::Stage::Mesh,
                (k + 1) as f64 / planned.len() as f64,
            )?;
        }
        meshes
    } else {
        each(&planned, mesh)?
    };
    place(
        placed,
        &meshes,
        options,
        &mut vertices[..size.vertices],
        &mut indices[..size.indices],
    );
    Ok(size)
}

/// Writes each tree's mesh moved by its placement, indices offset and joined.
fn place<V: Slot<Vertex>, I: Slot<u32>>(
    placed: &[Placed<'_>],
    meshes: &[Mesh],
    options: &MeshOptions,
    vertices: &mut [V],
    indices: &mut [I],
) {
    let (mut nv, mut ni) = (0usize, 0usize);
    let mut last: Option<u32> = None;
    for (p, m) in placed.iter().zip(meshes) {
        let t = glam::Mat4::from_cols_array(&transform(p, options));
        let base = nv as u32;
        for (slot, v) in vertices[nv..nv + m.vertices.len()]
            .iter_mut()
            .zip(&m.vertices)
        {
            slot.put(Vertex {
                position: t.transform_point3(glam::Vec3::from(v.position)).to_array(),
                normal: t
                    .transform_vector3(glam::Vec3::from(v.normal))
                    .normalize_or_zero()
                    .to_array(),
                uv: v.uv,
            });
        }
        nv += m.vertices.len();
        let Some(&first) = m.indices.first() else {
            continue;
        };
        if let Some(prev) = last {
            match options.topology {
                Topology::TriangleList => {}
                Topology::TriangleStripRestart => {
                    indices[ni].put(RESTART_INDEX);
                    ni += 1;
                }
                Topology::TriangleStripDegenerate => {
                    indices[ni].put(prev);
                    indices[ni + 1].put(base + first);
                    ni += 2;
                }
            }
        }
        for (slot, &i) in indices[ni..ni + m.indices.len()].iter_mut().zip(&m.indices) {
            slot.put(if i == RESTART_INDEX { i } else { base + i });
        }
        ni += m.indices.len();
        last = m.indices.last().map(|&i| base + i);
    }
    debug_assert_eq!((nv, ni), (vertices.len(), indices.len()));
}

/// Per placement: the index of its mesh in [`instanced`]'s list and its transform.
pub type Instance = (u32, [f32; 16]);

/// One mesh per distinct tree (same source and seed) and, per placement, the index of
/// its mesh and its transform ([`transform`]), for instanced drawing.
pub fn instanced(
    placed: &[Placed<'_>],
    options: &MeshOptions,
) -> Result<(Vec<Mesh>, Vec<Instance>)> {
    check_placed(placed)?;
    let mut distinct: Vec<Item<'_>> = Vec::new();
    let mut which = Vec::with_capacity(placed.len());
    for p in placed {
        let same = |a: &Item<'_>| a.seed == p.item.seed && a.source.same(&p.item.source);
        let k = match distinct.iter().position(same) {
            Some(k) => k,
            None => {
                distinct.push(p.item);
                distinct.len() - 1
            }
        };
        which.push((k as u32, transform(p, options)));
    }
    Ok((build(&distinct, options)?, which))
}
