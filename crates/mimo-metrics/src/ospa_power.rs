//! The power `d^p` of the OSPA and GOSPA costs ([`crate::ospa`]), bit for bit what `f64::powf`
//! gives, with the default order p = 2 taken as a product where that provably gives the same bits.
//!
//! `powf` is the platform's `pow`. A scored raid calls it for every truth–track pair closer than
//! the cut-off at every scoring time: at 512 raid aircraft it was a fifth of the score (`perf`,
//! reports/BENCHMARKS.md). For p = 2 the product `d·d` is the exact square rounded once. glibc's
//! `pow` differs from it only when the exact square lies very close to a midpoint between two
//! doubles: 0.08 % of random distances, every one of them within 0.009 ulp of a midpoint
//! (measured over 174 M samples).
//! The product's exact error is known from one fused multiply-add (`d² = d·d + e` exactly), so:
//!
//! * where the exact square is at least 0.05 ulp from every midpoint (`|e| ≤ 0.45 ulp`, the
//!   square not a power of two, whose lower neighbour is half an ulp nearer, and between 1e-200
//!   and 1e200, far from where the error `e` itself would underflow), both round to `d·d`, which
//!   is returned;
//! * anywhere else (about one distance in ten), `powf` is called, as before.
//!
//! The scores therefore keep their bytes (docs/decisions/0323-the-ospa-square-as-a-product.md). The test
//! below compares the two on millions of distances, so a platform whose `pow` is less accurate
//! fails it.

/// `d.powf(p)`, bit for bit (see the module docs).
#[inline]
pub(crate) fn cost_power(d: f64, p: f64) -> f64 {
    if p == 2.0 {
        let sq = d * d;
        let bits = sq.to_bits();
        // Far from underflow (where the fused error itself would be rounded) and overflow, and
        // not a power of two (a mantissa of zero).
        if (1e-200..=1e200).contains(&sq) && bits & ((1u64 << 52) - 1) != 0 {
            let ulp = f64::from_bits(bits + 1) - sq;
            if d.mul_add(d, -sq).abs() <= 0.45 * ulp {
                return sq;
            }
        }
    }
    // The order hidden from the optimiser, which would rewrite `powf(2.0)` as the product.
    d.powf(std::hint::black_box(p))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The power equals `powf` to the bit on distances of every scale (the scored ranges, tiny
    /// and huge ones, near powers of two), and takes the product for most of them.
    #[test]
    fn the_square_is_powf_bit_for_bit() {
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let (mut products, mut n) = (0u64, 0u64);
        for k in 0..4_000_000u64 {
            let u = (next() >> 11) as f64 / (1u64 << 53) as f64;
            let d = match k % 5 {
                0 => 1000.0 * u,
                1 => 10.0 * u,
                2 => 1e7 * u,
                3 => f64::from_bits(next() >> 2),
                _ => 2f64.powi((k % 40) as i32 - 20) * (1.0 + 1e-12 * (u - 0.5)),
            };
            let want = d.powf(std::hint::black_box(2.0));
            assert_eq!(cost_power(d, 2.0).to_bits(), want.to_bits(), "d = {d:e}");
            let sq = d * d;
            n += 1;
            products +=
                u64::from(sq.is_normal() && d.mul_add(d, -sq).abs() <= 0.45 * (f64::from_bits(sq.to_bits() + 1) - sq));
        }
        assert!(products * 10 > n * 8, "the product for {products} of {n}");
        for p in [1.0, 1.7, 3.0] {
            assert_eq!(cost_power(123.456, p).to_bits(), 123.456f64.powf(p).to_bits());
        }
        for d in [0.0, f64::MIN_POSITIVE, 1e-200, 1e200, f64::INFINITY] {
            assert_eq!(cost_power(d, 2.0).to_bits(), d.powf(std::hint::black_box(2.0)).to_bits(), "{d:e}");
        }
    }
}
