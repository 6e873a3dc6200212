//! Wind that plays in any viewer: a small skeleton of bones along the trunk and the main
//! limbs, every vertex of the bark and the leaves weighted to them, and a looping clip of
//! the bones swaying, so a glTF file moves in Blender, three.js, Godot or Unity's
//! importers with no shader of the host's.
//!
//! **Bones** ([`rig`]): the trunk's axis in [`TRUNK_BONES`] bones, then the limbs (the
//! axes that leave it, and theirs), thickest first, [`LIMB_BONES`] each, until the
//! budget; each bone a segment of its axis by arc length, its head where the segment
//! starts. A bone's parent is the bone of the branch its segment grows from.
//!
//! **Weights** ([`weights`]): a vertex takes the bone of its branch (a branch on no bone's
//! axis takes its parent's), blended with that bone's parent over the first
//! [`BLEND`] of the bone's length (two influences at most, summing to one); a leaf
//! rides its branch's bone.
//!
//! **Clip** ([`clip`]): each bone turns about a level axis across the wind (+X blowing,
//! turning about the horizontal axis perpendicular to it) by a sum of sines whose
//! frequencies are whole multiples of one over the clip's length (so the last key is the
//! first: it loops without a jump); its amplitude grows with the bone's slenderness
//! (length over radius, the stiffness of a beam) and its phase and gusts come from the
//! seed.

use crate::error::{Error, Result};
use crate::mesh::{Mesh, MeshOptions};
use crate::skeleton::{NO_PARENT, Skeleton};
use glam::{Quat, Vec3};

/// Bones along the trunk.
pub const TRUNK_BONES: usize = 4;

/// Bones along each limb.
pub const LIMB_BONES: usize = 2;

/// The share of a bone's length over which its vertices blend into its parent's.
pub const BLEND: f32 = 0.25;

/// The most bones a rig has.
pub const MAX_BONES: usize = 256;

/// One bone, 32 bytes; C: ArborBone. A segment of an axis, in the mesh's space.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Bone {
    /// Where it starts (its joint).
    pub head: [f32; 3],
    /// Where it ends.
    pub tail: [f32; 3],
    /// Its parent bone, or [`NO_PARENT`] (C: ARBOR_NO_PARENT) for the root.
    pub parent: u32,
    /// The radius of the wood at its head (mesh units).
    pub radius: f32,
}

/// The bones of a tree and which bone each branch rides.
#[derive(Clone, Debug, PartialEq)]
pub struct Rig {
    /// The bones, parents first; the first is the trunk's base.
    pub bones: Vec<Bone>,
    /// For each branch of the skeleton, its bone.
    pub branch_bone: Vec<u32>,
}

/// The axes of a skeleton: each a list of branches from its first to its tip.
fn axes(skeleton: &Skeleton) -> Vec<Vec<u32>> {
    let b = skeleton.branches();
    let adjacency = skeleton.adjacency();
    let mut out = Vec::new();
    for (i, x) in b.iter().enumerate() {
        let continues =
            x.parent != NO_PARENT && adjacency.continuation(x.parent as usize) == Some(i as u32);
        if continues {
            continue;
        }
        let mut axis = vec![i as u32];
        let mut at = i;
        while let Some(c) = adjacency.continuation(at) {
            axis.push(c);
            at = c as usize;
        }
        out.push(axis);
    }
    out
}

/// The rig of `skeleton` drawn with `mesh` (its conventions and scale): at most
/// `max_bones` (1..=[`MAX_BONES`]) bones.
pub fn rig(skeleton: &Skeleton, max_bones: usize, mesh: &MeshOptions) -> Result<Rig> {
    if !(1..=MAX_BONES).contains(&max_bones) {
        return Err(Error::invalid(
            "max_bones",
            format!("{max_bones}; expected 1..={MAX_BONES}"),
        ));
    }
    mesh.validate()?;
    let b = skeleton.branches();
    if b.is_empty() {
        return Err(Error::invalid("skeleton", "no branches; expected a tree"));
    }
    let out = mesh.out();
    let mut all = axes(skeleton);
    // The trunk (the first root's axis) first, then the thickest axes.
    let trunk = all.remove(0);
    all.sort_by(|p, q| {
        b[q[0] as usize]
            .start_radius
            .total_cmp(&b[p[0] as usize].start_radius)
            .then(p[0].cmp(&q[0]))
    });
    let mut rig = Rig {
        bones: Vec::new(),
        branch_bone: vec![u32::MAX; b.len()],
    };
    // Which bone each chosen axis' branch is on, bone by bone.
    let mut chosen: Vec<(Vec<u32>, usize)> = vec![(trunk, TRUNK_BONES)];
    let mut count = TRUNK_BONES.min(chosen[0].0.len());
    for axis in all {
        // Only axes that grow from a chosen one (so each bone's parent is a bone).
        let n = LIMB_BONES.min(axis.len());
        if count + n > max_bones {
            break;
        }
        count += n;
        chosen.push((axis, n));
    }
    let mut on_bone = vec![u32::MAX; b.len()];
    let mut segments: Vec<(Vec<u32>, usize)> = Vec::new();
    for (axis, n) in &chosen {
        let n = (*n).min(axis.len()).max(1);
        // Split by arc length into n segments.
        let lengths: Vec<f32> = axis.iter().map(|&i| b[i as usize].length()).collect();
        let total: f32 = lengths.iter().sum::<f32>().max(f32::MIN_POSITIVE);
        let mut acc = 0.0;
        let mut parts: Vec<Vec<u32>> = vec![Vec::new(); n];
        for (&i, &l) in axis.iter().zip(&lengths) {
            let k = (((acc + 0.5 * l) / total * n as f32) as usize).min(n - 1);
            parts[k].push(i);
            acc += l;
        }
        for p in parts.into_iter().filter(|p| !p.is_empty()) {
            segments.push((p, 0));
        }
    }
    // Bones in the order of their first branch (parents before children).
    segments.sort_by_key(|(p, _)| p[0]);
    for (k, (p, _)) in segments.iter().enumerate() {
        for &i in p {
            on_bone[i as usize] = k as u32;
        }
    }
    for (k, (p, _)) in segments.iter().enumerate() {
        let first = &b[p[0] as usize];
        let last = &b[*p.last().expect("a segment has branches") as usize];
        let _ = k;
        rig.bones.push(Bone {
            head: out.pos(first.start()),
            tail: out.pos(last.end()),
            parent: NO_PARENT,
            radius: first.start_radius * out.scale,
        });
    }
    // Every branch's bone: its own segment's, else its parent's (parents come first).
    for (i, x) in b.iter().enumerate() {
        rig.branch_bone[i] = if on_bone[i] != u32::MAX {
            on_bone[i]
        } else if x.parent != NO_PARENT {
            rig.branch_bone[x.parent as usize]
        } else {
            0
        };
    }
    // A bone's parent: the bone of the branch its first branch grows from.
    for (k, (p, _)) in segments.iter().enumerate() {
        let parent = b[p[0] as usize].parent;
        rig.bones[k].parent = if parent == NO_PARENT {
            NO_PARENT
        } else {
            rig.branch_bone[parent as usize]
        };
    }
    // One root: any other root bone hangs from the first.
    for k in 1..rig.bones.len() {
        if rig.bones[k].parent == NO_PARENT {
            rig.bones[k].parent = 0;
        }
    }
    Ok(rig)
}

/// Up to four bones and their weights (summing to one), per vertex.
pub type Influence = ([u16; 4], [f32; 4]);

impl Bone {
    /// Its inverse bind matrix (column-major, as glTF's): the translation that moves its
    /// head to the origin (a bone's rest has no rotation).
    pub fn inverse_bind(&self) -> [f32; 16] {
        let [x, y, z] = self.head;
        [
            1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -x, -y, -z, 1.0,
        ]
    }
}

/// The influences of `vertices` (in the rig's mesh space), each on the bone `bone_of(k)`
/// of vertex `k`: blended with the bone's parent near its head.
fn blend(rig: &Rig, positions: impl Iterator<Item = (Vec3, u32)>) -> Vec<Influence> {
    positions
        .map(|(p, j)| {
            let bone = &rig.bones[j as usize];
            let (h, t) = (Vec3::from(bone.head), Vec3::from(bone.tail));
            let d = t - h;
            let s = if d.length_squared() > 0.0 {
                (p - h).dot(d) / d.length_squared()
            } else {
                1.0
            };
            if bone.parent == NO_PARENT || s >= BLEND {
                return ([j as u16, 0, 0, 0], [1.0, 0.0, 0.0, 0.0]);
            }
            // Half its parent's at the joint, all its own at BLEND of its length.
            let own = 0.5 + 0.5 * (s.max(0.0) / BLEND);
            (
                [j as u16, bone.parent as u16, 0, 0],
                [own, 1.0 - own, 0.0, 0.0],
            )
        })
        .collect()
}

/// The influences of every vertex of `bark` (a mesh of the rig's skeleton with its branch
/// ranges, as [`crate::mesh::tubes`] writes it).
pub fn weights(rig: &Rig, bark: &Mesh) -> Result<Vec<Influence>> {
    let mut bone_of = vec![0u32; bark.vertices.len()];
    if bark.ranges.len() != rig.branch_bone.len() {
        return Err(Error::invalid(
            "bark",
            format!(
                "{} branch ranges; expected one per branch of the rig's skeleton ({})",
                bark.ranges.len(),
                rig.branch_bone.len()
            ),
        ));
    }
    for (r, &j) in bark.ranges.iter().zip(&rig.branch_bone) {
        let (a, n) = (r.first_vertex as usize, r.vertex_count as usize);
        if let Some(slice) = bone_of.get_mut(a..a + n) {
            slice.fill(j);
        }
    }
    Ok(blend(
        rig,
        bark.vertices
            .iter()
            .zip(bone_of)
            .map(|(v, j)| (Vec3::from(v.position), j)),
    ))
}

/// The influences of every vertex of a level of detail's `bark` (see [`crate::lod`]):
/// meshed from `skeleton` (the rig's) collapsed, each of its branch ranges the merged
/// branch `merged[i]` of the skeleton's branches `i` (an empty `merged`: `bark` is the
/// skeleton's own, as [`weights`]). A vertex rides the bone of the member of its merged
/// branch nearest it, so a level bends as the full tree does.
pub fn level_weights(
    rig: &Rig,
    skeleton: &Skeleton,
    mesh: &MeshOptions,
    bark: &Mesh,
    merged: &[u32],
) -> Result<Vec<Influence>> {
    if merged.is_empty() {
        return weights(rig, bark);
    }
    let b = skeleton.branches();
    if merged.len() != b.len() || rig.branch_bone.len() != b.len() {
        return Err(Error::invalid(
            "merged",
            format!(
                "{} entries; expected one per branch of the rig's skeleton ({})",
                merged.len(),
                rig.branch_bone.len()
            ),
        ));
    }
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); bark.ranges.len()];
    for (i, &s) in merged.iter().enumerate() {
        match members.get_mut(s as usize) {
            Some(m) => m.push(i as u32),
            None => {
                return Err(Error::invalid(
                    "merged",
                    format!(
                        "branch {i} merged into {s}; expected one of the bark's {} ranges",
                        bark.ranges.len()
                    ),
                ));
            }
        }
    }
    let out = mesh.out();
    let ends: Vec<(Vec3, Vec3)> = b
        .iter()
        .map(|x| (Vec3::from(out.pos(x.start())), Vec3::from(out.pos(x.end()))))
        .collect();
    let mut bone_of = vec![0u32; bark.vertices.len()];
    for (r, m) in bark.ranges.iter().zip(&members) {
        let (a, n) = (r.first_vertex as usize, r.vertex_count as usize);
        let Some(slice) = bark.vertices.get(a..a + n) else {
            continue;
        };
        for (k, v) in slice.iter().enumerate() {
            let p = Vec3::from(v.position);
            let nearest = m
                .iter()
                .map(|&i| {
                    let (s, e) = ends[i as usize];
                    (i, off_segment(p, s, e))
                })
                .fold((u32::MAX, f32::MAX), |x, y| if y.1 < x.1 { y } else { x })
                .0;
            if let Some(&j) = rig.branch_bone.get(nearest as usize) {
                bone_of[a + k] = j;
            }
        }
    }
    Ok(blend(
        rig,
        bark.vertices
            .iter()
            .zip(bone_of)
            .map(|(v, j)| (Vec3::from(v.position), j)),
    ))
}

/// The distance of `p` from the segment `a`..`b`.
fn off_segment(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let d = b - a;
    let t = if d.length_squared() > 0.0 {
        ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * t)).length()
}

/// The influences of every vertex of a baked leaf mesh whose leaf `k` is
/// `per_leaf` vertices from `k * per_leaf` on the branch `branches[k]`; the vertices
/// after the leaves (the turtle's polygons and organs) ride the root bone.
pub fn leaf_weights(rig: &Rig, leaves: &Mesh, branches: &[u32], per_leaf: usize) -> Vec<Influence> {
    leaves
        .vertices
        .iter()
        .enumerate()
        .map(|(k, _)| {
            let j = branches
                .get(k / per_leaf.max(1))
                .and_then(|&b| rig.branch_bone.get(b as usize))
                .copied()
                .unwrap_or(0);
            ([j as u16, 0, 0, 0], [1.0, 0.0, 0.0, 0.0])
        })
        .collect()
}

/// The influences of every vertex of a level of detail's bark (`leaves` false) or baked
/// leaves (`leaves` true; none without them), on `rig` made from `skeleton` and `mesh`,
/// the options of the chain's full tree: the bark as [`level_weights`], each leaf on its
/// branch's bone as [`leaf_weights`]. Every level of a chain rides one skeleton.
pub fn level_part_weights(
    rig: &Rig,
    skeleton: &Skeleton,
    mesh: &MeshOptions,
    level: &crate::lod::Level,
    leaves: bool,
) -> Result<Vec<Influence>> {
    if !leaves {
        return level_weights(
            rig,
            skeleton,
            &level.mesh_options,
            &level.bark,
            &level.merged,
        );
    }
    let (Some(options), Some(baked)) = (&level.leaf_options, &level.leaves) else {
        return Ok(Vec::new());
    };
    let branches = crate::mesh::leaf_branches(skeleton, options, mesh)?;
    Ok(leaf_weights(
        rig,
        baked,
        &branches,
        options.shape().vertices.len(),
    ))
}

/// A looping clip: key times and each bone's rotation (a unit quaternion x, y, z, w,
/// relative to its rest) at each key.
#[derive(Clone, Debug, PartialEq)]
pub struct Clip {
    /// Seconds.
    pub duration: f32,
    /// Key times from 0 to `duration`, the last key the first again.
    pub times: Vec<f32>,
    /// For each bone, its rotation at each key.
    pub rotations: Vec<Vec<[f32; 4]>>,
}

/// The wind clip of `rig`: `duration` seconds (0.5..=60) at `keys_per_second` (1..=60),
/// the wind blowing along `wind` (level; the mesh's own axes) at `strength` (0..=4: at 1,
/// a bone turns by up to 0.002 * sqrt(length / radius) radians, about 2 degrees for a
/// slender limb and a third of one for a stout trunk's segment), varied by `seed`.
pub fn clip(
    rig: &Rig,
    up: Vec3,
    wind: Vec3,
    strength: f32,
    duration: f32,
    keys_per_second: u32,
    seed: u64,
) -> Result<Clip> {
    if !(0.5..=60.0).contains(&duration) {
        return Err(Error::invalid(
            "duration",
            format!("{duration}; expected 0.5..=60 seconds"),
        ));
    }
    if !(1..=60).contains(&keys_per_second) {
        return Err(Error::invalid(
            "keys_per_second",
            format!("{keys_per_second}; expected 1..=60"),
        ));
    }
    if !(0.0..=4.0).contains(&strength) {
        return Err(Error::invalid(
            "strength",
            format!("{strength}; expected 0..=4"),
        ));
    }
    let up = up.normalize_or(Vec3::Y);
    let level = (wind - up * wind.dot(up)).normalize_or(up.any_orthonormal_vector());
    // A bone bends over: it turns about the level axis across the wind.
    let across = up.cross(level).normalize_or(Vec3::X);
    let keys = (duration * keys_per_second as f32).round().max(2.0) as usize;
    let times: Vec<f32> = (0..=keys)
        .map(|k| duration * k as f32 / keys as f32)
        .collect();
    let mut rng = crate::rng::Rng::new(seed);
    // Gusts: the same for the whole tree, two slow whole cycles over the clip.
    let gust: [(f32, f32); 2] = [(1.0, rng.next_f64() as f32), (2.0, rng.next_f64() as f32)];
    let tau = std::f32::consts::TAU;
    let rotations = rig
        .bones
        .iter()
        .map(|bone| {
            let length = (Vec3::from(bone.tail) - Vec3::from(bone.head)).length();
            // Slender bones sway more: length over radius, as a beam's deflection grows.
            let slender = (length / bone.radius.max(1e-4)).clamp(1.0, 400.0);
            let amplitude = strength * 0.002 * slender.sqrt();
            // Its own sway: a few whole cycles over the clip, at its own phase.
            let cycles = 2.0 + (rng.next_f64() * 3.0).floor() as f32;
            let phase = rng.next_f64() as f32;
            // A little sideways too, out of step.
            let side_cycles = cycles + 1.0;
            let side_phase = rng.next_f64() as f32;
            times
                .iter()
                .map(|&t| {
                    let u = t / duration;
                    let g: f32 = gust
                        .iter()
                        .map(|&(c, p)| 0.5 + 0.5 * (tau * (c * u + p)).sin())
                        .sum::<f32>()
                        / 2.0;
                    let bend = amplitude * (0.6 * g + 0.4 * (tau * (cycles * u + phase)).sin());
                    let side = 0.3 * amplitude * (tau * (side_cycles * u + side_phase)).sin();
                    let q =
                        Quat::from_axis_angle(across, bend) * Quat::from_axis_angle(level, side);
                    q.normalize().to_array()
                })
                .collect()
        })
        .collect();
    Ok(Clip {
        duration,
        times,
        rotations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree() -> (Skeleton, MeshOptions) {
        let mut p = crate::HondaParams::preset('b').unwrap();
        p.steps = 8;
        (
            crate::models::honda::build(&p).unwrap(),
            MeshOptions::default(),
        )
    }

    /// A straight trunk of 8 branches on 4 bones, collapsed into one branch: each vertex
    /// of the collapsed bark rides the bone of the branch it lies along.
    #[test]
    fn a_collapsed_level_rides_the_bones_of_the_branches_it_merged() {
        use crate::skeleton::{Branch, SkeletonParts};
        let branches: Vec<Branch> = (0..8)
            .map(|k| Branch {
                parent: if k == 0 { NO_PARENT } else { k - 1 },
                start: [0.0, k as f32, 0.0],
                end: [0.0, k as f32 + 1.0, 0.0],
                start_radius: 0.1,
                end_radius: 0.1,
                ..Branch::default()
            })
            .collect();
        let s = SkeletonParts {
            branches,
            ..SkeletonParts::default()
        }
        .build()
        .unwrap();
        let o = MeshOptions::default();
        let rig = rig(&s, 8, &o).unwrap();
        assert_eq!(rig.bones.len(), TRUNK_BONES);
        let (collapsed, merged) = crate::lod::collapse_merged(&s, 0.01).unwrap();
        assert_eq!(collapsed.len(), 1);
        let bark = crate::mesh::tubes(&collapsed, &o).unwrap();
        let w = level_weights(&rig, &s, &o, &bark, &merged).unwrap();
        assert_eq!(w.len(), bark.vertices.len());
        for (v, (j, x)) in bark.vertices.iter().zip(&w) {
            assert!((x.iter().sum::<f32>() - 1.0).abs() < 1e-5, "{x:?}");
            // Height y lies on branch floor(y), bone floor(y) / 2: the heaviest.
            let y = v.position[1].clamp(0.0, 7.99);
            let top = (0..4).max_by(|&a, &b| x[a].total_cmp(&x[b])).unwrap();
            let expected = rig.branch_bone[y as usize];
            // At a joint between bones either side is right.
            let near_joint = [2.0f32, 4.0, 6.0].iter().any(|&at| (y - at).abs() < 0.1);
            assert!(
                near_joint || j[top] as u32 == expected,
                "vertex at {y}: bone {} ({x:?}); expected {expected}",
                j[top]
            );
        }
        // The wrong length of `merged` is an error, not a panic.
        assert!(level_weights(&rig, &s, &o, &bark, &merged[1..]).is_err());
    }

    #[test]
    fn every_vertex_is_weighted_to_one_and_every_bone_moves_something() {
        let (s, o) = tree();
        let rig = rig(&s, 24, &o).unwrap();
        assert!(
            rig.bones.len() > TRUNK_BONES && rig.bones.len() <= 24,
            "{}",
            rig.bones.len()
        );
        for (k, b) in rig.bones.iter().enumerate() {
            assert!(
                k == 0 || (b.parent as usize) < k,
                "bone {k}: parent {}",
                b.parent
            );
        }
        let bark = crate::mesh::tubes(&s, &o).unwrap();
        let w = weights(&rig, &bark).unwrap();
        assert_eq!(w.len(), bark.vertices.len());
        let mut used = vec![false; rig.bones.len()];
        for (j, x) in &w {
            let sum: f32 = x.iter().sum();
            assert!((sum - 1.0).abs() < 1e-5, "{x:?}");
            assert!(x.iter().all(|&v| (0.0..=1.0).contains(&v)));
            for (&b, &v) in j.iter().zip(x) {
                if v > 0.0 {
                    used[b as usize] = true;
                }
            }
        }
        assert!(
            used.iter().all(|&u| u),
            "a bone without influence: {used:?}"
        );
        assert!(
            rig.branch_bone
                .iter()
                .all(|&b| (b as usize) < rig.bones.len())
        );
    }

    #[test]
    fn the_clip_loops_and_stays_gentle() {
        let (s, o) = tree();
        let rig = rig(&s, 16, &o).unwrap();
        let c = clip(&rig, Vec3::Y, Vec3::X, 1.0, 4.0, 30, 7).unwrap();
        assert_eq!(c.times.len(), 121);
        assert_eq!(*c.times.last().unwrap(), 4.0);
        for r in &c.rotations {
            assert_eq!(r.len(), c.times.len());
            let (a, b) = (Quat::from_array(r[0]), Quat::from_array(*r.last().unwrap()));
            assert!(a.angle_between(b) < 1e-4, "no loop: {a} {b}");
            for q in r {
                assert!(Quat::from_array(*q).angle_between(Quat::IDENTITY) < 0.5);
            }
        }
        assert!(clip(&rig, Vec3::Y, Vec3::X, 1.0, 0.1, 30, 7).is_err());
        assert!(rig_err());
    }

    fn rig_err() -> bool {
        let (s, o) = tree();
        rig(&s, 0, &o).is_err() && rig(&s, MAX_BONES + 1, &o).is_err()
    }
}

/// Wind data a host's shader reads from standard attributes, per vertex: `color` is glTF's
/// `COLOR_0` (unorm8: the branch's phase, its stiffness, its branch level, the leaf's
/// flutter) and `uv1` is `TEXCOORD_1` (how far along its branch, 0 at its base and 1 at its
/// tip; when it grows, 0..=1).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WindVertex {
    /// Phase (0..1, per branch), stiffness (1 for the trunk's widest wood, falling with
    /// the square root of the radius), branch level (order / 4, at most 1), flutter (0 on
    /// bark; on a leaf, 0 at its stem to 1 at its tip).
    pub color: [u8; 4],
    /// Along the branch, and the growth time.
    pub uv1: [f32; 2],
    /// The branch the vertex rides (glTF `TEXCOORD_2`.x, exact to 2^24): its row in the
    /// tree's [`pivots`].
    pub branch: u32,
}

/// Each branch's pivot for a Pivot-Painter-style shader, 32 bytes: where it turns (its
/// start), its length, its axis (unit, start to end) and its parent's index (-1 for a
/// root), in the mesh's space.
pub fn pivots(skeleton: &Skeleton, options: &MeshOptions) -> Vec<[f32; 8]> {
    let out = options.out();
    skeleton
        .branches()
        .iter()
        .map(|b| {
            let (s, e) = (Vec3::from(out.pos(b.start())), Vec3::from(out.pos(b.end())));
            let axis = (e - s).normalize_or_zero();
            let parent = if b.parent == NO_PARENT {
                -1.0
            } else {
                b.parent as f32
            };
            [
                s.x,
                s.y,
                s.z,
                (e - s).length(),
                axis.x,
                axis.y,
                axis.z,
                parent,
            ]
        })
        .collect()
}

/// How stiff each branch is: 1 for the tree's widest wood, falling with the square root
/// of the radius.
struct Stiffness<'a> {
    branches: &'a [crate::skeleton::Branch],
    widest: f32,
}

impl<'a> Stiffness<'a> {
    fn of(skeleton: &'a Skeleton) -> Self {
        let branches = skeleton.branches();
        let widest = branches
            .iter()
            .map(|x| x.start_radius.max(x.end_radius))
            .fold(0.0f32, f32::max)
            .max(f32::MIN_POSITIVE);
        Stiffness { branches, widest }
    }

    /// Branch `i`'s stiffness (0 for none such).
    fn branch(&self, i: u32) -> f32 {
        self.branches.get(i as usize).map_or(0.0, |x| {
            (x.start_radius.max(x.end_radius) / self.widest).sqrt()
        })
    }
}

fn unorm8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// The wind attributes of every vertex of `bark` (a mesh of `skeleton` drawn with
/// `options`, with its branch ranges).
pub fn bark_attributes(
    skeleton: &Skeleton,
    bark: &Mesh,
    options: &MeshOptions,
) -> Result<Vec<WindVertex>> {
    let anim = crate::mesh::animation(skeleton, options)?;
    if anim.len() != bark.vertices.len() || bark.ranges.len() != skeleton.len() {
        return Err(Error::invalid(
            "bark",
            "not the mesh of this skeleton and options; expected tubes(skeleton, options)",
        ));
    }
    let stiff = Stiffness::of(skeleton);
    let mut stiffness = vec![(0.0f32, 0u32); anim.len()];
    for (i, r) in bark.ranges.iter().enumerate() {
        let s = stiff.branch(i as u32);
        let (a, n) = (r.first_vertex as usize, r.vertex_count as usize);
        if let Some(slice) = stiffness.get_mut(a..a + n) {
            slice.fill((s, i as u32));
        }
    }
    Ok(anim
        .iter()
        .zip(stiffness)
        .map(|(a, (s, branch))| WindVertex {
            color: [unorm8(a.phase), unorm8(s), unorm8(a.order / 4.0), 0],
            uv1: [a.along, a.growth],
            branch,
        })
        .collect())
}

/// The wind attributes of every vertex of the baked leaf mesh of `skeleton` with `leaves`
/// and `options` (`leaf_mesh`): each leaf its branch's phase, stiffness and level, its
/// flutter rising from stem to tip; the turtle's polygons and organs after the leaves ride
/// still (zeros).
pub fn leaf_attributes(
    skeleton: &Skeleton,
    leaves: &crate::mesh::LeafOptions,
    options: &MeshOptions,
    leaf_mesh: &Mesh,
) -> Result<Vec<WindVertex>> {
    let anim = crate::mesh::leaf_animation(skeleton, leaves, options)?;
    let branches = crate::mesh::leaf_branches(skeleton, leaves, options)?;
    let shape = leaves.shape();
    let per_leaf = shape.vertices.len().max(1);
    let (lo, hi) = shape
        .vertices
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), v| {
            (lo.min(v.position[1]), hi.max(v.position[1]))
        });
    let stiff = Stiffness::of(skeleton);
    Ok((0..leaf_mesh.vertices.len())
        .map(|k| {
            let leaf = k / per_leaf;
            match (anim.get(leaf), branches.get(leaf)) {
                (Some(a), Some(&br)) => {
                    let s = stiff.branch(br);
                    let y = shape.vertices[k % per_leaf].position[1];
                    let flutter = if hi > lo { (y - lo) / (hi - lo) } else { 1.0 };
                    WindVertex {
                        color: [
                            unorm8(a.phase),
                            unorm8(s),
                            unorm8(a.order / 4.0),
                            unorm8(flutter),
                        ],
                        uv1: [1.0, a.growth],
                        branch: if br == NO_PARENT { 0 } else { br },
                    }
                }
                _ => WindVertex::default(),
            }
        })
        .collect())
}
