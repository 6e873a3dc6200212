//! The directions of new buds: a ring basis about a heading and the lateral bud's turn.

use glam::Vec3;

/// A unit vector perpendicular to unit `h`, continuous except near −Y: the ring basis of
/// the mesher ([`ring_basis`](crate::geom::transport::ring_basis)), in single precision
/// where that is exact enough (away from straight down).
#[inline]
pub(super) fn perpendicular(h: Vec3) -> Vec3 {
    if h.y > -0.9 {
        let a = 1.0 / (1.0 + h.y);
        Vec3::new(-h.z * h.x * a, -h.z, 1.0 - h.z * h.z * a)
    } else {
        crate::geom::transport::ring_basis(h.as_dvec3()).0.as_vec3()
    }
}

/// The lateral bud direction of an internode heading `h`, turned `phyllo` degrees about
/// it, at the branch angle whose (sine, cosine) is `branch`.
#[inline]
pub(super) fn lateral(h: Vec3, phyllo: f32, (sb, cb): (f32, f32)) -> Vec3 {
    let e = perpendicular(h);
    let (s, c) = libm::sincosf(phyllo.to_radians());
    let side = e * c + h.cross(e) * s;
    (h * cb + side * sb).normalize_or_zero()
}

/// (sine, cosine) of a branch angle in degrees.
pub(super) fn branch_turn(degrees: f32) -> (f32, f32) {
    libm::sincosf(degrees.to_radians())
}
