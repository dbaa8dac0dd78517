//! # mimo-metrics
//!
//! Scores a run directory: truth–track assignment, track metrics, radar usage metrics and Monte
//! Carlo averaging (docs/design.md §6). [`score`] reads the `truth`, `dwells` and `tracks` Parquet
//! tables (any number of files each, one per Monte Carlo run by convention) and returns a
//! [`Score`]; [`write_outputs`] writes `score/track_metrics.parquet`, the other tables and
//! `score/summary.json`. Charts are drawn by `mimo-report` from the plain Rust rows of [`Score`].
//!
//! ## Scoring times and intervals
//!
//! Scoring times are `t_k = k · interval_s` for `k = 1, 2, …, K`, where `K` is the last `k` with
//! `t_k` not after the run's last truth sample. Scoring time `t_k` closes scoring interval
//! `k = [t_k − interval_s, t_k)`: usage in interval `k` is normalized by the number of objects
//! scorable at `t_k`. Runs are the run ids of the truth table; a `tracks` or `dwells` row of any
//! other run is an input error.
//!
//! ## Truth and tracks at a scoring time
//!
//! * **Truth** at `t_k` comes from the truth samples: the sample itself when `t_k` falls on one
//!   (the usual case: 10 Hz truth, 1 s interval), otherwise cubic Hermite interpolation of the
//!   position using the sampled velocities (exact for constant velocity) and linear interpolation
//!   of velocity and altitude. A target is *present* only inside its own sampled span.
//! * A truth is **scorable** when the caller's predicate `(t_s, position ECEF, alt_m)` says so
//!   (the CLI builds it from the scenario's radars: horizon, scan limit, instrumented range).
//! * A **track** is live from the time of its first `confirmed` row (inclusive) until the time of
//!   its `deleted` row (exclusive), or to the end if it has none. Its state at `t_k` is its latest
//!   row at or before `t_k` extrapolated at constant velocity to `t_k`. Rows after the `deleted`
//!   row are ignored; a track deleted before it was confirmed never counts.
//!
//! ## Assignment
//!
//! At each scoring time the scorable truths and the live tracks are paired one-to-one by an exact
//! gated assignment ([`mimo_core::assign::assign_with_miss`]) on 3-D ECEF position distance. A
//! pair is allowed when its distance is at most `gate_m`. Among all allowed pairings the one with
//! the **most pairs** is chosen, and among those the one with the **least total distance**
//! (implemented with a per-truth miss cost larger than any possible total distance). Maximum
//! cardinality first is chosen because track completeness is the benchmark's headline figure: a
//! truth is never left unassigned to make another pair a little tighter.
//!
//! ## Track metrics at one scoring time (table `track_metrics`, one row per run and time)
//!
//! With `N` scorable truths, `M` live tracks and `A` assigned pairs:
//!
//! | column | definition |
//! |---|---|
//! | `completeness` | `A / N`; **null when `N = 0`** |
//! | `redundant_ratio` | unassigned tracks within the gate of some *scorable* truth ÷ `N`; null when `N = 0` |
//! | `spurious_ratio` | tracks within the gate of *no* truth ÷ `M`; null when `M = 0`. Every present truth counts here, scorable or not: a track on a real target that no radar can currently see (e.g. coasting below the horizon) is not spurious |
//! | `breaks` | truths assigned at the previous scoring time, scorable now and unassigned now. A truth that merely stops being scorable is not broken |
//! | `switches` | truths assigned now to a track other than the one they were *last* assigned to (at any earlier time, across gaps): a drop followed by a pick-up by another track is one break and one switch |
//! | `cum_breaks`, `cum_switches` | running sums within the run |
//! | `position_rmse_m`, `velocity_rmse_mps` | RMS of ‖Δposition‖ and ‖Δvelocity‖ (ECEF) over the assigned pairs; null when `A = 0`. `position_sq_sum_m2` and `velocity_sq_sum_m2ps2` hold the sums of squares for pooling |
//! | `ospa_m`, `gospa_m` | OSPA and GOSPA (α = 2) with cut-off `ospa_c_m` and order `ospa_p` between the scorable truths and all live tracks (see [`ospa`]); null when `N = M = 0` |
//!
//! Undefined values are nulls in Parquet and `null` in JSON (never a number that could be
//! mistaken for a result), and they are left out of every average.
//!
//! ## Averages (table `track_metrics_mean` and `summary.json`)
//!
//! * Per scoring time over runs: mean of each ratio over the runs where it is defined; RMSE pooled
//!   over all assigned pairs of all runs at that time; cumulative counts averaged over runs.
//! * Summary `completeness` and `redundant_ratio`: mean over all (run, scoring time) with `N > 0`;
//!   `spurious_ratio`: mean over all (run, time) with `M > 0`; `ospa`/`gospa` means over all
//!   (run, time) where defined. `breaks` and `switches`: the per-run totals averaged over runs.
//!   `position_rmse_m` and `velocity_rmse_mps`: pooled over every assigned pair of every time and
//!   run (each pair weighs equally). Undefined summary figures are `null`; the challenge is `met`
//!   only when `completeness` is defined and at least `completeness_required`.
//!
//! ## Usage (seed paper eqs. 1–6)
//!
//! Only transmit participation costs: rows with role `tx` or `txrx`; `rx` rows cost nothing even
//! if they carry a duration. For radar `m`, interval `j` and run `k`, the raw sums are
//! `S_T[m,j,k] = Σ duration_s` and `S_E[m,j,k] = Σ energy_j` over `m`'s transmit dwells whose
//! start `t_s` lies in interval `j`; the seed paper's normalized figures are
//! `T[m,j] = mean_k S_T[m,j,k] / N[j,k]` and `E[m,j]` likewise, with `N[j,k]` the scorable object
//! count at `t_j` in run `k`.
//!
//! * An interval with **no scorable object** (`N = 0`) has a **null normalized value** in that run
//!   (left out of the mean over runs; null if every run has `N = 0` there); its **raw sums are still
//!   reported** and still count in every total.
//! * Table `usage`: per radar and interval, the raw sums averaged over runs (`dwell_time_s`,
//!   `energy_j`), the normalized figures (`dwell_time_per_object_s`, `energy_per_object_j`), the
//!   cumulative raw sums (`cum_*`), each also for TA-requested dwells alone (`ta_*`).
//! * Table `usage_total`: the same summed over radars per interval (the paper's `T[j]`, `E[j]`).
//! * Table `usage_radar` and `summary.json` `usage.per_radar`: sensor totals `T[m]`, `E[m]` over
//!   the whole run (not normalized; every dwell, including any after the last scoring time),
//!   averaged over runs. `total_*` sum them over radars.
//! * Radars: every radar named in the dwells table (any role) plus [`ScoreOptions::radars`];
//!   a radar without transmit dwells reports zeros.
//! * **By purpose** (table `usage_by_purpose`, `summary.json` `usage.by_purpose` and each
//!   `per_run[].by_purpose`): every transmit row attributed to `search`, `confirm_true`,
//!   `confirm_false`, `track` or `track_false` by whether a truth was in its beam and range
//!   window ([`purpose_rule`], with the radars' faces of [`ScoreInput::beams`]); one row per run,
//!   radar, scoring interval and purpose, zeros included; the summary's totals cover every dwell
//!   and add up, over purposes, to the usage totals.
//!
//! ## Errors
//!
//! Input problems are [`MetricsError`] variants naming the file, the column, the row and what was
//! expected. Every file is read through the store's checks (`mimo_store::checked`, wrapped in
//! [`MetricsError::Table`]): the table's name and schema version in the metadata, every column of
//! the table's spec with exactly its type, each value keeping its column's rule (finite numbers,
//! non-negative dwell times and energies, labels of the enumerations, radar ids, covariances),
//! rows of `run-K.parquet` of run K. Truth and tracks are read with the store's reader of every
//! run table (`mimo_store::table_chunks`), which also checks their table rules (times out of
//! order, rows of one track at one time that `n_updates` cannot order) and words every error as
//! `mimo plot` and `mimo track` do. Beyond them: a missing table, a run of the tracks or dwells
//! that the truth does not have, the dwells' rule broken (start times out of order per radar).
#![warn(missing_docs)]

mod dwell_file;
mod dwell_pass;
mod dwell_read;
mod dwell_rows;
mod dwell_sums;
mod error;
mod first_track;
mod frame;
mod load;
mod mean;
pub mod memory;
pub mod ospa;
mod ospa_power;
mod output;
mod parallel;
mod parts;
mod purpose;
mod purpose_read;
pub mod purpose_rule;
mod read;
mod registration;
mod results;
mod row_order;
mod rules;
mod track_metrics;
mod track_results;
mod truth_reach;
mod usage;

pub use error::MetricsError;
pub use output::{NamedList, write_outputs};
pub use purpose_rule::{BeamGeometry, Purpose};
pub use results::*;

pub use dwell_rows::DwellRows;
use glam::DVec3;
use mean::GroupMean;
use mimo_store::layout::RunDir;
use read::list_parquet;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use track_metrics::TargetTally;
use track_results::{TrackResults, track_results_by_parts, track_results_whole};

/// Decides whether a truth is scorable: `(t_s, position ECEF (m), altitude (m)) → bool`.
pub type ScorablePredicate = Box<dyn Fn(f64, DVec3, f64) -> bool + Send + Sync>;

/// A predicate that makes every present truth scorable (for tests and quick looks).
pub fn always_scorable() -> ScorablePredicate {
    Box::new(|_, _, _| true)
}

/// Where the input tables are, and which truths are scorable.
pub struct ScoreInput {
    /// Truth table files (`truth/*.parquet`).
    pub truth: Vec<PathBuf>,
    /// Dwell table files (`dwells/*.parquet`).
    pub dwells: Vec<PathBuf>,
    /// Track table files (`tracks/*.parquet`).
    pub tracks: Vec<PathBuf>,
    /// Scorability of a truth at a time.
    pub scorable: ScorablePredicate,
    /// The radars' faces and beams, for the usage by purpose ([`purpose_rule`]).
    pub beams: BeamGeometry,
}

impl ScoreInput {
    /// Every `*.parquet` file of the three table directories, sorted by name. A directory that is
    /// missing or holds no Parquet file is [`MetricsError::MissingTable`].
    pub fn from_dirs(
        truth_dir: &Path,
        dwells_dir: &Path,
        tracks_dir: &Path,
        scorable: ScorablePredicate,
    ) -> Result<ScoreInput, MetricsError> {
        Ok(ScoreInput {
            truth: list_parquet("truth", truth_dir)?,
            dwells: list_parquet("dwells", dwells_dir)?,
            tracks: list_parquet("tracks", tracks_dir)?,
            scorable,
            beams: BeamGeometry::none(),
        })
    }

    /// The same input with the radars' faces and beams `beams` (without them, every
    /// confirmation, track and MIMO look counts as holding no truth).
    pub fn with_beams(self, beams: BeamGeometry) -> ScoreInput {
        ScoreInput { beams, ..self }
    }

    /// `run_dir/truth`, `run_dir/dwells` and `run_dir/tracks`.
    pub fn from_run_dir(run_dir: &Path, scorable: ScorablePredicate) -> Result<ScoreInput, MetricsError> {
        Self::from_runs(run_dir, run_dir, scorable)
    }

    /// Truth and dwells of the run directory `source` (a `mimo track` output's parent, or the run
    /// itself), tracks of the run directory `run`.
    pub fn from_runs(source: &Path, run: &Path, scorable: ScorablePredicate) -> Result<ScoreInput, MetricsError> {
        let (src, run) = (RunDir::new(source), RunDir::new(run));
        Self::from_dirs(&src.table_dir("truth"), &src.table_dir("dwells"), &run.table_dir("tracks"), scorable)
    }
}

/// Most scoring times a run may have (docs/decisions/0035-bounds-and-exit-statuses.md): 10^7 times (a 1000 s run at
/// 0.1 ms) already take minutes; more only exhausts memory.
pub const MAX_SCORING_TIMES: f64 = 1e7;

/// Scoring options (the `mimo score` flags).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScoreOptions {
    /// Scenario name, copied to the summary.
    pub scenario: String,
    /// Scoring interval (s), default 1.
    pub interval_s: f64,
    /// Assignment gate (m), default 1000.
    pub gate_m: f64,
    /// OSPA/GOSPA cut-off c (m), default 1000.
    pub ospa_c_m: f64,
    /// OSPA/GOSPA order p, default 2.
    pub ospa_p: f64,
    /// Track completeness the challenge requires, default 0.98.
    pub completeness_required: f64,
    /// Radars to report even if they have no dwell (e.g. the scenario's radars). Radars found in
    /// the dwells table are always reported.
    pub radars: Vec<String>,
    /// Worker threads for the per-run assignment loop (0 = all cores).
    pub threads: usize,
}

impl Default for ScoreOptions {
    fn default() -> Self {
        ScoreOptions {
            scenario: String::new(),
            interval_s: 1.0,
            gate_m: 1000.0,
            ospa_c_m: 1000.0,
            ospa_p: 2.0,
            completeness_required: 0.98,
            radars: Vec::new(),
            threads: 0,
        }
    }
}

impl ScoreOptions {
    fn validate(&self) -> Result<(), MetricsError> {
        let bad = |option: &'static str, value: f64, expected: &'static str| {
            Err(MetricsError::InvalidOption { option, value: value.to_string(), expected })
        };
        if !(self.interval_s.is_finite() && self.interval_s > 0.0) {
            return bad("interval_s", self.interval_s, "a positive number of seconds");
        }
        if !(self.gate_m.is_finite() && self.gate_m > 0.0) {
            return bad("gate_m", self.gate_m, "a positive number of metres");
        }
        if !(self.ospa_c_m.is_finite() && self.ospa_c_m > 0.0) {
            return bad("ospa_c_m", self.ospa_c_m, "a positive number of metres");
        }
        if !(self.ospa_p.is_finite() && self.ospa_p >= 1.0) {
            return bad("ospa_p", self.ospa_p, "a number >= 1");
        }
        if !(0.0..=1.0).contains(&self.completeness_required) {
            return bad("completeness_required", self.completeness_required, "a fraction between 0 and 1");
        }
        for r in &self.radars {
            if mimo_core::ids::RadarId::parse(r).is_none() {
                return Err(MetricsError::InvalidOption {
                    option: "radars",
                    value: r.clone(),
                    expected: "radar ids R1, R2, …",
                });
            }
        }
        Ok(())
    }
}

fn mean(values: impl Iterator<Item = f64>) -> Option<f64> {
    let (s, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    (n > 0).then(|| s / n as f64)
}

/// Add the registration error to `score` (docs/design.md §6, "Registration error"): the drawn
/// `biases` of its runs against a test article's `estimates`. Nothing changes when either is
/// empty.
pub fn attach_registration(
    score: &mut Score,
    biases: &[mimo_core::records::BiasRow],
    estimates: &[mimo_core::records::RegistrationRow],
) {
    score.registration = registration::registration_errors(biases, estimates);
    score.summary.registration = registration::registration_summary(&score.registration);
}

/// Score the tables of `input` with `opts`. See the crate docs for every definition.
pub fn score(input: &ScoreInput, opts: &ScoreOptions) -> Result<Score, MetricsError> {
    score_from(input, opts, None)
}

/// [`score`] of one run whose dwells were reduced as the run made them ([`DwellRows`]) instead
/// of read from files (`input.dwells` is not read): a study item that does not keep its run's
/// tables (docs/decisions/0321-study-runs-scored-from-their-dwell-rows.md). The figures are
/// those of [`score`] on the run's dwells file, bit for bit.
pub fn score_with_dwell_rows(
    input: &ScoreInput,
    opts: &ScoreOptions,
    dwells: DwellRows,
) -> Result<Score, MetricsError> {
    score_from(input, opts, Some(dwells))
}

fn score_from(input: &ScoreInput, opts: &ScoreOptions, dwell_rows: Option<DwellRows>) -> Result<Score, MetricsError> {
    opts.validate()?;
    let threads = if opts.threads == 0 {
        std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)
    } else {
        opts.threads
    };
    // Part by part when the files allow it (memory follows one run per thread); any error there
    // is reported by the whole-recording path, so that it names the same file and row as ever.
    let by_parts = parts::split(&input.truth, &input.tracks)
        .and_then(|split| split.map(|s| track_results_by_parts(&s, input, opts, threads)).transpose());
    let tr = match by_parts {
        Ok(Some(tr)) => tr,
        Ok(None) => track_results_whole(input, opts, threads)?,
        Err(e) => {
            let whole = track_results_whole(input, opts, threads);
            // Only bad input may fail here, and the whole read must find it too.
            debug_assert!(whole.is_err(), "scoring by parts failed ({e}) on input the whole read accepts");
            whole?
        }
    };
    let run_set: BTreeSet<u32> = tr.runs.iter().copied().collect();
    let purpose_input = purpose::PurposeInput {
        dwells: &input.dwells,
        truth: &input.truth,
        geometry: &input.beams,
        interval_s: opts.interval_s,
        threads,
    };
    // The dwells read once for the usage sums and the usage by purpose.
    let mut dwells = match dwell_rows {
        Some(rows) => dwell_pass::DwellPass::from_rows(&purpose_input, rows),
        None => dwell_pass::DwellPass::run(&purpose_input, &run_set),
    };
    let (dwell_sums, dwell_radars) = dwells.usage_sums()?;
    let TrackResults { runs, target_names, track_metrics, assignments, tally, n_scorable } = tr;
    let track_metrics_mean = mean_over_runs(&track_metrics)?;

    // Usage.
    let mut radars: BTreeSet<String> = opts.radars.iter().cloned().collect();
    radars.extend(dwell_radars);
    let mut radars: Vec<String> = radars.into_iter().collect();
    usage::sort_radars(&mut radars);
    let u = usage::usage(
        &dwell_sums,
        &usage::UsageInput { interval_s: opts.interval_s, runs: &runs, radars: &radars, n_scorable: &n_scorable },
    )?;

    let n_times: BTreeMap<u32, usize> = n_scorable.iter().map(|(&run, n)| (run, n.len())).collect();
    let by_purpose = purpose::purpose_output(&dwells.purpose_sums()?, &runs, &radars, &n_times, opts.interval_s);

    let first_track = first_track::first_track_rows(&assignments);
    let mut summary = summarize(opts, &runs, &target_names, &track_metrics, &tally, &u)?;
    summary.usage.totals.by_purpose = by_purpose.mean;
    summary.first_track = first_track::first_track_summary(first_track.iter());
    let mut per_object_means = [GroupMean::default(), GroupMean::default(), GroupMean::default(), GroupMean::default()];
    for r in &mut summary.per_run {
        r.usage.by_purpose = by_purpose.per_run.get(&r.run).copied().unwrap_or_default();
        r.first_track = first_track::first_track_summary(first_track.iter().filter(|f| f.run == r.run));
        let per_object = u.per_object.get(&r.run).copied().unwrap_or([None; 4]);
        [
            r.usage.dwell_time_per_object_s,
            r.usage.energy_per_object_j,
            r.usage.ta_dwell_time_per_object_s,
            r.usage.ta_energy_per_object_j,
        ] = per_object;
        for (m, v) in per_object_means.iter_mut().zip(per_object) {
            m.push(v);
        }
    }
    let t = &mut summary.usage.totals;
    [t.dwell_time_per_object_s, t.energy_per_object_j, t.ta_dwell_time_per_object_s, t.ta_energy_per_object_j] =
        per_object_means.map(|m| m.value());
    Ok(Score {
        options: opts.clone(),
        runs,
        radars,
        track_metrics,
        track_metrics_mean,
        assignments,
        usage: u.per_interval,
        usage_total: u.total,
        usage_radar: u.per_radar,
        usage_run: u.per_run,
        usage_by_purpose: by_purpose.rows,
        first_track,
        registration: Vec::new(),
        summary,
    })
}

/// Average the per-run rows over runs at each scoring time `k` (rows of a time in row order,
/// [`GroupMean`]s; RMSE pooled over the assigned pairs of every run).
fn mean_over_runs(rows: &[TrackMetricsRow]) -> Result<Vec<TrackMetricsMeanRow>, MetricsError> {
    #[derive(Default)]
    struct Time {
        t_s: f64,
        ratios: [GroupMean; 5],
        counts: [GroupMean; 4],
        sq_sums: [GroupMean; 3],
    }
    let mut by_k: BTreeMap<u32, Time> = BTreeMap::new();
    for r in rows {
        let time = by_k.entry(r.k).or_insert_with(|| Time { t_s: r.t_s, ..Time::default() });
        for (m, v) in
            time.ratios.iter_mut().zip([r.completeness, r.redundant_ratio, r.spurious_ratio, r.ospa_m, r.gospa_m])
        {
            m.push(v);
        }
        for (m, v) in time.counts.iter_mut().zip([r.n_scorable, r.n_tracks, r.cum_breaks, r.cum_switches]) {
            m.push(Some(f64::from(v)));
        }
        for (m, v) in
            time.sq_sums.iter_mut().zip([r.position_sq_sum_m2, r.velocity_sq_sum_m2ps2, f64::from(r.n_assigned)])
        {
            m.push(Some(v));
        }
    }
    let rmse = |sq: f64, n: f64| (n > 0.0).then(|| (sq / n).sqrt());
    Ok(by_k
        .into_iter()
        .map(|(k, time)| {
            let [completeness, redundant_ratio, spurious_ratio, ospa_m, gospa_m] = time.ratios.map(|m| m.value());
            let [n_scorable_mean, n_tracks_mean, cum_breaks_mean, cum_switches_mean] =
                time.counts.map(|m| m.value().unwrap_or(0.0));
            let [position_sq, velocity_sq, n_assigned] = time.sq_sums.map(|m| m.sum());
            TrackMetricsMeanRow {
                k,
                t_s: time.t_s,
                runs: time.counts[0].count(),
                n_scorable_mean,
                n_tracks_mean,
                completeness,
                redundant_ratio,
                spurious_ratio,
                ospa_m,
                gospa_m,
                cum_breaks_mean,
                cum_switches_mean,
                position_rmse_m: rmse(position_sq, n_assigned),
                velocity_rmse_mps: rmse(velocity_sq, n_assigned),
            }
        })
        .collect())
}

/// A run's track-metric rows, by run (every run present, with no rows if it has none).
struct RowsByRun<'a> {
    rows: BTreeMap<u32, Vec<&'a TrackMetricsRow>>,
    none: Vec<&'a TrackMetricsRow>,
}

impl<'a> RowsByRun<'a> {
    fn new(runs: &[u32], rows: &'a [TrackMetricsRow]) -> RowsByRun<'a> {
        let mut by_run: BTreeMap<u32, Vec<&TrackMetricsRow>> = runs.iter().map(|&r| (r, Vec::new())).collect();
        for r in rows {
            by_run.entry(r.run).or_default().push(r);
        }
        RowsByRun { rows: by_run, none: Vec::new() }
    }

    fn of(&self, run: u32) -> &[&'a TrackMetricsRow] {
        self.rows.get(&run).unwrap_or(&self.none)
    }

    fn breaks(&self, run: u32) -> u32 {
        self.of(run).iter().map(|r| r.breaks).sum()
    }

    fn switches(&self, run: u32) -> u32 {
        self.of(run).iter().map(|r| r.switches).sum()
    }
}

/// RMSE pooled over the assigned pairs of `rows` (`sq`: a row's sum of squared errors).
fn pooled_rmse(rows: &[&TrackMetricsRow], sq: fn(&TrackMetricsRow) -> f64) -> Option<f64> {
    let n: u64 = rows.iter().map(|r| u64::from(r.n_assigned)).sum();
    (n > 0).then(|| (rows.iter().map(|r| sq(r)).sum::<f64>() / n as f64).sqrt())
}

/// The summary's usage: sensor totals per radar and their sums (usage by purpose left for the
/// caller).
fn usage_summary(u: &usage::UsageOutput) -> UsageSummary {
    let per_radar = NamedList(
        u.per_radar
            .iter()
            .map(|r| {
                let totals = SensorTotals {
                    dwell_time_s: r.dwell_time_s,
                    energy_j: r.energy_j,
                    ta_dwell_time_s: r.ta_dwell_time_s,
                    ta_energy_j: r.ta_energy_j,
                };
                (r.radar.clone(), totals)
            })
            .collect(),
    );
    let totals = UsageTotals::summed(per_radar.0.iter().map(|(_, t)| t));
    UsageSummary { per_radar, totals }
}

/// The track figures over `rows` (breaks and switches given).
fn track_figures<Count>(rows: &[&TrackMetricsRow], breaks: Count, switches: Count) -> TrackFigures<Count> {
    TrackFigures {
        completeness: mean(rows.iter().filter_map(|r| r.completeness)),
        redundant_ratio: mean(rows.iter().filter_map(|r| r.redundant_ratio)),
        spurious_ratio: mean(rows.iter().filter_map(|r| r.spurious_ratio)),
        breaks,
        switches,
        position_rmse_m: pooled_rmse(rows, |r| r.position_sq_sum_m2),
        velocity_rmse_mps: pooled_rmse(rows, |r| r.velocity_sq_sum_m2ps2),
    }
}

/// The summary of each run (its usage by purpose left for the caller).
fn run_summaries(runs: &[u32], by_run: &RowsByRun<'_>, u: &usage::UsageOutput) -> Vec<RunSummary> {
    let mut usage_by_run: BTreeMap<u32, Vec<&SensorTotals>> = BTreeMap::new();
    for x in &u.per_run {
        usage_by_run.entry(x.run).or_default().push(&x.totals);
    }
    runs.iter()
        .map(|&run| {
            let rr = by_run.of(run);
            RunSummary {
                run,
                scoring_times: rr.len() as u32,
                track: track_figures(rr, by_run.breaks(run), by_run.switches(run)),
                ospa_m: mean(rr.iter().filter_map(|r| r.ospa_m)),
                gospa_m: mean(rr.iter().filter_map(|r| r.gospa_m)),
                gospa_localisation_m: mean(rr.iter().filter_map(|r| r.gospa_localisation_m)),
                gospa_missed: mean(rr.iter().filter_map(|r| r.gospa_missed.map(f64::from))),
                gospa_false: mean(rr.iter().filter_map(|r| r.gospa_false.map(f64::from))),
                usage: usage_by_run
                    .get(&run)
                    .map_or_else(UsageTotals::default, |v| UsageTotals::summed(v.iter().copied())),
                first_track: FirstTrackSummary::default(),
            }
        })
        .collect()
}

/// The summary of each target (tallies over every run).
fn target_summaries(target_names: &[String], tally: &[TargetTally], n_runs: f64) -> NamedList<TargetSummary> {
    NamedList(
        target_names
            .iter()
            .zip(tally)
            .map(|(name, t)| {
                (
                    name.clone(),
                    TargetSummary {
                        scorable_times: t.scorable,
                        completeness: (t.scorable > 0).then(|| t.assigned as f64 / t.scorable as f64),
                        breaks: t.breaks as f64 / n_runs,
                        switches: t.switches as f64 / n_runs,
                    },
                )
            })
            .collect(),
    )
}

fn summarize(
    opts: &ScoreOptions,
    runs: &[u32],
    target_names: &[String],
    rows: &[TrackMetricsRow],
    tally: &[TargetTally],
    u: &usage::UsageOutput,
) -> Result<Summary, MetricsError> {
    let n_runs = runs.len().max(1) as f64;
    let all: Vec<&TrackMetricsRow> = rows.iter().collect();
    let by_run = RowsByRun::new(runs, rows);
    let track: TrackSummary = track_figures(
        &all,
        runs.iter().map(|&r| f64::from(by_run.breaks(r))).sum::<f64>() / n_runs,
        runs.iter().map(|&r| f64::from(by_run.switches(r))).sum::<f64>() / n_runs,
    );
    let completeness = track.completeness;
    let usage = usage_summary(u);
    let per_run = run_summaries(runs, &by_run, u);
    let per_target = target_summaries(target_names, tally, n_runs);
    Ok(Summary {
        scenario: opts.scenario.clone(),
        runs: runs.len() as u32,
        interval_s: opts.interval_s,
        gate_m: opts.gate_m,
        track,
        usage,
        challenge: Challenge {
            completeness_required: opts.completeness_required,
            met: completeness.is_some_and(|c| c >= opts.completeness_required),
        },
        first_track: FirstTrackSummary::default(),
        ospa: DistanceSummary {
            c_m: opts.ospa_c_m,
            p: opts.ospa_p,
            alpha: None,
            mean_m: mean(all.iter().filter_map(|r| r.ospa_m)),
        },
        gospa: DistanceSummary {
            c_m: opts.ospa_c_m,
            p: opts.ospa_p,
            alpha: Some(2.0),
            mean_m: mean(all.iter().filter_map(|r| r.gospa_m)),
        },
        scoring: ScoringInfo {
            run_ids: runs.to_vec(),
            scoring_times: rows.iter().map(|r| r.k).max().unwrap_or(0),
            assignment: "exact gated one-to-one assignment on ECEF position distance: maximum number of pairs, then minimum total distance",
            undefined_values: "null: a figure with no defined value (no scorable truth, no track) is null and left out of averages",
        },
        per_run,
        per_target,
        registration: None,
        repaired_covariances: Default::default(),
    })
}
