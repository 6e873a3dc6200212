//! A plan brought up to date after an edit of one branch's curve, in time proportional to
//! its subtree.

use super::*;

impl MeshPlan {
    /// Brings the plan up to date after [`Skeleton::set_curve`] edited branch `i` of
    /// `skeleton` (the tree the plan was made for): recomputes the directions, joints and
    /// ring frames of the branch, its subtree and its parent, in time proportional to the
    /// subtree. Returns the branches whose vertices changed (in increasing order), for
    /// [`MeshPlan::rewrite`].
    ///
    /// Branch ranges stay as they were; an edit that would change them (a joint that
    /// stops or starts being mitred, or any edit while LOD or culling is on, whose sides
    /// depend on every radius) is [`Error::InvalidArgument`], and the mesh must be sized
    /// and written again (make a new plan).
    pub fn update_after_edit(&mut self, skeleton: &Skeleton, i: usize) -> Result<Vec<u32>> {
        self.check_skeleton(skeleton)?;
        let n = skeleton.len();
        if i >= n {
            return Err(Error::invalid(
                "branch",
                format!("{i}; the tree has {n} branches"),
            ));
        }
        let o = self.options;
        if o.min_radial_segments != 0 || o.cull_radius != 0.0 {
            return Err(Error::invalid(
                "options",
                "an edit cannot be rewritten in place while LOD (min_radial_segments) or \
                 cull_radius is on: write the mesh again",
            ));
        }
        let branches = skeleton.branches();
        let adjacency = skeleton.adjacency();
        // The subtree of i, then its parent (its end ring meets i), in index order.
        let mut affected = vec![i as u32];
        let mut k = 0;
        while k < affected.len() {
            let b = affected[k] as usize;
            affected.extend_from_slice(adjacency.children(b));
            k += 1;
        }
        if branches[i].parent != NO_PARENT {
            affected.push(branches[i].parent);
        }
        affected.sort_unstable();
        let plan = &mut self.plan;
        let inner = plan.inner;
        for &b in &affected {
            let b = b as usize;
            if inner > 0 {
                let (c, d) = (skeleton.curve(b), direction(&branches[b]));
                plan.t0[b] = c.tangent(0.0).try_normalize().unwrap_or(d);
                plan.t1[b] = c.tangent(1.0).try_normalize().unwrap_or(d);
            }
        }
        // The joints must stay as they were.
        for &b in &affected {
            let b = b as usize;
            if plan.segs[b] == 0 || branches[b].parent == NO_PARENT {
                continue;
            }
            let shares = plan.own_flags(branches, &o, b) & SHARES_START != 0;
            if shares != (plan.flags[b] & SHARES_START != 0) {
                return Err(Error::invalid(
                    "curve",
                    format!(
                        "the edit changes whether branch {b} shares its parent's ring (a bend \
                         past 90°): write the mesh again"
                    ),
                ));
            }
        }
        let inv_ts = 1.0 / o.texture_scale as f64;
        for &b in &affected {
            if plan.segs[b as usize] != 0 {
                let (b, sweep) = (b as usize, inner > 0);
                let own_ring = plan.flags[b] & SHARES_START == 0;
                let d = if sweep {
                    plan.t0[b]
                } else {
                    direction(&branches[b])
                };
                frames(
                    skeleton,
                    plan,
                    &mut self.layout,
                    b,
                    (d, None),
                    own_ring,
                    inv_ts,
                );
                if !sweep {
                    set_v_end(
                        &mut self.layout.v_end,
                        &branches[b],
                        b,
                        length(&branches[b]),
                        inv_ts,
                    );
                }
            }
        }
        let v_scale = v_scale(skeleton, &o, &self.layout);
        if v_scale != self.v_scale {
            // Every compact vertex's v is stored over the scale: all of them change.
            self.v_scale = v_scale;
            return Ok((0..n as u32).collect());
        }
        Ok(affected)
    }
}
