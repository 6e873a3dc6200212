//! Counts: each branch's sides and continuation, its vertices and indices, and the
//! mesh's size within its limits.

use super::*;

/// The mesh's size, within `max_vertices` and the u32 index range.
pub(super) fn check_size(nv: u64, ni: u64, o: &MeshOptions) -> Result<MeshSize> {
    if nv > o.max_vertices as u64 {
        return Err(Error::LimitExceeded {
            limit_name: "max_vertices",
            what: "mesh vertices",
            limit: o.max_vertices as u64,
            requested: nv,
            step: None,
        });
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
    Ok(MeshSize {
        vertices: nv as usize,
        indices: ni as usize,
    })
}

/// Each branch's sides (0: culled, with its subtree; in proportion to its radius when
/// `min_radial_segments` is set) and the kept branch that continues its axis (its first
/// kept child of the same order), once the tree's scaled extent is known to stay finite.
pub(super) fn sides_and_continuations(
    branches: &[Branch],
    o: &MeshOptions,
) -> Result<(Vec<u8>, Vec<u32>)> {
    let lod = o.min_radial_segments != 0;
    // LOD needs the largest radius before the first branch's sides.
    let r_max = if lod {
        branches
            .iter()
            .fold(0.0f32, |m, b| m.max(b.start_radius.max(b.end_radius)))
    } else {
        0.0
    };
    let max_seg = o.radial_segments;
    let n = branches.len();
    let (mut segs, mut cont) = (vec![0u8; n], vec![NO_PARENT; n]);
    let mut extent = 0.0f64;
    for (i, b) in branches.iter().enumerate() {
        let r = b.start_radius.max(b.end_radius);
        let far = Vec3::from(b.start)
            .abs()
            .max(Vec3::from(b.end).abs())
            .max_element();
        extent = extent.max(far as f64 + 2.0 * r as f64);
        let p = b.parent as usize;
        let parent_kept = b.parent == NO_PARENT || segs[p] != 0;
        if !parent_kept || r < o.cull_radius {
            continue;
        }
        let sides = if !lod || r_max <= 0.0 {
            max_seg
        } else {
            ((max_seg as f32 * r / r_max).ceil() as u32).clamp(o.min_radial_segments, max_seg)
        };
        // Even texels mirror u on thin branches (0 → 1 → 0 around): an even count puts
        // the turn on a vertex, where an odd one would leave a side without texels.
        segs[i] = if o.even_texels {
            (sides + (sides & 1)).min(MAX_RADIAL_SEGMENTS)
        } else {
            sides
        } as u8;
        if b.parent != NO_PARENT && cont[p] == NO_PARENT && b.order == branches[p].order {
            cont[p] = i as u32;
        }
    }
    if extent * o.out().scale as f64 > f32::MAX as f64 / 4.0 {
        return Err(Error::invalid(
            "scale",
            format!(
                "{}; the tree reaches {:e} units, so positions would leave the f32 range",
                o.scale, extent
            ),
        ));
    }
    Ok((segs, cont))
}

impl Plan {
    /// Vertices and indices branch `i` owns with flags `f`; `first`: no strip has been
    /// written yet.
    #[inline]
    pub(super) fn counts(&self, i: usize, f: u8, tip: Tip, first: &mut bool) -> (usize, usize) {
        let s = self.segs[i] as usize;
        if s == 0 {
            return (0, 0);
        }
        let rules = self.rules;
        let ring = s + 1;
        let mut v = ring * (1 + self.inner) + if f & SHARES_START != 0 { 0 } else { ring };
        let mut idx = rules.tube_count(ring, *first, f & SHARES_START == 0);
        *first = false;
        idx += self.inner * rules.count(2 * ring, false);
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
}
