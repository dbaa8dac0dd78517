//! What `report.html` shows, gathered from a study directory's tables and `report.md`
//! (docs/studies.md, "The page"): every cell with its points (mean completeness with a failed
//! run counting as 0, mean energy per scorable object over the completed runs — total, or the
//! test article's part when the plan builds its frontiers on it — the
//! summary's 95 % intervals of both, `on_frontier`) and its runs (the figures of the click
//! panel), the challenge's crossings, the failure points, and the tables of `report.md`. The page
//! draws from this alone; numbers are rounded to 6 significant digits, which is more than any
//! panel prints.

use crate::charts::COMPLETENESS_REQUIRED;
use crate::frontier_energy::FrontierEnergy;
use crate::page_tables::{PageError, Table};
use crate::plan::{Axis, Plan};
use mimo_store::challenge_schema::{STUDY_CHALLENGE, STUDY_FRONTIER};
use mimo_store::failure_point_schema::STUDY_FAILURE_POINTS;
use mimo_store::layout::StudyDir;
use mimo_store::schema::{STUDY_RESULTS, STUDY_SUMMARY};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// The per-run figures of the click panel, in the order of each run's row in [`CellData::runs`]
/// (after the run index, before the failure reason).
pub const RUN_FIGURES: [&str; 12] = [
    "completeness",
    "energy_per_object_j",
    "energy_search_j",
    "energy_confirm_true_j",
    "energy_confirm_false_j",
    "energy_track_j",
    "energy_track_false_j",
    "breaks",
    "switches",
    "first_track_mean_s",
    "first_track_max_s",
    "never_tracked",
];

/// A stress axis of the plan.
#[derive(Debug, Serialize)]
pub struct AxisData {
    /// Its key.
    pub name: &'static str,
    /// Its chart label.
    pub label: &'static str,
    /// Drawn on log10 of the value.
    pub log: bool,
    /// The value that leaves the scenario unchanged.
    pub baseline: f64,
}

/// One cell: a method at a scenario and stress point.
#[derive(Debug, Serialize)]
pub struct CellData {
    /// Method.
    pub m: String,
    /// Family.
    pub f: String,
    /// The family's architecture (from the challenge table).
    pub arch: Option<String>,
    /// Whether the family sweeps a knob.
    pub swept_knob: bool,
    /// Scenario label.
    pub sc: String,
    /// The stress point as a reader writes it (`—` without axes).
    pub pt: String,
    /// The axis swept on its own (`sweep = "each"`).
    pub sw: Option<String>,
    /// The value of every axis of the plan.
    pub ax: BTreeMap<String, f64>,
    /// The cell's path under the study's `runs/`.
    pub rel: String,
    /// Runs, and of them failed.
    pub n: u32,
    /// Failed runs.
    pub failed: u32,
    /// Mean completeness (a failed run counting as 0) and the summary's interval.
    pub c: [Option<f64>; 3],
    /// Mean energy per scorable object over the completed runs and the summary's interval, on
    /// the frontier's energy ([`PageData::energy`]: total, or the test article's part).
    pub e: [Option<f64>; 3],
    /// On its family's efficient frontier (null: not a family point, or no frontier table).
    pub front: Option<bool>,
    /// Each run: `[run, RUN_FIGURES…, failure]`.
    pub runs: Vec<Vec<serde_json::Value>>,
}

/// A family's crossing of 98 % at a scenario and stress point.
#[derive(Debug, Serialize)]
pub struct CrossingData {
    /// Family.
    pub f: String,
    /// Architecture.
    pub arch: Option<String>,
    /// Scenario.
    pub sc: String,
    /// Stress point.
    pub pt: String,
    /// Some point holds.
    pub holds: Option<bool>,
    /// Why there is no crossing.
    pub reason: Option<String>,
    /// Energy at 98 % and its interval, on the frontier's energy.
    pub e98: [Option<f64>; 3],
    /// Frontier points.
    pub frontier_points: Option<u32>,
    /// The bracketing methods.
    pub bracket: [Option<String>; 2],
}

/// A method's failure point on an axis.
#[derive(Debug, Serialize)]
pub struct FailureData {
    /// Method.
    pub m: String,
    /// Scenario.
    pub sc: String,
    /// Axis.
    pub axis: String,
    /// `crosses`, `holds` or `fails_at_baseline`.
    pub status: Option<String>,
    /// The failure point and its interval.
    pub fp: [Option<f64>; 3],
    /// How the interval ends.
    pub interval: Option<String>,
    /// Least and most stressing values.
    pub range: [Option<f64>; 2],
}

/// A table of `report.md`.
#[derive(Debug, Serialize)]
pub struct MdTable {
    /// The section it is in.
    pub section: String,
    /// Header cells.
    pub head: Vec<String>,
    /// Rows.
    pub rows: Vec<Vec<String>>,
}

/// Everything the page shows.
#[derive(Debug, Serialize)]
pub struct PageData {
    /// The plan's title.
    pub title: String,
    /// The plan file as the commands on the page name it.
    pub plan: String,
    /// Where the page's re-run commands write (a directory per run under it).
    pub rerun_root: String,
    /// Master seed.
    pub seed: u64,
    /// Monte Carlo runs per cell.
    pub runs: u32,
    /// The required completeness.
    pub required: f64,
    /// The energy the frontiers are built on (the plan's `frontier_energy`: `total` or
    /// `test_article`), which the cells' `e` and the crossings' `e98` give.
    pub energy: &'static str,
    /// The plan's stress axes.
    pub axes: Vec<AxisData>,
    /// The per-run figures' names ([`RUN_FIGURES`]).
    pub figures: Vec<&'static str>,
    /// Every cell, in the order of `results.parquet`.
    pub cells: Vec<CellData>,
    /// The challenge's crossings.
    pub crossings: Vec<CrossingData>,
    /// The failure points.
    pub failures: Vec<FailureData>,
    /// The tables of `report.md`.
    pub tables: Vec<MdTable>,
    /// What the page cannot show, and why.
    pub notes: Vec<String>,
}

/// A number rounded to 6 significant digits (null stays null).
fn round6(v: Option<f64>) -> Option<f64> {
    v.filter(|x| x.is_finite()).map(|x| format!("{x:.5e}").parse().unwrap_or(x))
}

/// The stress point key of a row: scenario, swept axis and every axis value.
fn place_key(sc: &str, sw: Option<&str>, values: &[Option<f64>]) -> String {
    let v: Vec<String> = values.iter().map(|x| x.map(crate::grid::value_text).unwrap_or_default()).collect();
    format!("{sc}|{}|{}", sw.unwrap_or(""), v.join(","))
}

/// The axis columns of a table, in [`Axis::ALL`] order.
fn axis_columns(t: &Table) -> Result<Vec<Vec<Option<f64>>>, PageError> {
    Axis::ALL.iter().map(|a| t.f64s(a.name(), false)).collect()
}

fn row_axes(cols: &[Vec<Option<f64>>], i: usize) -> Vec<Option<f64>> {
    cols.iter().map(|c| c[i]).collect()
}

/// Parse the pipe tables of `report.md` with the section heading above each.
pub fn md_tables(md: &str) -> Vec<MdTable> {
    let clean = |s: &str| s.trim().replace("**", "").replace('`', "");
    let cells = |l: &str| -> Vec<String> {
        let l = l.trim().trim_start_matches('|').trim_end_matches('|');
        l.split('|').map(clean).collect()
    };
    let lines: Vec<&str> = md.lines().collect();
    let mut out = Vec::new();
    let mut section = String::new();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i];
        if let Some(h) = l.strip_prefix('#') {
            section = h.trim_start_matches('#').trim().to_string();
        }
        let is_sep = |s: &str| s.trim_start().starts_with("|-") || s.trim_start().starts_with("|:");
        if l.trim_start().starts_with('|') && lines.get(i + 1).is_some_and(|n| is_sep(n)) {
            let head = cells(l);
            let mut rows = Vec::new();
            i += 2;
            while i < lines.len() && lines[i].trim_start().starts_with('|') {
                rows.push(cells(lines[i]));
                i += 1;
            }
            out.push(MdTable { section: section.clone(), head, rows });
            continue;
        }
        i += 1;
    }
    out
}

/// Gather the page's data from the study directory `dir` of `plan` (`plan_arg`: the plan file as
/// the page's commands name it).
pub fn page_data(plan: &Plan, plan_arg: &str, dir: &Path) -> Result<PageData, PageError> {
    let need = |spec: &mimo_store::schema::TableSpec| {
        Table::read(dir, spec, false)?.ok_or_else(|| PageError::Missing { path: StudyDir::new(dir).table(spec) })
    };
    let results = need(&STUDY_RESULTS)?;
    let summary = need(&STUDY_SUMMARY)?;
    let challenge = need(&STUDY_CHALLENGE)?;
    let failures_t = need(&STUDY_FAILURE_POINTS)?;
    let frontier = Table::read(dir, &STUDY_FRONTIER, true)?;
    let report_path = StudyDir::new(dir).report();
    let md = match std::fs::read_to_string(&report_path) {
        Ok(s) => s,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(PageError::Missing { path: report_path }),
        Err(e) => return Err(PageError::Damaged { path: report_path, why: e.to_string() }),
    };

    // Places of the plan's stage-0 cells: the path of each under runs/ without its method.
    let mut places: BTreeMap<String, (String, String)> = BTreeMap::new();
    for cell in crate::grid::cells(plan) {
        let values: Vec<Option<f64>> = Axis::ALL.iter().map(|a| cell.value(*a)).collect();
        let key = place_key(&plan.scenarios[cell.scenario].label(), cell.swept.map(Axis::name), &values);
        let rel = cell.rel_dir(plan);
        let place = rel.iter().skip(1).map(|p| p.to_string_lossy()).collect::<Vec<_>>().join("/");
        places.entry(key).or_insert((place, crate::report::point_text(&cell)));
    }
    let point_of = |key: &str| places.get(key).map(|(_, pt)| pt.clone()).unwrap_or_else(|| "—".into());

    // Architecture of each family.
    let ch_family = challenge.texts("family", true)?;
    let ch_arch = challenge.texts("architecture", true)?;
    let arch: BTreeMap<String, String> =
        ch_family.iter().zip(&ch_arch).filter_map(|(f, a)| Some((f.clone()?, a.clone()?))).collect();

    // Frontier membership.
    let mut on_front: BTreeMap<String, bool> = BTreeMap::new();
    let mut notes = Vec::new();
    match &frontier {
        Some(t) => {
            let (m, sc, sw, of) = (
                t.texts("method", true)?,
                t.texts("scenario", true)?,
                t.texts("swept", true)?,
                t.bools("on_frontier", true)?,
            );
            let ax = axis_columns(t)?;
            for i in 0..t.len() {
                let key = place_key(sc[i].as_deref().unwrap_or(""), sw[i].as_deref(), &row_axes(&ax, i));
                on_front.insert(format!("{}|{key}", m[i].as_deref().unwrap_or("")), of[i].unwrap_or(false));
            }
        }
        None => notes.push(format!(
            "{}: missing: this study was merged before the efficient frontier was tabled; points are drawn, the \
             frontier is not (merge the study again: mimo study PLAN --out DIR --merge)",
            StudyDir::new(dir).table(&STUDY_FRONTIER).display()
        )),
    }

    // Summary intervals.
    let s_m = summary.texts("method", true)?;
    let s_sc = summary.texts("scenario", true)?;
    let s_sw = summary.texts("swept", true)?;
    let s_ax = axis_columns(&summary)?;
    let basis = plan.frontier_energy;
    let (e_lo, e_hi) = (format!("{}_ci_lo", basis.metric()), format!("{}_ci_hi", basis.metric()));
    let s_ci: Vec<Vec<Option<f64>>> = ["completeness_ci_lo", "completeness_ci_hi", e_lo.as_str(), e_hi.as_str()]
        .iter()
        .map(|c| summary.f64s(c, false))
        .collect::<Result<_, _>>()?;
    let mut intervals: BTreeMap<String, [Option<f64>; 4]> = BTreeMap::new();
    for i in 0..summary.len() {
        let key = place_key(s_sc[i].as_deref().unwrap_or(""), s_sw[i].as_deref(), &row_axes(&s_ax, i));
        intervals.insert(
            format!("{}|{key}", s_m[i].as_deref().unwrap_or("")),
            [s_ci[0][i], s_ci[1][i], s_ci[2][i], s_ci[3][i]],
        );
    }

    // Cells and runs, from the results.
    let r_m = results.texts("method", true)?;
    let r_f = results.texts("family", true)?;
    let r_k = results.texts("knob", true)?;
    let r_sc = results.texts("scenario", true)?;
    let r_sw = results.texts("swept", true)?;
    let r_ax = axis_columns(&results)?;
    let r_run = results.u32s("run", true)?;
    let r_fail = results.texts("failure", true)?;
    let figs: Vec<Vec<Option<f64>>> = RUN_FIGURES
        .iter()
        .map(|n| results.f64s(n, matches!(*n, "completeness" | "energy_per_object_j")))
        .collect::<Result<_, _>>()?;
    // Each run's energy on the frontier's basis, per cell.
    let r_energy = results.f64s(basis.metric(), matches!(basis, FrontierEnergy::Total))?;
    let mut cell_energy: Vec<Vec<Option<f64>>> = Vec::new();
    let mut cells: Vec<CellData> = Vec::new();
    let mut index: BTreeMap<String, usize> = BTreeMap::new();
    for i in 0..results.len() {
        let m = r_m[i].clone().unwrap_or_default();
        let sc = r_sc[i].clone().unwrap_or_default();
        let values = row_axes(&r_ax, i);
        let place = place_key(&sc, r_sw[i].as_deref(), &values);
        let key = format!("{m}|{place}");
        let c = match index.get(&key) {
            Some(&c) => c,
            None => {
                let f = r_f[i].clone().unwrap_or_else(|| m.clone());
                let ax =
                    Axis::ALL.iter().zip(&values).filter_map(|(a, v)| Some((a.name().to_string(), (*v)?))).collect();
                let rel_place = places.get(&place).map(|(p, _)| p.clone()).unwrap_or_else(|| format!("scenario={sc}"));
                cells.push(CellData {
                    arch: arch.get(&f).cloned(),
                    swept_knob: r_k[i].is_some(),
                    f,
                    rel: format!("method={m}/{rel_place}"),
                    m,
                    sc,
                    pt: point_of(&place),
                    sw: r_sw[i].clone(),
                    ax,
                    n: 0,
                    failed: 0,
                    c: [None; 3],
                    e: [None; 3],
                    front: on_front.get(&key).copied(),
                    runs: Vec::new(),
                });
                index.insert(key, cells.len() - 1);
                cell_energy.push(Vec::new());
                cells.len() - 1
            }
        };
        let mut row = vec![serde_json::json!(r_run[i])];
        row.extend(figs.iter().map(|f| serde_json::json!(round6(f[i]))));
        row.push(serde_json::json!(r_fail[i]));
        cell_energy[c].push(r_energy[i]);
        let cell = &mut cells[c];
        cell.n += 1;
        cell.failed += u32::from(r_fail[i].is_some());
        cell.runs.push(row);
    }
    for (key, &c) in &index {
        let cell = &mut cells[c];
        let (mut c_sum, mut e_sum, mut e_n) = (0.0, 0.0, 0u32);
        for (r, energy) in cell.runs.iter().zip(&cell_energy[c]) {
            let failed = !r[RUN_FIGURES.len() + 1].is_null();
            c_sum += if failed { 0.0 } else { r[1].as_f64().unwrap_or(0.0) };
            if let Some(e) = energy.filter(|_| !failed) {
                e_sum += e;
                e_n += 1;
            }
        }
        let ci = intervals.get(key).copied().unwrap_or([None; 4]);
        cell.c = [round6(Some(c_sum / f64::from(cell.n.max(1)))), round6(ci[0]), round6(ci[1])];
        cell.e = [(e_n > 0).then(|| e_sum / f64::from(e_n)), ci[2], ci[3]].map(round6);
    }

    // Crossings.
    let c_sc = challenge.texts("scenario", true)?;
    let c_sw = challenge.texts("swept", true)?;
    let c_ax = axis_columns(&challenge)?;
    let c_holds = challenge.bools("holds", true)?;
    let c_reason = challenge.texts("reason", true)?;
    let e98_columns = match basis {
        FrontierEnergy::Total => ["energy_at_98_j", "energy_at_98_ci_lo_j", "energy_at_98_ci_hi_j"],
        FrontierEnergy::TestArticle => ["ta_energy_at_98_j", "ta_energy_at_98_ci_lo_j", "ta_energy_at_98_ci_hi_j"],
    };
    let e98: Vec<Vec<Option<f64>>> = e98_columns.iter().map(|c| challenge.f64s(c, true)).collect::<Result<_, _>>()?;
    let fp = challenge.u32s("frontier_points", false)?;
    let (b_lo, b_hi) = (challenge.texts("bracket_lo_method", false)?, challenge.texts("bracket_hi_method", false)?);
    let crossings = (0..challenge.len())
        .map(|i| CrossingData {
            f: ch_family[i].clone().unwrap_or_default(),
            arch: ch_arch[i].clone(),
            sc: c_sc[i].clone().unwrap_or_default(),
            pt: point_of(&place_key(c_sc[i].as_deref().unwrap_or(""), c_sw[i].as_deref(), &row_axes(&c_ax, i))),
            holds: c_holds[i],
            reason: c_reason[i].clone(),
            e98: [round6(e98[0][i]), round6(e98[1][i]), round6(e98[2][i])],
            frontier_points: fp[i],
            bracket: [b_lo[i].clone(), b_hi[i].clone()],
        })
        .collect();

    // Failure points.
    let t = &failures_t;
    let (f_m, f_sc, f_axis) = (t.texts("method", true)?, t.texts("scenario", true)?, t.texts("axis", true)?);
    let (f_status, f_int) = (t.texts("status", true)?, t.texts("interval", true)?);
    let (f_fp, f_lo, f_hi) = (t.f64s("failure_point", true)?, t.f64s("ci_lo", true)?, t.f64s("ci_hi", true)?);
    let (f_least, f_most) = (t.f64s("least_stress_value", true)?, t.f64s("most_stress_value", true)?);
    let failures = (0..t.len())
        .map(|i| FailureData {
            m: f_m[i].clone().unwrap_or_default(),
            sc: f_sc[i].clone().unwrap_or_default(),
            axis: f_axis[i].clone().unwrap_or_default(),
            status: f_status[i].clone(),
            fp: [f_fp[i], f_lo[i], f_hi[i]],
            interval: f_int[i].clone(),
            range: [f_least[i], f_most[i]],
        })
        .collect();

    if results.is_empty() {
        notes.push(format!("{}: no runs", results.path().display()));
    }
    let stem = plan.file.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_else(|| "study".into());
    Ok(PageData {
        title: plan.title.clone(),
        plan: plan_arg.to_string(),
        rerun_root: format!("runs/rerun/{stem}"),
        seed: plan.seed,
        runs: plan.runs,
        required: COMPLETENESS_REQUIRED,
        energy: basis.name(),
        axes: plan
            .axes
            .iter()
            .map(|(a, _)| AxisData { name: a.name(), label: a.label(), log: a.log_scale(), baseline: a.baseline() })
            .collect(),
        figures: RUN_FIGURES.to_vec(),
        cells,
        crossings,
        failures,
        tables: md_tables(&md),
        notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_tables_are_read_with_their_section() {
        let md = "# T\n\n## The challenge\n\ntext\n\n| a | b |\n|---|---|\n| **1** | `x` |\n| 2 | y |\n\nmore\n";
        let t = md_tables(md);
        assert_eq!(t.len(), 1);
        assert_eq!(t[0].section, "The challenge");
        assert_eq!(t[0].head, ["a", "b"]);
        assert_eq!(t[0].rows, [["1", "x"], ["2", "y"]]);
    }

    #[test]
    fn numbers_keep_six_significant_digits() {
        assert_eq!(round6(Some(0.123456789)), Some(0.123457));
        assert_eq!(round6(Some(18689.4321)), Some(18689.4));
        assert_eq!(round6(None), None);
        assert_eq!(round6(Some(f64::NAN)), None);
    }
}
