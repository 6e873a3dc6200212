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

    /// Rotation-minimising frames along the curve by the double-reflection method (Wang,
    /// Jüttler, Zheng & Liu 2008), at `segments + 1` equal parameter steps: calls `visit`
    /// with (step, point, unit tangent, unit frame vector, arc length so far) for step 0
    /// (the given `frame`, made perpendicular to `t0`) to `segments` (the end), and returns
    /// the frame at the end. `t0` is the unit tangent at the start.
    pub fn rotation_minimising_frames(
        &self,
        t0: Vec3,
        frame: Vec3,
        segments: usize,
        mut visit: impl FnMut(usize, Vec3, Vec3, Vec3, f32),
    ) -> Vec3 {
        let mut x = self.p0;
        let mut t = t0;
        let mut r = (frame - t * frame.dot(t)).try_normalize().unwrap_or(frame);
        let mut arc = 0.0f32;
        visit(0, x, t, r, 0.0);
        for j in 1..=segments {
            let u = j as f32 / segments as f32;
            let x1 = self.point(u);
            let t1 = self.tangent(u).try_normalize().unwrap_or(t);
            let v1 = x1 - x;
            let c1 = v1.length_squared();
            let (mut r_l, mut t_l) = (r, t);
            if c1 > 1e-24 {
                r_l = r - v1 * (2.0 / c1 * v1.dot(r));
                t_l = t - v1 * (2.0 / c1 * v1.dot(t));
            }
            let v2 = t1 - t_l;
            let c2 = v2.length_squared();
            let r1 = if c2 > 1e-24 {
                r_l - v2 * (2.0 / c2 * v2.dot(r_l))
            } else {
                r_l
            };
            // Keep it unit and perpendicular against rounding.
            r = (r1 - t1 * r1.dot(t1)).try_normalize().unwrap_or(r);
            arc += v1.length();
            x = x1;
            t = t1;
            visit(j, x, t, r, arc);
        }
        r
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
    fn rotation_minimising_frames_stay_perpendicular_and_do_not_twist_on_a_plane() {
        // A planar bend: the frame vector normal to the plane stays put.
        let c = Curve {
            p0: Vec3::ZERO,
            p1: Vec3::new(0.0, 1.0, 0.0),
            p2: Vec3::new(1.0, 2.0, 0.0),
            p3: Vec3::new(2.0, 2.0, 0.0),
        };
        let t0 = c.tangent(0.0).normalize();
        let mut n = 0;
        let end = c.rotation_minimising_frames(t0, Vec3::Z, 16, |_, _, t, r, _| {
            assert!(r.dot(t).abs() < 1e-5);
            assert!((r - Vec3::Z).length() < 1e-5, "{r}");
            n += 1;
        });
        assert_eq!(n, 17);
        assert!((end - Vec3::Z).length() < 1e-5);
        // A frame in the plane turns with the curve, staying perpendicular.
        let end = c.rotation_minimising_frames(t0, Vec3::X, 16, |_, _, t, r, _| {
            assert!(r.dot(t).abs() < 1e-5 && (r.length() - 1.0).abs() < 1e-5);
        });
        assert!(end.dot(Vec3::Y).abs() > 0.99, "turned with the bend: {end}");
    }

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
