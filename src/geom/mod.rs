//! Geometry shared by every stage: the turtle's frame and rotations, ring frames carried
//! along a tree, cubic Bézier curves, and a uniform 3-D grid.

pub mod curve;
mod frame;
pub mod grid;
pub(crate) mod lanes;
pub(crate) mod rotation;
pub mod transport;

pub use curve::Curve;
pub use frame::{Frame, cos_sin_deg};

/// `v` at unit length, or `None` when it has no direction (zero, or not finite).
///
/// Where the squared length is a normal float this is `Vec3::normalize` bit for bit.
/// Where it underflows (a vector of components near 1e-20, such as the Newell normal of
/// a nearly flat polygon), glam's `try_normalize` scales by a reciprocal computed from a
/// subnormal and returns a vector of the wrong length; here the vector is first divided
/// by its largest component, so the result is unit length whatever the magnitude.
#[inline]
pub fn unit(v: glam::Vec3) -> Option<glam::Vec3> {
    let l2 = v.length_squared();
    if l2.is_normal() {
        return Some(v * (1.0 / l2.sqrt()));
    }
    let m = v.abs().max_element();
    if !(v.is_finite() && m > 0.0) {
        return None;
    }
    let s = v / m;
    Some(s * (1.0 / s.length()))
}

#[cfg(test)]
mod unit_tests {
    use super::unit;
    use glam::Vec3;

    #[test]
    fn unit_is_unit_at_every_magnitude() {
        for scale in [1e-45f32, 1e-40, 1e-30, 1e-20, 1e-3, 1.0, 1e19, 1e30, 3e38] {
            for d in [
                Vec3::new(-1.0, 0.5, 0.0),
                Vec3::new(1.0, 2.0, 3.0),
                Vec3::new(0.0, 0.0, -7.0),
            ] {
                let v = d * scale;
                if v == Vec3::ZERO || !v.is_finite() {
                    continue;
                }
                let u = unit(v).unwrap();
                assert!((u.length() - 1.0).abs() < 1e-6, "{v:?} gave {u:?}");
                // The direction is kept where the components are representable.
                if (1e-30..=1e30).contains(&scale) {
                    assert!(u.dot(d.normalize()) > 0.9999, "{v:?} gave {u:?}");
                }
            }
        }
        assert_eq!(unit(Vec3::ZERO), None);
        assert_eq!(unit(Vec3::new(f32::NAN, 0.0, 1.0)), None);
        assert_eq!(unit(Vec3::new(f32::INFINITY, 0.0, 1.0)), None);
        // Glam's own normalize where the squared length is normal: the same bits.
        let v = Vec3::new(0.3, -0.2, 0.9);
        assert_eq!(unit(v), Some(v.normalize()));
    }
}
