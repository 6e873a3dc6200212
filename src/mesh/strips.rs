//! Every surface is made of triangle strips; this module turns strips into the index
//! layout of each topology and winding, and counts exactly what that takes.

use super::rings::Slot;
use super::{RESTART_INDEX, Topology};

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

impl StripRules {
    /// Indices a tube between two rings of `ring` vertices takes ([`StripWriter::tube`]);
    /// `fresh`: its bottom ring is its own, which a strip writes as two strips.
    #[inline]
    pub(crate) fn tube_count(self, ring: usize, first: bool, fresh: bool) -> usize {
        if fresh && self.topology != Topology::TriangleList {
            self.count(4, first) + self.count(2 * ring - 2, false)
        } else {
            self.count(2 * ring, first)
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
    /// The body of a tube between rings of `tube_ring` vertices (see [`Template`]).
    tube: Template,
    /// A strip's tube with a bottom ring of its own, as two strips: the first quad, then
    /// the rest ([`tube_fresh`](Self::tube_fresh)), one after the other.
    fresh: Template,
    tube_ring: u32,
}

/// Indices of a tube between a top and a bottom ring, relative to them: index k is
/// `top + body[k] + (bottom − top) & mask[k]` (the mask all ones for the bottom ring), so
/// a tube's indices are one add and one masked add each, with no branch. Offsets and masks
/// are kept apart so the loop runs in vector lanes.
#[derive(Default)]
struct Template {
    body: Vec<u32>,
    mask: Vec<u32>,
}

/// Ring offset of the top ring and of the bottom ring in a [`Template`]'s order.
const T: u32 = 0;
const B: u32 = u32::MAX;

impl Template {
    fn of(order: impl IntoIterator<Item = (u32, u32)>) -> Self {
        let (body, mask) = order.into_iter().unzip();
        Template { body, mask }
    }

    /// Writes indices `range` of the template for rings `top` and `bottom` at `out`'s
    /// start, returning the last one (`last` when the range is empty).
    #[inline(always)]
    fn put<I: Slot<u32>>(
        &self,
        range: std::ops::Range<usize>,
        top: u32,
        bottom: u32,
        out: &mut [I],
        last: u32,
    ) -> u32 {
        let (body, mask) = (&self.body[range.clone()], &self.mask[range]);
        let diff = bottom.wrapping_sub(top);
        let index = |offset: u32, mask: u32| top.wrapping_add(offset).wrapping_add(diff & mask);
        for ((slot, &offset), &mask) in out[..body.len()].iter_mut().zip(body).zip(mask) {
            slot.put(index(offset, mask));
        }
        match (body.last(), mask.last()) {
            (Some(&offset), Some(&mask)) => index(offset, mask),
            _ => last,
        }
    }
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
            tube: Template::default(),
            fresh: Template::default(),
            tube_ring: 0,
        }
    }

    /// Fills the tube template for rings of `ring` vertices (t: top ring, b: bottom ring).
    ///
    /// Strips: `b_j, t_j` for j from `ring − 1` down to 0, for a bottom ring the last tube
    /// made (the parent's end ring, or the previous ring of a sweep): the same triangles
    /// and winding as `t_j, b_j` upwards, reading the bottom ring from its newest vertex.
    /// A tube with a bottom ring of its own is written by [`tube_fresh`](Self::tube_fresh).
    ///
    /// Lists: one order for both, written so that with a FIFO vertex cache of 16 entries
    /// every vertex is made once along an axis (an average cache miss ratio of vertices /
    /// triangles, the least there is). Quad j holds B_j = (b_j, b_{j+1}, t_{j+1}) and
    /// A_j = (b_j, t_{j+1}, t_j), each written from the corner that reads the bottom ring
    /// first. The order B_m, B_{m-1}, A_m, A_{m-1}, then B_j, A_j for j from m − 2 down
    /// to 0 (m = ring − 2) makes the top ring from t_{m+1} down to t_0 with at most six
    /// bottom vertices made among them, and is done with each bottom vertex by the time
    /// the cache lets it go: a shared bottom ring is read from the cache, and this tube's
    /// top ring is still there for the next tube.
    fn tube_template(&mut self, ring: u32) {
        self.tube_ring = ring;
        if self.rules.topology != Topology::TriangleList {
            self.tube = Template::of((0..ring).rev().flat_map(|j| [(j, B), (j, T)]));
            let first_quad = [(0, T), (0, B), (1, T), (1, B)];
            let rest = (1..ring).rev().flat_map(|j| [(j, B), (j, T)]);
            self.fresh = Template::of(first_quad.into_iter().chain(rest));
            return;
        }
        let m = ring - 2;
        let cw = self.rules.clockwise;
        let quad_b = |j: u32| {
            let (b0, b1, t1) = ((j, B), (j + 1, B), (j + 1, T));
            if cw { [b1, b0, t1] } else { [b0, b1, t1] }
        };
        let quad_a = |j: u32| {
            let (b0, t0, t1) = ((j, B), (j, T), (j + 1, T));
            if cw { [b0, t0, t1] } else { [b0, t1, t0] }
        };
        let mut order = vec![quad_b(m), quad_b(m - 1), quad_a(m), quad_a(m - 1)];
        for j in (0..m - 1).rev() {
            order.push(quad_b(j));
            order.push(quad_a(j));
        }
        self.tube = Template::of(order.into_iter().flatten());
    }

    #[inline(always)]
    fn push(&mut self, v: u32) {
        self.out[self.pos].put(v);
        self.pos += 1;
        self.last = v;
    }

    /// Writes a tube between two rings of `ring` vertices in the order of
    /// [`tube_template`](Self::tube_template); `fresh`: the bottom ring is the tube's own
    /// (not the ring the last tube made), which a strip writes as two strips (see
    /// [`tube_fresh`](Self::tube_fresh)). A strip gives the same indices as
    /// [`strip`](Self::strip) of that order, without building it.
    #[inline(always)]
    pub(crate) fn tube(&mut self, top: u32, bottom: u32, ring: u32, fresh: bool) {
        if ring != self.tube_ring {
            self.tube_template(ring);
        }
        if self.rules.topology == Topology::TriangleList {
            self.first = false;
            return self.tube_body(top, bottom);
        }
        if fresh {
            return self.tube_fresh(top, bottom, ring);
        }
        self.open_strip(bottom + ring - 1);
        self.tube_body(top, bottom);
        self.close_strip(2 * ring as usize);
    }

    /// A tube with a bottom ring of its own, as two strips: the first quad upwards
    /// (`t_0, b_0, t_1, b_1`), then the rest downwards from the seam's far end
    /// (`b_j, t_j` for j from `ring − 1` down to 1). A single zig-zag would make two of the
    /// top ring's vertices among its first, and a cache of 16 would let them go before the
    /// next tube reads them; so split, the top ring is made late and in the order the next
    /// tube reads it.
    #[inline(always)]
    fn tube_fresh(&mut self, top: u32, bottom: u32, ring: u32) {
        let n = self.fresh.body.len();
        for (range, opening) in [(0..4, top), (4..n, bottom + ring - 1)] {
            let len = range.len();
            self.open_strip(opening);
            let out = &mut self.out[self.pos..self.pos + len];
            self.last = self.fresh.put(range, top, bottom, out, self.last);
            self.pos += len;
            self.close_strip(len);
        }
    }

    /// Writes the body of a tube from the template made for its ring.
    #[inline(always)]
    fn tube_body(&mut self, top: u32, bottom: u32) {
        let n = self.tube.body.len();
        let out = &mut self.out[self.pos..self.pos + n];
        self.last = self.tube.put(0..n, top, bottom, out, self.last);
        self.pos += n;
    }

    /// Writes one strip (front faces counter-clockwise in OpenGL's strip order).
    pub(crate) fn strip(&mut self, s: &[u32]) {
        debug_assert!(s.len() >= 3);
        match self.rules.topology {
            Topology::TriangleList => {
                self.first = false;
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
            _ => {
                self.open_strip(s[0]);
                for &v in s {
                    self.push(v);
                }
                self.close_strip(s.len());
            }
        }
    }

    /// Opens a strip that starts at `opening`: a restart index or a degenerate join after
    /// the strip before it, and the opening index doubled for clockwise front faces.
    #[inline]
    fn open_strip(&mut self, opening: u32) {
        if !std::mem::replace(&mut self.first, false) {
            if self.rules.topology == Topology::TriangleStripRestart {
                self.push(RESTART_INDEX);
            } else {
                let last = self.last;
                self.push(last);
                self.push(opening);
            }
        }
        if self.rules.clockwise {
            self.push(opening);
        }
    }

    /// Closes a strip of `len` indices: one joined by degenerate triangles ends on an
    /// even count (with the doubled opening index), so the next keeps the winding.
    #[inline]
    fn close_strip(&mut self, len: usize) {
        if self.rules.topology == Topology::TriangleStripDegenerate
            && (len + self.rules.clockwise as usize) % 2 == 1
        {
            let last = self.last;
            self.push(last);
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
    fn a_fresh_tube_is_its_two_strips() {
        for topology in Topology::ALL {
            for clockwise in [false, true] {
                let rules = StripRules {
                    topology,
                    clockwise,
                };
                for ring in [3u32, 4, 9, 65] {
                    let (top, bottom) = (1000, 7);
                    // What a fresh tube is: the first quad upwards, then the rest downwards
                    // from the seam's far end, after a tube that is not fresh.
                    let first_quad = [top, bottom, top + 1, bottom + 1];
                    let rest: Vec<u32> = (1..ring)
                        .rev()
                        .flat_map(|j| [bottom + j, top + j])
                        .collect();
                    let n = rules.tube_count(ring as usize, true, false)
                        + rules.tube_count(ring as usize, false, true);
                    let (mut got, mut want) = (vec![0u32; n], vec![0u32; n]);
                    let mut w = StripWriter::new(&mut got, rules, true);
                    w.tube(top - 500, bottom, ring, false);
                    w.tube(top, bottom, ring, true);
                    assert_eq!(w.pos, n, "{rules:?}, ring {ring}: counted");
                    let mut r = StripWriter::new(&mut want, rules, true);
                    r.tube(top - 500, bottom, ring, false);
                    if topology == Topology::TriangleList {
                        r.tube(top, bottom, ring, false);
                    } else {
                        r.strip(&first_quad);
                        r.strip(&rest);
                    }
                    assert_eq!(got, want, "{rules:?}, ring {ring}");
                }
            }
        }
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
