//! `mimo score`.

use crate::CliError;
use crate::cmd_track::scenario_of;
use mimo_metrics::{MetricsError, ScoreInput, ScoreOptions};
use mimo_store::layout::{RunDir, ScoreDir};
use mimo_store::manifest::Manifest;
use mimo_store::output::OutputLock;
use mimo_store::rundir::replace_dir_locked;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Score a run: track metrics, usage metrics, summary.json and charts into RUN/score/.
///
/// Reads RUN's tracks and the truth and dwells of RUN (or of its parent, for a `mimo track`
/// output). A truth is scorable when some radar could see it (horizon, scan limit, instrumented
/// range). At every scoring time truths and live confirmed tracks are paired by a gated,
/// globally optimal assignment. RUN/score/ is derived and always reproducible, so it is
/// replaced (and the command says so).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run directory to score.
    pub run: PathBuf,
    /// Scoring interval in seconds.
    #[arg(long, default_value_t = 1.0, value_name = "SECONDS")]
    pub interval: f64,
    /// Truth–track assignment gate in metres.
    #[arg(long, default_value_t = 1000.0, value_name = "METRES")]
    pub gate: f64,
    /// OSPA/GOSPA cut-off c in metres.
    #[arg(long, default_value_t = 1000.0, value_name = "METRES")]
    pub ospa_c: f64,
    /// OSPA/GOSPA order p (≥ 1).
    #[arg(long, default_value_t = 2.0, value_name = "P")]
    pub ospa_p: f64,
    /// Skip the charts (tables and summary.json only).
    #[arg(long)]
    pub no_charts: bool,
    /// Worker threads [default: all cores].
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Print nothing but errors.
    #[arg(long)]
    pub quiet: bool,
}

/// Largest gate and OSPA cut-off (m): about the earth's diameter.
pub const MAX_DISTANCE_M: f64 = 1.3e7;
/// Largest OSPA/GOSPA order: c^p must stay finite (docs/design.md §6).
pub const MAX_OSPA_P: f64 = 20.0;

/// The scoring interval against the memory budget: every row of a score is held until it is
/// written, so the interval sets the memory (mimo_metrics::memory).
fn check_memory(a: &Args, runs: u32, duration_s: f64, scenario: &mimo_scenario::Scenario) -> Result<(), CliError> {
    use mimo_metrics::memory::{MEMORY_BUDGET_BYTES, max_times_in_budget, score_memory_bytes};
    let (radars, targets) = (scenario.ships.len(), scenario.targets.len());
    let times = duration_s / a.interval;
    let bytes = score_memory_bytes(u64::from(runs), times, radars, targets);
    if bytes <= MEMORY_BUDGET_BYTES as f64 {
        return Ok(());
    }
    let gib = |b: f64| b / f64::from(1u32 << 30);
    Err(CliError::input(format!(
        "--interval: {} s gives {times:.3e} scoring times in each of {runs} run(s) of {radars} radar(s) and \
         {targets} target(s), about {:.1} GiB to score; the memory budget is {:.0} GiB (an interval of at least {:.2e} s)",
        a.interval,
        gib(bytes),
        gib(MEMORY_BUDGET_BYTES as f64),
        duration_s / max_times_in_budget(u64::from(runs), radars, targets)
    )))
}

/// The scoring options, named as the user typed them (docs/decisions/0035-bounds-and-exit-statuses.md).
fn check_options(a: &Args, duration_s: f64) -> Result<(), CliError> {
    let i = a.interval;
    if !(i.is_finite() && i > 0.0) {
        return Err(CliError::input(format!("--interval: expected a positive number of seconds, got {i}")));
    }
    let max = mimo_metrics::MAX_SCORING_TIMES;
    if duration_s / i > max {
        return Err(CliError::input(format!(
            "--interval: {i} s gives {:.1e} scoring times over the run's {duration_s} s; at most {max:e} \
             (an interval of at least {:e} s)",
            duration_s / i,
            duration_s / max
        )));
    }
    for (flag, v) in [("--gate", a.gate), ("--ospa-c", a.ospa_c)] {
        if !(v.is_finite() && v > 0.0 && v <= MAX_DISTANCE_M) {
            return Err(CliError::input(format!("{flag}: expected metres in (0, {MAX_DISTANCE_M:e}], got {v}")));
        }
    }
    let p = a.ospa_p;
    if !(p.is_finite() && (1.0..=MAX_OSPA_P).contains(&p)) {
        return Err(CliError::input(format!("--ospa-p: expected an order in [1, {MAX_OSPA_P}], got {p}")));
    }
    Ok(())
}

fn metrics_err(e: MetricsError) -> CliError {
    if e.is_bad_input() { CliError::Input(e.to_string()) } else { CliError::Other(e.to_string()) }
}

pub fn run(a: Args) -> Result<(), CliError> {
    let t0 = Instant::now();
    crate::cmd_simulate::check_threads(a.threads)?;
    let manifest = Manifest::read(&a.run)?;
    check_options(&a, manifest.duration_s)?;
    // One scorer per run, and no `simulate --force` replacing the run while it is read: the lock
    // on RUN/score is taken before any work, and what RUN/score holds is checked to be mimo's.
    let score_dir = RunDir::new(&a.run).score();
    let lock = OutputLock::acquire(score_dir.root())?;
    mimo_store::output::check_score_dir(&score_dir)?;
    // Files of an earlier score that were damaged are replaced with the rest of it.
    let damaged = mimo_store::recognise::damaged_in_score_dir(&score_dir)?;
    let src = mimo_store::lineage::source_dir(&a.run, &manifest)?;
    let scenario = scenario_of(&a.run, &manifest)?;
    check_memory(&a, manifest.runs, manifest.duration_s, &scenario)?;
    let radars: Vec<String> = scenario.ships.iter().map(|s| s.id.to_string()).collect();
    // Scoring needs the ships (what each radar can see), not the targets' flight: their truth is
    // the recorded truth table. `scenario_of` has validated the scenario.
    let ships = scenario.ships.clone();
    let scorable: mimo_metrics::ScorablePredicate =
        Box::new(move |t, pos, alt| ships.iter().any(|s| s.sees(t, pos, alt)));
    let input = ScoreInput::from_runs(&src, &a.run, scorable)
        .map_err(metrics_err)?
        .with_beams(mimo_study::beams::beam_geometry(&scenario));
    let opts = ScoreOptions {
        scenario: scenario.name.clone(),
        interval_s: a.interval,
        gate_m: a.gate,
        ospa_c_m: a.ospa_c,
        ospa_p: a.ospa_p,
        radars,
        threads: a.threads.unwrap_or(0),
        ..ScoreOptions::default()
    };
    let mut score = mimo_metrics::score(&input, &opts).map_err(metrics_err)?;
    // The registration error, when the source drew biases and the test article reported its
    // estimates (docs/design.md §6, "Registration error").
    let (biases_dir, estimates_dir) =
        (RunDir::new(&src).table_dir("biases"), RunDir::new(&a.run).table_dir("registration"));
    if biases_dir.is_dir() && estimates_dir.is_dir() {
        let biases: Vec<mimo_core::records::BiasRow> = mimo_store::read_table_dir(&src, "biases")?;
        let estimates: Vec<mimo_core::records::RegistrationRow> = mimo_store::read_table_dir(&a.run, "registration")?;
        mimo_metrics::attach_registration(&mut score, &biases, &estimates);
    }
    // Covariances accepted only after their repair (docs/design.md §7): counted in the summary
    // and said in one warning line.
    let mut repairs = mimo_store::checked::Repairs::default();
    for f in &input.tracks {
        repairs.add(mimo_store::checked::repaired_covariances(f, &mimo_store::schema::TRACKS)?);
    }
    if repairs.rows > 0 {
        score.summary.repaired_covariances.insert("tracks".to_string(), repairs.rows);
    }
    let t_score = t0.elapsed().as_secs_f64();
    let replaced = replace_dir_locked(score_dir.root(), &lock, |dir: &Path| -> Result<(), CliError> {
        // The tables and the charts are written side by side (separate files, each made from
        // `score` alone, so the bytes do not depend on it); the tables' error comes first.
        let charts = ScoreDir::new(dir).charts();
        let (tables, charts) = std::thread::scope(|s| {
            let charts = (!a.no_charts).then(|| s.spawn(|| mimo_report::render_all(&score, &charts)));
            let tables = mimo_metrics::write_outputs(&score, dir);
            (tables, charts.map(|c| c.join()))
        });
        tables.map_err(metrics_err)?;
        match charts {
            None | Some(Ok(Ok(_))) => Ok(()),
            Some(Ok(Err(e))) => Err(CliError::Other(e.to_string())),
            Some(Err(panic)) => std::panic::resume_unwind(panic),
        }
    })?;
    if let Some(w) = repairs.warning(&format!("{} tracks", a.run.display())).filter(|_| !a.quiet) {
        eprintln!("{w}");
    }
    if !a.quiet {
        let s = &score.summary;
        let pct = |x: Option<f64>| x.map(|v| format!("{:.2} %", 100.0 * v)).unwrap_or_else(|| "n/a".into());
        let num = |x: Option<f64>| x.map(|v| format!("{v:.1}")).unwrap_or_else(|| "n/a".into());
        if replaced {
            crate::outln!("replaced {}", score_dir.root().display());
        }
        for d in &damaged {
            crate::outln!("replaced the damaged {} of an earlier score", d.display());
        }
        crate::outln!(
            "{}: {} run(s), completeness {} (challenge {} %: {}), redundant {}, spurious {}, breaks {:.1}, switches {:.1}, RMSE {} m / {} m/s",
            s.scenario,
            s.runs,
            pct(s.track.completeness),
            100.0 * s.challenge.completeness_required,
            if s.challenge.met { "met" } else { "NOT met" },
            pct(s.track.redundant_ratio),
            pct(s.track.spurious_ratio),
            s.track.breaks,
            s.track.switches,
            num(s.track.position_rmse_m),
            num(s.track.velocity_rmse_mps),
        );
        if let Some(r) = &s.registration {
            let nees = r.nees_mean.map(|v| format!("{v:.2}")).unwrap_or_else(|| "n/a".into());
            crate::outln!(
                "registration error (RMS over {} estimates): range {:.2} m, u {:.2e}, v {:.2e}, heading {:.3}°; mean NEES {} (χ²₄: 4)",
                r.estimates,
                r.range_error_rms_m,
                r.u_error_rms,
                r.v_error_rms,
                r.heading_error_rms_deg,
                nees
            );
        }
        crate::outln!(
            "usage per run: energy {:.0} J ({:.0} J by the TA), dwell time {:.1} s ({:.1} s by the TA); scored in {:.2} s -> {}",
            s.usage.totals.total_energy_j,
            s.usage.totals.ta_energy_j,
            s.usage.totals.total_dwell_time_s,
            s.usage.totals.ta_dwell_time_s,
            t_score,
            score_dir.root().display()
        );
    }
    Ok(())
}
