//! Ring frames along a tree: a basis for a root's ring and parallel transport of a frame
//! vector from one branch direction to the next.

use super::lanes::{cross3, dot3, try_unit3};
use glam::{DVec3, Vec3, Vec3A};

/// An orthonormal pair `(p, q)` with `p × q = n` for a unit `n`, continuous everywhere but
/// at `n = −Y` (Frisvad's construction with its pole moved from −Z to −Y, where branches
/// rarely point). Only roots need it; every other ring's frame is transported.
///
/// `n` is normalised first and `p` made exactly perpendicular and unit afterwards: near
/// −Y the construction divides by 1 + n.y, which magnifies any rounding of `n` (a heading
/// a few thousandths from straight down used to give rings 1.6% too wide).
pub fn ring_basis(n: DVec3) -> (DVec3, DVec3) {
    let n = n.try_normalize().unwrap_or(DVec3::Y);
    let p = if n.y < -0.999_999 {
        DVec3::X - n * n.x
    } else {
        let a = 1.0 / (1.0 + n.y);
        DVec3::new(-n.z * n.x * a, -n.z, 1.0 - n.z * n.z * a)
    };
    let p = (p - n * n.dot(p))
        .try_normalize()
        .unwrap_or_else(|| n.any_orthonormal_vector());
    (p, n.cross(p))
}

/// `p` carried from the ring around `from` to the ring around `to` (unit, perpendicular to
/// `to`): the smallest rotation taking `from` to `to` (Rodrigues' formula with
/// k = from × to: R p = p c + k × p + k (k · p) / (1 + c), c = from · to), then the
/// projection onto the plane normal to `to`, which keeps rounding from tilting the frame,
/// and one Newton step back to unit length. Applied to the vector directly: about 40
/// operations, where the 3 × 3 map of the same rotation and projection took about 100.
/// Computed in four lanes (`Vec3A`), with the bits the same arithmetic on `Vec3` gives.
#[inline(always)]
pub fn transport(p: Vec3, from: Vec3, to: Vec3) -> Vec3 {
    let (pa, fa, ta) = (Vec3A::from(p), Vec3A::from(from), Vec3A::from(to));
    let c = dot3(fa, ta);
    let v = if c > -0.9999 {
        let k = cross3(fa, ta);
        pa * c + cross3(k, pa) + k * (dot3(k, pa) / (1.0 + c))
    } else {
        Vec3A::from(super::rotation::rotation_arc(from, to) * p)
    };
    let v = v - ta * dot3(ta, v);
    let l2 = dot3(v, v);
    if (0.9..1.1).contains(&l2) {
        // A rotation keeps the length to rounding: one Newton step of 1/√l2 from 1.
        Vec3::from(v * (1.5 - 0.5 * l2))
    } else {
        try_unit3(v).map_or_else(|| ring_basis(to.as_dvec3()).0.as_vec3(), Vec3::from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    #[test]
    fn ring_basis_is_right_handed_and_orthonormal() {
        let dirs = [
            DVec3::Y,
            DVec3::NEG_Y,
            DVec3::X,
            DVec3::NEG_Z,
            DVec3::new(1.0, -2.0, 3.0).normalize(),
            DVec3::new(1e-5, -1.0, 0.0).normalize(),
        ];
        for n in dirs {
            let (p, q) = ring_basis(n);
            assert_abs_diff_eq!(p.length(), 1.0, epsilon = 1e-9);
            assert_abs_diff_eq!(q.length(), 1.0, epsilon = 1e-9);
            assert_abs_diff_eq!(p.dot(q), 0.0, epsilon = 1e-9);
            let c = p.cross(q);
            assert_abs_diff_eq!((c - n).length(), 0.0, epsilon = 1e-8);
        }
    }

    #[test]
    fn transport_keeps_the_frame_perpendicular() {
        let from = Vec3::Y;
        let to = Vec3::new(1.0, 1.0, 0.0).normalize();
        let p = transport(Vec3::Z, from, to);
        assert_abs_diff_eq!(p.dot(to), 0.0, epsilon = 1e-6);
        assert_abs_diff_eq!(p.length(), 1.0, epsilon = 1e-6);
        // A rotation in the XY plane leaves Z alone.
        assert_abs_diff_eq!(p.z, 1.0, epsilon = 1e-6);
        let back = transport(Vec3::Z, Vec3::Y, Vec3::NEG_Y);
        assert_abs_diff_eq!(back.dot(Vec3::NEG_Y), 0.0, epsilon = 1e-6);
    }

    #[test]
    fn a_long_chain_of_transports_stays_unit_and_perpendicular() {
        // 100,000 branches along a wandering axis: the frame is carried by a matrix and
        // renormalised by one Newton step each time, so errors must not accumulate.
        let mut rng = crate::rng::Rng::new(3);
        let mut dir = Vec3::Y;
        let mut p = ring_basis(dir.as_dvec3()).0.as_vec3();
        for k in 0..100_000 {
            let jitter = Vec3::new(
                rng.next_f64() as f32 - 0.5,
                rng.next_f64() as f32 - 0.5,
                rng.next_f64() as f32 - 0.5,
            );
            // Mostly gentle bends, now and then a reversal (the matrix from a quaternion).
            let to = if k % 997 == 0 {
                -dir
            } else {
                (dir + jitter * 0.6).normalize()
            };
            p = transport(p, dir, to);
            dir = to;
            assert!(
                (p.length() - 1.0).abs() < 1e-5,
                "branch {k}: |p| = {}",
                p.length()
            );
            assert!(p.dot(dir).abs() < 1e-5, "branch {k}: p·d = {}", p.dot(dir));
        }
    }
}
