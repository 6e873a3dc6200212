//! A tree's snapshot as a skeleton.

use super::{BUD, Tree, branch_turn, is_child, perpendicular, pipe};
use crate::skeleton::{Branch, LeafSite, NO_PARENT, Skeleton, SkeletonParts};

impl Tree {
    /// The tree as a skeleton: one branch per internode, radii from the pipe model
    /// (start: this internode's; end: its continuation's, or the tip radius), a leaf site
    /// at every living bud.
    pub(crate) fn skeleton(&self) -> Skeleton {
        let inv = 1.0 / self.species.pipe_exponent;
        let radius = |rn: f32| libm::powf(rn, inv);
        let tip = self.species.tip_radius;
        let branch = branch_turn(self.species.branch_angle);
        let n = &self.nodes;
        // Radii as the next basipetal pass will make them.
        let mut stale_rn = Vec::new();
        let rn: &[f32] = if self.radii_stale {
            stale_rn.extend_from_slice(&n.rn);
            let tip_rn = libm::powf(tip, self.species.pipe_exponent);
            for i in (0..n.len()).rev() {
                pipe(&n.kids, &mut stale_rn, i, tip_rn);
            }
            &stale_rn
        } else {
            &n.rn
        };
        // Each stored internode's branch index (`NO_PARENT` for the shed ones still
        // stored: those no parent lists).
        let mut index = Vec::new();
        if self.dead > 0 {
            let mut k = 0;
            index.extend((0..n.len()).map(|i| {
                if n.lives(i) {
                    k += 1;
                    k - 1
                } else {
                    NO_PARENT
                }
            }));
        }
        let at = |i: usize| index.get(i).copied().unwrap_or(i as u32);
        let mut parts = SkeletonParts {
            branches: Vec::with_capacity(self.len()),
            ..Default::default()
        };
        for i in 0..n.len() {
            if at(i) == NO_PARENT {
                continue;
            }
            let r = radius(rn[i]);
            let [m, l] = n.kids[i];
            let end_radius = if is_child(m) {
                radius(rn[m as usize])
            } else {
                tip.min(r)
            };
            parts.branches.push(Branch {
                start: self.start(i).to_array(),
                end: n.end[i].to_array(),
                start_radius: r,
                end_radius,
                parent: match n.parent[i] {
                    NO_PARENT => NO_PARENT,
                    p => at(p as usize),
                },
                birth: n.birth[i],
                order: n.order[i],
                flags: 0,
            });
            for (k, slot) in [m, l].into_iter().enumerate() {
                if slot == BUD {
                    let heading = if k == 0 {
                        n.dir[i]
                    } else {
                        self.lateral_dir(i, branch)
                    };
                    parts.leaves.push(LeafSite {
                        position: n.end[i].to_array(),
                        heading: heading.to_array(),
                        up: perpendicular(heading).to_array(),
                        branch: at(i),
                        birth: n.birth[i],
                    });
                }
            }
        }
        Skeleton::from_trusted(parts)
    }
}
