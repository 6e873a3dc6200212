//! The tube mesher: every branch a truncated cone, axes joined into watertight tubes.

use super::strips::{Slot, StripRules, StripWriter};
use super::{
    Joints, MAX_RADIAL_SEGMENTS, MIN_RADIAL_SEGMENTS, Mesh, MeshOptions, MeshSize, RESTART_INDEX,
    Tip, UpAxis, Vertex, Winding,
};
use crate::error::{Error, Result};
use crate::skeleton::{Branch, NO_PARENT, Skeleton};
use glam::{DVec3, Quat, Vec3};
use std::mem::MaybeUninit;

/// The vertices and indices one branch owns: `first_vertex..first_vertex + vertex_count`
/// and `first_index..first_index + index_count`. Ranges of consecutive branches are
/// consecutive; a dropped branch has empty ranges. A branch that shares its parent's ring
/// indexes vertices of its parent. Same layout as the C type `ArborBranchRange`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BranchRange {
    /// First vertex the branch owns.
    pub first_vertex: u32,
    /// Number of vertices it owns.
    pub vertex_count: u32,
    /// First index it owns (joins and restarts before its strips included).
    pub first_index: u32,
    /// Number of indices it owns.
    pub index_count: u32,
}

/// One level of detail made by [`mesh_lods`].
#[derive(Clone, Debug, PartialEq)]
pub struct LodLevel {
    /// The mesh of this level.
    pub mesh: Mesh,
    /// Its number of vertices.
    pub vertex_count: usize,
    /// Its number of triangles (degenerate strip joins not counted).
    pub triangle_count: usize,
}

const SHARES_START: u8 = 1;
const MITRE_END: u8 = 2;
const BASE_CAP: u8 = 4;
const TIP: u8 = 8;

/// A joint is mitred only while the bend is below about 154° (cos > −0.9); sharper bends
/// get separate rings, since the bisecting plane would stretch the ring without bound.
const MITRE_MIN_COS: f32 = -0.9;

/// What each branch gets, decided once and shared by the size query and the writer.
struct Plan {
    /// Sides per branch; 0 for a dropped branch.
    segs: Vec<u8>,
    flags: Vec<u8>,
    /// The kept branch that continues each branch's axis, or NO_PARENT.
    cont: Vec<u32>,
    ranges: Vec<BranchRange>,
    size: MeshSize,
    rules: StripRules,
}

fn check_options(o: &MeshOptions) -> Result<()> {
    let s = o.radial_segments;
    if !(MIN_RADIAL_SEGMENTS..=MAX_RADIAL_SEGMENTS).contains(&s) {
        return Err(Error::invalid(
            "radial_segments",
            format!("{s}; expected {MIN_RADIAL_SEGMENTS}..={MAX_RADIAL_SEGMENTS}"),
        ));
    }
    let m = o.min_radial_segments;
    if m != 0 && !(MIN_RADIAL_SEGMENTS..=s).contains(&m) {
        return Err(Error::invalid(
            "min_radial_segments",
            format!("{m}; expected 0 (no LOD) or {MIN_RADIAL_SEGMENTS}..=radial_segments ({s})"),
        ));
    }
    if !(o.cull_radius.is_finite() && o.cull_radius >= 0.0) {
        return Err(Error::invalid(
            "cull_radius",
            format!("{}; expected a finite number >= 0", o.cull_radius),
        ));
    }
    for (field, v) in [("texture_scale", o.texture_scale), ("scale", o.scale)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::invalid(
                field,
                format!("{v}; expected a finite number > 0"),
            ));
        }
    }
    Ok(())
}

#[inline]
fn direction(b: &Branch) -> Vec3 {
    (b.end() - b.start()).try_normalize().unwrap_or(Vec3::Y)
}

fn plan(skeleton: &Skeleton, o: &MeshOptions) -> Result<Plan> {
    check_options(o)?;
    let branches = skeleton.branches();
    let n = branches.len();
    let max_seg = o.radial_segments;
    let radius = |b: &Branch| b.start_radius.max(b.end_radius);
    let r_max = branches.iter().map(radius).fold(0.0f32, f32::max);
    let mut segs = vec![0u8; n];
    for (i, b) in branches.iter().enumerate() {
        let r = radius(b);
        let parent_kept = b.parent == NO_PARENT || segs[b.parent as usize] != 0;
        if !parent_kept || r < o.cull_radius {
            continue;
        }
        let s = if o.min_radial_segments == 0 || r_max <= 0.0 {
            max_seg
        } else {
            ((max_seg as f32 * r / r_max).ceil() as u32).clamp(o.min_radial_segments, max_seg)
        };
        segs[i] = s as u8;
    }
    let mut cont = vec![NO_PARENT; n];
    for (i, b) in branches.iter().enumerate() {
        if segs[i] == 0 || b.parent == NO_PARENT {
            continue;
        }
        let p = b.parent as usize;
        if cont[p] == NO_PARENT && branches[p].order == b.order {
            cont[p] = i as u32;
        }
    }
    let mut flags = vec![0u8; n];
    for i in 0..n {
        if segs[i] == 0 {
            continue;
        }
        let b = &branches[i];
        if b.parent == NO_PARENT {
            if o.base_cap {
                flags[i] |= BASE_CAP;
            }
        } else {
            let p = b.parent as usize;
            if o.joints == Joints::Mitred
                && cont[p] == i as u32
                && segs[p] == segs[i]
                && direction(&branches[p]).dot(direction(b)) > MITRE_MIN_COS
            {
                flags[i] |= SHARES_START;
                flags[p] |= MITRE_END;
            }
        }
        if cont[i] == NO_PARENT && o.tip != Tip::Open {
            flags[i] |= TIP;
        }
    }
    let rules = StripRules {
        topology: o.topology,
        clockwise: o.winding == Winding::Clockwise,
    };
    let mut ranges = Vec::with_capacity(n);
    let (mut nv, mut ni): (u64, u64) = (0, 0);
    let mut first = true;
    for i in 0..n {
        let s = segs[i] as usize;
        let f = flags[i];
        let (mut v, mut idx) = (0usize, 0usize);
        if s > 0 {
            let ring = s + 1;
            v += ring + if f & SHARES_START != 0 { 0 } else { ring };
            idx += rules.count(2 * ring, first);
            first = false;
            if f & BASE_CAP != 0 {
                v += s;
                idx += rules.count(s, false);
            }
            if f & TIP != 0 {
                v += s;
                idx += match o.tip {
                    Tip::Cap => rules.count(s, false),
                    _ => s * rules.count(3, false),
                };
            }
        }
        ranges.push(BranchRange {
            first_vertex: nv as u32,
            vertex_count: v as u32,
            first_index: ni as u32,
            index_count: idx as u32,
        });
        nv += v as u64;
        ni += idx as u64;
        if nv > RESTART_INDEX as u64 || ni > u32::MAX as u64 {
            return Err(Error::LimitExceeded {
                limit_name: "u32 index range",
                what: if nv > RESTART_INDEX as u64 {
                    "vertices"
                } else {
                    "indices"
                },
                limit: RESTART_INDEX as u64,
                requested: nv.max(ni),
                step: None,
            });
        }
    }
    Ok(Plan {
        segs,
        flags,
        cont,
        ranges,
        size: MeshSize {
            vertices: nv as usize,
            indices: ni as usize,
        },
        rules,
    })
}

/// The exact vertex and index counts [`write_mesh`] needs for `skeleton`.
///
/// Fails with [`Error::InvalidArgument`] for bad options and [`Error::LimitExceeded`] when
/// the vertices or indices could not all be addressed with 32 bits ([`RESTART_INDEX`] is
/// reserved).
pub fn mesh_size(skeleton: &Skeleton, options: &MeshOptions) -> Result<MeshSize> {
    Ok(plan(skeleton, options)?.size)
}

/// For each branch, the vertices and indices it owns in the mesh of `options`.
pub fn branch_ranges(skeleton: &Skeleton, options: &MeshOptions) -> Result<Vec<BranchRange>> {
    Ok(plan(skeleton, options)?.ranges)
}

/// An owned mesh of `skeleton`, its buffers allocated once at their exact size, with the
/// branch ranges.
pub fn tubes(skeleton: &Skeleton, options: &MeshOptions) -> Result<Mesh> {
    let plan = plan(skeleton, options)?;
    let mut vertices = bytemuck::zeroed_vec::<Vertex>(plan.size.vertices);
    let mut indices = bytemuck::zeroed_vec::<u32>(plan.size.indices);
    write(skeleton, options, &plan, &mut vertices, &mut indices);
    Ok(Mesh {
        vertices,
        indices,
        topology: options.topology,
        ranges: plan.ranges,
    })
}

/// Several levels of detail of one tree in one call (for example the same options with
/// growing `cull_radius` and shrinking `radial_segments`), each with its counts.
pub fn mesh_lods(skeleton: &Skeleton, levels: &[MeshOptions]) -> Result<Vec<LodLevel>> {
    levels
        .iter()
        .map(|o| {
            let mesh = tubes(skeleton, o)?;
            Ok(LodLevel {
                vertex_count: mesh.vertices.len(),
                triangle_count: mesh.triangles().count(),
                mesh,
            })
        })
        .collect()
}

/// An orthonormal pair `(p, q)` with `p × q = n` for a unit `n`, continuous everywhere but
/// at `n = −Y` (Frisvad's construction with its pole moved from −Z to −Y, where branches
/// rarely point). Only roots need it; every other ring's frame is transported.
pub(crate) fn ring_basis(n: DVec3) -> (DVec3, DVec3) {
    if n.y < -0.999_999 {
        let p = (DVec3::X - n * n.x).normalize();
        return (p, n.cross(p));
    }
    let a = 1.0 / (1.0 + n.y);
    let b = -n.z * n.x * a;
    let p = DVec3::new(b, -n.z, 1.0 - n.z * n.z * a);
    let q = DVec3::new(1.0 - n.x * n.x * a, -n.x, b);
    (p, q)
}

/// `p` carried from a ring around `from` to a ring around `to` by the smallest rotation.
fn transport(p: Vec3, from: Vec3, to: Vec3) -> Vec3 {
    let moved = Quat::from_rotation_arc(from, to) * p;
    (moved - to * moved.dot(to))
        .try_normalize()
        .unwrap_or_else(|| ring_basis(to.as_dvec3()).0.as_vec3())
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
    write_checked(skeleton, options, vertices, indices)
}

/// [`write_mesh`] into uninitialised memory, such as a mapped GPU buffer or a fresh
/// allocation: every slot of the returned counts' prefixes is initialised on success.
pub fn write_mesh_uninit(
    skeleton: &Skeleton,
    options: &MeshOptions,
    vertices: &mut [MaybeUninit<Vertex>],
    indices: &mut [MaybeUninit<u32>],
) -> Result<MeshSize> {
    write_checked(skeleton, options, vertices, indices)
}

fn write_checked<V: Slot<Vertex>, I: Slot<u32>>(
    skeleton: &Skeleton,
    options: &MeshOptions,
    vertices: &mut [V],
    indices: &mut [I],
) -> Result<MeshSize> {
    let plan = plan(skeleton, options)?;
    let size = plan.size;
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
    write(
        skeleton,
        options,
        &plan,
        &mut vertices[..size.vertices],
        &mut indices[..size.indices],
    );
    Ok(size)
}

/// Unit circle per side count: (cos, sin, u) for j in 0..=segments, the seam repeated.
fn circle(segments: usize) -> Vec<(f32, f32, f32)> {
    let step = std::f64::consts::TAU / segments as f64;
    (0..=segments)
        .map(|j| {
            let (s, c) = ((j % segments) as f64 * step).sin_cos();
            (c as f32, s as f32, j as f32 / segments as f32)
        })
        .collect()
}

/// Output conventions: uniform scale, then the up-axis rotation.
#[derive(Clone, Copy)]
struct Out {
    scale: f32,
    z_up: bool,
}

impl Out {
    #[inline(always)]
    fn dir(self, v: Vec3) -> [f32; 3] {
        if self.z_up {
            [v.x, -v.z, v.y]
        } else {
            v.to_array()
        }
    }
    #[inline(always)]
    fn pos(self, v: Vec3) -> [f32; 3] {
        self.dir(v * self.scale)
    }
}

/// Writes vertices one after another from a position.
struct VertexCursor<'a, V: Slot<Vertex>> {
    out: &'a mut [V],
    pos: usize,
}

impl<V: Slot<Vertex>> VertexCursor<'_, V> {
    #[inline(always)]
    fn put(&mut self, v: Vertex) {
        self.out[self.pos].put(v);
        self.pos += 1;
    }
}

/// Zig-zag order of a convex polygon's `n` corners: a strip that covers it.
fn zigzag(n: usize, mut corner: impl FnMut(usize) -> u32, out: &mut Vec<u32>) {
    out.clear();
    out.push(corner(0));
    let (mut lo, mut hi) = (1, n - 1);
    while lo <= hi {
        out.push(corner(lo));
        lo += 1;
        if lo <= hi {
            out.push(corner(hi));
            hi -= 1;
        }
    }
}

fn write<V: Slot<Vertex>, I: Slot<u32>>(
    skeleton: &Skeleton,
    o: &MeshOptions,
    plan: &Plan,
    vertices: &mut [V],
    indices: &mut [I],
) {
    let branches = skeleton.branches();
    let n = branches.len();
    let out = Out {
        scale: o.scale,
        z_up: o.up_axis == UpAxis::Z,
    };
    let inv_ts = 1.0 / o.texture_scale;
    let mut tables: Vec<Vec<(f32, f32, f32)>> = vec![Vec::new(); MAX_RADIAL_SEGMENTS as usize + 1];
    // Per branch: ring frame vector p (at its end) and v at its end.
    let mut frame_p = vec![Vec3::ZERO; n];
    let mut v_end = vec![0.0f32; n];
    let mut end_ring = vec![0u32; n];
    let mut writer = StripWriter {
        out: indices,
        pos: 0,
        rules: plan.rules,
        first: true,
        last: 0,
    };
    let mut strip: Vec<u32> = Vec::with_capacity(2 * MAX_RADIAL_SEGMENTS as usize + 2);

    for i in 0..n {
        let s = plan.segs[i] as usize;
        if s == 0 {
            continue;
        }
        if tables[s].is_empty() {
            tables[s] = circle(s);
        }
        let table = &tables[s];
        let ring = s + 1;
        let f = plan.flags[i];
        let b = &branches[i];
        let range = plan.ranges[i];
        let d = direction(b);
        let start = b.start();
        let end = b.end();
        let len = (end - start).length();
        let root = b.parent == NO_PARENT;
        let p = if root {
            ring_basis(d.as_dvec3()).0.as_vec3()
        } else {
            let parent = b.parent as usize;
            transport(frame_p[parent], direction(&branches[parent]), d)
        };
        frame_p[i] = p;
        let q = d.cross(p);
        let r0 = b.start_radius;
        let r1 = if o.smooth_taper && plan.cont[i] != NO_PARENT {
            branches[plan.cont[i] as usize].start_radius
        } else {
            b.end_radius
        };
        let v0 = if root { 0.0 } else { v_end[b.parent as usize] };
        let v1 = v0 + len * inv_ts;
        v_end[i] = v1;
        // Cone normal: radial·h + axis·(r0 − r1), normalised.
        let dr = r0 - r1;
        let slant = (len * len + dr * dr).sqrt();
        let (nc, na) = if slant > 0.0 {
            (len / slant, dr / slant)
        } else {
            (1.0, 0.0)
        };
        let tilt = d * na;

        let mut vc = VertexCursor {
            out: &mut *vertices,
            pos: range.first_vertex as usize,
        };
        // Start ring, unless shared with the parent.
        let (start_ring, start_center, start_v) = if f & SHARES_START != 0 {
            (end_ring[b.parent as usize], start, v0)
        } else {
            let sink = if root {
                0.0
            } else {
                branches[b.parent as usize].end_radius
            };
            let c0 = start - d * sink;
            let v = v0 - sink * inv_ts;
            for &(c, sn, u) in table {
                let radial = p * c + q * sn;
                vc.put(Vertex {
                    position: out.pos(c0 + radial * r0),
                    normal: out.dir(radial * nc + tilt),
                    uv: [u, v],
                });
            }
            (range.first_vertex, c0, v)
        };
        // End ring: in the bisecting plane when the next branch of the axis shares it.
        let my_end_ring = vc.pos as u32;
        end_ring[i] = my_end_ring;
        if f & MITRE_END != 0 {
            let dc = direction(&branches[plan.cont[i] as usize]);
            let m = (d + dc).normalize();
            let dm = d.dot(m);
            for &(c, sn, u) in table {
                let radial = p * c + q * sn;
                let offset = radial * r1;
                let offset = offset - d * (offset.dot(m) / dm);
                let normal = (radial - m * radial.dot(m)).normalize();
                vc.put(Vertex {
                    position: out.pos(end + offset),
                    normal: out.dir(normal),
                    uv: [u, v1],
                });
            }
        } else {
            for &(c, sn, u) in table {
                let radial = p * c + q * sn;
                vc.put(Vertex {
                    position: out.pos(end + radial * r1),
                    normal: out.dir(radial * nc + tilt),
                    uv: [u, v1],
                });
            }
        }
        // Base cap: a disc facing −d at the start ring.
        let base_first = vc.pos as u32;
        if f & BASE_CAP != 0 {
            for &(c, sn, _) in &table[..s] {
                let radial = p * c + q * sn;
                vc.put(Vertex {
                    position: out.pos(start_center + radial * r0),
                    normal: out.dir(-d),
                    uv: [0.5 + 0.5 * c, 0.5 - 0.5 * sn],
                });
            }
        }
        // Tip: a disc facing +d, or apexes of a cone one radius beyond the end.
        let tip_first = vc.pos as u32;
        if f & TIP != 0 {
            match o.tip {
                Tip::Cap => {
                    for &(c, sn, _) in &table[..s] {
                        let radial = p * c + q * sn;
                        vc.put(Vertex {
                            position: out.pos(end + radial * r1),
                            normal: out.dir(d),
                            uv: [0.5 + 0.5 * c, 0.5 + 0.5 * sn],
                        });
                    }
                }
                _ => {
                    let apex = end + d * r1;
                    for j in 0..s {
                        let (c0, s0, u0) = table[j];
                        let (c1, s1, u1) = table[j + 1];
                        let radial = (p * (c0 + c1) + q * (s0 + s1)).normalize_or_zero();
                        vc.put(Vertex {
                            position: out.pos(apex),
                            normal: out.dir((radial + d).normalize()),
                            uv: [0.5 * (u0 + u1), v1 + r1 * inv_ts],
                        });
                    }
                }
            }
        }
        let _ = start_v;

        // Indices: the tube, then the caps.
        strip.clear();
        for j in 0..ring as u32 {
            strip.push(my_end_ring + j);
            strip.push(start_ring + j);
        }
        writer.strip(&strip);
        if f & BASE_CAP != 0 {
            zigzag(s, |k| base_first + ((s - k) % s) as u32, &mut strip);
            writer.strip(&strip);
        }
        if f & TIP != 0 {
            if o.tip == Tip::Cap {
                zigzag(s, |k| tip_first + k as u32, &mut strip);
                writer.strip(&strip);
            } else {
                for j in 0..s as u32 {
                    writer.strip(&[tip_first + j, my_end_ring + j, my_end_ring + j + 1]);
                }
            }
        }
        debug_assert_eq!(vc.pos as u32, range.first_vertex + range.vertex_count);
        debug_assert_eq!(
            writer.pos as u32,
            range.first_index + range.index_count,
            "branch {i}"
        );
    }
    debug_assert_eq!(writer.pos, writer.out.len());
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
    fn transport_keeps_the_frame_perpendicular() {
        let from = Vec3::Y;
        let to = Vec3::new(1.0, 1.0, 0.0).normalize();
        let p = transport(Vec3::Z, from, to);
        assert_abs_diff_eq!(p.dot(to), 0.0, epsilon = 1e-6);
        assert_abs_diff_eq!(p.length(), 1.0, epsilon = 1e-6);
        // A rotation in the XY plane leaves Z alone.
        assert_abs_diff_eq!(p.z, 1.0, epsilon = 1e-6);
        let back = transport(Vec3::Z, Vec3::Y, Vec3::NEG_Y);
        assert_abs_diff_eq!(back.dot(Vec3::NEG_Y), 0.0, epsilon = 1e-6);
    }

    #[test]
    fn bad_options_are_rejected_by_name() {
        let cases: [(&str, MeshOptions); 6] = [
            (
                "radial_segments",
                MeshOptions {
                    radial_segments: 2,
                    ..Default::default()
                },
            ),
            (
                "radial_segments",
                MeshOptions {
                    radial_segments: 65,
                    ..Default::default()
                },
            ),
            (
                "min_radial_segments",
                MeshOptions {
                    min_radial_segments: 9,
                    ..Default::default()
                },
            ),
            (
                "cull_radius",
                MeshOptions {
                    cull_radius: f32::NAN,
                    ..Default::default()
                },
            ),
            (
                "texture_scale",
                MeshOptions {
                    texture_scale: 0.0,
                    ..Default::default()
                },
            ),
            (
                "scale",
                MeshOptions {
                    scale: f32::INFINITY,
                    ..Default::default()
                },
            ),
        ];
        for (field, o) in cases {
            match mesh_size(&Skeleton::default(), &o) {
                Err(Error::InvalidArgument { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
    }
}
