//! `mimo score`.

use crate::CliError;
use crate::cmd_track::scenario_of;
use mimo_metrics::{MetricsError, ScoreInput, ScoreOptions};
use mimo_sim::World;
use mimo_store::manifest::Manifest;
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

fn metrics_err(e: MetricsError) -> CliError {
    if e.is_bad_input() { CliError::Input(e.to_string()) } else { CliError::Other(e.to_string()) }
}

/// The run directory holding truth and dwells: RUN itself, or its parent chain.
fn source_dir(run: &Path, m: &Manifest) -> Result<PathBuf, CliError> {
    let Some(parent) = &m.parent else { return Ok(run.to_path_buf()) };
    let given = PathBuf::from(parent);
    let candidates = [given.clone(), run.parent().map(|d| d.join(&given)).unwrap_or_else(|| given.clone())];
    for c in candidates {
        if c.join("manifest.json").is_file() {
            let pm = Manifest::read(&c)?;
            return source_dir(&c, &pm);
        }
    }
    Err(CliError::input(format!(
        "{}: field 'parent': run directory '{parent}' not found (expected the run this one was tracked from)",
        run.join("manifest.json").display()
    )))
}

pub fn run(a: Args) -> Result<(), CliError> {
    let t0 = Instant::now();
    if a.threads == Some(0) {
        return Err(CliError::input("--threads: expected at least 1"));
    }
    let manifest = Manifest::read(&a.run)?;
    let src = source_dir(&a.run, &manifest)?;
    let scenario = scenario_of(&a.run, &manifest)?;
    let radars: Vec<String> = scenario.ships.iter().map(|s| s.id.to_string()).collect();
    let world = World::new(scenario)?;
    let ships = world.scenario.ships.clone();
    let scorable: mimo_metrics::ScorablePredicate =
        Box::new(move |t, pos, alt| ships.iter().any(|s| s.sees(t, pos, alt)));
    let input = ScoreInput::from_dirs(&src.join("truth"), &src.join("dwells"), &a.run.join("tracks"), scorable)
        .map_err(metrics_err)?;
    let opts = ScoreOptions {
        scenario: world.scenario.name.clone(),
        interval_s: a.interval,
        gate_m: a.gate,
        ospa_c_m: a.ospa_c,
        ospa_p: a.ospa_p,
        radars,
        threads: a.threads.unwrap_or(0),
        ..ScoreOptions::default()
    };
    let score = mimo_metrics::score(&input, &opts).map_err(metrics_err)?;
    let t_score = t0.elapsed().as_secs_f64();
    let score_dir = a.run.join("score");
    let replaced = mimo_store::rundir::replace_dir(&score_dir, |dir: &Path| -> Result<(), CliError> {
        mimo_metrics::write_outputs(&score, dir).map_err(metrics_err)?;
        if !a.no_charts {
            mimo_report::render_all(&score, &dir.join("charts")).map_err(|e| CliError::Other(e.to_string()))?;
        }
        Ok(())
    })?;
    if !a.quiet {
        let s = &score.summary;
        let pct = |x: Option<f64>| x.map(|v| format!("{:.2} %", 100.0 * v)).unwrap_or_else(|| "n/a".into());
        let num = |x: Option<f64>| x.map(|v| format!("{v:.1}")).unwrap_or_else(|| "n/a".into());
        if replaced {
            println!("replaced {}", score_dir.display());
        }
        println!(
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
        println!(
            "usage per run: energy {:.0} J ({:.0} J by the TA), dwell time {:.1} s ({:.1} s by the TA); scored in {:.2} s -> {}",
            s.usage.total_energy_j,
            s.usage.ta_energy_j,
            s.usage.total_dwell_time_s,
            s.usage.ta_dwell_time_s,
            t_score,
            score_dir.display()
        );
    }
    Ok(())
}
