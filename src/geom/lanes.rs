//! Vector arithmetic in four lanes (glam's `Vec3A`) that gives the bits glam's scalar
//! `Vec3` gives, on every target: the same products, sums and divisions in the same
//! order, never fused. The mesh writer and the ring frames' transport run on these; the
//! golden hashes check that their output did not change.

use glam::{Vec3A, Vec3Swizzles};

/// The dot product, summed as `Vec3::dot` sums it (x, then y, then z; glam's NEON
/// `Vec3A::dot` sums in another order).
#[inline(always)]
pub fn dot3(a: Vec3A, b: Vec3A) -> f32 {
    let p = a * b;
    p.x + p.y + p.z
}

/// The cross product of two vectors held in four lanes, each lane's two products and
/// difference as glam's `Vec3::cross` makes them, unfused on every target (glam's
/// `Vec3A::cross` fuses them on NEON and where FMA is enabled).
#[inline(always)]
pub fn cross3(a: Vec3A, b: Vec3A) -> Vec3A {
    // Lane x of the difference is the product's y (a.z b.x - a.x b.z), and so on round.
    (a.zxy() * b - a * b.zxy()).zxy()
}

/// `v` scaled to unit length as glam's `Vec3::normalize` scales it (by the reciprocal of
/// the length).
#[inline(always)]
pub fn unit3(v: Vec3A) -> Vec3A {
    v * (1.0 / dot3(v, v).sqrt())
}

/// [`unit3`], or zero where the length has no finite positive reciprocal (as
/// `Vec3::normalize_or_zero`).
#[inline(always)]
pub fn unit3_or_zero(v: Vec3A) -> Vec3A {
    let rcp = 1.0 / dot3(v, v).sqrt();
    if rcp.is_finite() && rcp > 0.0 {
        v * rcp
    } else {
        Vec3A::ZERO
    }
}

/// [`unit3`] where the length has a finite positive reciprocal, as `Vec3::try_normalize`.
#[inline(always)]
pub fn try_unit3(v: Vec3A) -> Option<Vec3A> {
    let rcp = 1.0 / dot3(v, v).sqrt();
    (rcp.is_finite() && rcp > 0.0).then(|| v * rcp)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Vectors of every size and sign, zeros and tiny ones included.
    fn samples() -> Vec<Vec3> {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let unit = (state >> 40) as f32 / (1u64 << 24) as f32 - 0.5;
            unit * 10f32.powi((state % 9) as i32 - 4)
        };
        let mut v: Vec<Vec3> = (0..2000)
            .map(|_| Vec3::new(next(), next(), next()))
            .collect();
        v.extend([Vec3::ZERO, Vec3::X, -Vec3::Y, Vec3::new(1e-30, 0.0, -1e-30)]);
        v
    }

    #[test]
    fn lanes_give_the_scalar_bits() {
        let s = samples();
        for (a, b) in s.iter().zip(s.iter().rev()) {
            let (la, lb) = (Vec3A::from(*a), Vec3A::from(*b));
            assert_eq!(dot3(la, lb).to_bits(), a.dot(*b).to_bits(), "{a} · {b}");
            let (c, d) = (Vec3::from(cross3(la, lb)), a.cross(*b));
            assert_eq!(
                c.to_array().map(f32::to_bits),
                d.to_array().map(f32::to_bits)
            );
            let bits = |v: Option<Vec3>| v.map(|v| v.to_array().map(f32::to_bits));
            assert_eq!(bits(try_unit3(la).map(Vec3::from)), bits(a.try_normalize()));
            assert_eq!(
                bits(Some(unit3_or_zero(la).into())),
                bits(Some(a.normalize_or_zero()))
            );
            if a.try_normalize().is_some() {
                assert_eq!(bits(Some(unit3(la).into())), bits(Some(a.normalize())));
            }
        }
    }
}
