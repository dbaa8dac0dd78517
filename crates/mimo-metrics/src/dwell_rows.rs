//! A run's dwells reduced as the run makes them, with no file (docs/design.md §6): what a study
//! item scores when it does not keep the run's tables
//! (docs/decisions/0321-study-runs-scored-from-their-dwell-rows.md).
//!
//! The rows go through the same reduction as a dwells file's chunks ([`crate::dwell_file`]), in
//! the same row order: the usage sums' pass ([`crate::dwell_sums::FilePass`], whose slices count
//! rows, not files or row groups) and the usage by purpose's rows ([`crate::purpose::FileRows`]),
//! radars indexed in order of first appearance, the same checks. The sums are therefore those a
//! score of the run's dwells file gives, bit for bit. Rows are held, as columns, [`CHUNK_ROWS`] at a time, so
//! the memory is that of the sums and of the few non-search parts the usage by purpose keeps for
//! classification, whatever the run's length.

use crate::MetricsError;
use crate::dwell_sums::{DWELL_SLICE_ROWS, DwellSums, FilePass};
use crate::purpose::FileRows;
use mimo_core::ids::RadarId;
use mimo_core::records::DwellRow;
use mimo_store::dwell_chunks::DwellChunk;
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
    /// The rows held, as the chunk a reader of their file gives (at most [`CHUNK_ROWS`]).
    chunk: DwellChunk,
    /// The radars of the rows held, as indices in `radars`.
    radar_index: Vec<usize>,
    /// The first check that failed, if any (the rows after it are not reduced).
    broken: Option<String>,
    /// The radars in order of first appearance (a row's radar index into them), and the last
    /// row's.
    radars: Vec<RadarId>,
    last_radar: Option<(RadarId, u8)>,
}

impl DwellRows {
    /// The dwells of run `run`, summed per scoring interval of `interval_s`.
    pub fn new(run: u32, interval_s: f64) -> DwellRows {
        DwellRows {
            run,
            interval_s,
            pass: FilePass::with_runs(Cow::Owned(BTreeSet::from([run])), interval_s, DWELL_SLICE_ROWS),
            purposes: FileRows::default(),
            chunk: DwellChunk::default(),
            radar_index: Vec::new(),
            broken: None,
            radars: Vec::new(),
            last_radar: None,
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
                    self.broken = Some(format!("radar {} beyond the 255 a dwells file may name", r.radar));
                    return;
                }
            },
        };
        self.chunk.push(r, radar);
        if self.chunk.len() == CHUNK_ROWS {
            self.reduce();
        }
    }

    /// The index of `radar` among the run's radars (its first appearance adds it).
    fn radar_label(&mut self, radar: RadarId) -> Option<u8> {
        let i = match self.radars.iter().position(|r| *r == radar) {
            Some(i) => i,
            None => {
                self.radars.push(radar);
                self.radars.len() - 1
            }
        };
        u8::try_from(i).ok()
    }

    /// The rows held reduced, in order, and let go.
    fn reduce(&mut self) {
        if let Err(why) = self.reduce_held() {
            self.broken = Some(why);
        }
        let first_row = self.chunk.first_row + self.chunk.len();
        self.chunk.clear();
        self.chunk.first_row = first_row;
    }

    fn reduce_held(&mut self) -> Result<(), String> {
        let c = &self.chunk;
        // The column rules a reader of the file checks (times, durations and energies finite and
        // >= 0 are the pass's own).
        let finite = [&c.beam_u, &c.beam_v, &c.aim_m[0], &c.aim_m[1], &c.aim_m[2]]
            .iter()
            .all(|v| v.iter().all(|x| x.is_finite()));
        self.pass.rows(&crate::dwell_file::sums_rows(c)).ok_or_else(|| {
            "a row breaks the dwells table's rules (a run other than its own, a time going back for \
             a radar, or a time, duration or energy that is negative or not finite)"
                .to_string()
        })?;
        if !finite {
            return Err("a beam direction or aim point is not finite".to_string());
        }
        self.radar_index.clear();
        self.radar_index.extend(c.radar.iter().map(|&r| usize::from(r)));
        self.purposes.add(&crate::dwell_file::purpose_cols(c, &self.radar_index), self.interval_s);
        Ok(())
    }

    /// The run's usage sums and usage-by-purpose rows, as a score of its dwells file reduces them;
    /// an error names the run and the check its rows broke.
    pub(crate) fn finish(mut self) -> Result<(DwellSums, FileRows), MetricsError> {
        if self.broken.is_none() && !self.chunk.is_empty() {
            self.reduce();
        }
        if let Some(why) = self.broken {
            return Err(MetricsError::Internal {
                context: "scoring a run's dwell rows",
                detail: format!("run {}: {why}", self.run),
            });
        }
        let sums = self.pass.finish(self.radars.iter().map(|r| r.to_string()).collect());
        let mut rows = self.purposes;
        rows.set_radars(sums.radar_names.clone());
        Ok((sums, rows))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dwell_file::tests::rows;

    /// The rows reduced in memory give, bit for bit, what the pass over the same rows' file gives:
    /// the usage sums and the purpose rows (search sums and kept parts), across chunks.
    #[test]
    fn rows_in_memory_reduce_as_their_file_does() {
        let dir = tempfile::tempdir().expect("tempdir");
        let rows = rows(2 * CHUNK_ROWS + 700);
        let path = dir.path().join("run-0003.parquet");
        mimo_store::write_table(&path, &rows).expect("write");
        let runs = BTreeSet::from([3]);
        let (file_sums, file_rows) = crate::dwell_file::file_pass(&path, &runs, 1.0, DWELL_SLICE_ROWS).expect("pass");
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
