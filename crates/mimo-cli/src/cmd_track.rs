//! `mimo track`: re-run a tracker over a recording.

use crate::CliError;
use crate::ta_args::TaArgs;
use mimo_core::records::{DwellRow, MeasurementRow, PrimitiveRow};
use mimo_scenario::Scenario;
use mimo_sim::{EngineConfig, SearchConfig, World};
use mimo_store::layout::RunDir;
use mimo_store::manifest::{Manifest, TableFile, TrackerInfo};
use mimo_store::run_sink::ParquetRunSink;
use mimo_store::rundir::RunDirWriter;
use mimo_ta::replay::{DwellKeyColumns, Recording, ReplayError, ReplayFrom, replay_selected};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Re-run a tracker offline over a recorded run directory.
///
/// Reads RUN's dwells and its primitives (re-forming measurements with the radar model's own
/// clustering and centroiding) or its measurements, and runs the tracker over them in the order
/// the closed loop delivered them. The recording's dwell schedule is fixed: a re-run is OPEN
/// LOOP (the tracker cannot ask for new dwells), so it measures a tracker, not a resource
/// manager. Writes OUT with new measurements (from primitives), tracks, and a manifest naming
/// RUN as its parent; `mimo score OUT` reads truth and dwells through that link.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The recorded run directory (made by `mimo simulate`).
    pub run: PathBuf,
    #[command(flatten)]
    pub ta: TaArgs,
    /// What to start from: primitives (re-form measurements) or measurements.
    #[arg(long, default_value = "primitives", value_name = "primitives|measurements")]
    pub from: String,
    /// Output run directory (must not exist unless --force).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Worker threads [default: all cores]. Results do not depend on it.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Replace OUT if it exists.
    #[arg(long)]
    pub force: bool,
    /// Print nothing but errors.
    #[arg(long)]
    pub quiet: bool,
}

/// The scenario a run directory was made from, checked.
pub fn scenario_of(run_dir: &Path, m: &Manifest) -> Result<Scenario, CliError> {
    let file = RunDir::new(run_dir).manifest();
    let s: Scenario = serde_json::from_value(m.scenario.resolved.clone())
        .map_err(|e| CliError::input(format!("{}: field 'scenario.resolved': {e}", file.display())))?;
    // The scenario's own errors name fields, not files: say which manifest holds it.
    s.validate().map_err(|e| CliError::input(format!("{}: field 'scenario.resolved': {e}", file.display())))?;
    Ok(s)
}

/// The store's key columns as the replay's keys (a view: the columns are held once).
fn key_columns(k: &mimo_store::dwell_keys::DwellKeys) -> DwellKeyColumns<'_> {
    DwellKeyColumns {
        run: &k.run,
        dwell_id: &k.dwell_id,
        group_id: &k.group_id,
        radar: &k.radar,
        face: &k.face,
        requested_by: &k.requested_by,
    }
}

/// `--from`, and the table it reads.
fn parse_from(from: &str) -> Result<(ReplayFrom, &'static str), CliError> {
    match from {
        "primitives" => Ok((ReplayFrom::Primitives, "primitives")),
        "measurements" => Ok((ReplayFrom::Measurements, "measurements")),
        other => Err(CliError::input(format!("--from: expected primitives or measurements, got '{other}'"))),
    }
}

/// Every input file of every run is there (checked before anything is written). A run that
/// never recorded the table `--from` names (a study cell records its plan's `tables`, without
/// primitives by default: docs/studies.md) is told which tables it holds and what to run.
fn check_inputs(run: &RunDir, m: &Manifest, source: &str) -> Result<(), CliError> {
    for t in ["dwells", source] {
        if !m.tables.contains_key(t) {
            let held: Vec<&str> = m.tables.keys().map(String::as_str).collect();
            let other = if source == "primitives" { "measurements" } else { "primitives" };
            let hint = if t == source && m.tables.contains_key(other) {
                format!(
                    "; re-run it from its {other} instead: mimo track {} --from {other} --out OUT",
                    run.root().display()
                )
            } else {
                "; a run to re-track needs dwells and primitives or measurements (a study records them with \
                 its plan's `tables`, e.g. tables = [\"truth\", \"dwells\", \"primitives\", \"measurements\", \
                 \"tracks\"], and keeps them with keep_runs = true)"
                    .to_string()
            };
            return Err(CliError::input(format!(
                "{}: holds no '{t}' table (its manifest lists {}){hint}",
                run.root().display(),
                if held.is_empty() { "none".to_string() } else { held.join(", ") }
            )));
        }
    }
    let runs = m.runs;
    for k in 0..runs {
        for t in ["dwells", source] {
            let f = run.table_file(t, k);
            if !f.is_file() {
                return Err(CliError::input(format!("{}: missing (table '{t}' of run {k})", f.display())));
            }
        }
    }
    Ok(())
}

/// What a re-run of one Monte Carlo run needs.
struct Rerun<'a> {
    input: RunDir,
    world: &'a World,
    cfg: EngineConfig,
    from: ReplayFrom,
    ta: &'a crate::ta_args::TaChoice,
    writer: &'a RunDirWriter,
}

/// What a re-run of one Monte Carlo run gave: its files, its counters, the tracker.
type Reran = (Vec<(&'static str, TableFile)>, mimo_ta::replay::ReplayStats, mimo_sim::TaInfo);

impl Rerun<'_> {
    /// Re-run run `k`, its tables streamed into the output's staging directory as they come.
    fn one(&self, k: u32) -> Result<Reran, CliError> {
        // The dwells' keys first; whole rows only for the groups the test article is sent.
        let dwells_file = self.input.table_file("dwells", k);
        let store_keys = mimo_store::dwell_keys::read_dwell_keys(&dwells_file)?;
        let mut load = |at: &[usize]| -> Result<Vec<DwellRow>, Box<dyn std::error::Error + Send + Sync>> {
            Ok(mimo_store::dwell_keys::read_dwell_rows(&dwells_file, &store_keys, at)?)
        };
        let (prims, meas): (Vec<PrimitiveRow>, Vec<MeasurementRow>) = match self.from {
            ReplayFrom::Primitives => (mimo_store::read_table(&self.input.table_file("primitives", k))?, Vec::new()),
            ReplayFrom::Measurements => {
                (Vec::new(), mimo_store::read_table(&self.input.table_file("measurements", k))?)
            }
        };
        let mut tester = self.ta.build(self.world)?;
        let mut sink = ParquetRunSink::for_rerun(self.writer, k, self.from == ReplayFrom::Primitives)?;
        // With biases on, the test article's registration estimates are kept (docs/model.md §6.9).
        if !self.world.scenario.biases.is_off() {
            sink = sink.with_registration(self.writer, k)?;
        }
        let recording = Recording {
            run: k,
            keys: key_columns(&store_keys),
            load: &mut load,
            primitives: prims,
            measurements: meas,
            from: self.from,
        };
        let stats =
            replay_selected(self.world, &self.cfg, tester.as_mut(), recording, &mut sink).map_err(|e| match e {
                ReplayError::UnknownDwell { .. } | ReplayError::UnknownFace { .. } => {
                    CliError::input(format!("{}: {e}", self.input.root().display()))
                }
                other => CliError::from(other),
            })?;
        let files = sink.finish()?;
        let info = mimo_sim::TaInfo { name: tester.name().to_string(), config: tester.config() };
        Ok((files, stats, info))
    }
}

/// Files by table, in run order.
type Tables = BTreeMap<String, Vec<TableFile>>;

/// The re-runs' files by table (in run order), measurements delivered, the covariances repaired,
/// and the tracker.
fn gather(
    results: Vec<Result<Reran, CliError>>,
) -> Result<(Tables, u64, mimo_store::checked::Repairs, mimo_sim::TaInfo), CliError> {
    let mut tables = Tables::new();
    let mut n_meas = 0u64;
    let mut repairs = mimo_store::checked::Repairs::default();
    let mut info = None;
    for r in results {
        let (files, st, i) = r?;
        n_meas += st.measurements;
        repairs.add(mimo_store::checked::Repairs {
            rows: st.repaired_covariances,
            worst_ratio: st.worst_covariance_ratio,
        });
        info.get_or_insert(i);
        for (t, f) in files {
            tables.entry(t.to_string()).or_default().push(f);
        }
    }
    for v in tables.values_mut() {
        v.sort_by(|x, y| x.file.cmp(&y.file));
    }
    let info = info.ok_or_else(|| CliError::Other("no run was re-run".into()))?;
    Ok((tables, n_meas, repairs, info))
}

pub fn run(a: Args) -> Result<(), CliError> {
    let t_start = Instant::now();
    let (from, source) = parse_from(&a.from)?;
    let ta = a.ta.resolve()?;
    if matches!(ta, crate::ta_args::TaChoice::ResourceManager { .. }) {
        return Err(CliError::input(
            "--ta-role: resource-manager needs the closed loop (`mimo simulate`); `mimo track` re-runs a recording's dwells, with no looks to decide".to_string(),
        ));
    }
    if !ta.tracks() {
        return Err(CliError::input(format!(
            "--tracker: '{}' forms no tracks, so it cannot re-run a recording (expected a tracker such as default or imm)",
            ta.label()
        )));
    }
    crate::cmd_simulate::check_threads(a.threads)?;
    mimo_store::lineage::check_output_apart(&a.run, &a.out)?;
    let manifest = Manifest::read(&a.run)?;
    // Its `parent` links, if any, must lead somewhere (a run that is its own parent is refused).
    mimo_store::lineage::source_dir(&a.run, &manifest)?;
    // The replay needs the ships' faces, never the targets: their trajectories are not built.
    let world = World::ships_only(scenario_of(&a.run, &manifest)?);
    let input = RunDir::new(&a.run);
    check_inputs(&input, &manifest, source)?;
    let writer = RunDirWriter::create(&a.out, a.force)?;
    let (parent, parent_check) = mimo_store::lineage::link(&a.out, &a.run, &manifest)?;
    let cfg = EngineConfig {
        seed: manifest.seed,
        duration_s: manifest.duration_s,
        record_voltages: false,
        search: SearchConfig::default(),
        ta_config: ta.overrides().clone(),
    };
    let rerun = Rerun { input, world: &world, cfg, from, ta: &ta, writer: &writer };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()
        .map_err(|e| CliError::Other(format!("thread pool: {e}")))?;
    let pb = crate::progress::bar(u64::from(manifest.runs), "track", a.quiet);
    let t_track = Instant::now();
    let results: Vec<Result<Reran, CliError>> =
        pool.install(|| (0..manifest.runs).into_par_iter().map(|k| rerun.one(k).inspect(|_| pb.inc(1))).collect());
    pb.finish_and_clear();
    let track_s = t_track.elapsed().as_secs_f64();
    let (tables, n_meas, repairs, info) = gather(results)?;
    let mut timing = BTreeMap::new();
    timing.insert("track".to_string(), track_s);
    timing.insert("total".to_string(), t_start.elapsed().as_secs_f64());
    let m = Manifest {
        mimo_version: env!("CARGO_PKG_VERSION").to_string(),
        schema_version: mimo_store::schema::SCHEMA_VERSION,
        scenario: manifest.scenario.clone(),
        seed: manifest.seed,
        runs: manifest.runs,
        duration_s: manifest.duration_s,
        fidelity: manifest.fidelity.clone(),
        tracker: Some(TrackerInfo {
            name: info.name,
            config: serde_json::json!({"config": info.config, "from": a.from}),
        }),
        schedule: format!("open-loop re-run of the recorded schedule of {}", a.run.display()),
        parent: Some(parent),
        parent_check: Some(parent_check),
        tables,
        timing_s: timing,
    };
    let out = writer.finish(&m)?;
    if let Some(w) = repairs.warning(&format!("{}: the test article's track rows", out.display())).filter(|_| !a.quiet)
    {
        eprintln!("{w}");
    }
    if !a.quiet {
        crate::outln!(
            "tracked {} run(s) of {} with '{}' from {} in {:.2} s ({:.0} measurements/s) -> {}",
            manifest.runs,
            a.run.display(),
            ta.label(),
            a.from,
            track_s,
            n_meas as f64 / track_s.max(1e-9),
            out.display()
        );
    }
    Ok(())
}
