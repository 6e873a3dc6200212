//! Collision shapes: capsules along the trunk and the main limbs, the shape physics
//! engines collide trees with.
//!
//! Each axis of the tree (the trunk, then every limb, thickest first) is walked from its
//! base while its branches stay thicker than a radius; its internodes are gathered into
//! one capsule while the axis turns less than a bend, so a straight trunk is one capsule
//! and a crooked limb a few. The radius of a capsule is the widest of its internodes.
//!
//! ```
//! use arbor::collision::capsules;
//! use arbor::mesh::MeshOptions;
//!
//! let tree = arbor::models::honda::build(&arbor::models::honda::HondaParams::preset('b').unwrap())?;
//! let c = capsules(&tree, 16, 0.0, &MeshOptions::default())?;
//! assert!(!c.is_empty() && c.len() <= 16);
//! # Ok::<(), arbor::Error>(())
//! ```

use crate::error::{Error, Result};
use crate::mesh::MeshOptions;
use crate::skeleton::{NO_PARENT, Skeleton};
use glam::Vec3;

/// One capsule, 32 bytes; C: ArborCapsule. The segment from `a` to `b` swept by a sphere
/// of `radius`, in the mesh's output conventions (up axis, scale).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Capsule {
    /// The end nearer the axis' base.
    pub a: [f32; 3],
    /// The other end.
    pub b: [f32; 3],
    /// The sphere's radius.
    pub radius: f32,
    /// The branch the capsule starts on.
    pub branch: u32,
}

const _: () = assert!(std::mem::size_of::<Capsule>() == 32);

/// The most capsules a call may ask for.
pub const MAX_CAPSULES: usize = 4096;

/// How far an axis may turn along one capsule, degrees.
const MAX_BEND: f32 = 20.0;

/// At most `max` capsules (1..=4096) for `skeleton`'s trunk and limbs whose branches are
/// thicker than `min_radius` (model units; 0: a tenth of the trunk's radius), in the
/// output conventions of `mesh` (its up axis and scale). The trunk comes first, then the
/// limbs, thickest first; a tree of no branches has none.
pub fn capsules(
    skeleton: &Skeleton,
    max: usize,
    min_radius: f32,
    mesh: &MeshOptions,
) -> Result<Vec<Capsule>> {
    if !(1..=MAX_CAPSULES).contains(&max) {
        return Err(Error::invalid(
            "max_capsules",
            format!("{max}; expected 1..={MAX_CAPSULES}"),
        ));
    }
    if !(min_radius.is_finite() && min_radius >= 0.0) {
        return Err(Error::invalid(
            "min_radius",
            format!("{min_radius}; expected a finite radius >= 0"),
        ));
    }
    crate::mesh::check_options(mesh)?;
    let b = skeleton.branches();
    let adjacency = skeleton.adjacency();
    let thick = |i: usize| b[i].start_radius.max(b[i].end_radius);
    let trunk = b
        .iter()
        .enumerate()
        .filter(|(_, x)| x.parent == NO_PARENT)
        .map(|(i, _)| thick(i))
        .fold(0.0f32, f32::max);
    let min_r = if min_radius > 0.0 {
        min_radius
    } else {
        0.1 * trunk
    };
    // The axes' first branches: a root, or a branch that does not continue its parent.
    let mut axes: Vec<usize> = (0..b.len())
        .filter(|&i| {
            let p = b[i].parent;
            (p == NO_PARENT || adjacency.continuation(p as usize) != Some(i as u32))
                && thick(i) >= min_r
        })
        .collect();
    // The trunk first, then the thickest.
    axes.sort_by(|&i, &j| {
        let root = |k: usize| b[k].parent == NO_PARENT && b[k].order == 0;
        root(j)
            .cmp(&root(i))
            .then(thick(j).total_cmp(&thick(i)))
            .then(i.cmp(&j))
    });
    let out = mesh.out();
    let cos_bend = MAX_BEND.to_radians().cos();
    let mut caps = Vec::new();
    for first in axes {
        let mut i = first;
        // The run being gathered: its first branch, start, direction, end and radius.
        let mut run: Option<(usize, Vec3, Vec3, Vec3, f32)> = None;
        loop {
            let x = &b[i];
            let d = (x.end() - x.start()).normalize_or_zero();
            run = match run {
                Some((k, a, d0, _, r)) if d.dot(d0) >= cos_bend => {
                    Some((k, a, d0, x.end(), r.max(thick(i))))
                }
                Some((k, a, _, end, r)) => {
                    caps.push(capsule(&out, k, a, end, r));
                    Some((i, x.start(), d, x.end(), thick(i)))
                }
                None => Some((i, x.start(), d, x.end(), thick(i))),
            };
            if caps.len() >= max {
                return Ok(caps);
            }
            match adjacency.continuation(i) {
                Some(c) if thick(c as usize) >= min_r => i = c as usize,
                _ => break,
            }
        }
        if let Some((k, a, _, end, r)) = run {
            caps.push(capsule(&out, k, a, end, r));
        }
        if caps.len() >= max {
            break;
        }
    }
    Ok(caps)
}

fn capsule(out: &crate::mesh::Out, branch: usize, a: Vec3, b: Vec3, radius: f32) -> Capsule {
    Capsule {
        a: out.pos(a),
        b: out.pos(b),
        radius: radius * out.scale,
        branch: branch as u32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::UpAxis;

    /// A grown tree: its radii follow the pipe model, thick trunk, thin twigs.
    fn tree() -> Skeleton {
        use crate::models::growth::{GrowthParams, Species};
        crate::source::Source::Growth(GrowthParams::preset(Species::Decurrent), 24)
            .grow(1)
            .unwrap()
    }

    /// The distance from `p` to capsule `c`'s segment.
    fn distance(c: &Capsule, p: Vec3) -> f32 {
        let (a, b) = (Vec3::from(c.a), Vec3::from(c.b));
        let d = b - a;
        let t = ((p - a).dot(d) / d.length_squared().max(1e-12)).clamp(0.0, 1.0);
        (p - (a + d * t)).length()
    }

    #[test]
    fn capsules_hold_the_thick_wood_within_the_budget() {
        let s = tree();
        let caps = capsules(&s, 64, 0.0, &MeshOptions::default()).unwrap();
        assert!(!caps.is_empty() && caps.len() <= 64);
        let trunk = s.branches()[0].start_radius.max(s.branches()[0].end_radius);
        // Every capsule at least a tenth of the trunk; the first on the trunk's base.
        assert!(caps.iter().all(|c| c.radius >= 0.1 * trunk - 1e-6));
        assert_eq!(caps[0].branch, 0);
        assert_eq!(caps[0].a, s.branches()[0].start);
        // The trunk's every internode end is inside a capsule.
        let a = s.adjacency();
        let mut i = 0usize;
        loop {
            let p = Vec3::from(s.branches()[i].end);
            assert!(
                caps.iter().any(|c| distance(c, p) <= c.radius + 1e-4),
                "{i}"
            );
            match a.continuation(i) {
                Some(c) if s.branches()[c as usize].start_radius >= 0.1 * trunk => i = c as usize,
                _ => break,
            }
        }
        // A budget of three: three, the trunk's first.
        let few = capsules(&s, 3, 0.0, &MeshOptions::default()).unwrap();
        assert_eq!(few.len(), 3);
        assert_eq!(few[0], caps[0]);
        // Without a budget, a higher floor: fewer, all above it.
        let all = capsules(&s, MAX_CAPSULES, 0.0, &MeshOptions::default()).unwrap();
        let thick = capsules(&s, MAX_CAPSULES, 0.5 * trunk, &MeshOptions::default()).unwrap();
        assert!(
            thick.len() < all.len() && all.len() > 64,
            "{} {}",
            thick.len(),
            all.len()
        );
        assert!(thick.iter().all(|c| c.radius >= 0.5 * trunk - 1e-6));
    }

    #[test]
    fn capsules_follow_the_output_conventions() {
        let s = tree();
        let y = capsules(&s, 8, 0.0, &MeshOptions::default()).unwrap();
        let z = capsules(
            &s,
            8,
            0.0,
            &MeshOptions::default().up_axis(UpAxis::Z).scale(2.0),
        )
        .unwrap();
        assert_eq!(y.len(), z.len());
        for (p, q) in y.iter().zip(&z) {
            // Y up becomes Z up, everything twice as large.
            assert!((q.b[2] - 2.0 * p.b[1]).abs() < 1e-3, "{p:?} {q:?}");
            assert!((q.radius - 2.0 * p.radius).abs() < 1e-5);
        }
    }

    #[test]
    fn bad_budgets_and_radii_are_refused() {
        let s = tree();
        let o = MeshOptions::default();
        for (max, r, field) in [
            (0, 0.0, "max_capsules"),
            (MAX_CAPSULES + 1, 0.0, "max_capsules"),
            (8, -1.0, "min_radius"),
            (8, f32::NAN, "min_radius"),
        ] {
            let e = capsules(&s, max, r, &o).unwrap_err();
            assert!(e.to_string().contains(field), "{e}");
        }
        assert!(
            capsules(&Skeleton::default(), 8, 0.0, &o)
                .unwrap()
                .is_empty()
        );
    }
}
