//! Monte Carlo means and their 95 % confidence intervals: `mean ± t(0.975, n−1) · s / √n` with
//! the sample standard deviation `s` and Student's t quantile (tabulated to 30 degrees of
//! freedom, then a Cornish–Fisher expansion good to 1e-4), clipped to the range the metric can
//! take ([`metric_range`]: completeness within [0, 1], counts and energies ≥ 0). Clipping a
//! confidence interval to the parameter's range keeps its coverage (the true mean lies in the
//! range), and the t interval keeps its coverage with the three to ten runs studies use, where
//! a percentile bootstrap of the mean covers far less (docs/decisions/0148-challenge-statistics.md).

/// Two-sided 95 % quantiles of Student's t for 1–30 degrees of freedom.
const T975: [f64; 30] = [
    12.706_204_7,
    4.302_652_7,
    3.182_446_3,
    2.776_445_1,
    2.570_581_8,
    2.446_911_9,
    2.364_624_3,
    2.306_004_1,
    2.262_157_2,
    2.228_138_9,
    2.200_985_2,
    2.178_812_8,
    2.160_368_7,
    2.144_786_7,
    2.131_449_5,
    2.119_905_3,
    2.109_815_6,
    2.100_922_0,
    2.093_024_1,
    2.085_963_4,
    2.079_613_8,
    2.073_873_1,
    2.068_657_6,
    2.063_898_6,
    2.059_538_6,
    2.055_529_4,
    2.051_830_5,
    2.048_407_1,
    2.045_229_6,
    2.042_272_5,
];

/// Student's t 0.975 quantile with `df` ≥ 1 degrees of freedom.
pub fn t975(df: u32) -> f64 {
    if (1..=30).contains(&df) {
        return T975[df as usize - 1];
    }
    // Cornish–Fisher expansion around the normal quantile z (Abramowitz & Stegun 26.7.5).
    let z = 1.959_963_984_540_054_f64;
    let n = f64::from(df.max(1));
    let g1 = (z.powi(3) + z) / 4.0;
    let g2 = (5.0 * z.powi(5) + 16.0 * z.powi(3) + 3.0 * z) / 96.0;
    let g3 = (3.0 * z.powi(7) + 19.0 * z.powi(5) + 17.0 * z.powi(3) - 15.0 * z) / 384.0;
    z + g1 / n + g2 / (n * n) + g3 / (n * n * n)
}

/// Mean and 95 % interval of `values`: `(mean, lo, hi)`; the interval is `None` with fewer than
/// two values, everything is `None` with none.
pub fn mean_ci(values: &[f64]) -> (Option<f64>, Option<f64>, Option<f64>) {
    let n = values.len();
    if n == 0 {
        return (None, None, None);
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    if n < 2 {
        return (Some(mean), None, None);
    }
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    let half = t975(n as u32 - 1) * (var / n as f64).sqrt();
    (Some(mean), Some(mean - half), Some(mean + half))
}

/// The range a study metric can take: `[0, 1]` for completeness and the spurious-track ratio,
/// `[0, c]` for OSPA (its cut-off, 1000 m), `[0, ∞)` for every other metric (counts, distances,
/// ratios of counts, energies, times: none is negative).
pub fn metric_range(name: &str) -> (f64, f64) {
    match name {
        "completeness" | "spurious_ratio" => (0.0, 1.0),
        "ospa_m" => (0.0, mimo_metrics::ScoreOptions::default().ospa_c_m),
        _ => (0.0, f64::INFINITY),
    }
}

/// [`mean_ci`] with the interval clipped to `range`.
pub fn bounded_mean_ci(values: &[f64], range: (f64, f64)) -> (Option<f64>, Option<f64>, Option<f64>) {
    let (m, lo, hi) = mean_ci(values);
    (m, lo.map(|x| x.clamp(range.0, range.1)), hi.map(|x| x.clamp(range.0, range.1)))
}

/// The paired difference `a − b` of two methods over the runs where both are defined: the
/// mean of the per-run differences and its t interval clipped to `range`.
pub fn paired_difference(
    a: &[Option<f64>],
    b: &[Option<f64>],
    range: (f64, f64),
) -> (Option<f64>, Option<f64>, Option<f64>) {
    let d: Vec<f64> = a.iter().zip(b).filter_map(|(x, y)| Some((*x)? - (*y)?)).collect();
    bounded_mean_ci(&d, range)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_expansion_meets_the_table_and_the_normal_limit() {
        // At 30 degrees of freedom the expansion agrees with the table to 1e-4, and it tends to
        // the normal quantile.
        let cf = {
            let z = 1.959_963_984_540_054_f64;
            let n = 30.0;
            z + (z.powi(3) + z) / 4.0 / n
                + (5.0 * z.powi(5) + 16.0 * z.powi(3) + 3.0 * z) / 96.0 / (n * n)
                + (3.0 * z.powi(7) + 19.0 * z.powi(5) + 17.0 * z.powi(3) - 15.0 * z) / 384.0 / (n * n * n)
        };
        assert!((cf - t975(30)).abs() < 1e-4, "{cf}");
        assert!((t975(120) - 1.979_930_4).abs() < 1e-5, "{}", t975(120));
        assert!((t975(1_000_000) - 1.959_966).abs() < 1e-5);
        assert!(t975(31) < t975(30) && t975(31) > t975(32));
    }

    #[test]
    fn a_hand_case() {
        // 1, 2, 3: mean 2, s = 1, half width t(2) / √3 = 2.4841.
        let (m, lo, hi) = mean_ci(&[1.0, 2.0, 3.0]);
        assert_eq!(m, Some(2.0));
        let h = 4.302_652_7 / 3f64.sqrt();
        assert!((lo.expect("lo") - (2.0 - h)).abs() < 1e-12 && (hi.expect("hi") - (2.0 + h)).abs() < 1e-12);
        assert_eq!(mean_ci(&[5.0]), (Some(5.0), None, None));
        assert_eq!(mean_ci(&[]), (None, None, None));
    }

    #[test]
    fn clipped_intervals_stay_in_range_and_keep_their_coverage() {
        // Completeness-like samples of three runs, skewed towards 1: values 1 − e²/10 with e
        // uniform. The clipped t interval stays in [0, 1] and covers the true mean far more often
        // in 4000 trials than the percentile bootstrap of the same samples (the reason the
        // summary uses the t interval).
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let truth = 1.0 - 1.0 / 30.0;
        let (mut t_cover, mut boot_cover, trials) = (0, 0, 4000);
        for _ in 0..trials {
            let v: Vec<f64> = (0..3).map(|_| 1.0 - uniform().powi(2) / 10.0).collect();
            let (m, lo, hi) = bounded_mean_ci(&v, metric_range("completeness"));
            let (lo, hi) = (lo.expect("lo"), hi.expect("hi"));
            assert!((0.0..=1.0).contains(&lo) && (0.0..=1.0).contains(&hi) && lo <= m.expect("m") && m <= Some(hi));
            t_cover += usize::from(lo <= truth && truth <= hi);
            // All 27 equally likely resamples of three values: their means' 2.5 % and 97.5 %.
            let mut means: Vec<f64> = (0..27).map(|k| (v[k % 3] + v[k / 3 % 3] + v[k / 9]) / 3.0).collect();
            means.sort_by(f64::total_cmp);
            boot_cover += usize::from(means[0] <= truth && truth <= means[26]);
        }
        let rate = |c: usize| c as f64 / f64::from(trials);
        // Three skewed values are hard for any interval: t covers 88.6 % here, the bootstrap's
        // range of three values 1 − 0.577³ − 0.423³ = 73 % (exactly, by symmetry of ranks).
        let (t, boot) = (rate(t_cover), rate(boot_cover));
        assert!(t > 0.86 && (boot - 0.732).abs() < 0.03 && t > boot + 0.1, "t {t}, bootstrap {boot}");
        let (m, lo, hi) =
            paired_difference(&[Some(1.0), Some(0.9), None], &[Some(0.5), Some(0.6), Some(0.1)], (-1.0, 1.0));
        assert!((m.expect("m") - 0.4).abs() < 1e-12);
        assert!(lo.expect("lo") >= -1.0 && hi == Some(1.0), "{lo:?} {hi:?}");
    }

    #[test]
    fn the_interval_covers_the_mean_95_times_in_100() {
        // 4000 samples of 5 standard normal values (a fixed generator): the interval covers 0 in
        // 95 % ± 1 % of them (3 binomial standard deviations are 1.0 %).
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut normal = || {
            let (u1, u2) = (uniform().max(1e-300), uniform());
            (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
        };
        let trials = 4000;
        let covered = (0..trials)
            .filter(|_| {
                let v: Vec<f64> = (0..5).map(|_| normal()).collect();
                let (_, lo, hi) = mean_ci(&v);
                lo.expect("lo") <= 0.0 && 0.0 <= hi.expect("hi")
            })
            .count();
        let rate = covered as f64 / f64::from(trials);
        assert!((rate - 0.95).abs() < 0.0104, "coverage {rate}");
    }
}
