//! Paired differences between a MIMO method and its conventional counterpart (docs/studies.md):
//! the same test article (built-in name or command) at the same knob value(s), one MIMO and one
//! conventional, on the same scenario and stress point. Run `k` of both cells shares its random
//! draws, so the difference is taken run by run and its interval is the paired t interval.

use crate::estimate::paired_difference;
use crate::grid::Cell;
use crate::plan::{Architecture, MethodTa, Plan};
use crate::tables::ResultRow;

/// One pair and its differences (MIMO − conventional): (mean, lo, hi).
#[derive(Debug, Clone, PartialEq)]
pub struct PairedRow {
    /// The MIMO method's cell.
    pub mimo: usize,
    /// The conventional method's cell.
    pub conventional: usize,
    /// Runs where both completed.
    pub runs: usize,
    /// Completeness difference, within [−1, 1].
    pub completeness: (Option<f64>, Option<f64>, Option<f64>),
    /// Total energy (search and TA) per scorable object difference (J).
    pub energy_j: (Option<f64>, Option<f64>, Option<f64>),
}

fn same_ta(a: &MethodTa, b: &MethodTa) -> bool {
    match (a, b) {
        (MethodTa::Builtin { ta: x, .. }, MethodTa::Builtin { ta: y, .. }) => x == y,
        (MethodTa::Process { cmd: x, .. }, MethodTa::Process { cmd: y, .. }) => x == y,
        _ => false,
    }
}

fn metric(recs: &[ResultRow], name: &str) -> Vec<Option<f64>> {
    recs.iter().map(|r| if r.failure.is_some() { None } else { r.metric(name) }).collect()
}

/// Every (MIMO, conventional) counterpart pair of cells, in cell order of the MIMO method.
pub fn paired_rows(plan: &Plan, cells: &[Cell], records: &[Vec<ResultRow>]) -> Vec<PairedRow> {
    let mut out = Vec::new();
    for (a, ca) in cells.iter().enumerate() {
        let ma = &plan.methods[ca.method];
        if ma.architecture != Architecture::Mimo {
            continue;
        }
        for (b, cb) in cells.iter().enumerate() {
            let mb = &plan.methods[cb.method];
            let counterpart = mb.architecture == Architecture::Conventional
                && same_ta(&ma.ta, &mb.ta)
                && ma.grid == mb.grid
                && ca.scenario == cb.scenario
                && ca.point == cb.point
                && ca.swept == cb.swept;
            if !counterpart {
                continue;
            }
            let (ra, rb) = (&records[a], &records[b]);
            let runs = ra.iter().zip(rb).filter(|(x, y)| x.failure.is_none() && y.failure.is_none()).count();
            let diff = |name: &str, range| paired_difference(&metric(ra, name), &metric(rb, name), range);
            out.push(PairedRow {
                mimo: a,
                conventional: b,
                runs,
                completeness: diff("completeness", (-1.0, 1.0)),
                energy_j: diff("energy_per_object_j", (f64::NEG_INFINITY, f64::INFINITY)),
            });
        }
    }
    out
}
