//! The shipped studies are not stale: for each study under `reports/studies/*/` (a directory
//! holding `plan.toml`), one (cell, run) item is re-run from the plan and its metrics must equal
//! the committed `results.parquet` row bit for bit. The item is the cheapest cell's run 0: the
//! cell with the shortest simulated duration, then the fewest targets, then the first in grid
//! order. A study directory without `results.parquet` or `MADE_BY.md`, or whose `plan.toml` is
//! no longer the plan of the same name under `studies/`, fails (regenerate it with
//! `scripts/studies.sh` and commit it); a directory without `plan.toml` is not a study.
//! A metric added to `STUDY_METRICS` after a study was made has no column in its results and is
//! not compared; every metric the results have is.
//! The check itself is tested on a small study generated into a temporary directory, and on a
//! tampered copy of its results.

use arrow::array::{Array, AsArray, RecordBatch};
use arrow::datatypes::{Float64Type, UInt32Type, UInt64Type};
use mimo_store::challenge_schema::{StudyChallengeColumns, StudyChallengeRow};
use mimo_store::study_schema::{
    STUDY_METRICS, StudyCostsColumns, StudyCostsRow, StudyIds, StudyIdsColumns, StudyMethod, StudyMethodColumns,
    StudyPoint, StudyPointColumns, StudyResultsColumns, StudyResultsRow,
};
use mimo_study::item::do_item;
use mimo_study::plan::Axis;
use mimo_study::prepare::prepare;
use mimo_study::{Options, Plan, run_study};
use parquet::arrow::ArrowWriter;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use std::path::{Path, PathBuf};

/// The column names the checks read, as the study tables declare them.
const RESULTS: StudyResultsColumns = StudyResultsRow::COLUMNS;
const IDS: StudyIdsColumns = StudyIds::COLUMNS;
const METHOD: StudyMethodColumns = StudyMethod::COLUMNS;
const POINT: StudyPointColumns = StudyPoint::COLUMNS;
const CHALLENGE: StudyChallengeColumns = StudyChallengeRow::COLUMNS;
const COSTS: StudyCostsColumns = StudyCostsRow::COLUMNS;

fn read_batches(path: &Path) -> Result<Vec<RecordBatch>, String> {
    let f = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let r = ParquetRecordBatchReaderBuilder::try_new(f)
        .and_then(|b| b.build())
        .map_err(|e| format!("{}: {e}", path.display()))?;
    r.collect::<Result<Vec<_>, _>>().map_err(|e| format!("{}: {e}", path.display()))
}

fn text(b: &RecordBatch, col: &str, i: usize) -> Result<Option<String>, String> {
    let c = b.column_by_name(col).ok_or(format!("no column {col}"))?;
    let s = c.as_string_opt::<i32>().ok_or(format!("{col} is not text"))?;
    Ok(s.is_valid(i).then(|| s.value(i).to_string()))
}

fn float(b: &RecordBatch, col: &str, i: usize) -> Result<Option<f64>, String> {
    let c = b.column_by_name(col).ok_or(format!("no column {col}"))?;
    let f = c.as_primitive_opt::<Float64Type>().ok_or(format!("{col} is not float64"))?;
    Ok(f.is_valid(i).then(|| f.value(i)))
}

/// An axis column's value; a study made before the axis existed has no column for it, which
/// reads as null (its plan cannot sweep the axis, so every cell's value is null too).
fn axis_value(b: &RecordBatch, axis: Axis, i: usize) -> Result<Option<f64>, String> {
    match b.column_by_name(axis.name()) {
        None => Ok(None),
        Some(_) => float(b, axis.name(), i),
    }
}

/// A shipped study says how it was made, and its plan is still the one under `studies/` of the
/// same name (a plan edited since is a stale study), when there is one.
fn check_made_by(dir: &Path) -> Result<(), String> {
    if !dir.join("MADE_BY.md").is_file() {
        return Err(format!("{}: no MADE_BY.md: regenerate with scripts/studies.sh", dir.display()));
    }
    let name = dir.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../studies").join(format!("{name}.toml"));
    let read = |p: &Path| std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()));
    if source.is_file() && read(&source)? != read(&dir.join("plan.toml"))? {
        return Err(format!(
            "{}: plan.toml differs from studies/{name}.toml: regenerate with scripts/studies.sh {name}",
            dir.display()
        ));
    }
    Ok(())
}

/// Check one directory: `Ok(None)` when it is not a study, `Ok(Some(item))` naming the item
/// re-run when its metrics match, `Err` saying what is stale or missing.
fn check_study(dir: &Path) -> Result<Option<String>, String> {
    let plan_file = dir.join("plan.toml");
    if !plan_file.is_file() {
        return Ok(None);
    }
    let results = dir.join("results.parquet");
    if !results.is_file() {
        return Err(format!("{}: no results.parquet: regenerate with scripts/studies.sh and commit it", dir.display()));
    }
    check_made_by(dir)?;
    let plan = Plan::read(&plan_file).map_err(|e| e.to_string())?;
    let prep = prepare(&plan).map_err(|e| e.to_string())?;
    let cost = |c: usize| {
        let w = &prep.worlds[prep.world_of[c]];
        (w.scenario.duration_s, w.scenario.targets.len(), c)
    };
    let c = (0..prep.cells.len()).min_by(|a, b| cost(*a).partial_cmp(&cost(*b)).unwrap_or(std::cmp::Ordering::Equal));
    let c = c.ok_or("the plan has no cell")?;
    let cell = &prep.cells[c];
    let (method, scenario) = (&plan.methods[cell.method].name, plan.scenarios[cell.scenario].label());
    let item = format!("{} run 0", cell.rel_dir(&plan).display());
    let work = tempfile::tempdir().map_err(|e| e.to_string())?;
    let rec = do_item(&plan, cell, &prep.worlds[prep.world_of[c]], work.path(), 0, None).map_err(|e| e.to_string())?;
    for b in read_batches(&results)? {
        let runs = b.column_by_name(RESULTS.run).and_then(|r| r.as_primitive_opt::<UInt32Type>().cloned());
        let runs = runs.ok_or("results.parquet: no uint32 run column")?;
        for i in 0..b.num_rows() {
            let same_axes = Axis::ALL.iter().map(|a| axis_value(&b, *a, i)).collect::<Result<Vec<_>, _>>()?
                == Axis::ALL.iter().map(|a| cell.value(*a)).collect::<Vec<_>>();
            let here = text(&b, METHOD.method, i)?.as_deref() == Some(method.as_str())
                && text(&b, IDS.scenario, i)?.as_deref() == Some(scenario.as_str())
                && text(&b, POINT.swept, i)? == cell.swept.map(|a| a.name().to_string())
                && same_axes
                && runs.value(i) == 0;
            if !here {
                continue;
            }
            let seed =
                b.column_by_name(RESULTS.seed).and_then(|s| s.as_primitive_opt::<UInt64Type>().map(|s| s.value(i)));
            if seed != Some(plan.seed) {
                return Err(format!("{item}: committed seed {seed:?}, the plan's is {}", plan.seed));
            }
            if text(&b, RESULTS.failure, i)? != rec.failure {
                return Err(format!(
                    "{item}: failure {:?} committed, {:?} now",
                    text(&b, RESULTS.failure, i)?,
                    rec.failure
                ));
            }
            for (name, _, _) in STUDY_METRICS {
                // A metric added after the study was made has no column in it: there is nothing
                // committed to compare (the metrics it has are still checked bit for bit).
                if b.column_by_name(name).is_none() {
                    continue;
                }
                let (was, now) = (float(&b, name, i)?, rec.metrics.get(*name).copied().flatten());
                if was.map(f64::to_bits) != now.map(f64::to_bits) {
                    return Err(format!(
                        "{}: {item}: {name} is {was:?} in results.parquet, {now:?} now",
                        dir.display()
                    ));
                }
            }
            return Ok(Some(item));
        }
    }
    Err(format!("{}: results.parquet has no row for {item}", dir.display()))
}

#[test]
fn every_shipped_study_matches_a_rerun_of_its_cheapest_item() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../reports/studies");
    let mut dirs: Vec<PathBuf> =
        std::fs::read_dir(&root).expect("reports/studies").filter_map(|e| e.ok().map(|e| e.path())).collect();
    dirs.sort();
    let mut studies = 0;
    let mut stale = Vec::new();
    for d in dirs.iter().filter(|d| d.is_dir()) {
        match check_study(d) {
            Ok(Some(_)) => studies += 1,
            Ok(None) => {}
            Err(e) => stale.push(e),
        }
    }
    assert!(stale.is_empty(), "stale or incomplete shipped studies:\n{}", stale.join("\n"));
    assert!(studies > 0, "no study under {}", root.display());
}

/// Rewrite `path` with `metric` of row `row` replaced by `value`, keeping schema and metadata.
fn tamper(path: &Path, metric: &str, row: usize, value: f64) {
    let batches = read_batches(path).expect("read");
    let schema = batches[0].schema();
    let tmp = path.with_extension("tmp");
    let mut w =
        ArrowWriter::try_new(std::fs::File::create(&tmp).expect("create"), schema.clone(), None).expect("writer");
    let mut offset = 0;
    for b in batches {
        let k = schema.index_of(metric).expect("metric");
        let old = b.column(k).as_primitive::<Float64Type>();
        let new: arrow::array::Float64Array = (0..b.num_rows())
            .map(|i| if offset + i == row { Some(value) } else { old.is_valid(i).then(|| old.value(i)) })
            .collect();
        let mut cols = b.columns().to_vec();
        cols[k] = std::sync::Arc::new(new);
        offset += b.num_rows();
        w.write(&RecordBatch::try_new(schema.clone(), cols).expect("batch")).expect("write");
    }
    w.close().expect("close");
    std::fs::rename(&tmp, path).expect("rename");
}

#[test]
fn the_check_passes_on_a_fresh_study_and_catches_a_changed_metric() {
    // Two scenarios of different durations would need scenario files; two methods, one swept,
    // on scenario 1 for 20 s, and an axis: the cheapest cell is the first.
    let plan_text = "scenarios = [1]\nruns = 2\nduration_s = 20\n\
        [[methods]]\nname = \"conv\"\nta = \"default\"\nconfig = { resource_manager = { mimo = false } }\n\
        [[methods]]\nname = \"mimo\"\nta = \"default\"\nsweep = { \"resource_manager.max_ta_share\" = [0.2, 0.5] }\n\
        [axes]\nrcs_offset_db = [0, -3]\n";
    let tmp = tempfile::tempdir().expect("tmp");
    std::fs::write(tmp.path().join("p.toml"), plan_text).expect("plan");
    let plan = Plan::read(&tmp.path().join("p.toml")).expect("plan");
    let out = tmp.path().join("study");
    let opts =
        Options { out: out.clone(), resume: false, force: false, shard: None, merge: false, init: false, threads: 2 };
    run_study(&plan, plan_text, &opts, &|_, _| {}).expect("study");
    // The study's challenge tables: two families on two stress points, one ratio per point; the
    // report opens with the challenge.
    let ch = &read_batches(&out.join("challenge.parquet")).expect("challenge")[0];
    assert_eq!(ch.num_rows(), 4);
    assert_eq!(text(ch, CHALLENGE.family, 0), Ok(Some("conv".into())));
    assert_eq!(text(ch, CHALLENGE.architecture, 0), Ok(Some("conventional".into())));
    assert_eq!(text(ch, CHALLENGE.knob, 1), Ok(Some("resource_manager.max_ta_share".into())));
    assert_eq!(
        text(ch, CHALLENGE.reason, 0),
        Ok(Some(mimo_study::challenge::reason(&mimo_study::challenge::Crossing::OnePoint).into()))
    );
    assert_eq!(read_batches(&out.join("challenge_ratios.parquet")).expect("ratios")[0].num_rows(), 2);
    let report = std::fs::read_to_string(out.join("report.md")).expect("report");
    assert!(report.lines().nth(2).is_some_and(|l| l.starts_with("## The challenge")), "{report}");
    let results = &read_batches(&out.join("results.parquet")).expect("results")[0];
    assert_eq!(text(results, METHOD.method, 4), Ok(Some("mimo@0.2".into())));
    assert_eq!(float(results, METHOD.knob_value, 4), Ok(Some(0.2)));
    assert_eq!(float(results, METHOD.knob_value, 0), Ok(None));
    let costs = &read_batches(&out.join("costs.parquet")).expect("costs")[0];
    let (cpu, kf, kfu) =
        (float(costs, COSTS.ta_cpu_s, 0), float(costs, COSTS.kf_cycle_s, 0), float(costs, COSTS.ta_cpu_kfu, 0));
    let (cpu, kf, kfu) = (cpu.expect("c").expect("c"), kf.expect("k").expect("k"), kfu.expect("u").expect("u"));
    assert!(kf > 0.0 && kfu == cpu / kf, "{cpu} / {kf} = {kfu}");

    assert!(check_study(&out).expect_err("no MADE_BY.md").contains("MADE_BY.md"));
    std::fs::write(out.join("MADE_BY.md"), "made by this test\n").expect("made by");
    let item = check_study(&out).expect("a fresh study is not stale").expect("a study");
    assert_eq!(item, "method=conv/scenario=1/rcs_offset_db=0 run 0", "the first cheapest cell");

    // The row of that item is the first of results.parquet: change its completeness.
    let b = &read_batches(&out.join("results.parquet")).expect("read")[0];
    let was = float(b, "completeness", 0).expect("column").expect("scored");
    tamper(&out.join("results.parquet"), "completeness", 0, was - 1e-12);
    let e = check_study(&out).expect_err("a changed metric is caught");
    assert!(e.contains("completeness"), "{e}");
    // Another row's change is not this item's business.
    tamper(&out.join("results.parquet"), "completeness", 0, was);
    tamper(&out.join("results.parquet"), "gospa_m", 3, 1.0);
    assert!(check_study(&out).is_ok());

    // A study named like a shipped plan whose plan is no longer that plan is stale.
    let named = tmp.path().join("challenge");
    std::fs::create_dir(&named).expect("dir");
    for f in ["plan.toml", "results.parquet", "MADE_BY.md"] {
        std::fs::copy(out.join(f), named.join(f)).expect("copy");
    }
    assert!(check_study(&named).expect_err("another plan").contains("differs from studies/challenge.toml"));

    // Without results.parquet the study fails the check; a directory without a plan is no study.
    std::fs::remove_file(out.join("results.parquet")).expect("rm");
    assert!(check_study(&out).expect_err("missing").contains("no results.parquet"));
    assert_eq!(check_study(&out.join("charts")), Ok(None));
}
