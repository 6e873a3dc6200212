//! Rings of vertices: the unit circle per side count, the output conventions, and a ring as
//! an affine map of the unit circle evaluated in 4-lane vectors.

use super::Vertex;
use glam::{Vec3, Vec3A, Vec4};

/// Unit circle per side count: (cos, sin, u) for j in 0..=segments, the seam repeated.
/// It reads as that slice; beside it are the same values as the ring writers load them.
/// Public in a private module, as [`Slot`] names it.
#[derive(Clone, Debug, Default)]
pub struct Circle {
    points: Vec<(f32, f32, f32)>,
    /// Per point, cos, sin and u each splatted over four lanes.
    splats: Vec<[Vec4; 3]>,
    /// Per four points, their cosines and sines in four lanes; lanes past the ring's end
    /// take (1, 0), a point of the circle.
    pub(crate) quads: Vec<[Vec4; 2]>,
    /// Per four points, their u in four lanes (0 past the ring's end).
    pub(crate) u_quads: Vec<Vec4>,
    /// Per four points, their u as the compact format's unorm16, one a lane.
    pub(crate) u_unorm: Vec<[u32; 4]>,
    /// u runs 0 → 1 → 0 around the circle (a mirrored repeat, see [`circle_mirrored`])
    /// instead of 0 → 1: the seam's u is point 0's.
    pub(crate) mirrored: bool,
}

impl Circle {
    /// How many of `n` vertices of a ring on this circle are worked out (the rest is the
    /// seam), and whether the last is the seam: a ring of every point repeats point 0 at
    /// its end with u = 1, which [`Affine::seam_of`] makes from vertex 0.
    #[inline(always)]
    pub(crate) fn body(&self, n: usize) -> (usize, bool) {
        if n == self.points.len() && n > 1 {
            (n - 1, true)
        } else {
            (n, false)
        }
    }
}

impl std::ops::Deref for Circle {
    type Target = [(f32, f32, f32)];
    fn deref(&self) -> &Self::Target {
        &self.points
    }
}

pub(crate) fn circle(segments: usize) -> Circle {
    circle_with(segments, false)
}

/// The unit circle with u running 0 → 1 at the half-turn → 0 again (1 − |2j/n − 1|): a
/// texture repeated mirrored, so u meets itself at the seam whatever it is multiplied by
/// (a branch thinner than the texture's tile takes a fraction of it, twice).
pub(crate) fn circle_mirrored(segments: usize) -> Circle {
    circle_with(segments, true)
}

fn circle_with(segments: usize, mirrored: bool) -> Circle {
    let step = std::f64::consts::TAU / segments as f64;
    let points: Vec<(f32, f32, f32)> = (0..=segments)
        .map(|j| {
            let (s, c) = libm::sincos((j % segments) as f64 * step);
            let t = j as f32 / segments as f32;
            let u = if mirrored {
                1.0 - (2.0 * t - 1.0).abs()
            } else {
                t
            };
            (c as f32, s as f32, u)
        })
        .collect();
    let splats = points
        .iter()
        .map(|&(c, s, u)| [Vec4::splat(c), Vec4::splat(s), Vec4::splat(u)])
        .collect();
    let quads = points
        .chunks(4)
        .map(|chunk| {
            let (mut c, mut s) = ([1.0f32; 4], [0.0f32; 4]);
            for (k, &(ck, sk, _)) in chunk.iter().enumerate() {
                (c[k], s[k]) = (ck, sk);
            }
            [Vec4::from_array(c), Vec4::from_array(s)]
        })
        .collect();
    let u_quads: Vec<Vec4> = points
        .chunks(4)
        .map(|chunk| {
            let mut u = [0.0f32; 4];
            for (k, &(_, _, uk)) in chunk.iter().enumerate() {
                u[k] = uk;
            }
            Vec4::from_array(u)
        })
        .collect();
    let u_unorm = u_quads
        .iter()
        .map(|u| u.to_array().map(|u| super::quantize::unorm16(u) as u32))
        .collect();
    Circle {
        points,
        splats,
        quads,
        u_quads,
        u_unorm,
        mirrored,
    }
}

/// A signed permutation of the axes: output axis k is `sign[k]` times input axis
/// `from[k]`. Exact (a sign change or a copy), so the identity leaves every bit as it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct AxisMap {
    from: [usize; 3],
    sign: [f32; 3],
    /// `from` is [0, 1, 2] and every sign +1: `apply` returns its input.
    identity: bool,
}

impl AxisMap {
    pub(crate) const IDENTITY: AxisMap = AxisMap {
        from: [0, 1, 2],
        sign: [1.0, 1.0, 1.0],
        identity: true,
    };
    /// (x, y, z) → (x, −z, y): +90° about X.
    pub(crate) const Z_UP: AxisMap = AxisMap {
        from: [0, 2, 1],
        sign: [1.0, -1.0, 1.0],
        identity: false,
    };
    /// (x, y, z) → (−x, y, z).
    pub(crate) const UNITY: AxisMap = AxisMap {
        from: [0, 1, 2],
        sign: [-1.0, 1.0, 1.0],
        identity: false,
    };
    /// (x, y, z) → (x, z, y).
    pub(crate) const UNREAL: AxisMap = AxisMap {
        from: [0, 2, 1],
        sign: [1.0, 1.0, 1.0],
        identity: false,
    };

    #[inline(always)]
    pub(crate) fn apply(self, v: Vec3) -> [f32; 3] {
        let a = v.to_array();
        if self.identity {
            return a;
        }
        let at = |k: usize| {
            let x = a[self.from[k]];
            if self.sign[k] < 0.0 { -x } else { x }
        };
        [at(0), at(1), at(2)]
    }

    /// [`apply`](Self::apply) on a vector held in four lanes.
    #[inline(always)]
    pub(crate) fn apply_a(self, v: Vec3A) -> Vec3A {
        if self.identity {
            return v;
        }
        Vec3A::from_array(self.apply(Vec3::from(v)))
    }

    /// Whether the map is a mirror (determinant −1): an odd permutation or an odd number of
    /// sign changes, not both.
    pub(crate) fn mirrors(self) -> bool {
        let f = self.from;
        let inversions =
            usize::from(f[0] > f[1]) + usize::from(f[0] > f[2]) + usize::from(f[1] > f[2]);
        let negatives = self.sign.iter().filter(|s| **s < 0.0).count();
        (inversions + negatives) % 2 == 1
    }

    /// What the map does to an instance's rotation (turning a prefab's space into the
    /// tree's) in the output. A rotation M turns it (M·R: the prefab keeps its own space);
    /// a mirror conjugates it (M·R·M, again a rotation, of the mirrored axis by the
    /// opposite angle: the prefab is read in the mirrored space, as an engine imports it).
    pub(crate) fn rotation(self) -> impl Fn(glam::Quat) -> glam::Quat {
        let turn = (!self.mirrors()).then(|| {
            glam::Quat::from_mat3(&glam::Mat3::from_cols(
                glam::Vec3::from(self.apply(glam::Vec3::X)),
                glam::Vec3::from(self.apply(glam::Vec3::Y)),
                glam::Vec3::from(self.apply(glam::Vec3::Z)),
            ))
        });
        move |q| match turn {
            Some(t) => (t * q).normalize(),
            None => {
                let v = self.apply(glam::Vec3::new(q.x, q.y, q.z));
                glam::Quat::from_xyzw(-v[0], -v[1], -v[2], q.w)
            }
        }
    }
}

impl AxisMap {
    /// Rotation `q` of model space as a rotation of the mapped space: `M q M⁻¹`, for a
    /// prototype meshed with the same map (a twig) and placed by `q`.
    pub(crate) fn conjugate(self) -> impl Fn(glam::Quat) -> glam::Quat {
        let turn = (!self.mirrors()).then(|| {
            glam::Quat::from_mat3(&glam::Mat3::from_cols(
                glam::Vec3::from(self.apply(glam::Vec3::X)),
                glam::Vec3::from(self.apply(glam::Vec3::Y)),
                glam::Vec3::from(self.apply(glam::Vec3::Z)),
            ))
        });
        let mirrored = self.rotation();
        move |q| match turn {
            Some(t) => (t * q * t.inverse()).normalize(),
            None => mirrored(q),
        }
    }
}

/// Output conventions: uniform scale (with the engine's units), then the axis map.
#[derive(Clone, Copy)]
pub(crate) struct Out {
    pub(crate) scale: f32,
    pub(crate) map: AxisMap,
}

impl Out {
    #[inline(always)]
    pub(crate) fn dir(self, v: Vec3) -> [f32; 3] {
        self.map.apply(v)
    }
    #[inline(always)]
    pub(crate) fn pos(self, v: Vec3) -> [f32; 3] {
        self.dir(v * self.scale)
    }
    /// [`dir`](Self::dir) in four lanes (the same values: a copy or a sign change).
    #[inline(always)]
    pub(crate) fn dir_a(self, v: Vec3A) -> Vec3A {
        self.map.apply_a(v)
    }
    /// [`pos`](Self::pos) in four lanes (the same values).
    #[inline(always)]
    pub(crate) fn pos_a(self, v: Vec3A) -> Vec3A {
        self.dir_a(v * self.scale)
    }
}

/// `x` as f32, clamped to the finite range.
#[inline]
pub(crate) fn to_f32(x: f64) -> f32 {
    x.clamp(-(f32::MAX as f64), f32::MAX as f64) as f32
}

/// A place the writers can store a value into: an initialised element or an uninitialised
/// slot (a mapped GPU buffer). Public in a private module: [`VertexSlot`](super::VertexSlot) names it, no user can.
pub trait Slot<T> {
    fn put(&mut self, value: T);

    /// Writes a ring of vertices affine in the unit circle (`normalized`: with unit
    /// normals, as [`Affine::put_normalized`]) its
    /// own way and returns true, or returns false to have it written vertex by vertex. A
    /// format that encodes (compact vertices) writes four at a time.
    #[inline(always)]
    fn put_affine(_out: &mut [Self], _ring: &Affine, _table: &Circle, _normalized: bool) -> bool
    where
        Self: Sized,
    {
        false
    }
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

/// A ring of vertices affine in the unit circle: the vertex at (cos, sin) = (c, s) with
/// texture coordinate u is `a + c·b + s·d + u·e`, each term the 8 floats of a [`Vertex`]
/// (position, normal, uv) held in two 4-lane vectors. Cones, caps and the mitred ring's
/// positions are all of this form, so a vertex is a few vector multiply-adds and two
/// 16-byte stores.
#[derive(Clone, Copy)]
pub struct Affine {
    a: [Vec4; 2],
    b: [Vec4; 2],
    d: [Vec4; 2],
    e: [Vec4; 2],
}

impl Affine {
    /// The terms from a center and radial directions, normals and uv.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn new(
        center: Vec3A,
        radius_p: Vec3A,
        radius_q: Vec3A,
        normal: Vec3A,
        normal_p: Vec3A,
        normal_q: Vec3A,
        uv: [f32; 2],
        uv_p: [f32; 2],
        uv_q: [f32; 2],
        uv_u: [f32; 2],
    ) -> Self {
        let pack =
            |pos: Vec3A, n: Vec3A, t: [f32; 2]| [pos.extend(n.x), Vec4::new(n.y, n.z, t[0], t[1])];
        Affine {
            a: pack(center, normal, uv),
            b: pack(radius_p, normal_p, uv_p),
            d: pack(radius_q, normal_q, uv_q),
            e: pack(Vec3A::ZERO, Vec3A::ZERO, uv_u),
        }
    }

    #[inline(always)]
    fn at(&self, [c, s, u]: &[Vec4; 3]) -> [Vec4; 2] {
        [
            self.a[0] + self.b[0] * c + self.d[0] * s,
            self.a[1] + self.b[1] * c + self.d[1] * s + self.e[1] * u,
        ]
    }

    /// Writes the ring: one vertex per entry of `table`.
    #[inline(always)]
    pub(crate) fn put<V: Slot<Vertex>>(&self, out: &mut [V], table: &Circle) {
        if V::put_affine(out, self, table, false) {
            return;
        }
        for (slot, splat) in out.iter_mut().zip(&table.splats) {
            slot.put(vertex(self.at(splat)));
        }
    }

    /// The seam's vertex (the circle's point 0 again, with u = 1) from vertex 0's lanes as
    /// written: u and v gain e's terms, the rest is the same. Bit for bit what [`at`]
    /// gives for the seam: `x + e·0` is x (or +0 for −0), and adding e after it gives
    /// `x + e`; the normal's lanes of e are zero, so a normalised ring's scale does not
    /// change this.
    ///
    /// [`at`]: Self::at
    #[inline(always)]
    pub(crate) fn seam_of(&self, [lo, hi]: [Vec4; 2]) -> [Vec4; 2] {
        let e = self.e[1];
        [lo, Vec4::new(hi.x, hi.y, hi.z + e.z, hi.w + e.w)]
    }

    /// Writes the ring with each normal scaled to unit length: the mitred ring, whose
    /// normal `na + c·nb + s·nd` is affine in the circle only before normalising. The
    /// inverse lengths are computed four vertices at a time, one vector square root and
    /// division each. The normal part of `e` must be zero.
    #[inline(always)]
    pub(crate) fn put_normalized<V: Slot<Vertex>>(&self, out: &mut [V], table: &Circle) {
        debug_assert_eq!(Self::normal_of(&self.e), Vec3::ZERO);
        if V::put_affine(out, self, table, true) {
            return;
        }
        // |na + c nb + s nd|² = aa + 2c ab + 2s ad + c² bb + 2cs bd + s² dd, the dot
        // products three at a time: lane k of `x` is the x of term k's normal (na, nb, nd)
        // and of `next(x)` its neighbour's (nb, nd, na), summed in the order of a scalar
        // dot product.
        let (a, b, d) = (self.a, self.b, self.d);
        let x = Vec4::new(a[0].w, b[0].w, d[0].w, 0.0);
        let y = Vec4::new(a[1].x, b[1].x, d[1].x, 0.0);
        let z = Vec4::new(a[1].y, b[1].y, d[1].y, 0.0);
        let next = |v: Vec4| Vec4::new(v.y, v.z, v.x, 0.0);
        let squares = x * x + y * y + z * z;
        let pairs = (x * next(x) + y * next(y) + z * next(z)) * 2.0;
        let (aa, bb, dd) = (
            Vec4::splat(squares.x),
            Vec4::splat(squares.y),
            Vec4::splat(squares.z),
        );
        // pairs: (2 na·nb, 2 nb·nd, 2 nd·na)
        let (ab2, bd2, ad2) = (
            Vec4::splat(pairs.x),
            Vec4::splat(pairs.y),
            Vec4::splat(pairs.z),
        );
        let inverse_lengths = |[c, s]: [Vec4; 2]| {
            let l2 = aa + c * ab2 + s * ad2 + c * c * bb + c * s * bd2 + s * s * dd;
            Vec4::ONE / l2.sqrt()
        };
        let put = |slot: &mut V, splat: &[Vec4; 3], k: f32| {
            let [lo, hi] = self.at(splat);
            let v = [
                lo * Vec4::new(1.0, 1.0, 1.0, k),
                hi * Vec4::new(k, k, 1.0, 1.0),
            ];
            slot.put(vertex(v));
            v
        };
        // Four vertices at a time: their inverse normal lengths in one vector, then the
        // vertices themselves; the last, partial four after; then the seam.
        let (n, seam) = table.body(out.len());
        let (splats, quads) = (&table.splats[..n], &table.quads[..n.div_ceil(4)]);
        let (full, rest) = out[..n].split_at_mut(n / 4 * 4);
        let mut first = None;
        for ((slots, chunk), &quad) in full
            .chunks_exact_mut(4)
            .zip(splats.chunks_exact(4))
            .zip(quads)
        {
            let inv = inverse_lengths(quad);
            let v0 = put(&mut slots[0], &chunk[0], inv.x);
            first.get_or_insert(v0);
            put(&mut slots[1], &chunk[1], inv.y);
            put(&mut slots[2], &chunk[2], inv.z);
            put(&mut slots[3], &chunk[3], inv.w);
        }
        if let Some(&quad) = quads.get(n / 4) {
            let inv = inverse_lengths(quad).to_array();
            for ((slot, splat), &k) in rest.iter_mut().zip(&splats[n / 4 * 4..]).zip(&inv) {
                let v = put(slot, splat, k);
                first.get_or_insert(v);
            }
        }
        if let (true, Some(v0)) = (seam, first) {
            // A mirrored circle's seam has point 0's u: vertex 0 again.
            out[n].put(vertex(if table.mirrored { v0 } else { self.seam_of(v0) }));
        }
    }

    /// `Some(v)` where the ring's texture coordinates are a tube's: u the circle's own
    /// (no constant, no term in cos or sin, u's own term 1) and v one value for the whole
    /// ring.
    #[inline(always)]
    pub(crate) fn tube_v(&self) -> Option<f32> {
        let [a, b, d, e] = [self.a[1], self.b[1], self.d[1], self.e[1]];
        let zero = |v: Vec4| v.z == 0.0 && v.w == 0.0;
        (a.z == 0.0 && zero(b) && zero(d) && e.z == 1.0 && e.w == 0.0).then_some(a.w)
    }

    /// The terms of component k (0..8: position x, y, z, normal x, y, z, u, v) as splats:
    /// a ring's four vertices at (c, s, u) are `a + b·c + d·s + e·u` lane by lane.
    #[inline(always)]
    pub(crate) fn component_terms(&self) -> [[Vec4; 4]; 8] {
        let comp = |t: &[Vec4; 2], k: usize| if k < 4 { t[0][k] } else { t[1][k - 4] };
        std::array::from_fn(|k| {
            [
                Vec4::splat(comp(&self.a, k)),
                Vec4::splat(comp(&self.b, k)),
                Vec4::splat(comp(&self.d, k)),
                Vec4::splat(comp(&self.e, k)),
            ]
        })
    }

    /// The normal part of a term.
    #[inline(always)]
    fn normal_of(t: &[Vec4; 2]) -> Vec3 {
        Vec3::new(t[0].w, t[1].x, t[1].y)
    }
}

#[inline(always)]
fn vertex([lo, hi]: [Vec4; 2]) -> Vertex {
    bytemuck::cast([lo.to_array(), hi.to_array()])
}

#[cfg(test)]
mod tests {
    use super::{Affine, AxisMap, Circle, Vertex, circle, vertex};
    use glam::{Vec3A, Vec4};

    /// Rings of random terms, some with −0, as cones (the f32 writer's e: u along the
    /// ring), as caps (e zero) and with any texture term in u.
    fn rings(seed: u64) -> Vec<Affine> {
        let mut rng = crate::rng::Rng::new(seed);
        let mut x = move || {
            let r = rng.next_f64();
            if r < 0.1 {
                -0.0
            } else {
                (r * 4.0 - 2.0) as f32
            }
        };
        (0..64)
            .map(|k| {
                let mut v = || Vec3A::new(x(), x(), x());
                let (c, p, q, n, np, nq) = (v(), v(), v(), v(), v(), v());
                let mut t = || [x(), x()];
                let (uv, uv_p, uv_q) = (t(), t(), t());
                let uv_u = match k % 3 {
                    0 => [1.0, 0.0],
                    1 => [0.0, -0.0],
                    _ => t(),
                };
                Affine::new(c, p, q, n, np, nq, uv, uv_p, uv_q, uv_u)
            })
            .collect()
    }

    fn bits(v: &[Vertex]) -> Vec<[u32; 8]> {
        v.iter()
            .map(|v| bytemuck::cast::<Vertex, [f32; 8]>(*v).map(f32::to_bits))
            .collect()
    }

    /// Every vertex of a ring worked out on its own, the seam too, normalised four at a
    /// time as `put_normalized` does: what the seam's shortcut must equal bit for bit.
    fn reference(ring: &Affine, table: &Circle, normalized: bool) -> Vec<Vertex> {
        let n = table.len();
        let mut out = Vec::with_capacity(n);
        for (q, chunk) in table.splats.chunks(4).enumerate() {
            let [c, s] = table.quads[q];
            let nt = |t: &[Vec4; 2]| glam::Vec3::new(t[0].w, t[1].x, t[1].y);
            let (na, nb, nd) = (nt(&ring.a), nt(&ring.b), nt(&ring.d));
            let l2 = Vec4::splat(na.dot(na))
                + c * Vec4::splat(2.0 * na.dot(nb))
                + s * Vec4::splat(2.0 * na.dot(nd))
                + c * c * Vec4::splat(nb.dot(nb))
                + c * s * Vec4::splat(2.0 * nb.dot(nd))
                + s * s * Vec4::splat(nd.dot(nd));
            let inv = (Vec4::ONE / l2.sqrt()).to_array();
            for (splat, &k) in chunk.iter().zip(&inv) {
                let [lo, hi] = ring.at(splat);
                out.push(if normalized {
                    vertex([
                        lo * Vec4::new(1.0, 1.0, 1.0, k),
                        hi * Vec4::new(k, k, 1.0, 1.0),
                    ])
                } else {
                    vertex([lo, hi])
                });
            }
        }
        out
    }

    #[test]
    fn a_rings_seam_made_from_its_first_vertex_is_the_seam_worked_out() {
        for segments in [3, 4, 5, 7, 8, 12, 64] {
            let table = circle(segments);
            for (k, ring) in rings(segments as u64).iter().enumerate() {
                let mut got = vec![Vertex::default(); segments + 1];
                ring.put(&mut got, &table);
                assert_eq!(bits(&got), bits(&reference(ring, &table, false)), "{k}");
                // As a mitred ring (e's normal part is zero, as put_normalized asks).
                ring.put_normalized(&mut got, &table);
                let want = reference(ring, &table, true);
                assert_eq!(bits(&got), bits(&want), "{segments} sides, ring {k}");
                if k % 3 == 0 {
                    assert_eq!(got[segments].uv[0], 1.0 + got[0].uv[0]);
                }
            }
        }
    }

    #[test]
    fn only_the_identity_says_it_is_one() {
        for m in [
            AxisMap::IDENTITY,
            AxisMap::Z_UP,
            AxisMap::UNITY,
            AxisMap::UNREAL,
        ] {
            let copies = m.from == [0, 1, 2] && m.sign == [1.0; 3];
            assert_eq!(m.identity, copies, "{m:?}");
        }
    }
}
