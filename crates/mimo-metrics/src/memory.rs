//! How much memory a score takes, so that a scoring interval whose score would not fit in the
//! budget of a `mimo` command is refused before anything is read (docs/design.md §7 "Bounds").
//!
//! A score holds every row of its tables until they are written: per run and scoring time one
//! `track_metrics` row, an `assignments` row per present truth, and per radar a usage row and
//! five `usage_by_purpose` rows, with the sums and means they are made from. Measured peak
//! resident memory of `mimo score --no-charts` (`/usr/bin/time -v`, 10⁵–6·10⁵ scoring times):
//! 2.6 kB per run and scoring time with 1 radar and 1 target, 9.0 kB with 4 radars and 4 targets
//! (scenario 1), 9.3 kB with 4 radars and 7 targets (scenario 7); charts add nothing to the peak.
//! [`score_memory_bytes`] is a linear fit that lies above each of them.

/// Memory one `mimo` command may use (docs/design.md §7): 4 GiB.
pub const MEMORY_BUDGET_BYTES: u64 = 4 << 30;

/// Bytes per run and scoring time, before radars and targets.
const BYTES_PER_RUN_TIME: f64 = 512.0;
/// Bytes per run, scoring time and radar.
const BYTES_PER_RADAR: f64 = 2100.0;
/// Bytes per run, scoring time and target.
const BYTES_PER_TARGET: f64 = 128.0;
/// What the command holds whatever the interval (code, tables' metadata, thread stacks).
const BASE_BYTES: f64 = 64.0 * 1024.0 * 1024.0;

/// Estimated peak memory (bytes) of scoring `runs` runs of `times_per_run` scoring times each,
/// with `radars` radars and `targets` targets.
pub fn score_memory_bytes(runs: u64, times_per_run: f64, radars: usize, targets: usize) -> f64 {
    let per_time = BYTES_PER_RUN_TIME + BYTES_PER_RADAR * radars as f64 + BYTES_PER_TARGET * targets as f64;
    BASE_BYTES + runs as f64 * times_per_run * per_time
}

/// The most scoring times per run that fit in [`MEMORY_BUDGET_BYTES`] (at least 0).
pub fn max_times_in_budget(runs: u64, radars: usize, targets: usize) -> f64 {
    let one = score_memory_bytes(runs, 1.0, radars, targets) - BASE_BYTES;
    ((MEMORY_BUDGET_BYTES as f64 - BASE_BYTES) / one).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The measurements quoted in the module docs: the estimate lies above each.
    #[test]
    fn the_estimate_covers_the_measured_peaks() {
        // (runs, scoring times per run, radars, targets, measured peak RSS in kB)
        let measured = [
            (1, 6.0e5, 1, 1, 1_571_228.0),
            (1, 6.0e4, 1, 1, 172_396.0),
            (1, 1.0e5, 4, 4, 897_268.0),
            (1, 1.0e5, 4, 7, 932_400.0),
            (2, 1.0e5, 4, 7, 1_819_792.0),
        ];
        for (runs, n, radars, targets, kb) in measured {
            let est = score_memory_bytes(runs, n, radars, targets);
            let peak = kb * 1024.0;
            assert!(est >= peak && est <= 1.5 * peak, "{runs} × {n} × {radars}/{targets}: {est} for {peak}");
        }
    }

    #[test]
    fn the_most_times_in_budget_fill_it() {
        let n = max_times_in_budget(2, 4, 7);
        let b = score_memory_bytes(2, n, 4, 7);
        assert!((b - MEMORY_BUDGET_BYTES as f64).abs() < 1.0, "{b}");
        // Two 1000-s runs of scenario 7 fit at 5 ms, not at 0.1 ms.
        assert!(1000.0 / 5e-3 < n && n < 1000.0 / 1e-4, "{n}");
    }
}
