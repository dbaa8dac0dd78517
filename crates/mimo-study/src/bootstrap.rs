//! The bootstrap over Monte Carlo runs (docs/studies.md, "The challenge"): resamples of the run
//! indices, drawn once from a stream keyed by the plan's seed so that the bytes never change,
//! and percentile intervals that allow for results censored by the ends of a sweep.
//!
//! Run `k` of every cell of a study shares its random draws, so a figure that combines several
//! cells (the points of a family, or two families) is resampled by applying *one* resample of
//! run indices to all of them: the intervals keep the pairing.

use mimo_core::rng::Stream;

/// Resamples drawn (percentile intervals need at least 1 000).
pub const RESAMPLES: usize = 2000;

/// The key of the bootstrap's random stream (`"boot"`), beside the plan's seed.
const STREAM_KEY: u64 = 0x626f_6f74;

/// `count` resamples of `runs` run indices, each drawn with replacement from `0..runs`.
pub fn resamples(seed: u64, runs: usize, count: usize) -> Vec<Vec<usize>> {
    (0..count)
        .map(|b| {
            let mut s = Stream::new(seed, &[STREAM_KEY, runs as u64, b as u64]);
            (0..runs).map(|_| s.below(runs.max(1) as u64) as usize).collect()
        })
        .collect()
}

/// `count` resamples of `runs` run indices for the independent sample `key` (a grid point
/// whose runs share no random draws with the others'): a stream of its own per key, so that
/// the resamples of different keys are independent.
pub fn resamples_keyed(seed: u64, key: u64, runs: usize, count: usize) -> Vec<Vec<usize>> {
    (0..count)
        .map(|b| {
            let mut s = Stream::new(seed, &[STREAM_KEY, runs as u64, b as u64, key]);
            (0..runs).map(|_| s.below(runs.max(1) as u64) as usize).collect()
        })
        .collect()
}

/// A bootstrap replicate of a figure that a sweep may leave open on one side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Replicate {
    /// Below every value the sweep can give (the crossing lies below the swept range).
    Below,
    /// A value.
    Value(f64),
    /// Above every value the sweep can give.
    Above,
    /// Not defined in this resample.
    Undefined,
}

impl Replicate {
    fn rank(&self) -> (u8, f64) {
        match self {
            Replicate::Below => (0, 0.0),
            Replicate::Value(v) => (1, *v),
            Replicate::Above => (2, 0.0),
            Replicate::Undefined => (3, 0.0),
        }
    }
}

/// The ends of the 95 % percentile interval of the defined replicates by nearest rank (the
/// ⌈0.025 n⌉-th and ⌈0.975 n⌉-th smallest, censored replicates ranked below and above every
/// value): `None` with no defined replicate. An end may itself be censored.
pub fn percentile_95_ends(reps: &[Replicate]) -> Option<(Replicate, Replicate)> {
    let mut r: Vec<Replicate> = reps.iter().copied().filter(|x| *x != Replicate::Undefined).collect();
    if r.is_empty() {
        return None;
    }
    r.sort_by(|a, b| {
        let (ka, va) = a.rank();
        let (kb, vb) = b.rank();
        ka.cmp(&kb).then(va.total_cmp(&vb))
    });
    let n = r.len();
    let at = |q: f64| r[((q * n as f64).ceil() as usize).clamp(1, n) - 1];
    Some((at(0.025), at(0.975)))
}

/// The 95 % percentile interval of the defined replicates by nearest rank
/// ([`percentile_95_ends`]): its ends are replicates, so it lies inside any bounds the figure
/// has. An end that falls on a censored replicate is `None` (outside the sweep). `(None, None)`
/// with no defined replicate.
pub fn percentile_95(reps: &[Replicate]) -> (Option<f64>, Option<f64>) {
    let value = |r: Replicate| match r {
        Replicate::Value(v) => Some(v),
        _ => None,
    };
    percentile_95_ends(reps).map_or((None, None), |(lo, hi)| (value(lo), value(hi)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resamples_are_fixed_and_uniform() {
        let a = resamples(7, 5, 3000);
        assert_eq!(a, resamples(7, 5, 3000), "same seed, same resamples");
        assert_ne!(a, resamples(8, 5, 3000));
        // Each index is drawn with probability 1/5: 15 000 draws, counts within 4 sigma.
        let mut count = [0usize; 5];
        for r in &a {
            assert_eq!(r.len(), 5);
            for &k in r {
                count[k] += 1;
            }
        }
        let sigma = (15_000.0 * 0.2 * 0.8f64).sqrt();
        for c in count {
            assert!((c as f64 - 3000.0).abs() < 4.0 * sigma, "{count:?}");
        }
    }

    #[test]
    fn the_percentile_interval_takes_nearest_ranks_and_censoring() {
        let v: Vec<Replicate> = (1..=1000).map(|i| Replicate::Value(f64::from(i))).collect();
        assert_eq!(percentile_95(&v), (Some(25.0), Some(975.0)));
        let mut c = v.clone();
        for x in c.iter_mut().take(30) {
            *x = Replicate::Below;
        }
        assert_eq!(percentile_95(&c), (None, Some(975.0)), "the low end falls among the censored");
        c.push(Replicate::Undefined);
        assert_eq!(percentile_95(&c), (None, Some(975.0)), "undefined replicates are left out");
        assert_eq!(percentile_95(&[Replicate::Undefined]), (None, None));
        assert_eq!(percentile_95(&[Replicate::Value(3.0)]), (Some(3.0), Some(3.0)));
    }
}
