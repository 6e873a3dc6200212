//! The tube mesher: one truncated cone per branch.

use super::{
    MAX_RADIAL_SEGMENTS, MIN_RADIAL_SEGMENTS, Mesh, MeshOptions, MeshSize, RESTART_INDEX, Topology,
    Vertex,
};
use crate::error::{Error, Result};
use crate::skeleton::Skeleton;
use glam::{DVec3, Vec3};
use std::mem::MaybeUninit;

/// Per-branch counts for `segments` sides.
fn per_branch(segments: usize, topology: Topology) -> (usize, usize) {
    let ring = segments + 1;
    let indices = match topology {
        Topology::TriangleList => 6 * segments,
        Topology::TriangleStripRestart | Topology::TriangleStripDegenerate => 2 * ring,
    };
    (2 * ring, indices)
}

fn check_options(options: &MeshOptions) -> Result<usize> {
    let s = options.radial_segments;
    if !(MIN_RADIAL_SEGMENTS..=MAX_RADIAL_SEGMENTS).contains(&s) {
        return Err(Error::invalid(
            "radial_segments",
            format!("{s}; expected {MIN_RADIAL_SEGMENTS}..={MAX_RADIAL_SEGMENTS}"),
        ));
    }
    Ok(s as usize)
}

/// The exact vertex and index counts [`write_mesh`] needs for `skeleton`.
///
/// Fails with [`Error::InvalidArgument`] for bad options and [`Error::LimitExceeded`] when
/// the vertices could not all be addressed by 32-bit indices (more than 2^32 − 1, since
/// [`RESTART_INDEX`] is reserved).
pub fn mesh_size(skeleton: &Skeleton, options: &MeshOptions) -> Result<MeshSize> {
    let segments = check_options(options)?;
    let n = skeleton.len() as u64;
    let (v, i) = per_branch(segments, options.topology);
    let vertices = n * v as u64;
    if vertices > RESTART_INDEX as u64 {
        return Err(Error::LimitExceeded {
            limit_name: "u32 index range",
            what: "vertices",
            limit: RESTART_INDEX as u64,
            requested: vertices,
            step: None,
        });
    }
    let joins = n.saturating_sub(1)
        * match options.topology {
            Topology::TriangleList => 0,
            Topology::TriangleStripRestart => 1,
            Topology::TriangleStripDegenerate => 2,
        };
    let indices = n * i as u64 + joins;
    Ok(MeshSize {
        vertices: vertices as usize,
        indices: usize::try_from(indices).map_err(|_| Error::LimitExceeded {
            limit_name: "address space",
            what: "indices",
            limit: usize::MAX as u64,
            requested: indices,
            step: None,
        })?,
    })
}

/// An owned mesh of `skeleton`, its buffers allocated once at their exact size.
pub fn tubes(skeleton: &Skeleton, options: &MeshOptions) -> Result<Mesh> {
    let size = mesh_size(skeleton, options)?;
    let mut vertices = bytemuck::zeroed_vec::<Vertex>(size.vertices);
    let mut indices = bytemuck::zeroed_vec::<u32>(size.indices);
    write_mesh(skeleton, options, &mut vertices, &mut indices)?;
    Ok(Mesh {
        vertices,
        indices,
        topology: options.topology,
    })
}

/// An orthonormal pair `(p, q)` with `p × q = n` for a unit `n`, continuous everywhere but
/// at `n = −Y` (Frisvad's construction with its pole moved from −Z to −Y, where branches
/// rarely point).
fn ring_basis(n: DVec3) -> (DVec3, DVec3) {
    if n.y < -0.999_999 {
        // Near the pole: project X onto the plane of the ring instead.
        let p = (DVec3::X - n * n.x).normalize();
        return (p, n.cross(p));
    }
    let a = 1.0 / (1.0 + n.y);
    let b = -n.z * n.x * a;
    let p = DVec3::new(b, -n.z, 1.0 - n.z * n.z * a);
    let q = DVec3::new(1.0 - n.x * n.x * a, -n.x, b);
    (p, q)
}

/// Writes the mesh of `skeleton` into `vertices` and `indices` and returns the counts
/// written (those of [`mesh_size`]). Longer slices are fine; only the prefix is written.
///
/// A slice shorter than needed gives [`Error::BufferTooSmall`] and nothing is written.
pub fn write_mesh(
    skeleton: &Skeleton,
    options: &MeshOptions,
    vertices: &mut [Vertex],
    indices: &mut [u32],
) -> Result<MeshSize> {
    write_into(skeleton, options, vertices, indices)
}

/// [`write_mesh`] into uninitialised memory, such as a mapped GPU buffer or a fresh
/// allocation: every slot of the returned counts' prefixes is initialised on success.
pub fn write_mesh_uninit(
    skeleton: &Skeleton,
    options: &MeshOptions,
    vertices: &mut [MaybeUninit<Vertex>],
    indices: &mut [MaybeUninit<u32>],
) -> Result<MeshSize> {
    write_into(skeleton, options, vertices, indices)
}

/// A place the writers can store a value into: an initialised element or an uninitialised
/// slot.
trait Slot<T> {
    fn put(&mut self, value: T);
}

impl<T> Slot<T> for T {
    #[inline(always)]
    fn put(&mut self, value: T) {
        *self = value;
    }
}

impl<T> Slot<T> for MaybeUninit<T> {
    #[inline(always)]
    fn put(&mut self, value: T) {
        self.write(value);
    }
}

fn write_into<V: Slot<Vertex>, I: Slot<u32>>(
    skeleton: &Skeleton,
    options: &MeshOptions,
    vertices: &mut [V],
    indices: &mut [I],
) -> Result<MeshSize> {
    let size = mesh_size(skeleton, options)?;
    if vertices.len() < size.vertices {
        return Err(Error::BufferTooSmall {
            buffer: "vertices",
            required: size.vertices,
            capacity: vertices.len(),
        });
    }
    if indices.len() < size.indices {
        return Err(Error::BufferTooSmall {
            buffer: "indices",
            required: size.indices,
            capacity: indices.len(),
        });
    }
    let segments = options.radial_segments as usize;
    write_vertices(skeleton, segments, &mut vertices[..size.vertices]);
    write_indices(
        skeleton.len(),
        segments,
        options.topology,
        &mut indices[..size.indices],
    );
    Ok(size)
}

fn write_vertices<V: Slot<Vertex>>(skeleton: &Skeleton, segments: usize, out: &mut [V]) {
    let ring = segments + 1;
    // Unit circle and u per ring vertex; the seam vertex repeats the first exactly.
    let step = std::f64::consts::TAU / segments as f64;
    let circle: Vec<(f32, f32, f32)> = (0..ring)
        .map(|j| {
            let (s, c) = ((j % segments) as f64 * step).sin_cos();
            (c as f32, s as f32, j as f32 / segments as f32)
        })
        .collect();

    for (b, chunk) in skeleton
        .branches()
        .iter()
        .zip(out.chunks_exact_mut(2 * ring))
    {
        let start = b.start();
        let end = b.end();
        let d = end.as_dvec3() - start.as_dvec3();
        let h = d.length();
        let axis = if h > 0.0 { d / h } else { DVec3::Y };
        let (p, q) = ring_basis(axis);
        let (p, q, axis) = (p.as_vec3(), q.as_vec3(), axis.as_vec3());
        let (r0, r1) = (b.start_radius, b.end_radius);
        // Cone normal: radial·h + axis·(r0 − r1), normalised.
        let dr = (r0 - r1) as f64;
        let slant = (h * h + dr * dr).sqrt();
        let (nc, na) = if slant > 0.0 {
            ((h / slant) as f32, (dr / slant) as f32)
        } else {
            (1.0, 0.0)
        };
        let tilt = axis * na;
        let (bottom, top) = chunk.split_at_mut(ring);
        for ((&(c, s, u), vb), vt) in circle.iter().zip(bottom).zip(top) {
            let radial: Vec3 = p * c + q * s;
            let normal = (radial * nc + tilt).to_array();
            vb.put(Vertex {
                position: (start + radial * r0).to_array(),
                normal,
                uv: [u, 0.0],
            });
            vt.put(Vertex {
                position: (end + radial * r1).to_array(),
                normal,
                uv: [u, 1.0],
            });
        }
    }
}

fn write_indices<I: Slot<u32>>(
    branches: usize,
    segments: usize,
    topology: Topology,
    out: &mut [I],
) {
    let ring = segments as u32 + 1;
    let verts_per_branch = 2 * ring;
    // Indices of one branch relative to its first vertex: bottom ring j is j, top ring j is
    // ring + j. With p × q = axis, (top_j, bottom_j, top_j+1) is counter-clockwise from
    // outside.
    let pattern: Vec<u32> = match topology {
        Topology::TriangleList => (0..ring - 1)
            .flat_map(|j| {
                let (b0, b1, t0, t1) = (j, j + 1, ring + j, ring + j + 1);
                [t0, b0, t1, t1, b0, b1]
            })
            .collect(),
        _ => (0..ring).flat_map(|j| [ring + j, j]).collect(),
    };
    let first = pattern[0];
    let last = *pattern.last().expect("a pattern has at least 12 indices");
    let mut pos = 0;
    for i in 0..branches as u32 {
        let base = i * verts_per_branch;
        if i > 0 {
            match topology {
                Topology::TriangleList => {}
                Topology::TriangleStripRestart => {
                    out[pos].put(RESTART_INDEX);
                    pos += 1;
                }
                Topology::TriangleStripDegenerate => {
                    out[pos].put(base - verts_per_branch + last);
                    out[pos + 1].put(base + first);
                    pos += 2;
                }
            }
        }
        for (o, &k) in out[pos..pos + pattern.len()].iter_mut().zip(&pattern) {
            o.put(base + k);
        }
        pos += pattern.len();
    }
    debug_assert_eq!(pos, out.len());
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    #[test]
    fn ring_basis_is_right_handed_and_orthonormal() {
        let dirs = [
            DVec3::Y,
            DVec3::NEG_Y,
            DVec3::X,
            DVec3::NEG_Z,
            DVec3::new(1.0, -2.0, 3.0).normalize(),
            DVec3::new(1e-5, -1.0, 0.0).normalize(),
        ];
        for n in dirs {
            let (p, q) = ring_basis(n);
            assert_abs_diff_eq!(p.length(), 1.0, epsilon = 1e-9);
            assert_abs_diff_eq!(q.length(), 1.0, epsilon = 1e-9);
            assert_abs_diff_eq!(p.dot(q), 0.0, epsilon = 1e-9);
            let c = p.cross(q);
            assert_abs_diff_eq!((c - n).length(), 0.0, epsilon = 1e-8);
        }
    }

    #[test]
    fn bad_segment_counts_are_rejected_by_name() {
        for s in [0, 2, 65, u32::MAX] {
            let o = MeshOptions {
                radial_segments: s,
                ..Default::default()
            };
            let e = mesh_size(&Skeleton::default(), &o).unwrap_err();
            assert!(e.to_string().contains("radial_segments"), "{e}");
        }
    }
}
