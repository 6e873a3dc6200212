//! Every surface is made of triangle strips; this module turns strips into the index
//! layout of each topology and winding, and counts exactly what that takes.

use super::{RESTART_INDEX, Topology};

/// A place the writers can store a value into: an initialised element or an uninitialised
/// slot (a mapped GPU buffer).
pub(crate) trait Slot<T> {
    fn put(&mut self, value: T);
}

impl<T> Slot<T> for T {
    #[inline(always)]
    fn put(&mut self, value: T) {
        *self = value;
    }
}

impl<T> Slot<T> for std::mem::MaybeUninit<T> {
    #[inline(always)]
    fn put(&mut self, value: T) {
        self.write(value);
    }
}

/// Topology and winding: how a strip becomes indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct StripRules {
    pub(crate) topology: Topology,
    /// Clockwise front faces: each strip is written with its first index doubled (one
    /// degenerate triangle shifts the parity), a list with each triangle's last two swapped.
    pub(crate) clockwise: bool,
}

impl StripRules {
    /// Indices a strip of `len` (≥ 3) indices takes; `first`: it opens the buffer.
    #[inline]
    pub(crate) fn count(self, len: usize, first: bool) -> usize {
        let cw = self.clockwise as usize;
        match self.topology {
            Topology::TriangleList => 3 * (len - 2),
            Topology::TriangleStripRestart => len + cw + usize::from(!first),
            Topology::TriangleStripDegenerate => {
                let l = len + cw;
                l + (l & 1) + if first { 0 } else { 2 }
            }
        }
    }
}

/// Writes strips into an index buffer from a start position.
pub(crate) struct StripWriter<'a, I: Slot<u32>> {
    pub(crate) out: &'a mut [I],
    pub(crate) pos: usize,
    pub(crate) rules: StripRules,
    /// Whether the next strip opens the buffer.
    pub(crate) first: bool,
    /// The last index written (for degenerate joins).
    pub(crate) last: u32,
    /// The body of a tube between rings of `tube_ring` vertices: index k is
    /// `top + offset + (bottom − top) & mask` (mask all ones for the bottom ring), so a
    /// tube's indices are one add and one masked add each, with no branch.
    tube_body: Vec<(u32, u32)>,
    tube_ring: u32,
}

impl<'a, I: Slot<u32>> StripWriter<'a, I> {
    /// A writer at the start of `out` (`first`: no strip of the buffer comes before).
    pub(crate) fn new(out: &'a mut [I], rules: StripRules, first: bool) -> Self {
        StripWriter {
            out,
            pos: 0,
            rules,
            first,
            last: 0,
            tube_body: Vec::new(),
            tube_ring: 0,
        }
    }

    /// Fills `tube_body` for rings of `ring` vertices.
    fn tube_template(&mut self, ring: u32) {
        self.tube_ring = ring;
        self.tube_body.clear();
        const T: u32 = 0;
        const B: u32 = u32::MAX;
        if self.rules.topology == Topology::TriangleList {
            for j in 0..ring - 1 {
                let (t0, b0, t1, b1) = ((j, T), (j, B), (j + 1, T), (j + 1, B));
                self.tube_body.extend(if self.rules.clockwise {
                    [t0, t1, b0, t1, b1, b0]
                } else {
                    [t0, b0, t1, t1, b0, b1]
                });
            }
        } else {
            for j in 0..ring {
                self.tube_body.extend([(j, T), (j, B)]);
            }
        }
    }

    #[inline(always)]
    fn push(&mut self, v: u32) {
        self.out[self.pos].put(v);
        self.pos += 1;
        self.last = v;
    }

    /// Writes the strip of a tube between two rings of `ring` vertices, `top_j, bottom_j`
    /// for j in 0..ring: the same indices as [`strip`](Self::strip), without building it.
    #[inline]
    pub(crate) fn tube(&mut self, top: u32, bottom: u32, ring: u32) {
        let first = std::mem::replace(&mut self.first, false);
        let cw = self.rules.clockwise;
        match self.rules.topology {
            Topology::TriangleList => {
                self.tube_body(top, bottom, ring);
                self.last = if cw {
                    bottom + ring - 2
                } else {
                    bottom + ring - 1
                };
            }
            topology => {
                if !first {
                    if topology == Topology::TriangleStripRestart {
                        self.push(RESTART_INDEX);
                    } else {
                        let last = self.last;
                        self.push(last);
                        self.push(top);
                    }
                }
                if cw {
                    self.push(top);
                }
                self.tube_body(top, bottom, ring);
                self.last = bottom + ring - 1;
                if cw && topology == Topology::TriangleStripDegenerate {
                    let last = self.last;
                    self.push(last);
                }
            }
        }
    }

    /// Writes the body of a tube from the template for `ring`.
    #[inline]
    fn tube_body(&mut self, top: u32, bottom: u32, ring: u32) {
        if ring != self.tube_ring {
            self.tube_template(ring);
        }
        let n = self.tube_body.len();
        let diff = bottom.wrapping_sub(top);
        let out = &mut self.out[self.pos..self.pos + n];
        for (slot, &(offset, mask)) in out.iter_mut().zip(&self.tube_body) {
            slot.put(top.wrapping_add(offset).wrapping_add(diff & mask));
        }
        self.pos += n;
    }

    /// Writes one strip (front faces counter-clockwise in OpenGL's strip order).
    pub(crate) fn strip(&mut self, s: &[u32]) {
        debug_assert!(s.len() >= 3);
        let first = std::mem::replace(&mut self.first, false);
        match self.rules.topology {
            Topology::TriangleList => {
                for k in 0..s.len() - 2 {
                    let (a, b, c) = if k % 2 == 0 {
                        (s[k], s[k + 1], s[k + 2])
                    } else {
                        (s[k + 1], s[k], s[k + 2])
                    };
                    if self.rules.clockwise {
                        self.push(a);
                        self.push(c);
                        self.push(b);
                    } else {
                        self.push(a);
                        self.push(b);
                        self.push(c);
                    }
                }
            }
            Topology::TriangleStripRestart => {
                if !first {
                    self.push(RESTART_INDEX);
                }
                if self.rules.clockwise {
                    self.push(s[0]);
                }
                for &v in s {
                    self.push(v);
                }
            }
            Topology::TriangleStripDegenerate => {
                if !first {
                    let last = self.last;
                    self.push(last);
                    self.push(s[0]);
                }
                if self.rules.clockwise {
                    self.push(s[0]);
                }
                for &v in s {
                    self.push(v);
                }
                if (s.len() + self.rules.clockwise as usize) % 2 == 1 {
                    let last = self.last;
                    self.push(last);
                }
            }
        }
    }
}

/// Zig-zag order of a convex polygon's `n` corners: a strip that covers it.
pub(crate) fn zigzag(n: usize, mut corner: impl FnMut(usize) -> u32, out: &mut Vec<u32>) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Triangles;

    fn emit(topology: Topology, clockwise: bool, strips: &[&[u32]]) -> Vec<u32> {
        let rules = StripRules {
            topology,
            clockwise,
        };
        let total: usize = strips
            .iter()
            .enumerate()
            .map(|(i, s)| rules.count(s.len(), i == 0))
            .sum();
        let mut out = vec![0u32; total];
        let mut w = StripWriter::new(&mut out, rules, true);
        for s in strips {
            w.strip(s);
        }
        assert_eq!(w.pos, total, "count matches what is written");
        out
    }

    #[test]
    fn every_topology_and_winding_gives_the_same_triangles() {
        let strips: [&[u32]; 3] = [&[0, 1, 2, 3, 4], &[5, 6, 7], &[8, 9, 10, 11]];
        let want: Vec<[u32; 3]> = Triangles::new(
            &emit(Topology::TriangleList, false, &strips),
            Topology::TriangleList,
        )
        .collect();
        assert_eq!(want.len(), 3 + 1 + 2);
        for topology in Topology::ALL {
            let got: Vec<[u32; 3]> =
                Triangles::new(&emit(topology, false, &strips), topology).collect();
            assert_eq!(got, want, "{topology:?}");
            let cw: Vec<[u32; 3]> =
                Triangles::new(&emit(topology, true, &strips), topology).collect();
            let flipped: Vec<[u32; 3]> = want.iter().map(|&[a, b, c]| [a, c, b]).collect();
            let canon = |t: &[u32; 3]| {
                let k = (0..3).min_by_key(|&k| t[k]).unwrap();
                [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
            };
            assert_eq!(
                cw.iter().map(canon).collect::<Vec<_>>(),
                flipped.iter().map(canon).collect::<Vec<_>>(),
                "{topology:?} clockwise"
            );
        }
    }
}
