//! Rotations built with libm's sine and cosine, so that they are the same bits on every
//! platform (glam's own constructors take the platform's).

use glam::{DQuat, DVec3, Quat, Vec3};

/// The rotation by `angle` radians about the unit `axis` (glam's `Quat::from_axis_angle`).
#[inline]
pub(crate) fn axis_angle(axis: Vec3, angle: f32) -> Quat {
    let (s, c) = libm::sincosf(angle * 0.5);
    let v = axis * s;
    Quat::from_xyzw(v.x, v.y, v.z, c)
}

/// [`axis_angle`] in double precision.
#[inline]
pub(crate) fn daxis_angle(axis: DVec3, angle: f64) -> DQuat {
    let (s, c) = libm::sincos(angle * 0.5);
    let v = axis * s;
    DQuat::from_xyzw(v.x, v.y, v.z, c)
}

/// The shortest rotation from unit `from` to unit `to` (glam's `Quat::from_rotation_arc`;
/// half a turn about a vector orthogonal to `from` when the two are opposite).
#[inline]
pub(crate) fn rotation_arc(from: Vec3, to: Vec3) -> Quat {
    const ONE_MINUS_EPS: f32 = 1.0 - 2.0 * f32::EPSILON;
    if from.dot(to) < -ONE_MINUS_EPS {
        axis_angle(from.any_orthonormal_vector(), std::f32::consts::PI)
    } else {
        Quat::from_rotation_arc(from, to)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The constructors give glam's rotations (to rounding), bit for bit what glam gave
    /// when it took libm.
    #[test]
    fn rotations_are_glams() {
        let axis = Vec3::new(0.3, -0.5, 0.8).normalize();
        for angle in [0.0f32, 0.7, -2.9, 3.1] {
            let (a, b) = (axis_angle(axis, angle), Quat::from_axis_angle(axis, angle));
            assert!(a.abs_diff_eq(b, 1e-6), "{a} {b}");
            let d = daxis_angle(axis.as_dvec3(), angle as f64);
            assert!(d.abs_diff_eq(DQuat::from_axis_angle(axis.as_dvec3(), angle as f64), 1e-12));
        }
        let r = rotation_arc(axis, -axis);
        assert!((r * axis).abs_diff_eq(-axis, 1e-6));
        let to = Vec3::new(0.0, 1.0, 0.0);
        assert!((rotation_arc(axis, to) * axis).abs_diff_eq(to, 1e-6));
    }
}
