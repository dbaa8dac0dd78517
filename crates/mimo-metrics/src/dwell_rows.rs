//! A run's dwells reduced as the run makes them, with no file (docs/design.md §6): what a study
//! item scores when it does not keep the run's tables
//! (docs/decisions/0321-study-runs-scored-from-their-dwell-rows.md).
//!
//! The rows go through the same reduction as a dwells file's pages ([`crate::dwell_pages`]), in
//! the same row order: the usage sums' pass ([`crate::dwell_sums::FilePass`], whose slices count
//! rows, not files or row groups) and the usage by purpose's rows ([`crate::purpose::FileRows`]),
//! radars indexed in order of first appearance, the same checks. The sums are therefore those a
//! score of the run's dwells file gives, bit for bit. Rows are held, as columns, [`CHUNK_ROWS`] at a time, so
//! the memory is that of the sums and of the few non-search parts the usage by purpose keeps for
//! classification, whatever the run's length.

use crate::MetricsError;
use crate::dwell_pages::Buffers;
use crate::dwell_sums::{DWELL_SLICE_ROWS, DwellSums, FilePass};
use crate::purpose::FileRows;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellRow, Requester, Role};
use std::borrow::Cow;
use std::collections::BTreeSet;

/// Rows held before they are reduced.
pub const CHUNK_ROWS: usize = 1 << 14;

/// The dwells of one run, reduced as they come ([`DwellRows::push`]); scored by
/// [`crate::score_with_dwell_rows`].
pub struct DwellRows {
    run: u32,
    interval_s: f64,
    pass: FilePass<'static>,
    purposes: FileRows,
    /// The rows held, as the columns a row group of a file decodes to (at most [`CHUNK_ROWS`]).
    cols: Buffers,
    /// Index in the run of the first row held.
    first_row: usize,
    /// The first check that failed, if any (the rows after it are not reduced).
    broken: Option<String>,
    /// Each radar's label index, as the pass gave it, and the last row's.
    radars: Vec<(RadarId, u8)>,
    last_radar: Option<(RadarId, u8)>,
    /// The last row's role and requester with their label indices (runs of equal values are the
    /// rule).
    last_role: Option<(Role, u8)>,
    last_by: Option<(Requester, u8)>,
}

/// The index of `label` in the fixed list `labels` (as the pass's fixed labels index it).
fn fixed_index(labels: &[&str], label: &str) -> u8 {
    labels.iter().position(|l| *l == label).and_then(|i| u8::try_from(i).ok()).unwrap_or(u8::MAX)
}

impl DwellRows {
    /// The dwells of run `run`, summed per scoring interval of `interval_s`.
    pub fn new(run: u32, interval_s: f64) -> DwellRows {
        DwellRows {
            run,
            interval_s,
            pass: FilePass::with_runs(Cow::Owned(BTreeSet::from([run])), interval_s, DWELL_SLICE_ROWS),
            purposes: FileRows::default(),
            cols: Buffers::default(),
            first_row: 0,
            broken: None,
            radars: Vec::new(),
            last_radar: None,
            last_role: None,
            last_by: None,
        }
    }

    /// The run's next dwell row, in the order the run makes them.
    pub fn push(&mut self, r: &DwellRow) {
        if self.broken.is_some() {
            return;
        }
        let radar = match self.last_radar {
            Some((id, i)) if id == r.radar => i,
            _ => match self.radar_label(r.radar) {
                Some(i) => {
                    self.last_radar = Some((r.radar, i));
                    i
                }
                None => {
                    self.broken = Some(format!("radar {} refused", r.radar));
                    return;
                }
            },
        };
        let role = match self.last_role {
            Some((x, i)) if x == r.role => i,
            _ => fixed_index(&Role::LABELS, r.role.as_str()),
        };
        self.last_role = Some((r.role, role));
        let by = match self.last_by {
            Some((x, i)) if x == r.requested_by => i,
            _ => fixed_index(&Requester::LABELS, r.requested_by.as_str()),
        };
        self.last_by = Some((r.requested_by, by));
        let c = &mut self.cols;
        c.run.push(r.run);
        c.radar.push(radar);
        c.radar_index.push(usize::from(radar));
        c.role.push(role);
        c.by.push(by);
        c.roles.push(r.role);
        c.kinds.push(r.kind);
        c.t_s.push(r.t_s);
        c.duration_s.push(r.duration_s);
        c.energy_j.push(r.energy_j);
        c.group.push(r.group_id);
        c.face.push(r.face);
        c.beam_u.push(r.beam_u);
        c.beam_v.push(r.beam_v);
        c.aim_m[0].push(r.aim_x_m);
        c.aim_m[1].push(r.aim_y_m);
        c.aim_m[2].push(r.aim_z_m);
        if c.run.len() == CHUNK_ROWS {
            self.reduce();
        }
    }

    /// The label index of `radar` in the pass (its first appearance adds it).
    fn radar_label(&mut self, radar: RadarId) -> Option<u8> {
        if let Some(&(_, i)) = self.radars.iter().find(|(r, _)| *r == radar) {
            return Some(i);
        }
        let i = self.pass.radar.index(&radar.to_string(), None)?;
        self.radars.push((radar, i));
        Some(i)
    }

    /// The rows held reduced, in order, and let go.
    fn reduce(&mut self) {
        if let Err(why) = self.reduce_held() {
            self.broken = Some(why);
        }
        self.first_row += self.cols.run.len();
        self.cols.clear();
    }

    fn reduce_held(&mut self) -> Result<(), String> {
        let c = &self.cols;
        self.pass.rows(&c.sums_rows()).ok_or_else(|| {
            "a row breaks the dwells table's rules (a run other than its own, a time going back for \
             a radar, or a time, duration or energy that is negative or not finite)"
                .to_string()
        })?;
        // Finite, as the usage by purpose's checked read requires.
        let finite = [&c.beam_u, &c.beam_v, &c.aim_m[0], &c.aim_m[1], &c.aim_m[2]]
            .iter()
            .all(|v| v.iter().all(|x| x.is_finite()));
        if !finite {
            return Err("a beam direction or aim point is not finite".to_string());
        }
        self.purposes.add(&c.purpose_cols(self.first_row), self.interval_s);
        Ok(())
    }

    /// The run's usage sums and usage-by-purpose rows, as a score of its dwells file reduces them;
    /// an error names the run and the check its rows broke.
    pub(crate) fn finish(mut self) -> Result<(DwellSums, FileRows), MetricsError> {
        if self.broken.is_none() && !self.cols.run.is_empty() {
            self.reduce();
        }
        if let Some(why) = self.broken {
            return Err(MetricsError::Internal {
                context: "scoring a run's dwell rows",
                detail: format!("run {}: {why}", self.run),
            });
        }
        let sums = self.pass.finish();
        let mut rows = self.purposes;
        rows.set_radars(sums.radar_names.clone());
        Ok((sums, rows))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dwell_pages::tests::rows;

    /// The rows reduced in memory give, bit for bit, what the pass over the same rows' file gives:
    /// the usage sums and the purpose rows (search sums and kept parts), across chunks.
    #[test]
    fn rows_in_memory_reduce_as_their_file_does() {
        let dir = tempfile::tempdir().expect("tempdir");
        let rows = rows(2 * CHUNK_ROWS + 700);
        let path = dir.path().join("run-0003.parquet");
        mimo_store::write_table(&path, &rows).expect("write");
        let runs = BTreeSet::from([3]);
        let (file_sums, file_rows) = crate::dwell_pages::file_pass(&path, &runs, 1.0, DWELL_SLICE_ROWS).expect("pass");
        let mut memory = DwellRows::new(3, 1.0);
        rows.iter().for_each(|r| memory.push(r));
        let (sums, purpose_rows) = memory.finish().expect("rows");
        assert_eq!(format!("{sums:?}"), format!("{file_sums:?}"));
        assert_eq!(purpose_rows.view(), file_rows.view());
        assert!(purpose_rows.view().contains("Track"), "non-search parts were kept");
    }

    /// A row of another run, or a non-finite aim point, is an error naming the run and the rule.
    #[test]
    fn a_row_breaking_a_rule_is_an_error() {
        let mut other = rows(100);
        other[40].run = 4;
        let mut memory = DwellRows::new(3, 1.0);
        other.iter().for_each(|r| memory.push(r));
        let e = memory.finish().map(|_| ()).expect_err("another run").to_string();
        assert!(e.contains("run 3") && e.contains("a run other than its own"), "{e}");
        let mut aim = rows(100);
        aim[7].aim_z_m = f64::NAN;
        let mut memory = DwellRows::new(3, 1.0);
        aim.iter().for_each(|r| memory.push(r));
        let e = memory.finish().map(|_| ()).expect_err("aim").to_string();
        assert!(e.contains("aim point is not finite"), "{e}");
    }
}
