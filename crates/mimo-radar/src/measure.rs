//! Measurements from detection primitives (docs/model.md §4.5 step 4, docs/design.md §3).
//!
//! [`measurements_from_primitives`] is the **only** implementation: the simulator calls it on each
//! dwell's primitives, and `mimo track --from primitives` calls it on recorded primitives, so it
//! depends on nothing but the fields of [`PrimitiveRow`] and the first measurement id.
//!
//! Rule: primitives of one channel and dwell — the same `(run, dwell_id, rx, tx)` — are sorted by
//! range cell, and a primitive joins the previous one's cluster when its range cell is at most
//! [`CLUSTER_CELLS`] cells beyond it. A cluster becomes one measurement carrying the values and
//! variances of its strongest primitive (highest `snr_db`, the first in sorted order on ties):
//! primitives of one cluster share cells and are strongly correlated, so averaging them would not
//! reduce the error as an average of independent estimates would. `n_primitives` counts the
//! cluster; `merged` is set when any primitive of it is merged; `target_hint` is the strongest
//! primitive's.
//!
//! Two primitives of one channel never share a range cell except the two halves of a two-target
//! fit (docs/model.md §4.9), which both carry the cluster's peak cell: a primitive with the same
//! range cell as the previous one starts a new measurement, so each half is a measurement of its
//! own.
//!
//! Output order, and so the `meas_id`s (`first_meas_id`, `first_meas_id + 1`, …), follows the
//! sort by `(run, dwell_id, rx, tx)` then range cell, so it does not depend on the input order
//! (except between primitives identical in those keys and in `range_m`).

use mimo_core::records::{MeasurementRow, PrimitiveRow};
use std::cmp::Ordering;

/// Primitives whose range cells are at most this far apart (in cells) are one measurement.
pub const CLUSTER_CELLS: i64 = 2;

fn order(a: &PrimitiveRow, b: &PrimitiveRow) -> Ordering {
    (a.run, a.dwell_id, a.rx, a.tx, a.range_cell)
        .cmp(&(b.run, b.dwell_id, b.rx, b.tx, b.range_cell))
        .then(a.range_m.total_cmp(&b.range_m))
        .then(b.snr_db.total_cmp(&a.snr_db))
}

fn same_channel(a: &PrimitiveRow, b: &PrimitiveRow) -> bool {
    (a.run, a.dwell_id, a.rx, a.tx) == (b.run, b.dwell_id, b.rx, b.tx)
}

/// Cluster and centroid primitives into measurements, numbering them from `first_meas_id`.
pub fn measurements_from_primitives(primitives: &[PrimitiveRow], first_meas_id: u64) -> Vec<MeasurementRow> {
    let mut sorted: Vec<&PrimitiveRow> = primitives.iter().collect();
    sorted.sort_by(|a, b| order(a, b));
    let mut out = Vec::new();
    let mut i = 0;
    while i < sorted.len() {
        let mut j = i + 1;
        while j < sorted.len()
            && same_channel(sorted[j - 1], sorted[j])
            && sorted[j].range_cell - sorted[j - 1].range_cell <= CLUSTER_CELLS
            && sorted[j].range_cell != sorted[j - 1].range_cell
        {
            j += 1;
        }
        let cluster = &sorted[i..j];
        let mut best = cluster[0];
        for p in &cluster[1..] {
            if p.snr_db > best.snr_db {
                best = p;
            }
        }
        out.push(MeasurementRow {
            run: best.run,
            meas_id: first_meas_id + out.len() as u64,
            dwell_id: best.dwell_id,
            t_s: best.t_s,
            rx: best.rx,
            tx: best.tx,
            rx_face: best.rx_face,
            range_m: best.range_m,
            u: best.u,
            v: best.v,
            snr_db: best.snr_db,
            var_range_m2: best.var_range_m2,
            var_u: best.var_u,
            var_v: best.var_v,
            n_primitives: cluster.len() as u32,
            merged: cluster.iter().any(|p| p.merged),
            target_hint: best.target_hint.clone(),
        });
        i = j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::ids::RadarId;

    fn prim(dwell: u64, cell: i64, snr: f64, merged: bool) -> PrimitiveRow {
        PrimitiveRow {
            run: 0,
            dwell_id: dwell,
            t_s: 1.0,
            rx: RadarId(0),
            tx: RadarId(0),
            rx_face: 1,
            range_cell: cell,
            range_m: cell as f64 * 30.0 + 3.0,
            u: 0.1,
            v: 0.2,
            snr_db: snr,
            eta_q: 0.5,
            merged,
            beam_u: 0.1,
            beam_v: 0.2,
            var_range_m2: 25.0,
            var_u: 1e-6,
            var_v: 1e-6,
            target_hint: Some(format!("T{cell}")),
        }
    }

    #[test]
    fn clusters_by_channel_and_cell_and_is_order_independent() {
        let prims = vec![
            prim(7, 100, 20.0, false),
            prim(7, 102, 25.0, true),
            prim(7, 200, 15.0, false),
            prim(8, 101, 18.0, false),
            prim(7, 105, 14.0, false),
        ];
        let m = measurements_from_primitives(&prims, 10);
        assert_eq!(m.len(), 4);
        assert_eq!(m[0].meas_id, 10);
        assert_eq!(m[0].n_primitives, 2);
        assert!(m[0].merged);
        assert_eq!(m[0].snr_db, 25.0);
        assert_eq!(m[0].target_hint.as_deref(), Some("T102"));
        assert_eq!(m[1].n_primitives, 1);
        assert_eq!(m[1].range_m, 105.0 * 30.0 + 3.0);
        assert_eq!(m[2].range_m, 200.0 * 30.0 + 3.0);
        assert_eq!(m[3].dwell_id, 8);
        let mut rev = prims.clone();
        rev.reverse();
        assert_eq!(measurements_from_primitives(&rev, 10), m);
        assert!(measurements_from_primitives(&[], 0).is_empty());
    }

    /// The two halves of a two-target fit share the peak cell (docs/model.md §4.9): each is a
    /// measurement of its own, and a primitive two cells further joins the second half.
    #[test]
    fn split_halves_sharing_a_cell_stay_apart() {
        let mut a = prim(7, 100, 20.0, false);
        a.range_m = 3000.0;
        let mut b = prim(7, 100, 18.0, false);
        b.range_m = 3040.0;
        let c = prim(7, 102, 25.0, false);
        let m = measurements_from_primitives(&[c.clone(), b.clone(), a.clone()], 0);
        assert_eq!(m.len(), 2);
        assert_eq!((m[0].range_m, m[0].n_primitives, m[0].meas_id), (3000.0, 1, 0));
        assert_eq!((m[1].range_m, m[1].n_primitives, m[1].meas_id), (c.range_m, 2, 1));
        assert_eq!(
            measurements_from_primitives(&[a, b], 5).iter().map(|m| m.range_m).collect::<Vec<_>>(),
            [3000.0, 3040.0]
        );
    }
}
