//! Twigs: small prototypes of stems, grown once and placed at the young tips and along the
//! young shoots of a tree, so a crown carries its leaves on a fine, three-dimensional
//! spray of twigs without the growth model growing every one of them.
//!
//! A [`Twig`] lives in its own space: its base at the origin, +Y along the twig, +Z the
//! side its spray faces (up, toward the light), lengths in units of the twig's length.
//! [`twig_sites`] finds where a tree carries twigs, each as a transform (the 32-byte
//! [`LeafInstance`]: position, rotation, scale) that a host draws an instanced twig with;
//! [`graft`] bakes the twigs into the skeleton as branches, so the bark mesh has their
//! stems and the leaves sit on their tips.

use super::{Branch, NO_PARENT, Skeleton};
use crate::error::{Error, Result};
use crate::geom::transport::ring_basis;
use crate::mesh::LeafInstance;
use crate::rng::Rng;
use glam::{Mat3, Quat, Vec3};

/// The shape of a species' twig.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwigShape {
    /// Side stems along the main stem (0: the main stem alone). At most 12.
    pub stems: u32,
    /// Angle of the side stems from the main stem, degrees.
    pub spread: f32,
    /// The main stem's radius at its base over its length.
    pub thickness: f32,
    /// How far a twig hangs: 0 it points as its branch does, 1 straight down.
    pub droop: f32,
}

impl TwigShape {
    /// Four side stems at 45 degrees, a little drooping.
    pub fn new() -> Self {
        TwigShape {
            stems: 4,
            spread: 45.0,
            thickness: 0.012,
            droop: 0.1,
        }
    }
}

impl Default for TwigShape {
    fn default() -> Self {
        Self::new()
    }
}

/// Variants of a twig a tree draws from (chosen in turn).
pub const TWIG_VARIANTS: usize = 4;

/// A twig prototype: its stems in twig space, the main stem first (from the origin to
/// about (0, 1, 0)), then its side stems, leaving it base to tip; each side stem's
/// `parent` is 0, the main stem's [`NO_PARENT`].
#[derive(Clone, Debug, PartialEq)]
pub struct Twig {
    /// The stems, as branches of order 0 (main) and 1 (sides), birth 0.
    pub stems: Vec<Branch>,
}

impl Twig {
    /// A twig of `shape`, its side stems' places, angles and lengths varied by `seed`.
    pub fn new(shape: &TwigShape, seed: u64) -> Result<Twig> {
        let n = shape.stems;
        if n > 12 || !(0.0..=90.0).contains(&shape.spread) || !(0.0..=1.0).contains(&shape.droop) {
            return Err(Error::invalid(
                "twig",
                format!(
                    "{} side stems at {} degrees, droop {}; expected 0..=12 stems, 0..=90 \
                     degrees and droop 0..=1",
                    shape.stems, shape.spread, shape.droop
                ),
            ));
        }
        if !(shape.thickness > 0.0 && shape.thickness <= 0.2) {
            return Err(Error::invalid(
                "twig",
                format!(
                    "thickness {}; expected above 0, at most 0.2",
                    shape.thickness
                ),
            ));
        }
        let mut rng = Rng::new(seed ^ 0x7719_0000_0000_0000);
        let mut r = || rng.next_f64() as f32 * 2.0 - 1.0;
        let r0 = shape.thickness;
        // Where the side stems leave the main stem (the main stem's nodes), base to tip.
        let at: Vec<f32> = (0..n)
            .map(|j| {
                let t = if n == 1 {
                    0.5
                } else {
                    j as f32 / (n - 1) as f32
                };
                (0.2 + 0.6 * t + 0.04 * r()).clamp(0.1, 0.9)
            })
            .collect();
        let main_radius = |t: f32| r0 * (1.0 - 0.45 * t);
        // The main stem leans a little off its branch's line, in its own plane.
        let lean = 0.08 * r();
        let main_at = |t: f32| Vec3::new(lean * t, t, 0.0);
        let mut stems = Vec::with_capacity(n as usize + 1);
        stems.push(Branch {
            start: [0.0; 3],
            end: main_at(1.0).to_array(),
            start_radius: main_radius(0.0),
            end_radius: main_radius(1.0),
            parent: NO_PARENT,
            birth: 0,
            order: 0,
            flags: 0,
        });
        for (j, &t) in at.iter().enumerate() {
            // Alternate sides in the spray's plane, lifted a little toward its face.
            let side = if j % 2 == 0 { 1.0 } else { -1.0 };
            let angle = (shape.spread + 8.0 * r()).to_radians();
            let lift = (10.0 + 8.0 * r()).to_radians();
            let dir = Vec3::new(side * angle.sin(), angle.cos(), 0.0);
            let dir = (dir + Vec3::Z * lift.tan()).normalize();
            let len = 0.55 * (1.0 - 0.45 * t) * (1.0 + 0.12 * r());
            let start = main_at(t);
            let base = 0.6 * main_radius(t);
            stems.push(Branch {
                start: start.to_array(),
                end: (start + dir * len).to_array(),
                start_radius: base,
                end_radius: 0.65 * base,
                parent: 0,
                birth: 0,
                order: 1,
                flags: 0,
            });
        }
        Ok(Twig { stems })
    }

    /// The twig as a skeleton of its own at `scale` (its length), with `leaves` leaf
    /// sites at each stem's tip (pointing along the stem, facing the spray's +Z): a
    /// prototype a host meshes once (bark, and leaves on its sites) and draws at every
    /// [`twig_sites`] transform.
    pub fn skeleton(&self, scale: f32, leaves: u32) -> Result<Skeleton> {
        let stems: Vec<Branch> = self
            .stems
            .iter()
            .map(|b| Branch {
                start: (Vec3::from(b.start) * scale).to_array(),
                end: (Vec3::from(b.end) * scale).to_array(),
                start_radius: b.start_radius * scale,
                end_radius: b.end_radius * scale,
                ..*b
            })
            .collect();
        let mut sites = Vec::new();
        for (k, b) in stems.iter().enumerate() {
            let heading = (Vec3::from(b.end) - Vec3::from(b.start)).normalize_or(Vec3::Y);
            let up = (Vec3::Z - heading * heading.z).normalize_or(Vec3::X);
            for _ in 0..leaves {
                sites.push(super::LeafSite {
                    position: b.end,
                    heading: heading.to_array(),
                    up: up.to_array(),
                    branch: k as u32,
                    birth: 0,
                });
            }
        }
        let mut parts = Skeleton::new(stems)?.into_parts();
        parts.leaves = sites;
        parts.build()
    }
}

/// Where a tree carries twigs: one at the tip of every branch born at `min_birth` or
/// later, and along each such branch that has children one per 1.5 twig lengths of it
/// (spaced evenly, each leaving it to a side; the fraction by chance), each `length`
/// long. Returns the branch each sits on and its
/// transform from twig space (+Y along, +Z the spray's face) to the tree's, pointing as
/// the branch does, turned toward the ground by `droop` (0..=1) and facing up.
pub fn twig_sites(
    skeleton: &Skeleton,
    min_birth: u32,
    length: f32,
    droop: f32,
    seed: u64,
) -> Vec<(u32, LeafInstance)> {
    let b = skeleton.branches();
    let adjacency = skeleton.adjacency();
    let mut rng = Rng::new(seed ^ 0x5eed_7719);
    let mut out = Vec::new();
    let droop = droop.clamp(0.0, 1.0);
    let length = length.max(f32::MIN_POSITIVE);
    for (i, x) in b.iter().enumerate() {
        if x.birth < min_birth || x.parent == NO_PARENT && x.order == 0 && b.len() > 1 {
            continue;
        }
        let axis = (x.end() - x.start()).normalize_or(Vec3::Y);
        if adjacency.is_tip(i) {
            out.push((i as u32, frame(x.end(), axis, length, droop, &mut rng)));
            continue;
        }
        // Along the shoot, one twig per 1.5 twig lengths of it (the fraction by chance),
        // each leaving it at 50 degrees to a side of its own.
        let expected = x.length() / (1.5 * length);
        let count = expected as u32 + u32::from((rng.next_f64() as f32) < expected.fract());
        let (u, v) = ring_basis(axis.as_dvec3());
        for j in 0..count {
            let a = (rng.next_f64() * std::f64::consts::TAU) as f32;
            let side = (u.as_vec3() * a.cos() + v.as_vec3() * a.sin()).normalize_or(Vec3::X);
            let angle = 50f32.to_radians();
            let at = x.start().lerp(x.end(), (j as f32 + 0.5) / count as f32);
            let heading = axis * angle.cos() + side * angle.sin();
            out.push((i as u32, frame(at, heading, length, droop, &mut rng)));
        }
    }
    out
}

/// A twig's transform at `position` pointing along `heading` turned toward the ground by
/// `droop`, its spray facing up, spun and sized a little at random.
fn frame(position: Vec3, heading: Vec3, length: f32, droop: f32, rng: &mut Rng) -> LeafInstance {
    let heading = heading.lerp(Vec3::NEG_Y, droop).normalize_or(Vec3::NEG_Y);
    // The spray faces up: +Z is the world's up made square to the heading.
    let up = (Vec3::Y - heading * heading.y)
        .try_normalize()
        .unwrap_or_else(|| ring_basis(heading.as_dvec3()).0.as_vec3());
    // Twig space: +Y the heading, +Z up, +X = Y × Z.
    let frame = Quat::from_mat3(&Mat3::from_cols(heading.cross(up), heading, up));
    let spin = (rng.next_f64() as f32 * 2.0 - 1.0) * 0.5;
    let grow = 1.0 + (rng.next_f64() as f32 * 2.0 - 1.0) * 0.15;
    LeafInstance {
        position: position.to_array(),
        rotation: (Quat::from_axis_angle(heading, spin) * frame)
            .normalize()
            .to_array(),
        scale: length * grow,
    }
}

/// `skeleton` with twig `twigs[k % twigs.len()]` grafted at each site `k` (from
/// [`twig_sites`]): the twig's stems become branches on the site's branch, born at
/// `birth`, their radii the twig's at the site's scale but no thicker than the branch
/// they leave. No twigs or no sites: the skeleton as it is.
pub fn graft(
    skeleton: &Skeleton,
    twigs: &[Twig],
    sites: &[(u32, LeafInstance)],
    birth: u32,
) -> Result<Skeleton> {
    if twigs.is_empty() || sites.is_empty() {
        return Ok(skeleton.clone());
    }
    let stems: usize = sites
        .iter()
        .enumerate()
        .map(|(k, _)| twigs[k % twigs.len()].stems.len())
        .sum();
    let mut parts = skeleton.clone().into_parts();
    let n0 = parts.branches.len();
    if n0 + stems > crate::limits::DEFAULT_MAX_BRANCHES {
        return Err(Error::LimitExceeded {
            limit_name: "max_branches",
            what: "branches with their twigs",
            limit: crate::limits::DEFAULT_MAX_BRANCHES as u64,
            requested: (n0 + stems) as u64,
            step: None,
        });
    }
    parts.branches.reserve(stems);
    let (has_ups, has_curves, has_colors) = (
        !parts.ups.is_empty(),
        !parts.curves.is_empty(),
        !parts.colors.is_empty(),
    );
    for (k, &(on, t)) in sites.iter().enumerate() {
        let twig = &twigs[k % twigs.len()];
        let host = parts.branches[on as usize];
        let rotation = Quat::from_array(t.rotation);
        let place = |p: [f32; 3]| Vec3::from(t.position) + rotation * (Vec3::from(p) * t.scale);
        let widest = host.end_radius.max(f32::MIN_POSITIVE);
        let first = parts.branches.len() as u32;
        let up = (rotation * Vec3::Z).to_array();
        for s in &twig.stems {
            let (start, end) = (place(s.start), place(s.end));
            parts.branches.push(Branch {
                start: start.to_array(),
                end: end.to_array(),
                start_radius: (s.start_radius * t.scale).min(widest),
                end_radius: (s.end_radius * t.scale).min(widest),
                parent: if s.parent == NO_PARENT {
                    on
                } else {
                    first + s.parent
                },
                birth,
                order: host.order + 1 + s.order,
                flags: 0,
            });
            if has_ups {
                parts.ups.push(up);
            }
            if has_curves {
                let third = |f: f32| start.lerp(end, f).to_array();
                parts.curves.push([third(1.0 / 3.0), third(2.0 / 3.0)]);
            }
            if has_colors {
                let c = parts.colors[on as usize];
                parts.colors.push(c);
            }
        }
    }
    parts.build()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree() -> Skeleton {
        let b = |start: [f32; 3], end: [f32; 3], parent: u32, order: u32, birth: u32| Branch {
            start,
            end,
            start_radius: 0.1,
            end_radius: 0.08,
            parent,
            birth,
            order,
            flags: 0,
        };
        Skeleton::new(vec![
            b([0.0; 3], [0.0, 1.0, 0.0], NO_PARENT, 0, 0),
            b([0.0, 1.0, 0.0], [0.0, 2.0, 0.0], 0, 0, 1),
            b([0.0, 1.0, 0.0], [1.0, 1.5, 0.0], 0, 1, 1),
            b([1.0, 1.5, 0.0], [1.5, 2.0, 0.0], 2, 1, 2),
        ])
        .unwrap()
    }

    #[test]
    fn a_twig_is_a_main_stem_with_its_side_stems() {
        let shape = TwigShape::new();
        let t = Twig::new(&shape, 3).unwrap();
        assert_eq!(t.stems.len(), shape.stems as usize + 1);
        let main = &t.stems[0];
        assert_eq!(
            (main.start, main.parent, main.order),
            ([0.0; 3], NO_PARENT, 0)
        );
        assert!((main.end[1] - 1.0).abs() < 1e-6);
        let axis = Vec3::from(main.end);
        for s in &t.stems[1..] {
            // A side stem leaves the main stem, at about the spread, toward the face.
            assert_eq!((s.parent, s.order), (0, 1));
            let on = Vec3::from(s.start);
            assert!(
                on.cross(axis).length() < 1e-5 && (0.1..0.95).contains(&on.y),
                "{on}"
            );
            let d = (Vec3::from(s.end) - on).normalize();
            let angle = d.angle_between(Vec3::Y).to_degrees();
            assert!((30.0..65.0).contains(&angle), "{angle}");
            assert!(d.z > 0.0);
            assert!(s.start_radius < main.start_radius);
        }
        assert_ne!(t, Twig::new(&shape, 4).unwrap());
        assert!(Twig::new(&TwigShape { stems: 13, ..shape }, 0).is_err());
        assert!(
            Twig::new(
                &TwigShape {
                    thickness: 0.0,
                    ..shape
                },
                0
            )
            .is_err()
        );
    }

    #[test]
    fn sites_are_the_young_tips_and_shoots_facing_up() {
        let s = tree();
        let sites = twig_sites(&s, 1, 0.3, 0.0, 1);
        // Branch 1 and 3 are tips (one twig each); 2 is a young shoot 1.12 long with a
        // child (2.5 twigs of 1.5 x 0.3 along it: 2 or 3); 0 the old trunk (none).
        let on = |b: u32| sites.iter().filter(|x| x.0 == b).count();
        assert_eq!((on(0), on(1), on(3)), (0, 1, 1));
        assert!((2..=3).contains(&on(2)), "{}", on(2));
        for (b, t) in &sites {
            let r = Quat::from_array(t.rotation);
            let (heading, up) = (r * Vec3::Y, r * Vec3::Z);
            assert!((heading.length() - 1.0).abs() < 1e-5);
            assert!(heading.dot(up).abs() < 1e-5);
            // Facing up unless it points straight up.
            assert!(up.y >= -1e-5, "{up}");
            assert!((0.25..0.35).contains(&t.scale));
            let x = &s.branches()[*b as usize];
            if s.adjacency().is_tip(*b as usize) {
                assert_eq!(t.position, x.end);
            }
        }
        // Drooping turns them toward the ground.
        let hung = twig_sites(&s, 1, 0.3, 1.0, 1);
        for (_, t) in &hung {
            assert!((Quat::from_array(t.rotation) * Vec3::Y).y < -0.99);
        }
    }

    #[test]
    fn grafted_twigs_are_branches_on_their_sites() {
        let s = tree();
        let twigs: Vec<Twig> = (0..2)
            .map(|k| Twig::new(&TwigShape::new(), k).unwrap())
            .collect();
        let sites = twig_sites(&s, 1, 0.3, 0.2, 1);
        let g = graft(&s, &twigs, &sites, 9).unwrap();
        let added = g.branches().len() - s.branches().len();
        assert_eq!(added, sites.len() * twigs[0].stems.len());
        // The old tips carry twigs now; every new tip is a twig's stem, born at 9.
        let a = g.adjacency();
        for (i, b) in g.branches().iter().enumerate() {
            if a.is_tip(i) {
                assert_eq!(b.birth, 9, "{i}");
            }
            if i >= s.branches().len() {
                let p = &g.branches()[b.parent as usize];
                assert!(b.start_radius <= p.end_radius.max(p.start_radius) + 1e-6);
                assert!(b.order > 0);
            }
        }
        // The first stem of the twig on branch 1 starts at that branch's tip.
        let first = &g.branches()[s.branches().len()];
        assert_eq!(first.parent, 1);
        assert_eq!(first.start, s.branches()[1].end);
        assert_eq!(graft(&s, &twigs, &[], 9).unwrap(), s);
    }
}
