//! A run's measurements and primitives by dwell group, for a re-run (`super::replay_selected`):
//! each row beside its group in one vector, ordered by group, so a run in flight holds its rows
//! once and no vector per group.

use super::{Parts, ReplayError, ReplayFrom};
use mimo_core::records::{MeasurementRow, PrimitiveRow};
use mimo_core::sink::RunSink;
use mimo_sim::engine::first_meas_id;

/// One run's rows of a table by dwell group: each row beside its group, ordered by group and in
/// file order within a group, in one vector (no vector per group).
pub(super) struct GroupedRows<R> {
    /// (group_id, row), by group.
    pub(super) rows: Vec<(u64, R)>,
}

impl<R: Clone> GroupedRows<R> {
    /// Rows tagged with their groups, ordered by group (a stable sort: file order within one).
    fn of(mut rows: Vec<(u64, R)>) -> GroupedRows<R> {
        if !rows.windows(2).all(|w| w[0].0 <= w[1].0) {
            rows.sort_by_key(|r| r.0);
        }
        GroupedRows { rows }
    }

    /// The rows of group `gid`.
    pub(super) fn group(&self, gid: u64) -> &[(u64, R)] {
        let lo = self.rows.partition_point(|r| r.0 < gid);
        let hi = lo + self.rows[lo..].partition_point(|r| r.0 == gid);
        &self.rows[lo..hi]
    }

    /// A copy of the rows of group `gid` (a report owns its rows).
    pub(super) fn cloned(&self, gid: u64) -> Vec<R> {
        self.group(gid).iter().map(|r| r.1.clone()).collect()
    }

    /// The groups that have rows, ascending, each with its rows.
    fn groups(&self) -> impl Iterator<Item = (u64, &[(u64, R)])> {
        self.rows.chunk_by(|a, b| a.0 == b.0).map(|g| (g[0].0, g))
    }
}

/// The run's rows of `rows` tagged with their groups; a row of a dwell the run lacks is refused,
/// naming `table`.
fn tag_groups<R>(
    parts: &Parts<'_>,
    rows: Vec<R>,
    of: impl Fn(&R) -> (u32, u64),
    run: u32,
    table: &'static str,
) -> Result<Vec<(u64, R)>, ReplayError> {
    let mut tagged = Vec::with_capacity(rows.iter().filter(|r| of(r).0 == run).count());
    for r in rows.into_iter().filter(|r| of(r).0 == run) {
        let dwell_id = of(&r).1;
        let gid = parts.group_of(dwell_id).ok_or(ReplayError::UnknownDwell { table, dwell_id })?;
        tagged.push((gid, r));
    }
    Ok(tagged)
}

/// Measurements by group, and primitives by group.
pub(super) type ByGroup = (GroupedRows<MeasurementRow>, GroupedRows<PrimitiveRow>);

/// The run's measurements (recorded, or re-formed from primitives and sent to `sink`) and
/// primitives, per group.
pub(super) fn by_group(
    parts: &Parts<'_>,
    run: u32,
    primitives: Vec<PrimitiveRow>,
    measurements: Vec<MeasurementRow>,
    from: ReplayFrom,
    sink: &mut dyn RunSink,
) -> Result<ByGroup, ReplayError> {
    let prims = GroupedRows::of(tag_groups(parts, primitives, |p| (p.run, p.dwell_id), run, "primitives")?);
    let meas = match from {
        ReplayFrom::Measurements => {
            GroupedRows::of(tag_groups(parts, measurements, |m| (m.run, m.dwell_id), run, "measurements")?)
        }
        ReplayFrom::Primitives => {
            drop(measurements);
            // A group's primitives form at most as many measurements: room taken once.
            let mut tagged = Vec::with_capacity(prims.rows.len());
            for (gid, ps) in prims.groups() {
                let ps: Vec<PrimitiveRow> = ps.iter().map(|p| p.1.clone()).collect();
                let ms = mimo_radar::measurements_from_primitives(&ps, first_meas_id(gid));
                tagged.extend(ms.into_iter().map(|m| (gid, m)));
            }
            let mut all: Vec<MeasurementRow> = tagged.iter().map(|m| m.1.clone()).collect();
            all.sort_by_key(|m| m.meas_id);
            if !all.is_empty() {
                sink.measurements(all)?;
            }
            GroupedRows::of(tagged)
        }
    };
    Ok((meas, prims))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows grouped keep file order within a group, and a group without rows has none.
    #[test]
    fn grouped_rows_keep_file_order_within_a_group() {
        let tagged: Vec<(u64, &str)> = vec![(7, "a"), (2, "b"), (7, "c"), (5, "d"), (2, "e")];
        let g = GroupedRows::of(tagged);
        assert_eq!(g.cloned(7), vec!["a", "c"]);
        assert_eq!(g.cloned(2), vec!["b", "e"]);
        assert_eq!(g.cloned(5), vec!["d"]);
        assert!(g.cloned(3).is_empty() && g.cloned(1).is_empty() && g.cloned(9).is_empty());
        let groups: Vec<(u64, usize)> = g.groups().map(|(gid, rows)| (gid, rows.len())).collect();
        assert_eq!(groups, vec![(2, 2), (5, 1), (7, 2)]);
    }
}
