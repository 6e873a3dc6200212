//! The random stream of a derivation's expressions (`ran`, `nran`, `bran`, `biran`,
//! `srand`), cpfg's or arbor's (see `docs/grammars.md`, "Random streams"), and how
//! stochastic productions are chosen.

use crate::rng::{Drand48, Rng};

/// How a table's applicable productions are chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Choice {
    /// arbor's: the first applicable production decides; one with a probability is drawn
    /// by weight among all applicable productions with one.
    Arbor,
    /// cpfg's for a grammar without `seed:` (and for its interpretation and decomposition
    /// rules): the first applicable production, probabilities ignored.
    First,
    /// cpfg's for a grammar with `seed:`: every applicable production weighs its
    /// probability (1 without one), and every module draws once from drand48.
    Weighted,
}

/// cpfg's `ran`, `nran`, `bran`, `biran` state: the erand48 words `main_xsubi` and
/// `nrand`'s pair (it returns the mean on its first call, as cpfg's does).
#[derive(Clone, Debug)]
pub(crate) struct CpfgRan {
    xsubi: Drand48,
    iset: i32,
    gset: f64,
}

/// The stream expressions draw from.
#[derive(Clone, Debug)]
pub(crate) enum Random {
    Arbor(Rng),
    Cpfg(CpfgRan),
}

impl Random {
    /// cpfg's stream as a run starts: the words {0x330E, 0, 0}, `nrand` not yet primed.
    pub(crate) fn cpfg() -> Random {
        Random::Cpfg(CpfgRan {
            xsubi: Drand48::from_words([0x330E, 0, 0]),
            iset: 10,
            gset: 0.0,
        })
    }

    /// Uniform in [0, 1) (`ran(x)` is x times this).
    #[inline]
    pub(crate) fn uniform(&mut self) -> f64 {
        match self {
            Random::Arbor(r) => r.next_f64(),
            Random::Cpfg(c) => c.xsubi.next_f64(),
        }
    }

    /// `nran(mean, sd)`.
    pub(crate) fn normal(&mut self, mean: f64, sd: f64) -> f64 {
        let c = match self {
            Random::Arbor(r) => return r.normal(mean, sd),
            Random::Cpfg(c) => c,
        };
        // cpfg's polar method, one value of each pair kept for the next call.
        if c.iset == 0 {
            let (mut v1, mut v2, mut rsq);
            // The polar method accepts about 79% of pairs; 1,000 tries never all fail.
            let mut tries = 0;
            loop {
                v1 = 2.0 * c.xsubi.next_f64() - 1.0;
                v2 = 2.0 * c.xsubi.next_f64() - 1.0;
                rsq = v1 * v1 + v2 * v2;
                tries += 1;
                if (rsq < 1.0 && rsq != 0.0) || tries >= 1000 {
                    break;
                }
            }
            let fac = (-2.0 * libm::log(rsq) / rsq).sqrt();
            c.gset = v1 * fac;
            c.iset = 1;
            v2 * fac * sd + mean
        } else {
            c.iset = 0;
            c.gset * sd + mean
        }
    }

    /// `srand(a)`.
    pub(crate) fn srand(&mut self, a: f64) {
        match self {
            Random::Arbor(r) => *r = Rng::new(a as i64 as u64),
            Random::Cpfg(c) => {
                let a = a as i64;
                c.xsubi =
                    Drand48::from_words([0x330E, (a & 0xFFFF) as u16, ((a >> 16) & 0xFFFF) as u16]);
                c.iset = 0;
            }
        }
    }

    /// `bran(a, b)`: a draw from Beta(a, b).
    /// `tries` counts the rejection method's tries (at most 1,000), for the work budget.
    pub(crate) fn beta(&mut self, a: f64, b: f64, tries: &mut u64) -> f64 {
        if !(a > 0.0 && b > 0.0 && a.is_finite() && b.is_finite()) {
            return f64::NAN;
        }
        if let Random::Arbor(r) = self {
            // Jöhnk's method, at most 1,000 tries, then the mean.
            for _ in 0..1000 {
                *tries += 1;
                let x = r.next_f64().powf(1.0 / a);
                let y = r.next_f64().powf(1.0 / b);
                if x + y <= 1.0 && x + y > 0.0 {
                    return x / (x + y);
                }
            }
            return a / (a + b);
        }
        // cpfg's (Cheng's rejection method), at most 1,000 tries, then the mean.
        let s = a + b;
        let lambda = if a.min(b) <= 1.0 {
            a.min(b)
        } else {
            ((2.0 * a * b - s) / (s - 2.0)).sqrt()
        };
        let u = a + lambda;
        for _ in 0..1000 {
            *tries += 1;
            let u1 = self.nonzero_uniform();
            let u2 = self.nonzero_uniform();
            let v = (1.0 / lambda) * libm::log(u1 / (1.0 - u1));
            let ym = a * libm::exp(v);
            let reject =
                s * libm::log(s / (b + ym)) + u * v - libm::log(4.0) < libm::log(u1 * u1 * u2);
            if !reject {
                return ym / (b + ym);
            }
        }
        a / (a + b)
    }

    /// `biran(n, p)`: a draw from Binomial(n, p) by counting trials (n at most 100,000).
    pub(crate) fn binomial(&mut self, n: f64, p: f64) -> f64 {
        if !(n.is_finite() && (0.0..=100_000.0).contains(&n) && (0.0..=1.0).contains(&p)) {
            return f64::NAN;
        }
        let cpfg = matches!(self, Random::Cpfg(_));
        (0..n as u32)
            .filter(|_| {
                let u = self.uniform();
                if cpfg { u <= p } else { u < p }
            })
            .count() as f64
    }

    /// A uniform draw that is not 0 (cpfg draws again on 0).
    fn nonzero_uniform(&mut self) -> f64 {
        loop {
            let u = self.uniform();
            if u != 0.0 {
                return u;
            }
        }
    }
}
