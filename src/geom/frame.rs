//! The 3-D turtle's frame and its rotations, exactly as cpfg computes them.
//!
//! The turtle starts at the origin with heading H = +Y, left L = −X and up U = L × H = −Z.
//! Angles are in degrees; the frame is kept in `f64` so that long chains of rotations stay
//! accurate before the skeleton stores `f32`.

use glam::DVec3;

/// Position and orientation of the turtle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Position.
    pub position: DVec3,
    /// Heading H: the direction `F` draws in.
    pub heading: DVec3,
    /// Left L.
    pub left: DVec3,
    /// Up U = L × H.
    pub up: DVec3,
}

impl Default for Frame {
    fn default() -> Self {
        Frame {
            position: DVec3::ZERO,
            heading: DVec3::Y,
            left: DVec3::NEG_X,
            up: DVec3::NEG_Z,
        }
    }
}

/// Cosine and sine of an angle in degrees, reduced to one turn first so that huge angles
/// stay exact to the reduction.
#[inline]
pub fn cos_sin_deg(degrees: f64) -> (f64, f64) {
    let (s, c) = libm::sincos((degrees % 360.0).to_radians());
    (c, s)
}

impl Frame {
    /// `+(θ)`: turn left about U: H' = H cosθ + L sinθ, L' = L cosθ − H sinθ.
    /// `-(θ)` is `turn` by −θ. Viewed from +Z a positive turn of the initial frame is
    /// counter-clockwise.
    #[inline]
    pub fn turn(&mut self, (c, s): (f64, f64)) {
        let h = self.heading;
        self.heading = h * c + self.left * s;
        self.left = self.left * c - h * s;
    }

    /// `&(θ)`: pitch down about L: H' = H cosθ + U sinθ, U' = U cosθ − H sinθ.
    /// `^(θ)` is `pitch` by −θ.
    #[inline]
    pub fn pitch(&mut self, (c, s): (f64, f64)) {
        let h = self.heading;
        self.heading = h * c + self.up * s;
        self.up = self.up * c - h * s;
    }

    /// `/(θ)`: roll about H: L' = L cosθ + U sinθ, U' = U cosθ − L sinθ.
    /// `\(θ)` is `roll` by −θ.
    #[inline]
    pub fn roll(&mut self, (c, s): (f64, f64)) {
        let l = self.left;
        self.left = l * c + self.up * s;
        self.up = self.up * c - l * s;
    }

    /// Moves the turtle `length` units along its heading and returns the new position.
    #[inline]
    pub fn forward(&mut self, length: f64) -> DVec3 {
        self.position += self.heading * length;
        self.position
    }
}

impl Frame {
    /// `|`: turn around (H and L negated).
    #[inline]
    pub fn turn_around(&mut self) {
        self.heading = -self.heading;
        self.left = -self.left;
    }

    /// `$` / `@v`: roll about H so that L is horizontal: L = (Y × H)/|Y × H|, U = L × H.
    /// Nothing changes while H is vertical.
    pub fn roll_horizontal(&mut self) {
        let l = DVec3::Y.cross(self.heading);
        let len = l.length();
        if len > 1e-12 {
            self.left = l / len;
            self.up = self.left.cross(self.heading);
        }
    }

    /// Rotates the whole frame about the unit `axis` by `angle` radians.
    fn rotate(&mut self, axis: DVec3, angle: f64) {
        let q = super::rotation::daxis_angle(axis, angle);
        self.heading = (q * self.heading).normalize();
        self.left = (q * self.left).normalize();
        self.up = (q * self.up).normalize();
    }

    /// Tropism: bends H toward `t` by `e·|H × t|` radians (at most 1), as cpfg does.
    pub fn bend(&mut self, t: DVec3, e: f64) {
        let axis = self.heading.cross(t);
        let len = axis.length();
        if len > 1e-12 && e != 0.0 {
            self.rotate(axis / len, (e * len).clamp(-1.0, 1.0));
        }
    }

    /// cpfg's older tropism toward the unit vector `t` with elasticity `e`: H turns
    /// toward U by asin(e·(t·U)), then toward L by asin(e·(t·L)).
    pub fn bend_old_style(&mut self, t: DVec3, e: f64) {
        if e == 0.0 {
            return;
        }
        let a = (e * t.dot(self.up)).clamp(-1.0, 1.0).asin();
        if let Some(axis) = self.heading.cross(self.up).try_normalize() {
            self.rotate(axis, a);
        }
        let b = (e * t.dot(self.left)).clamp(-1.0, 1.0).asin();
        if let Some(axis) = self.heading.cross(self.left).try_normalize() {
            self.rotate(axis, b);
        }
    }

    /// `@R(hx,hy,hz[,ux,uy,uz])`: sets the heading (and the up vector); L = H × U.
    pub fn set_heading(&mut self, h: DVec3, up: Option<DVec3>) {
        let Some(h) = h.try_normalize() else { return };
        let u = up.unwrap_or(self.up);
        let u = (u - h * u.dot(h))
            .try_normalize()
            .or_else(|| h.any_orthonormal_vector().try_normalize())
            .unwrap_or(DVec3::NEG_Z);
        self.heading = h;
        self.up = u;
        self.left = h.cross(u);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    fn assert_vec(a: DVec3, b: DVec3) {
        assert_abs_diff_eq!(a.x, b.x, epsilon = 1e-12);
        assert_abs_diff_eq!(a.y, b.y, epsilon = 1e-12);
        assert_abs_diff_eq!(a.z, b.z, epsilon = 1e-12);
    }

    #[test]
    fn initial_frame_is_right_handed() {
        let f = Frame::default();
        assert_vec(f.left.cross(f.heading), f.up);
    }

    #[test]
    fn plus_turns_counter_clockwise_seen_from_plus_z() {
        let mut f = Frame::default();
        f.turn(cos_sin_deg(90.0));
        assert_vec(f.heading, DVec3::NEG_X);
        assert_vec(f.left, DVec3::NEG_Y);
    }

    #[test]
    fn pitch_down_tilts_heading_toward_up() {
        let mut f = Frame::default();
        f.pitch(cos_sin_deg(90.0));
        assert_vec(f.heading, DVec3::NEG_Z);
        assert_vec(f.up, DVec3::NEG_Y);
    }

    #[test]
    fn roll_keeps_heading_and_turns_left_toward_up() {
        let mut f = Frame::default();
        f.roll(cos_sin_deg(90.0));
        assert_vec(f.heading, DVec3::Y);
        assert_vec(f.left, DVec3::NEG_Z);
        assert_vec(f.up, DVec3::X);
        assert_vec(f.left.cross(f.heading), f.up);
    }

    #[test]
    fn huge_angles_are_reduced() {
        let (c, s) = cos_sin_deg(360.0 * 1e6 + 30.0);
        assert_abs_diff_eq!(c, 30f64.to_radians().cos(), epsilon = 1e-9);
        assert_abs_diff_eq!(s, 0.5, epsilon = 1e-9);
    }
}
