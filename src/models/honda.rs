//! The branching model of Prusinkiewicz, Hammel, Hanan & Měch (1996), after Honda, with the
//! paper's nine trees a–i as presets.
//!
//! ```text
//! ω : A(100, w0)
//! p1: A(s,w) : s >= min -> !(w) F(s) [ +(α1) /(φ1) A(s*r1, w*q^e) ] [ +(α2) /(φ2) A(s*r2, w*(1-q)^e) ]
//! ```
//!
//! [`build`] grows the skeleton directly, without a module string, with an explicit stack
//! (no recursion), in the order the turtle would read the derived string: each branch, then
//! the whole first child's subtree, then the second's. It uses the cpfg turtle of
//! the L-system interpreter, so the result equals the grammar's, branch by branch.
//!
//! **Axis rule.** Of the two children, the one whose branching angle has the smaller
//! magnitude continues its parent's axis (same `order`); the other starts a lateral axis
//! (`order + 1`). On a tie (tree a: ±35°) the first child continues the axis. This is
//! [`assign_axis_orders`], the rule the turtle uses for every grammar.

use crate::error::{Error, Result};
use crate::geom::{Frame, cos_sin_deg};
use crate::skeleton::{Branch, NO_PARENT, Skeleton, SkeletonParts, assign_axis_orders};

pub use crate::limits::DEFAULT_MAX_BRANCHES;

/// Largest accepted derivation length.
pub const MAX_STEPS: u32 = 1024;

/// The names of the presets, in the paper's order.
pub const PRESET_NAMES: [char; 9] = ['a', 'b', 'c', 'd', 'e', 'f', 'g', 'h', 'i'];

/// Parameters of the 1996 branching model of Prusinkiewicz, Hammel, Hanan & Mech (trees
/// a-i); C: ArborHondaParams.
///
/// Lengths and widths are in the model's units (the paper's trunk is 100 long); widths are
/// diameters (`!(w)`), so a branch radius is half its width. Angles are in degrees.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[non_exhaustive]
pub struct HondaParams {
    /// s0: length of the trunk (100 in the paper). Finite, > 0.
    pub trunk_length: f32,
    /// w0: width (diameter) of the trunk. Finite, > 0.
    pub trunk_width: f32,
    /// r1: length ratio of the first child. Finite, > 0.
    pub r1: f32,
    /// r2: length ratio of the second child. Finite, > 0.
    pub r2: f32,
    /// alpha1: branching angle of the first child (`+`). Finite.
    pub alpha1: f32,
    /// alpha2: branching angle of the second child (`+`). Finite.
    pub alpha2: f32,
    /// phi1: divergence angle of the first child (`/`). Finite.
    pub phi1: f32,
    /// phi2: divergence angle of the second child (`/`). Finite.
    pub phi2: f32,
    /// q: share of the width that goes to the first child, in [0, 1].
    pub q: f32,
    /// e: width exponent, finite, >= 0. Children widths are w*q^e and w*(1-q)^e.
    pub e: f32,
    /// min: an apex grows only while its length s >= min. Finite, >= 0.
    pub min_length: f32,
    /// n: derivation length (rewriting steps; the axiom is step 0), at most 1024
    /// (`MAX_STEPS`).
    pub steps: u32,
}

impl HondaParams {
    /// One of the paper's trees `'a'`..=`'i'` (upper case accepted too); `None` otherwise.
    pub fn preset(name: char) -> Option<Self> {
        #[rustfmt::skip]
        let (r1, r2, alpha1, alpha2, phi1, phi2, trunk_width, q, e, min_length, steps) =
            match name.to_ascii_lowercase() {
                'a' => (0.75, 0.77, 35.0, -35.0, 0.0, 0.0, 30.0, 0.50, 0.40, 0.0, 10),
                'b' => (0.65, 0.71, 27.0, -68.0, 0.0, 0.0, 20.0, 0.53, 0.50, 1.7, 12),
                'c' => (0.50, 0.85, 25.0, -15.0, 180.0, 0.0, 20.0, 0.45, 0.50, 0.5, 9),
                'd' => (0.60, 0.85, 25.0, -15.0, 180.0, 180.0, 20.0, 0.45, 0.50, 0.0, 10),
                'e' => (0.58, 0.83, 30.0, 15.0, 0.0, 180.0, 20.0, 0.40, 0.50, 1.0, 11),
                'f' => (0.92, 0.37, 0.0, 60.0, 180.0, 0.0, 2.0, 0.50, 0.00, 0.5, 15),
                'g' => (0.80, 0.80, 30.0, -30.0, 137.0, 137.0, 30.0, 0.50, 0.50, 0.0, 10),
                'h' => (0.95, 0.75, 5.0, -30.0, -90.0, 90.0, 40.0, 0.60, 0.45, 25.0, 12),
                'i' => (0.55, 0.95, -5.0, 30.0, 137.0, 137.0, 5.0, 0.40, 0.00, 5.0, 12),
                _ => return None,
            };
        Some(HondaParams {
            trunk_length: 100.0,
            trunk_width,
            r1,
            r2,
            alpha1,
            alpha2,
            phi1,
            phi2,
            q,
            e,
            min_length,
            steps,
        })
    }

    /// Checks every field; the error names the first field out of range.
    pub fn validate(&self) -> Result<()> {
        let positive = [
            ("trunk_length", self.trunk_length),
            ("trunk_width", self.trunk_width),
            ("r1", self.r1),
            ("r2", self.r2),
        ];
        let angles = [
            ("alpha1", self.alpha1),
            ("alpha2", self.alpha2),
            ("phi1", self.phi1),
            ("phi2", self.phi2),
        ];
        let checks = positive.map(|(f, v)| (f, v, v > 0.0, "a finite number > 0"));
        let checks = checks
            .into_iter()
            .chain(angles.map(|(f, v)| (f, v, true, "a finite angle in degrees")));
        for (field, v, in_range, expected) in checks {
            if !(v.is_finite() && in_range) {
                return Err(Error::invalid(field, format!("{v}; expected {expected}")));
            }
        }
        if !(self.q.is_finite() && (0.0..=1.0).contains(&self.q)) {
            return Err(Error::invalid(
                "q",
                format!("{}; expected 0 <= q <= 1", self.q),
            ));
        }
        for (field, v) in [("e", self.e), ("min_length", self.min_length)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::invalid(
                    field,
                    format!("{v}; expected a finite number >= 0"),
                ));
            }
        }
        if self.steps > MAX_STEPS {
            return Err(Error::invalid(
                "steps",
                format!("{}; expected at most {MAX_STEPS}", self.steps),
            ));
        }
        Ok(())
    }

    /// The exact number of branches the model makes (saturating at `u64::MAX`), counted
    /// without building: O(steps²) time, O(steps) memory.
    ///
    /// An apex with `k1` first-child and `k2` second-child choices on its path has length
    /// s0*r1^k1*r2^k2, so whether it grows depends only on `(k1, k2)`, and the number of
    /// growing paths to each `(k1, k2)` is the sum over its two predecessors.
    pub fn branch_count(&self) -> u64 {
        self.count_until(u64::MAX).0
    }

    /// Counts branches step by step; stops at the first step whose running total passes
    /// `limit` and returns `(total, Some(step))`, else `(total, None)`.
    fn count_until(&self, limit: u64) -> (u64, Option<u32>) {
        let (r1, r2, min) = (self.r1 as f64, self.r2 as f64, self.min_length as f64);
        // For generation g (= step - 1), index k1 in 0..=g: (paths alive, length).
        let mut cur: Vec<(u64, f64)> = vec![(1, self.trunk_length as f64)];
        let mut next: Vec<(u64, f64)> = Vec::new();
        let mut total: u64 = 0;
        for step in 1..=self.steps {
            let mut grown: u64 = 0;
            for c in cur.iter_mut() {
                if c.1 < min {
                    c.0 = 0;
                }
                grown = grown.saturating_add(c.0);
            }
            total = total.saturating_add(grown);
            if total > limit {
                return (total, Some(step));
            }
            if grown == 0 {
                break;
            }
            // Children of generation g: k1 from 0..=g+1; (k1) comes from (k1-1) via r1 and
            // from (k1) via r2.
            next.clear();
            for k1 in 0..=cur.len() {
                let from_r2 = cur.get(k1).map_or(0, |c| c.0);
                let from_r1 = if k1 > 0 { cur[k1 - 1].0 } else { 0 };
                let len = if k1 < cur.len() {
                    cur[k1].1 * r2
                } else {
                    cur[k1 - 1].1 * r1
                };
                next.push((from_r1.saturating_add(from_r2), len));
            }
            std::mem::swap(&mut cur, &mut next);
        }
        (total, None)
    }
}

crate::options::options! {
/// Seeded per-branch variation of the model, so that trees grown from the same parameters
/// differ the way real ones do. Every child's branching and divergence angles move by up
/// to ± the angles given, its length and width by up to ± the fractions given (uniformly).
/// Applied as the tree grows, so it stays connected. Seed 0 means no variation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Variation {
    /// Seed of the variation; 0: none (the paper's tree exactly).
    pub seed: u64 = 0,
    /// Largest change of a branching angle (`+`), degrees. Default 4.
    pub branching: f32 = 4.0, checked AtLeast(0.0), "a finite angle >= 0",
    /// Largest change of a divergence angle (`/`), degrees. Default 10.
    pub divergence: f32 = 10.0, checked AtLeast(0.0), "a finite angle >= 0",
    /// Largest relative change of a length, 0..1. Default 0.06.
    pub length: f32 = 0.06, checked InBelow(0.0, 1.0), "0 <= x < 1",
    /// Largest relative change of a width, 0..1. Default 0.06.
    pub width: f32 = 0.06, checked InBelow(0.0, 1.0), "0 <= x < 1",
}
}

impl Variation {
    /// Refuses amounts that are not finite or are negative, naming the first.
    pub fn validate(&self) -> Result<()> {
        self.check_fields()
    }
}

/// Grows the model with seeded [`Variation`] (and the default branch limit).
pub fn build_varied(params: &HondaParams, variation: &Variation) -> Result<Skeleton> {
    variation.validate()?;
    grow(params, DEFAULT_MAX_BRANCHES, Some(variation))
}

/// Grows the model's skeleton with the default branch limit [`DEFAULT_MAX_BRANCHES`].
pub fn build(params: &HondaParams) -> Result<Skeleton> {
    build_with_limit(params, DEFAULT_MAX_BRANCHES)
}

/// Grows the model's skeleton; a model that would make more than `max_branches` branches
/// returns [`Error::LimitExceeded`] at once, before building anything.
pub fn build_with_limit(params: &HondaParams, max_branches: usize) -> Result<Skeleton> {
    grow(params, max_branches, None)
}

/// A branch still to grow: where it starts and how, and what it hangs from.
struct Apex {
    frame: Frame,
    length: f64,
    width: f64,
    parent: u32,
    /// Heading of the parent branch.
    parent_heading: glam::DVec3,
    step: u32,
}

/// A child's turn and roll (cosine, sine), length ratio and width factor.
type ChildRule = ((f64, f64), (f64, f64), f64, f64);

/// The two children's rules: the branching and divergence angles, r1 and r2, and the
/// pipe model's width factors q^e and (1 - q)^e.
fn child_rules(p: &HondaParams) -> [ChildRule; 2] {
    let (q, e) = (p.q as f64, p.e as f64);
    [
        (
            cos_sin_deg(p.alpha1 as f64),
            cos_sin_deg(p.phi1 as f64),
            p.r1 as f64,
            libm::pow(q, e),
        ),
        (
            cos_sin_deg(p.alpha2 as f64),
            cos_sin_deg(p.phi2 as f64),
            p.r2 as f64,
            libm::pow(1.0 - q, e),
        ),
    ]
}

/// Pushes the two children of the branch `index` grown from `apex` (its end frame
/// `frame`), each rule jittered by the variation when there is one; the second first, so
/// that the first child's subtree is walked first.
fn push_children(
    stack: &mut Vec<Apex>,
    apex: &Apex,
    frame: Frame,
    index: u32,
    p: &HondaParams,
    rules: &[ChildRule; 2],
    mut rng: Option<&mut (crate::rng::Rng, Variation)>,
) {
    for i in [1, 0] {
        let (mut turn, mut roll, mut ratio, mut width_factor) = rules[i];
        if let Some((rng, v)) = rng.as_deref_mut() {
            let mut jitter = |amount: f32| (rng.next_f64() * 2.0 - 1.0) * amount as f64;
            let (alpha, phi) = if i == 0 {
                (p.alpha1, p.phi1)
            } else {
                (p.alpha2, p.phi2)
            };
            turn = cos_sin_deg(alpha as f64 + jitter(v.branching));
            roll = cos_sin_deg(phi as f64 + jitter(v.divergence));
            ratio *= 1.0 + jitter(v.length);
            width_factor *= 1.0 + jitter(v.width);
        }
        let mut child = frame;
        child.turn(turn);
        child.roll(roll);
        stack.push(Apex {
            frame: child,
            length: apex.length * ratio,
            width: apex.width * width_factor,
            parent: index,
            parent_heading: frame.heading,
            step: apex.step + 1,
        });
    }
}

fn grow(
    params: &HondaParams,
    max_branches: usize,
    variation: Option<&Variation>,
) -> Result<Skeleton> {
    params.validate()?;
    let mut rng = variation
        .filter(|v| v.seed != 0)
        .map(|v| (crate::rng::Rng::new(v.seed), *v));
    let limit = max_branches as u64;
    let (count, over) = params.count_until(limit);
    if let Some(step) = over {
        return Err(Error::LimitExceeded {
            limit_name: "max_branches",
            what: "branches",
            limit,
            requested: count,
            step: Some(step),
        });
    }
    let p = params;
    let min = p.min_length as f64;
    let rules = child_rules(p);
    let n = count as usize;
    let (mut branches, mut cos_to_parent, mut ups): (Vec<Branch>, Vec<f64>, Vec<[f32; 3]>) =
        (Vec::new(), Vec::new(), Vec::new());
    crate::limits::try_room(
        &mut [&mut branches, &mut cos_to_parent, &mut ups],
        n,
        true,
        || format!("the tree's {n} branches"),
    )?;
    let mut stack = Vec::with_capacity(p.steps as usize + 1);
    stack.push(Apex {
        frame: Frame::default(),
        length: p.trunk_length as f64,
        width: p.trunk_width as f64,
        parent: NO_PARENT,
        parent_heading: glam::DVec3::Y,
        step: 1,
    });
    while let Some(apex) = stack.pop() {
        if apex.step > p.steps || apex.length < min {
            continue;
        }
        if branches.len() >= max_branches {
            // Unreachable unless rounding made the count disagree with the walk.
            return Err(Error::LimitExceeded {
                limit_name: "max_branches",
                what: "branches",
                limit,
                requested: branches.len() as u64 + 1,
                step: Some(apex.step),
            });
        }
        let index = branches.len() as u32;
        let mut frame = apex.frame;
        let start = frame.position;
        let end = frame.forward(apex.length);
        let radius = (apex.width * 0.5) as f32;
        branches.push(Branch {
            start: start.as_vec3().to_array(),
            end: end.as_vec3().to_array(),
            start_radius: radius,
            end_radius: radius,
            parent: apex.parent,
            birth: apex.step,
            order: 0,
            flags: 0,
        });
        cos_to_parent.push(frame.heading.dot(apex.parent_heading));
        ups.push(frame.up.as_vec3().to_array());
        if apex.step < p.steps {
            push_children(&mut stack, &apex, frame, index, p, &rules, rng.as_mut());
        }
    }

    assign_axis_orders(&mut branches, &cos_to_parent);
    let skeleton = SkeletonParts {
        branches,
        ups,
        ..Default::default()
    }
    .build()
    .map_err(|_| {
        Error::invalid(
            "trunk_length",
            "the tree's coordinates overflow f32; reduce trunk_length, r1 or r2",
        )
    })?;
    Ok(skeleton)
}
