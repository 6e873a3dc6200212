//! The tube mesher: every branch a truncated cone, axes joined into watertight tubes.

use super::strips::{Slot, StripRules, StripWriter, zigzag};
use super::{
    Joints, MAX_RADIAL_SEGMENTS, MIN_RADIAL_SEGMENTS, Mesh, MeshOptions, MeshSize, RESTART_INDEX,
    Tip, UpAxis, Vertex, Winding,
};
use crate::error::{Error, Result};
use crate::skeleton::{Branch, NO_PARENT, Skeleton};
use glam::{DVec3, Mat3, Quat, Vec2, Vec3, Vec4};
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
    /// Unit direction of every branch.
    dir: Vec<Vec3>,
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

/// Unit direction of a branch (+Y for a zero-length branch); in f64 only when the f32
/// difference of its ends overflows or underflows.
#[inline]
fn direction(b: &Branch) -> Vec3 {
    let d = Vec3::from(b.end) - Vec3::from(b.start);
    let l2 = d.length_squared();
    if l2.is_finite() && l2 > 1e-30 {
        return d * l2.sqrt().recip();
    }
    (b.end().as_dvec3() - b.start().as_dvec3())
        .try_normalize()
        .map_or(Vec3::Y, |d| d.as_vec3())
}

/// Length of a branch, in f64 when its f32 difference overflows.
#[inline]
fn length(b: &Branch) -> f64 {
    let l = (Vec3::from(b.end) - Vec3::from(b.start)).length();
    if l.is_finite() {
        l as f64
    } else {
        (b.end().as_dvec3() - b.start().as_dvec3()).length()
    }
}

fn plan(skeleton: &Skeleton, o: &MeshOptions) -> Result<Plan> {
    check_options(o)?;
    let branches = skeleton.branches();
    let n = branches.len();
    let max_seg = o.radial_segments;
    let radius = |b: &Branch| b.start_radius.max(b.end_radius);
    // Scaled positions (caps and point tips reach one radius further) must stay finite.
    let (mut r_max, mut extent) = (0.0f32, 0.0f64);
    for b in branches {
        let r = radius(b);
        r_max = r_max.max(r);
        let far = Vec3::from(b.start)
            .abs()
            .max(Vec3::from(b.end).abs())
            .max_element();
        extent = extent.max(far as f64 + 2.0 * r as f64);
    }
    if extent * o.scale as f64 > f32::MAX as f64 / 4.0 {
        return Err(Error::invalid(
            "scale",
            format!(
                "{}; the tree reaches {extent:e} units, so positions would leave the f32 range",
                o.scale
            ),
        ));
    }
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
    let dir: Vec<Vec3> = branches.iter().map(direction).collect();
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
                && dir[p].dot(dir[i]) > MITRE_MIN_COS
            {
                flags[i] |= SHARES_START;
                flags[p] |= MITRE_END;
            }
        }
        if cont[i] == NO_PARENT && o.tip != Tip::Open {
            flags[i] |= TIP;
        }
    }
    let mut plan = Plan {
        segs,
        flags,
        cont,
        dir,
        size: MeshSize::default(),
        rules: StripRules {
            topology: o.topology,
            clockwise: o.winding == Winding::Clockwise,
        },
    };
    let (mut nv, mut ni): (u64, u64) = (0, 0);
    let mut first = true;
    for i in 0..n {
        let (v, idx) = plan.counts(i, o.tip, &mut first);
        nv += v as u64;
        ni += idx as u64;
    }
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
    plan.size = MeshSize {
        vertices: nv as usize,
        indices: ni as usize,
    };
    Ok(plan)
}

impl Plan {
    /// Vertices and indices branch `i` owns; `first`: no strip has been written yet.
    #[inline]
    fn counts(&self, i: usize, tip: Tip, first: &mut bool) -> (usize, usize) {
        let s = self.segs[i] as usize;
        if s == 0 {
            return (0, 0);
        }
        let f = self.flags[i];
        let rules = self.rules;
        let ring = s + 1;
        let mut v = ring + if f & SHARES_START != 0 { 0 } else { ring };
        let mut idx = rules.count(2 * ring, *first);
        *first = false;
        if f & BASE_CAP != 0 {
            v += s;
            idx += rules.count(s, false);
        }
        if f & TIP != 0 {
            v += s;
            idx += match tip {
                Tip::Cap => rules.count(s, false),
                _ => s * rules.count(3, false),
            };
        }
        (v, idx)
    }

    fn ranges(&self, tip: Tip) -> Vec<BranchRange> {
        let mut first = true;
        let (mut nv, mut ni) = (0u32, 0u32);
        (0..self.segs.len())
            .map(|i| {
                let (v, idx) = self.counts(i, tip, &mut first);
                let r = BranchRange {
                    first_vertex: nv,
                    vertex_count: v as u32,
                    first_index: ni,
                    index_count: idx as u32,
                };
                nv += v as u32;
                ni += idx as u32;
                r
            })
            .collect()
    }
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
    Ok(plan(skeleton, options)?.ranges(options.tip))
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
        ranges: plan.ranges(options.tip),
    })
}

/// Per-vertex animation data for a host's growth and wind shaders: an optional second
/// vertex stream, one element per vertex of [`tubes`] with the same options (16 bytes; the
/// layout of the C type `ArborAnimationVertex`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct AnimationVertex {
    /// When the vertex appears as the tree grows, 0..=1: (depth − first depth + along) /
    /// (number of depths). Draw vertices with `growth <= t` and move t from 0 to 1.
    pub growth: f32,
    /// Branching order of the branch (0 on the trunk axis), for wind stiffness.
    pub order: f32,
    /// Position along the branch, 0 at its base and 1 at its tip.
    pub along: f32,
    /// A per-branch phase in [0, 1), so branches sway out of step.
    pub phase: f32,
}

/// A per-branch phase in [0, 1) from the branch index (the same on every run).
pub(crate) fn branch_phase(i: u32) -> f32 {
    let mut z = (i as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
}

/// The depths of the kept branches: (first, number of depths).
pub(crate) fn depth_span(skeleton: &Skeleton) -> (u32, u32) {
    let b = skeleton.branches();
    let lo = b.iter().map(|x| x.depth).min().unwrap_or(0);
    let hi = b.iter().map(|x| x.depth).max().unwrap_or(0);
    (lo, hi - lo + 1)
}

/// The animation stream of the mesh [`tubes`] makes with `options` (see
/// [`AnimationVertex`]); its length is the mesh's vertex count.
pub fn animation(skeleton: &Skeleton, options: &MeshOptions) -> Result<Vec<AnimationVertex>> {
    let plan = plan(skeleton, options)?;
    let (lo, span) = depth_span(skeleton);
    let mut out = Vec::with_capacity(plan.size.vertices);
    for (i, b) in skeleton.branches().iter().enumerate() {
        let s = plan.segs[i] as usize;
        if s == 0 {
            continue;
        }
        let f = plan.flags[i];
        let at = |along: f32| AnimationVertex {
            growth: ((b.depth - lo) as f32 + along) / span as f32,
            order: b.order as f32,
            along,
            phase: branch_phase(i as u32),
        };
        if f & SHARES_START == 0 {
            out.extend(std::iter::repeat_n(at(0.0), s + 1));
        }
        out.extend(std::iter::repeat_n(at(1.0), s + 1));
        if f & BASE_CAP != 0 {
            out.extend(std::iter::repeat_n(at(0.0), s));
        }
        if f & TIP != 0 {
            out.extend(std::iter::repeat_n(at(1.0), s));
        }
    }
    debug_assert_eq!(out.len(), plan.size.vertices);
    Ok(out)
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

/// The linear map that carries a ring vector from a ring around `from` to a ring around
/// `to`: the smallest rotation (Rodrigues' formula with k = from × to:
/// R p = p c + k × p + k (k · p) / (1 + c)), then the projection onto the plane normal to
/// `to`, which keeps rounding from tilting the frame. It does not depend on the vector
/// carried, so along an axis the chain of frames is one matrix product and one
/// renormalisation per branch.
#[inline]
fn transport_map(from: Vec3, to: Vec3) -> Mat3 {
    let c = from.dot(to);
    let rotation = if c > -0.9999 {
        let k = from.cross(to);
        let h = 1.0 / (1.0 + c);
        Mat3::from_diagonal(Vec3::splat(c))
            + Mat3::from_cols(
                Vec3::new(0.0, k.z, -k.y),
                Vec3::new(-k.z, 0.0, k.x),
                Vec3::new(k.y, -k.x, 0.0),
            )
            + Mat3::from_cols(k * (h * k.x), k * (h * k.y), k * (h * k.z))
    } else {
        Mat3::from_quat(Quat::from_rotation_arc(from, to))
    };
    let projection = Mat3::IDENTITY - Mat3::from_cols(to * to.x, to * to.y, to * to.z);
    projection * rotation
}

/// `p` carried by `map` (see [`transport_map`]) onto the ring around `to`, unit length.
#[inline]
fn carry(map: &Mat3, p: Vec3, to: Vec3) -> Vec3 {
    let v = *map * p;
    let l2 = v.length_squared();
    if (0.9..1.1).contains(&l2) {
        // A rotation keeps the length to rounding: one Newton step of 1/√l2 from 1.
        v * (1.5 - 0.5 * l2)
    } else {
        v.try_normalize()
            .unwrap_or_else(|| ring_basis(to.as_dvec3()).0.as_vec3())
    }
}

#[cfg(test)]
fn transport(p: Vec3, from: Vec3, to: Vec3) -> Vec3 {
    carry(&transport_map(from, to), p, to)
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

fn write_checked<V: Slot<Vertex> + Send, I: Slot<u32> + Send>(
    skeleton: &Skeleton,
    options: &MeshOptions,
    vertices: &mut [V],
    indices: &mut [I],
) -> Result<MeshSize> {
    let plan = plan(skeleton, options)?;
    let size = plan.size;
    size.check_capacity(vertices.len(), indices.len())?;
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

/// `x` as f32, clamped to the finite range.
#[inline]
fn to_f32(x: f64) -> f32 {
    x.clamp(-(f32::MAX as f64), f32::MAX as f64) as f32
}

/// A ring of vertices affine in the unit circle: the vertex at (cos, sin) = (c, s) with
/// texture coordinate u is `a + c·b + s·d + u·e`, each term the 8 floats of a [`Vertex`]
/// (position, normal, uv) held in two 4-lane vectors. Cones, caps and the mitred ring's
/// positions are all of this form, so a vertex is a few vector multiply-adds and two
/// 16-byte stores.
#[derive(Clone, Copy)]
struct Affine {
    a: [Vec4; 2],
    b: [Vec4; 2],
    d: [Vec4; 2],
    e: [Vec4; 2],
}

impl Affine {
    /// The terms from a center and radial directions, normals and uv.
    #[allow(clippy::too_many_arguments)]
    fn new(
        center: Vec3,
        radius_p: Vec3,
        radius_q: Vec3,
        normal: Vec3,
        normal_p: Vec3,
        normal_q: Vec3,
        uv: [f32; 2],
        uv_p: [f32; 2],
        uv_q: [f32; 2],
        uv_u: [f32; 2],
    ) -> Self {
        let pack = |pos: Vec3, n: Vec3, t: [f32; 2]| {
            [
                Vec4::new(pos.x, pos.y, pos.z, n.x),
                Vec4::new(n.y, n.z, t[0], t[1]),
            ]
        };
        Affine {
            a: pack(center, normal, uv),
            b: pack(radius_p, normal_p, uv_p),
            d: pack(radius_q, normal_q, uv_q),
            e: pack(Vec3::ZERO, Vec3::ZERO, uv_u),
        }
    }

    #[inline(always)]
    fn at(&self, c: f32, s: f32, u: f32) -> [Vec4; 2] {
        let (c, s, u) = (Vec4::splat(c), Vec4::splat(s), Vec4::splat(u));
        [
            self.a[0] + self.b[0] * c + self.d[0] * s,
            self.a[1] + self.b[1] * c + self.d[1] * s + self.e[1] * u,
        ]
    }

    /// Writes the ring: one vertex per entry of `table`.
    #[inline(always)]
    fn put<V: Slot<Vertex>>(&self, out: &mut [V], table: &[(f32, f32, f32)]) {
        for (slot, &(c, s, u)) in out.iter_mut().zip(table) {
            slot.put(vertex(self.at(c, s, u)));
        }
    }

    /// Writes the ring with each normal scaled to unit length: the mitred ring, whose
    /// normal `c·nb + s·nd` (the constant term's normal is zero) is affine in the circle
    /// only before normalising. The inverse lengths are computed four vertices at a time,
    /// one vector square root and division each.
    #[inline(always)]
    fn put_normalized<V: Slot<Vertex>>(&self, out: &mut [V], table: &[(f32, f32, f32)]) {
        debug_assert_eq!(Self::normal_of(&self.a), Vec3::ZERO);
        let (nb, nd) = (Self::normal_of(&self.b), Self::normal_of(&self.d));
        let (bb, bd2, dd) = (
            Vec4::splat(nb.dot(nb)),
            Vec4::splat(2.0 * nb.dot(nd)),
            Vec4::splat(nd.dot(nd)),
        );
        let mut inv = [1.0f32; MAX_RADIAL_SEGMENTS as usize + 4];
        for (chunk, dst) in table.chunks(4).zip(inv.chunks_exact_mut(4)) {
            // Lanes past the ring's end take (1, 0), a point of the circle.
            let (mut c, mut s) = ([1.0f32; 4], [0.0f32; 4]);
            for (k, &(ck, sk, _)) in chunk.iter().enumerate() {
                (c[k], s[k]) = (ck, sk);
            }
            let (c, s) = (Vec4::from_array(c), Vec4::from_array(s));
            let l2 = c * c * bb + c * s * bd2 + s * s * dd;
            dst.copy_from_slice(&(Vec4::ONE / l2.sqrt()).to_array());
        }
        for ((slot, &(c, s, u)), &k) in out.iter_mut().zip(table).zip(&inv) {
            let [lo, hi] = self.at(c, s, u);
            slot.put(vertex([
                lo * Vec4::new(1.0, 1.0, 1.0, k),
                hi * Vec4::new(k, k, 1.0, 1.0),
            ]));
        }
    }

    /// The normal part of a term.
    #[inline(always)]
    fn normal_of(t: &[Vec4; 2]) -> Vec3 {
        Vec3::new(t[0].w, t[1].x, t[1].y)
    }
}

#[inline(always)]
fn vertex([lo, hi]: [Vec4; 2]) -> Vertex {
    bytemuck::cast([lo.to_array(), hi.to_array()])
}

/// Per-branch values the writer reads, computed in one pass from parents to children (ring
/// frames and arc length flow down the tree); the writing itself can then run on chunks of
/// branches independently.
struct Layout {
    first_vertex: Vec<u32>,
    first_index: Vec<u32>,
    /// Ring frame vector p of each branch.
    frame_p: Vec<Vec3>,
    /// v at each branch's end.
    v_end: Vec<f32>,
    /// First vertex of each branch's end ring.
    end_ring: Vec<u32>,
}

fn layout(skeleton: &Skeleton, o: &MeshOptions, plan: &Plan) -> Layout {
    let branches = skeleton.branches();
    let n = branches.len();
    let inv_ts = 1.0 / o.texture_scale as f64;
    let mut l = Layout {
        first_vertex: vec![0; n],
        first_index: vec![0; n],
        frame_p: vec![Vec3::ZERO; n],
        v_end: vec![0.0; n],
        end_ring: vec![0; n],
    };
    let (mut nv, mut ni) = (0u32, 0u32);
    let mut first = true;
    for (i, b) in branches.iter().enumerate() {
        l.first_vertex[i] = nv;
        l.first_index[i] = ni;
        let (v, idx) = plan.counts(i, o.tip, &mut first);
        nv += v as u32;
        ni += idx as u32;
        let s = plan.segs[i] as usize;
        if s == 0 {
            continue;
        }
        let d = plan.dir[i];
        let root = b.parent == NO_PARENT;
        l.frame_p[i] = if root {
            ring_basis(d.as_dvec3()).0.as_vec3()
        } else {
            let parent = b.parent as usize;
            carry(&transport_map(plan.dir[parent], d), l.frame_p[parent], d)
        };
        let v0 = if root {
            0.0
        } else {
            l.v_end[b.parent as usize]
        };
        let len = length(b);
        // Clamped so that absurd lengths cannot push uv past the f32 range.
        l.v_end[i] = to_f32(v0 as f64 + len * inv_ts);
        let own_start = if plan.flags[i] & SHARES_START != 0 {
            0
        } else {
            s + 1
        };
        l.end_ring[i] = l.first_vertex[i] + own_start as u32;
    }
    l
}

fn write<V: Slot<Vertex> + Send, I: Slot<u32> + Send>(
    skeleton: &Skeleton,
    o: &MeshOptions,
    plan: &Plan,
    vertices: &mut [V],
    indices: &mut [I],
) {
    let lay = layout(skeleton, o, plan);
    let mut tables: Vec<Vec<(f32, f32, f32)>> = vec![Vec::new(); MAX_RADIAL_SEGMENTS as usize + 1];
    for &s in &plan.segs {
        if s > 0 && tables[s as usize].is_empty() {
            tables[s as usize] = circle(s as usize);
        }
    }
    let n = skeleton.len();
    // Chunks of branches write disjoint parts of both buffers; a degenerate strip joins
    // each strip to the previous one's last index, so it stays on one thread.
    #[cfg(feature = "parallel")]
    if n >= 8192 && plan.rules.topology != super::Topology::TriangleStripDegenerate {
        use rayon::prelude::*;
        let chunks = rayon::current_num_threads() * 4;
        let per = n.div_ceil(chunks);
        let mut parts = Vec::with_capacity(chunks);
        let (mut v_rest, mut i_rest) = (vertices, indices);
        let (mut v_at, mut i_at) = (0usize, 0usize);
        let mut lo = 0;
        while lo < n {
            let hi = (lo + per).min(n);
            let (v_to, i_to) = if hi < n {
                (lay.first_vertex[hi] as usize, lay.first_index[hi] as usize)
            } else {
                (plan.size.vertices, plan.size.indices)
            };
            let (va, vb) = std::mem::take(&mut v_rest).split_at_mut(v_to - v_at);
            let (ia, ib) = std::mem::take(&mut i_rest).split_at_mut(i_to - i_at);
            parts.push((lo..hi, va, v_at, ia, i_at));
            (v_rest, i_rest, v_at, i_at, lo) = (vb, ib, v_to, i_to, hi);
        }
        parts
            .into_par_iter()
            .for_each(|(range, v, v_base, i, i_base)| {
                write_branches(
                    skeleton,
                    o,
                    plan,
                    &lay,
                    &tables,
                    range,
                    v,
                    v_base,
                    i,
                    i_base == 0,
                );
            });
        return;
    }
    write_branches(
        skeleton,
        o,
        plan,
        &lay,
        &tables,
        0..n,
        vertices,
        0,
        indices,
        true,
    );
}

/// Writes branches `range` into `vertices` (which starts at vertex `v_base` of the mesh)
/// and `indices` (which starts at the first index of `range`); `first`: no strip of the
/// mesh comes before.
#[allow(clippy::too_many_arguments)]
fn write_branches<V: Slot<Vertex>, I: Slot<u32>>(
    skeleton: &Skeleton,
    o: &MeshOptions,
    plan: &Plan,
    lay: &Layout,
    tables: &[Vec<(f32, f32, f32)>],
    range: std::ops::Range<usize>,
    vertices: &mut [V],
    v_base: usize,
    indices: &mut [I],
    first: bool,
) {
    let branches = skeleton.branches();
    let out = Out {
        scale: o.scale,
        z_up: o.up_axis == UpAxis::Z,
    };
    // The output conventions are linear: apply them to each branch's centers and frame
    // vectors once, so the per-vertex loops are two multiply-adds.
    let rot = |v: Vec3| Vec3::from_array(out.dir(v));
    // In f64: a tiny texture scale must not turn v infinite.
    let inv_ts = 1.0 / o.texture_scale as f64;
    let dir = &plan.dir;
    let mut writer = StripWriter::new(indices, plan.rules, first);
    let mut strip: Vec<u32> = Vec::with_capacity(2 * MAX_RADIAL_SEGMENTS as usize + 2);
    // Where this chunk's indices start in the whole buffer (for the debug check below).
    let index_base = lay.first_index.get(range.start).map_or(0, |&i| i as usize);

    for i in range {
        let b = &branches[i];
        let d = dir[i];
        let s = plan.segs[i] as usize;
        if s == 0 {
            continue;
        }
        let table = &tables[s];
        let ring = s + 1;
        let f = plan.flags[i];
        let first_vertex = lay.first_vertex[i] as usize;
        debug_assert_eq!(
            writer.pos + index_base,
            lay.first_index[i] as usize,
            "branch {i}"
        );
        let start = b.start();
        let end = b.end();
        let root = b.parent == NO_PARENT;
        let p = lay.frame_p[i];
        let q = d.cross(p);
        let r0 = b.start_radius;
        let r1 = if o.smooth_taper && plan.cont[i] != NO_PARENT {
            branches[plan.cont[i] as usize].start_radius
        } else {
            b.end_radius
        };
        let v0 = if root {
            0.0
        } else {
            lay.v_end[b.parent as usize]
        };
        let v1 = lay.v_end[i];
        // Cone normal: radial·h + axis·(r0 − r1), normalised (in f64 only when the f32
        // sum of squares overflows).
        let slope = Vec2::new((end - start).length(), r0 - r1);
        let (nc, na) = match slope.try_normalize() {
            Some(n) => (n.x, n.y),
            None if slope == Vec2::ZERO => (1.0, 0.0),
            None => {
                let (h, dr) = (length(b), (r0 - r1) as f64);
                let slant = (h * h + dr * dr).sqrt();
                ((h / slant) as f32, (dr / slant) as f32)
            }
        };
        // Output-space frame.
        let (po, qo, d_o) = (rot(p), rot(q), rot(d));
        let tilt = d_o * na;
        let (r0s, r1s) = (r0 * o.scale, r1 * o.scale);
        let mut pos = first_vertex - v_base;
        // A ring of the cone: radial·r around the center, normal radial·nc + tilt.
        let cone = |center: Vec3, r: f32, v: f32| {
            Affine::new(
                center,
                po * r,
                qo * r,
                tilt,
                po * nc,
                qo * nc,
                [0.0, v],
                [0.0; 2],
                [0.0; 2],
                [1.0, 0.0],
            )
        };

        // Start ring, unless shared with the parent.
        let (start_ring, start_center) = if f & SHARES_START != 0 {
            (lay.end_ring[b.parent as usize], start)
        } else {
            let sink = if root {
                0.0
            } else {
                branches[b.parent as usize].end_radius
            };
            let c0 = start - d * sink;
            let co = Vec3::from_array(out.pos(c0));
            let v = to_f32(v0 as f64 - sink as f64 * inv_ts);
            cone(co, r0s, v).put(&mut vertices[pos..pos + ring], table);
            pos += ring;
            (first_vertex as u32, c0)
        };
        // End ring: in the bisecting plane when the next branch of the axis shares it.
        let my_end_ring = lay.end_ring[i];
        debug_assert_eq!(my_end_ring as usize, pos + v_base);
        let eo = Vec3::from_array(out.pos(end));
        let ring_out = &mut vertices[pos..pos + ring];
        if f & MITRE_END != 0 {
            let m = rot((d + dir[plan.cont[i] as usize]).normalize());
            // Each point of the circle slides along d onto the bisecting plane: the
            // position gives up `slide · (radial · m)`, the normal its part along m.
            let slide = d_o * (r1s / d_o.dot(m));
            let (pm, qm) = (po.dot(m), qo.dot(m));
            Affine::new(
                eo,
                po * r1s - slide * pm,
                qo * r1s - slide * qm,
                Vec3::ZERO,
                po - m * pm,
                qo - m * qm,
                [0.0, v1],
                [0.0; 2],
                [0.0; 2],
                [1.0, 0.0],
            )
            .put_normalized(ring_out, table);
        } else {
            cone(eo, r1s, v1).put(ring_out, table);
        }
        pos += ring;
        // Base cap: a disc facing −d at the start ring.
        let base_first = (pos + v_base) as u32;
        if f & BASE_CAP != 0 {
            let co = Vec3::from_array(out.pos(start_center));
            Affine::new(
                co,
                po * r0s,
                qo * r0s,
                -d_o,
                Vec3::ZERO,
                Vec3::ZERO,
                [0.5, 0.5],
                [0.5, 0.0],
                [0.0, -0.5],
                [0.0; 2],
            )
            .put(&mut vertices[pos..pos + s], table);
            pos += s;
        }
        // Tip: a disc facing +d, or apexes of a cone one radius beyond the end.
        let tip_first = (pos + v_base) as u32;
        if f & TIP != 0 {
            match o.tip {
                Tip::Cap => {
                    Affine::new(
                        eo,
                        po * r1s,
                        qo * r1s,
                        d_o,
                        Vec3::ZERO,
                        Vec3::ZERO,
                        [0.5, 0.5],
                        [0.5, 0.0],
                        [0.0, 0.5],
                        [0.0; 2],
                    )
                    .put(&mut vertices[pos..pos + s], table);
                }
                _ => {
                    let apex = Vec3::from_array(out.pos(end + d * r1));
                    for (j, slot) in vertices[pos..pos + s].iter_mut().enumerate() {
                        let (c0, s0, u0) = table[j];
                        let (c1, s1, u1) = table[j + 1];
                        let radial = (po * (c0 + c1) + qo * (s0 + s1)).normalize_or_zero();
                        slot.put(Vertex {
                            position: apex.to_array(),
                            normal: (radial + d_o).normalize().to_array(),
                            uv: [0.5 * (u0 + u1), to_f32(v1 as f64 + r1 as f64 * inv_ts)],
                        });
                    }
                }
            }
            pos += s;
        }

        // Indices: the tube, then the caps.
        writer.tube(my_end_ring, start_ring, ring as u32);
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
        debug_assert!(pos <= vertices.len());
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
    fn a_long_chain_of_transports_stays_unit_and_perpendicular() {
        // 100,000 branches along a wandering axis: the frame is carried by a matrix and
        // renormalised by one Newton step each time, so errors must not accumulate.
        let mut rng = crate::lsystem::Rng::new(3);
        let mut dir = Vec3::Y;
        let mut p = ring_basis(dir.as_dvec3()).0.as_vec3();
        for k in 0..100_000 {
            let jitter = Vec3::new(
                rng.next_f64() as f32 - 0.5,
                rng.next_f64() as f32 - 0.5,
                rng.next_f64() as f32 - 0.5,
            );
            // Mostly gentle bends, now and then a reversal (the matrix from a quaternion).
            let to = if k % 997 == 0 {
                -dir
            } else {
                (dir + jitter * 0.6).normalize()
            };
            p = transport(p, dir, to);
            dir = to;
            assert!(
                (p.length() - 1.0).abs() < 1e-5,
                "branch {k}: |p| = {}",
                p.length()
            );
            assert!(p.dot(dir).abs() < 1e-5, "branch {k}: p·d = {}", p.dot(dir));
        }
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
