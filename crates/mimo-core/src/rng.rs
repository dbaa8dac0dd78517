//! Counter-keyed random streams.
//!
//! [`Stream::new`]`(seed, &[keys…])` hashes the seed and keys with SplitMix64 into the state of a
//! xoshiro256++ generator. A stream is cheap to make, so every independent source of randomness
//! (a run's truth, a radar's dwell, a false-alarm draw) gets its own, and a result never depends
//! on how work is split across threads. The generator and distributions are written here rather
//! than taken from a crate so that a dependency upgrade can never change a recorded run's bytes.

/// Key namespaces, so that streams for different purposes never collide.
pub mod domain {
    /// Reserved for truth; unused, since truth is deterministic.
    pub const TRUTH: u64 = 1;
    /// Receiver noise of one Tx–Rx channel of a dwell.
    pub const DWELL: u64 = 2;
    /// False-alarm draws of one Tx–Rx channel of a dwell (docs/model.md §4.4).
    pub const FALSE_ALARM: u64 = 3;
    /// RCS fluctuation of one target on one Tx–Rx channel of a dwell (docs/model.md §3.2).
    pub const RCS: u64 = 4;
    /// Reserved for trackers; unused (the built-in trackers draw nothing).
    pub const TRACKER: u64 = 5;
    /// Reserved for background search; unused (the search raster is deterministic).
    pub const SEARCH: u64 = 6;
    /// The aircraft of a raid stress (docs/model.md §8.4).
    pub const RAID: u64 = 7;
    /// A radar's registration biases, drawn once per run (docs/model.md §5.5).
    pub const BIAS: u64 = 8;
    /// The jitter of a message between a ship and the test article (docs/model.md §5.6).
    pub const LINK: u64 = 9;
    /// Tests and benchmarks only.
    pub const TEST: u64 = 99;
}

fn splitmix64(x: &mut u64) -> u64 {
    *x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *x;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A xoshiro256++ random stream keyed by a seed and a list of integers.
#[derive(Debug, Clone)]
pub struct Stream {
    s: [u64; 4],
    spare_normal: Option<f64>,
}

impl Stream {
    /// A stream for `(seed, keys…)`. Different key lists give independent streams.
    pub fn new(seed: u64, keys: &[u64]) -> Stream {
        let mut h = seed ^ 0x6A09_E667_F3BC_C908;
        let mut acc = splitmix64(&mut h);
        for &k in keys {
            let mut x = acc ^ k.wrapping_mul(0x9E37_79B9_7F4A_7C15);
            acc = splitmix64(&mut x) ^ acc.rotate_left(17);
        }
        let mut x = acc;
        let s = [splitmix64(&mut x), splitmix64(&mut x), splitmix64(&mut x), splitmix64(&mut x)];
        Stream { s, spare_normal: None }
    }

    /// Next raw 64-bit value.
    pub fn next_u64(&mut self) -> u64 {
        let s = &mut self.s;
        let result = (s[0].wrapping_add(s[3])).rotate_left(23).wrapping_add(s[0]);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        result
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in (0, 1] (safe for logarithms).
    pub fn uniform_open0(&mut self) -> f64 {
        1.0 - self.uniform()
    }

    /// Uniform integer in [0, n). `n` must be > 0.
    pub fn below(&mut self, n: u64) -> u64 {
        // Lemire's nearly-divisionless method, unbiased.
        let mut m = (self.next_u64() as u128) * (n as u128);
        let mut lo = m as u64;
        if lo < n {
            let t = n.wrapping_neg() % n;
            while lo < t {
                m = (self.next_u64() as u128) * (n as u128);
                lo = m as u64;
            }
        }
        (m >> 64) as u64
    }

    /// Standard normal N(0, 1) (Marsaglia polar method).
    pub fn normal(&mut self) -> f64 {
        if let Some(z) = self.spare_normal.take() {
            return z;
        }
        loop {
            let a = 2.0 * self.uniform() - 1.0;
            let b = 2.0 * self.uniform() - 1.0;
            let s = a * a + b * b;
            if s > 0.0 && s < 1.0 {
                let f = (-2.0 * s.ln() / s).sqrt();
                self.spare_normal = Some(b * f);
                return a * f;
            }
        }
    }

    /// Exponential with mean 1.
    pub fn exp1(&mut self) -> f64 {
        -self.uniform_open0().ln()
    }

    /// Circular complex Gaussian CN(0, 1): real and imaginary parts each N(0, ½).
    pub fn cn01(&mut self) -> (f64, f64) {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        (self.normal() * s, self.normal() * s)
    }

    /// Uniform phase in [0, 2π).
    pub fn phase(&mut self) -> f64 {
        self.uniform() * std::f64::consts::TAU
    }

    /// Poisson with mean `lambda` (inversion for small means, normal-free PTRS-like fallback by
    /// splitting for large means).
    pub fn poisson(&mut self, lambda: f64) -> u64 {
        if lambda <= 0.0 {
            return 0;
        }
        if lambda > 30.0 {
            // Split into halves: the sum of independent Poissons is Poisson.
            let half = lambda / 2.0;
            return self.poisson(half) + self.poisson(lambda - half);
        }
        let l = (-lambda).exp();
        let mut k = 0u64;
        let mut p = self.uniform_open0();
        while p > l {
            k += 1;
            p *= self.uniform_open0();
        }
        k
    }

    /// Binomial(n, p): exact inversion by geometric skips, cost proportional to the number of
    /// successes (fast when n·p is small, as for false alarms).
    pub fn binomial(&mut self, n: u64, p: f64) -> u64 {
        if n == 0 || p <= 0.0 {
            return 0;
        }
        if p >= 1.0 {
            return n;
        }
        if p > 0.5 {
            return n - self.binomial(n, 1.0 - p);
        }
        let log_q = (1.0 - p).ln();
        let mut k = 0u64;
        let mut pos = 0u64;
        loop {
            // Gap before the next success ~ Geometric(p) on {0, 1, …}.
            let gap = (self.uniform_open0().ln() / log_q).floor();
            if !gap.is_finite() || gap >= (n - pos) as f64 {
                return k;
            }
            pos += gap as u64 + 1;
            k += 1;
            if pos >= n {
                return k;
            }
        }
    }
}

/// A prepared test of "a `Binomial(n, p)` draw is zero" ([`Stream::binomial_is_zero`]): the
/// threshold `(1 − p)^n` on the first uniform draw of [`Stream::binomial`], so that nearly every
/// test is one comparison instead of two logarithms. Near the threshold (within 1e-9 relative)
/// the answer is computed exactly as [`Stream::binomial`] computes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZeroBinomial {
    n: u64,
    p: f64,
    log_q: f64,
    /// A first draw below this certainly gives zero, above `u_hi` certainly not.
    u_lo: f64,
    u_hi: f64,
}

impl ZeroBinomial {
    /// The test for `Binomial(n, p)`.
    pub fn new(n: u64, p: f64) -> ZeroBinomial {
        // The expression of `Stream::binomial`, so the exact path gives its answer bit for bit.
        let log_q = (1.0 - p).ln();
        let x = n as f64 * log_q;
        // (1 − p)^n, with a margin far above the rounding of ln, exp and the division for
        // |n ln(1 − p)| ≤ 1e6; beyond that (or for a NaN) every test takes the exact path.
        let (u_lo, u_hi) = if x.abs() <= 1e6 {
            let u_star = x.exp();
            (u_star * (1.0 - 1e-9), u_star * (1.0 + 1e-9))
        } else {
            (-1.0, f64::INFINITY)
        };
        ZeroBinomial { n, p, log_q, u_lo, u_hi }
    }
}

impl Stream {
    /// Whether [`Stream::binomial`]`(n, p)` would return 0, for the `n` and `p` of `z`, drawing
    /// the same numbers up to the answer (when it is `false`, `binomial` would go on drawing: the
    /// stream's state then differs from the one `binomial` leaves).
    pub fn binomial_is_zero(&mut self, z: &ZeroBinomial) -> bool {
        let (n, p) = (z.n, z.p);
        if n == 0 || p <= 0.0 {
            return true;
        }
        // p > 1/2, p ≥ 1 or NaN: as `binomial` does.
        if p > 0.5 || p.is_nan() {
            return self.binomial(n, p) == 0;
        }
        // `binomial`'s first step: zero iff the first gap ⌊ln U / ln(1 − p)⌋ is not finite or at
        // least n, i.e. iff U ≤ (1 − p)^n up to rounding.
        let u = self.uniform_open0();
        if u < z.u_lo {
            return true;
        }
        if u > z.u_hi {
            return false;
        }
        let gap = (u.ln() / z.log_q).floor();
        !gap.is_finite() || gap >= n as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let mut a = Stream::new(7, &[1, 2, 3]);
        let mut b = Stream::new(7, &[1, 2, 3]);
        let mut c = Stream::new(7, &[1, 2, 4]);
        let mut d = Stream::new(8, &[1, 2, 3]);
        let va: Vec<u64> = (0..8).map(|_| a.next_u64()).collect();
        let vb: Vec<u64> = (0..8).map(|_| b.next_u64()).collect();
        let vc: Vec<u64> = (0..8).map(|_| c.next_u64()).collect();
        let vd: Vec<u64> = (0..8).map(|_| d.next_u64()).collect();
        assert_eq!(va, vb);
        assert_ne!(va, vc);
        assert_ne!(va, vd);
    }

    #[test]
    fn moments_within_confidence_bands() {
        let n = 200_000;
        let mut s = Stream::new(1, &[domain::TEST]);
        let (mut m, mut m2, mut e) = (0.0, 0.0, 0.0);
        for _ in 0..n {
            let z = s.normal();
            m += z;
            m2 += z * z;
            e += s.exp1();
        }
        let nf = n as f64;
        // Mean of N(0,1): std error 1/sqrt(n) ≈ 0.0022; 4.5 sigma band.
        assert!((m / nf).abs() < 4.5 / nf.sqrt());
        // Variance: std error sqrt(2/n) ≈ 0.0032.
        assert!((m2 / nf - 1.0).abs() < 4.5 * (2.0 / nf).sqrt());
        // Exp(1) mean: std error 1/sqrt(n).
        assert!((e / nf - 1.0).abs() < 4.5 / nf.sqrt());
    }

    #[test]
    fn binomial_is_zero_answers_as_binomial() {
        let cases: [(u64, f64); 12] = [
            (0, 0.3),
            (5, 0.0),
            (3000, 1e-6),
            (3000, 1e-4),
            (20, 0.03),
            (7, 0.2),
            (2, 0.5),
            (3, 0.7),
            (4, 1.0),
            (10, f64::NAN),
            (1_000_000, 1e-300),
            (1_500_000, 0.5),
        ];
        let (mut zero, mut not_zero) = (0, 0);
        for (c, &(n, p)) in cases.iter().enumerate() {
            let z = ZeroBinomial::new(n, p);
            // |n ln(1 − p)| > 1e6 (every test exact) makes `binomial` loop n p times: few draws.
            let draws = if n > 1_000_000 { 10 } else { 4000u64 };
            for k in 0..draws {
                let mut a = Stream::new(3, &[domain::TEST, c as u64, k]);
                let mut b = a.clone();
                let want = a.binomial(n, p) == 0;
                assert_eq!(b.binomial_is_zero(&z), want, "n {n} p {p} draw {k}");
                if want {
                    zero += 1;
                } else {
                    not_zero += 1;
                }
            }
        }
        assert!(zero > 10_000 && not_zero > 10_000, "zero {zero}, not zero {not_zero}");
    }

    #[test]
    fn binomial_and_poisson_means() {
        let mut s = Stream::new(2, &[domain::TEST]);
        let trials = 20_000;
        let (n, p) = (30_000u64, 1e-4);
        let mean: f64 = (0..trials).map(|_| s.binomial(n, p) as f64).sum::<f64>() / trials as f64;
        let mu = n as f64 * p;
        let se = (mu * (1.0 - p) / trials as f64).sqrt();
        assert!((mean - mu).abs() < 4.5 * se, "binomial mean {mean} vs {mu}");
        let lam = 45.0;
        let pm: f64 = (0..trials).map(|_| s.poisson(lam) as f64).sum::<f64>() / trials as f64;
        assert!((pm - lam).abs() < 4.5 * (lam / trials as f64).sqrt());
        for _ in 0..1000 {
            assert!(s.below(7) < 7);
        }
    }
}
