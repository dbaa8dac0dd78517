//! The grid of a study: cells (method × scenario × stress point), the (cell, run) items, their
//! deterministic split into shards, and each cell's hive-style directory.

use crate::plan::{Axis, Plan, PlanError, Sweep};
use std::path::PathBuf;

/// One point of the stress axes: a value for every axis of the plan, in [`Axis::ALL`] order.
pub type AxisPoint = Vec<(Axis, f64)>;

/// One cell: a method on a scenario at one stress point.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// Index into the plan's methods.
    pub method: usize,
    /// Index into the plan's scenarios.
    pub scenario: usize,
    /// The stress point. With `sweep = "each"`, axes other than the swept one sit at their
    /// baseline and are not applied.
    pub point: AxisPoint,
    /// With `sweep = "each"`, the one axis this cell varies (`None` in a grid).
    pub swept: Option<Axis>,
}

/// A value as it appears in a path or a label: the shortest text that reads back the same.
pub fn value_text(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else {
        format!("{v:e}").replace("e0", "").replace("e-0", "e-")
    }
}

/// Every stress point of the plan, in a fixed order.
pub fn points(plan: &Plan) -> Vec<(AxisPoint, Option<Axis>)> {
    if plan.axes.is_empty() {
        return vec![(Vec::new(), None)];
    }
    match plan.sweep {
        Sweep::Grid => {
            let mut out: Vec<AxisPoint> = vec![Vec::new()];
            for (axis, values) in &plan.axes {
                out = out
                    .into_iter()
                    .flat_map(|p| {
                        values.iter().map(move |&v| {
                            let mut q = p.clone();
                            q.push((*axis, v));
                            q
                        })
                    })
                    .collect();
            }
            out.into_iter().map(|p| (p, None)).collect()
        }
        Sweep::Each => {
            let mut out = Vec::new();
            for (axis, values) in &plan.axes {
                for &v in values {
                    let p = plan.axes.iter().map(|(a, _)| (*a, if a == axis { v } else { a.baseline() })).collect();
                    out.push((p, Some(*axis)));
                }
            }
            out
        }
    }
}

/// Most cells a study may have (docs/studies.md "Limits"): methods × scenarios × stress points.
/// Ten thousand cells of one 1000-s run each already take days on one machine; the list of
/// cells, their directories and their items must be held in memory before anything runs.
pub const MAX_CELLS: u64 = 10_000;
/// Most (cell, run) items a study may have (docs/studies.md "Limits").
pub const MAX_ITEMS: u64 = 1_000_000;

/// The number of stress points of a plan, counted without listing them (saturating).
pub fn point_count(plan: &Plan) -> u64 {
    if plan.axes.is_empty() {
        return 1;
    }
    match plan.sweep {
        Sweep::Grid => plan.axes.iter().fold(1u64, |n, (_, v)| n.saturating_mul(v.len() as u64)),
        Sweep::Each => plan.axes.iter().map(|(_, v)| v.len() as u64).sum(),
    }
}

/// The number of cells of a plan, counted without listing them (saturating).
pub fn cell_count(plan: &Plan) -> u64 {
    (plan.methods.len() as u64).saturating_mul(plan.scenarios.len() as u64).saturating_mul(point_count(plan))
}

/// Refuse a plan with more than [`MAX_CELLS`] cells or [`MAX_ITEMS`] items, before any is
/// listed: the message names the plan keys that multiply and the limit.
pub fn check_size(plan: &Plan) -> Result<(), PlanError> {
    let (cells, points) = (cell_count(plan), point_count(plan));
    let err = |key: &str, expected: String| PlanError {
        file: plan.file.display().to_string(),
        key: key.to_string(),
        expected,
        at: None,
    };
    if cells > MAX_CELLS {
        return Err(err(
            "axes",
            format!(
                "at most {MAX_CELLS} cells (methods × scenarios × stress points), got {} × {} × {points} = {cells}",
                plan.methods.len(),
                plan.scenarios.len()
            ),
        ));
    }
    let items = cells.saturating_mul(u64::from(plan.runs));
    if items > MAX_ITEMS {
        return Err(err(
            "runs",
            format!("at most {MAX_ITEMS} runs in all (cells × runs), got {cells} × {} = {items}", plan.runs),
        ));
    }
    Ok(())
}

/// Every cell: methods × scenarios × points, in that nesting order.
pub fn cells(plan: &Plan) -> Vec<Cell> {
    let pts = points(plan);
    let mut out = Vec::new();
    for method in 0..plan.methods.len() {
        for scenario in 0..plan.scenarios.len() {
            for (point, swept) in &pts {
                out.push(Cell { method, scenario, point: point.clone(), swept: *swept });
            }
        }
    }
    out
}

impl Cell {
    /// The cell's directory under the study's `runs/`, hive style:
    /// `method=NAME/scenario=S/axis=value/…`.
    pub fn rel_dir(&self, plan: &Plan) -> PathBuf {
        let mut p = PathBuf::from(format!("method={}", plan.methods[self.method].name));
        p.push(format!("scenario={}", plan.scenarios[self.scenario].label()));
        if let Some(axis) = self.swept {
            // One axis at a time: the swept axis names a partition of its own, so that every
            // cell of the study still has every axis column.
            p.push(format!("swept={}", axis.name()));
        }
        for (axis, v) in &self.point {
            p.push(format!("{}={}", axis.name(), value_text(*v)));
        }
        p
    }

    /// The value of an axis at this cell, if the plan has the axis.
    pub fn value(&self, axis: Axis) -> Option<f64> {
        self.point.iter().find(|(a, _)| *a == axis).map(|(_, v)| *v)
    }

    /// The value an axis is applied with (`None`: leave the scenario's own value).
    pub fn applied(&self, axis: Axis) -> Option<f64> {
        match self.swept {
            Some(s) if s != axis => None,
            _ => self.value(axis),
        }
    }
}

/// One (cell, run) item.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Item {
    /// Index into [`cells`].
    pub cell: usize,
    /// Monte Carlo run.
    pub run: u32,
}

/// Every item, cell-major.
pub fn items(n_cells: usize, runs: u32) -> Vec<Item> {
    (0..n_cells).flat_map(|cell| (0..runs).map(move |run| Item { cell, run })).collect()
}

/// A shard `K/N` (0 ≤ K < N): item `i` of the item list belongs to shard `i mod N`, so shards are
/// balanced over cells and runs and the split never depends on the machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard (0-based).
    pub k: usize,
    /// Number of shards.
    pub n: usize,
}

impl Shard {
    /// Parse `K/N`.
    pub fn parse(s: &str) -> Result<Shard, String> {
        let (k, n) = s.split_once('/').ok_or_else(|| format!("expected K/N (for example 0/4), got '{s}'"))?;
        let k: usize = k.trim().parse().map_err(|_| format!("K in K/N: expected a whole number, got '{k}'"))?;
        let n: usize = n.trim().parse().map_err(|_| format!("N in K/N: expected a whole number, got '{n}'"))?;
        if n == 0 || k >= n {
            return Err(format!(
                "expected 0 <= K < N (shards are numbered from 0, like Slurm array and Kubernetes job indices), got {k}/{n}"
            ));
        }
        Ok(Shard { k, n })
    }

    /// The items of this shard.
    pub fn select(&self, items: &[Item]) -> Vec<Item> {
        items.iter().enumerate().filter(|(i, _)| i % self.n == self.k).map(|(_, it)| *it).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn plan(axes: &str, sweep: &str) -> Plan {
        let text = format!(
            "scenarios = [7, 1]\nruns = 3\nsweep = \"{sweep}\"\n[[methods]]\nname = \"a\"\nta = \"default\"\n\
             [[methods]]\nname = \"b\"\nta = \"imm\"\n[axes]\n{axes}"
        );
        Plan::parse(&text, Path::new("p.toml")).expect("plan")
    }

    #[test]
    fn a_grid_is_every_combination_and_each_is_one_axis_at_a_time() {
        let p = plan("pfa = [1e-6, 1e-4]\nrcs_offset_db = [-3, 0, 3]", "grid");
        let c = cells(&p);
        assert_eq!(c.len(), 2 * 2 * 6);
        assert_eq!(c[0].rel_dir(&p), PathBuf::from("method=a/scenario=7/rcs_offset_db=-3/pfa=1e-6"));
        assert_eq!(c[5].rel_dir(&p), PathBuf::from("method=a/scenario=7/rcs_offset_db=3/pfa=1e-4"));
        let q = plan("pfa = [1e-6, 1e-4]\nrcs_offset_db = [-3, 0, 3]", "each");
        let c = cells(&q);
        assert_eq!(c.len(), 2 * 2 * 5);
        assert_eq!(c[1].rel_dir(&q), PathBuf::from("method=a/scenario=7/swept=rcs_offset_db/rcs_offset_db=0/pfa=1e-6"));
        assert_eq!(c[1].applied(Axis::RcsOffsetDb), Some(0.0));
        assert_eq!(c[1].applied(Axis::Pfa), None, "not swept here: the scenario's own value");
        // Every directory is distinct.
        let mut dirs: Vec<_> = c.iter().map(|x| x.rel_dir(&q)).collect();
        dirs.sort();
        dirs.dedup();
        assert_eq!(dirs.len(), c.len());
    }

    #[test]
    fn cells_are_counted_without_listing_them() {
        for sweep in ["grid", "each"] {
            let p = plan("pfa = [1e-6, 1e-4]\nrcs_offset_db = [-3, 0, 3]\nsearch_pulses = [1, 2, 4, 8]", sweep);
            assert_eq!(cell_count(&p), cells(&p).len() as u64, "{sweep}");
            check_size(&p).expect("small");
        }
        // 2 methods × 2 scenarios × 51 × 51 × 2 = 20 808 cells: refused before any is listed.
        let values: Vec<String> = (0..51).map(|i| format!("{}", -25 + i)).collect();
        let axes =
            format!("rcs_offset_db = [{0}]\npeak_power_offset_db = [{0}]\npfa = [1e-6, 1e-4]", values.join(", "));
        let e = check_size(&plan(&axes, "grid")).expect_err("too many cells");
        assert_eq!(e.key, "axes");
        assert!(e.expected.contains("got 2 × 2 × 5202 = 20808"), "{}", e.expected);
    }

    #[test]
    fn shards_partition_the_items() {
        let it = items(7, 3);
        assert_eq!(it.len(), 21);
        let mut all: Vec<Item> = (0..4).flat_map(|k| Shard { k, n: 4 }.select(&it)).collect();
        all.sort();
        assert_eq!(all, it);
        assert_eq!(Shard::parse("2/4"), Ok(Shard { k: 2, n: 4 }));
        assert!(Shard::parse("4/4").is_err());
        assert!(Shard::parse("1/0").is_err());
        assert!(Shard::parse("x").is_err());
    }

    #[test]
    fn values_read_back() {
        for v in [0.0, -3.0, 1e-6, 2.5, 0.05, 1e-12, 16.0, -0.5] {
            let t = value_text(v);
            assert_eq!(t.parse::<f64>().expect("number"), v, "{t}");
        }
        assert_eq!(value_text(1e-6), "1e-6");
        assert_eq!(value_text(0.05), "5e-2");
        assert_eq!(value_text(-3.0), "-3");
    }
}
