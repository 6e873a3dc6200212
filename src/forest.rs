//! Many trees at once: a forest from a list of tree sources and seeds, each grown and
//! meshed independently. With the `parallel` feature the trees are built on all cores
//! (rayon); the result is identical to [`build_serial`], tree by tree and byte by byte.
//!
//! [`merged`] places trees (position, turn about the up axis, scale) into one mesh;
//! [`instanced`] makes one mesh per distinct tree and a transform per placement, for
//! instanced drawing. A 1996-model tree with a non-zero seed gets seeded
//! [`Variation`](crate::models::honda::Variation), so neighbours differ.

use crate::error::Result;
use crate::lsystem::{LSystem, LsystemOptions};
use crate::mesh::{self, Mesh, MeshOptions};
use crate::models::honda::{self, HondaParams};

/// What one tree of the forest grows from.
#[derive(Clone, Copy, Debug)]
pub enum Source<'a> {
    /// The 1996 model with these parameters.
    Honda(HondaParams),
    /// A grammar with derivation options (its `seed` is replaced by the item's seed).
    Grammar(&'a LSystem, LsystemOptions),
}

/// One tree of a forest.
#[derive(Clone, Copy, Debug)]
pub struct Item<'a> {
    /// What it grows from.
    pub source: Source<'a>,
    /// Its seed (for stochastic grammars; the 1996 model has no randomness).
    pub seed: u64,
}

fn grow(item: &Item<'_>) -> Result<crate::skeleton::Skeleton> {
    match item.source {
        Source::Honda(p) => honda::build_varied(
            &p,
            &honda::Variation {
                seed: item.seed,
                ..Default::default()
            },
        ),
        Source::Grammar(ls, o) => ls.skeleton(&LsystemOptions {
            seed: item.seed,
            ..o
        }),
    }
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
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        items.par_iter().map(|i| build_one(i, options)).collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        build_serial(items, options)
    }
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
    let up = match options.up_axis {
        crate::mesh::UpAxis::Y => glam::Vec3::Y,
        crate::mesh::UpAxis::Z => glam::Vec3::Z,
    };
    glam::Mat4::from_scale_rotation_translation(
        glam::Vec3::splat(p.scale),
        glam::Quat::from_axis_angle(up, p.rotation.to_radians()),
        glam::Vec3::from(p.position),
    )
    .to_cols_array()
}

fn check_placed(placed: &[Placed<'_>]) -> Result<()> {
    for (i, p) in placed.iter().enumerate() {
        let finite = p.position.iter().all(|v| v.is_finite()) && p.rotation.is_finite();
        if !(finite && p.scale.is_finite() && p.scale > 0.0) {
            return Err(crate::Error::invalid(
                "placement",
                format!("tree {i}: position and rotation must be finite and scale > 0"),
            ));
        }
    }
    Ok(())
}

/// Exact counts of [`merged`]'s mesh, from the trees' skeletons (no meshing).
pub fn merged_size(placed: &[Placed<'_>], options: &MeshOptions) -> Result<crate::mesh::MeshSize> {
    check_placed(placed)?;
    let mut vertices = 0usize;
    let mut indices = 0usize;
    let mut non_empty = 0usize;
    for p in placed {
        let s = mesh::mesh_size(&grow(&p.item)?, options)?;
        vertices += s.vertices;
        indices += s.indices;
        non_empty += usize::from(s.indices > 0);
    }
    let per_join = match options.topology {
        crate::mesh::Topology::TriangleList => 0,
        crate::mesh::Topology::TriangleStripRestart => 1,
        crate::mesh::Topology::TriangleStripDegenerate => 2,
    };
    Ok(crate::mesh::MeshSize {
        vertices,
        indices: indices + non_empty.saturating_sub(1) * per_join,
    })
}

/// Every placed tree in one mesh (one draw call): each tree's vertices are moved by its
/// placement (normals turned with it) and its indices offset, joined as the topology asks.
pub fn merged(placed: &[Placed<'_>], options: &MeshOptions) -> Result<Mesh> {
    check_placed(placed)?;
    let items: Vec<Item<'_>> = placed.iter().map(|p| p.item).collect();
    let meshes = build(&items, options)?;
    let vertices: usize = meshes.iter().map(|m| m.vertices.len()).sum();
    if vertices > crate::mesh::RESTART_INDEX as usize {
        return Err(crate::Error::LimitExceeded {
            limit_name: "u32 index range",
            what: "forest vertices",
            limit: crate::mesh::RESTART_INDEX as u64,
            requested: vertices as u64,
            step: None,
        });
    }
    let joins = meshes
        .iter()
        .filter(|m| !m.indices.is_empty())
        .count()
        .saturating_sub(1);
    let per_join = match options.topology {
        crate::mesh::Topology::TriangleList => 0,
        crate::mesh::Topology::TriangleStripRestart => 1,
        crate::mesh::Topology::TriangleStripDegenerate => 2,
    };
    let indices: usize = meshes.iter().map(|m| m.indices.len()).sum::<usize>() + joins * per_join;
    let mut out = Mesh {
        vertices: Vec::with_capacity(vertices),
        indices: Vec::with_capacity(indices),
        topology: options.topology,
        ranges: Vec::new(),
    };
    for (p, m) in placed.iter().zip(&meshes) {
        let t = glam::Mat4::from_cols_array(&transform(p, options));
        let base = out.vertices.len() as u32;
        out.vertices.extend(m.vertices.iter().map(|v| {
            crate::mesh::Vertex {
                position: t.transform_point3(glam::Vec3::from(v.position)).to_array(),
                normal: t
                    .transform_vector3(glam::Vec3::from(v.normal))
                    .normalize_or_zero()
                    .to_array(),
                uv: v.uv,
            }
        }));
        if m.indices.is_empty() {
            continue;
        }
        if !out.indices.is_empty() {
            match options.topology {
                crate::mesh::Topology::TriangleList => {}
                crate::mesh::Topology::TriangleStripRestart => {
                    out.indices.push(crate::mesh::RESTART_INDEX)
                }
                crate::mesh::Topology::TriangleStripDegenerate => {
                    let last = *out.indices.last().expect("not empty");
                    out.indices.push(last);
                    out.indices.push(base + m.indices[0]);
                }
            }
        }
        out.indices.extend(m.indices.iter().map(|&i| {
            if i == crate::mesh::RESTART_INDEX {
                i
            } else {
                base + i
            }
        }));
    }
    debug_assert_eq!(out.indices.len(), indices);
    Ok(out)
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
        let same = |a: &Item<'_>| {
            a.seed == p.item.seed
                && match (a.source, p.item.source) {
                    (Source::Honda(x), Source::Honda(y)) => x == y,
                    (Source::Grammar(x, ox), Source::Grammar(y, oy)) => {
                        std::ptr::eq(x, y) && ox == oy
                    }
                    _ => false,
                }
        };
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
