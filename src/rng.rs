//! The random streams of grammars.
//!
//! Two families, chosen per derivation (see `docs/grammars.md`, "Random streams"):
//! - cpfg's own: the drand48 family's 48-bit generator ([`Drand48`]), seeded and drawn as
//!   cpfg draws it, so a published stochastic model grows cpfg's plant;
//! - arbor's: SplitMix64 ([`Rng`]), tiny, fast and the same on every platform, used when
//!   the host asks for a seed of its own (`LsystemOptions::seed` without a `seed:` line, or
//!   `variation_seed`).

/// A seeded pseudo-random generator.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
}

impl Rng {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Rng { state: seed }
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Normal with mean `mean` and standard deviation `sd` (Box–Muller).
    pub fn normal(&mut self, mean: f64, sd: f64) -> f64 {
        let u1 = 1.0 - self.next_f64(); // (0, 1]
        let u2 = self.next_f64();
        mean + sd * (-2.0 * libm::log(u1)).sqrt() * libm::cos(std::f64::consts::TAU * u2)
    }
}

/// The drand48 family's generator: X' = (0x5DEECE66D X + 0xB) mod 2^48, each draw
/// X' / 2^48, as the C library's `drand48` and `erand48` compute it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Drand48 {
    x: u64,
}

impl Drand48 {
    const MASK: u64 = (1 << 48) - 1;

    /// The state before any `seed48` or `srand48`: glibc's, X = 0 (cpfg is built on it).
    pub const fn initial() -> Self {
        Drand48 { x: 0 }
    }

    /// The state of the three 16-bit words an `xsubi` array or `seed48` holds, the low
    /// word first.
    pub const fn from_words(w: [u16; 3]) -> Self {
        Drand48 {
            x: (w[2] as u64) << 32 | (w[1] as u64) << 16 | w[0] as u64,
        }
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        self.x = (self.x.wrapping_mul(0x5_DEEC_E66D).wrapping_add(0xB)) & Self::MASK;
        self.x as f64 / (1u64 << 48) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drand48_draws_as_the_c_library() {
        // Values glibc gives (printed with %.17g): erand48 of {0x330E, 0, 0} twice,
        // drand48 never seeded, and drand48 after seed48({2454, 0, 155}) twice.
        let mut r = Drand48::from_words([0x330E, 0, 0]);
        assert_eq!(r.next_f64(), 0.17082803610628972);
        assert_eq!(r.next_f64(), 0.7499019804849638);
        assert_eq!(Drand48::initial().next_f64(), 3.907985046680551e-14);
        let mut s = Drand48::from_words([2454, 0, 155]);
        assert_eq!(s.next_f64(), 0.7354423349833361);
        assert_eq!(s.next_f64(), 0.09894781226580562);
    }

    #[test]
    fn same_seed_same_sequence_and_uniform_range() {
        let mut a = Rng::new(42);
        let mut b = Rng::new(42);
        let mut c = Rng::new(43);
        let xs: Vec<u64> = (0..8).map(|_| a.next_u64()).collect();
        let ys: Vec<u64> = (0..8).map(|_| b.next_u64()).collect();
        let zs: Vec<u64> = (0..8).map(|_| c.next_u64()).collect();
        assert_eq!(xs, ys);
        assert_ne!(xs, zs);
        let mut r = Rng::new(1);
        let mean = (0..10_000).map(|_| r.next_f64()).sum::<f64>() / 10_000.0;
        assert!((mean - 0.5).abs() < 0.02, "{mean}");
        let sd = (0..10_000).map(|_| r.normal(0.0, 2.0).powi(2)).sum::<f64>() / 10_000.0;
        assert!((sd.sqrt() - 2.0).abs() < 0.1, "{sd}");
    }
}
