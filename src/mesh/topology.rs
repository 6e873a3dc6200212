//! Decoding index buffers of any [`Topology`] back into triangles.

use super::{RESTART_INDEX, Topology};

/// Iterator over the triangles of an index buffer, as index triples in front-face order.
///
/// Strips follow OpenGL's rule: triangle k of a strip is `(i[k], i[k+1], i[k+2])` for even
/// k and `(i[k+1], i[k], i[k+2])` for odd k. [`RESTART_INDEX`] starts a new strip, and
/// triangles that repeat an index (the degenerate joins) are skipped.
#[derive(Clone, Debug)]
pub struct Triangles<'a> {
    indices: &'a [u32],
    topology: Topology,
    pos: usize,
    /// Strips only: the two previous indices and how many indices the strip has so far.
    prev: [u32; 2],
    run: usize,
}

impl<'a> Triangles<'a> {
    /// Decodes `indices` laid out as `topology`.
    pub fn new(indices: &'a [u32], topology: Topology) -> Self {
        Triangles {
            indices,
            topology,
            pos: 0,
            prev: [0; 2],
            run: 0,
        }
    }
}

impl Iterator for Triangles<'_> {
    type Item = [u32; 3];

    fn next(&mut self) -> Option<[u32; 3]> {
        if self.topology == Topology::TriangleList {
            let t = self.indices.get(self.pos..self.pos + 3)?;
            self.pos += 3;
            return Some([t[0], t[1], t[2]]);
        }
        while let Some(&x) = self.indices.get(self.pos) {
            self.pos += 1;
            if x == RESTART_INDEX && self.topology == Topology::TriangleStripRestart {
                self.run = 0;
                continue;
            }
            let [a, b] = self.prev;
            self.prev = [b, x];
            self.run += 1;
            if self.run < 3 {
                continue;
            }
            if a == b || b == x || a == x {
                continue;
            }
            // The k-th triangle of the strip, k = run - 3.
            return Some(if (self.run - 3) % 2 == 0 {
                [a, b, x]
            } else {
                [b, a, x]
            });
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strip_alternates_winding() {
        let t: Vec<_> = Triangles::new(&[0, 1, 2, 3], Topology::TriangleStripRestart).collect();
        assert_eq!(t, vec![[0, 1, 2], [2, 1, 3]]);
    }

    #[test]
    fn restart_starts_a_new_strip() {
        let idx = [0, 1, 2, RESTART_INDEX, 3, 4, 5, 6];
        let t: Vec<_> = Triangles::new(&idx, Topology::TriangleStripRestart).collect();
        assert_eq!(t, vec![[0, 1, 2], [3, 4, 5], [5, 4, 6]]);
    }

    #[test]
    fn degenerate_joins_are_skipped_and_keep_parity() {
        let idx = [0, 1, 2, 3, 3, 4, 4, 5, 6, 7];
        let t: Vec<_> = Triangles::new(&idx, Topology::TriangleStripDegenerate).collect();
        assert_eq!(t, vec![[0, 1, 2], [2, 1, 3], [4, 5, 6], [6, 5, 7]]);
    }

    #[test]
    fn list_is_read_in_threes() {
        let t: Vec<_> = Triangles::new(&[0, 1, 2, 2, 1, 3, 9], Topology::TriangleList).collect();
        assert_eq!(t, vec![[0, 1, 2], [2, 1, 3]]);
    }
}
