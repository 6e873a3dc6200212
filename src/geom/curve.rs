//! Cubic Bézier curves: the shape of a branch. A straight branch has its inner control
//! points at the thirds of its axis.

use glam::Vec3;

/// A cubic Bézier curve p0 → p3 with inner control points p1 and p2.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Curve {
    /// Start.
    pub p0: Vec3,
    /// First inner control point (the tangent at p0 is 3 (p1 − p0)).
    pub p1: Vec3,
    /// Second inner control point (the tangent at p3 is 3 (p3 − p2)).
    pub p2: Vec3,
    /// End.
    pub p3: Vec3,
}

impl Curve {
    /// The straight segment from `a` to `b`: control points at the thirds, so the curve's
    /// parameter is proportional to arc length.
    pub fn straight(a: Vec3, b: Vec3) -> Self {
        let d = (b - a) / 3.0;
        Curve {
            p0: a,
            p1: a + d,
            p2: b - d,
            p3: b,
        }
    }

    /// The point at parameter `t` in [0, 1] (de Casteljau).
    pub fn point(&self, t: f32) -> Vec3 {
        let u = 1.0 - t;
        self.p0 * (u * u * u)
            + self.p1 * (3.0 * u * u * t)
            + self.p2 * (3.0 * u * t * t)
            + self.p3 * (t * t * t)
    }

    /// The derivative at parameter `t`.
    pub fn tangent(&self, t: f32) -> Vec3 {
        let u = 1.0 - t;
        (self.p1 - self.p0) * (3.0 * u * u)
            + (self.p2 - self.p1) * (6.0 * u * t)
            + (self.p3 - self.p2) * (3.0 * t * t)
    }

    /// Whether the inner control points lie at the thirds of p0 → p3 (within `tolerance`).
    pub fn is_straight(&self, tolerance: f32) -> bool {
        let s = Curve::straight(self.p0, self.p3);
        s.p1.distance(self.p1) <= tolerance && s.p2.distance(self.p2) <= tolerance
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    #[test]
    fn a_straight_curve_is_its_segment_at_uniform_speed() {
        let (a, b) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, -2.0, 3.0));
        let c = Curve::straight(a, b);
        assert!(c.is_straight(1e-6));
        for k in 0..=10 {
            let t = k as f32 / 10.0;
            assert_abs_diff_eq!(c.point(t).distance(a.lerp(b, t)), 0.0, epsilon = 1e-5);
            assert_abs_diff_eq!(c.tangent(t).distance(b - a), 0.0, epsilon = 1e-5);
        }
        let bent = Curve {
            p1: c.p1 + Vec3::X,
            ..c
        };
        assert!(!bent.is_straight(0.5));
        assert_eq!(bent.point(0.0), a);
        assert_eq!(bent.point(1.0), b);
    }
}
