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
use crate::dwell_sums::{DWELL_SLICE_ROWS, DwellSums, FilePass, Rows};
use crate::purpose::{FileRows, PurposeCols};
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, DwellRow, Requester, Role};
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
    /// The rows held, as columns (at most [`CHUNK_ROWS`]).
    cols: Cols,
    /// Index in the run of the first row held.
    first_row: usize,
    /// The first check that failed, if any (the rows after it are not reduced).
    broken: Option<String>,
    /// Each radar's label index, as the pass gave it, and the last row's.
    radars: Vec<(RadarId, u8)>,
    last_radar: Option<(RadarId, u8)>,
}

/// The columns of the rows held, in the pass's label indices (radars, roles, requesters) and as
/// the usage by purpose reads them.
#[derive(Default)]
struct Cols {
    run: Vec<u32>,
    radar: Vec<u8>,
    role: Vec<u8>,
    by: Vec<u8>,
    t_s: Vec<f64>,
    duration_s: Vec<f64>,
    energy_j: Vec<f64>,
    group: Vec<u64>,
    face: Vec<u8>,
    beam_u: Vec<f64>,
    beam_v: Vec<f64>,
    aim_m: [Vec<f64>; 3],
    radar_index: Vec<usize>,
    roles: Vec<Role>,
    kinds: Vec<DwellKind>,
}

impl Cols {
    /// Every column emptied, its capacity kept.
    fn clear(&mut self) {
        for v in [&mut self.radar, &mut self.role, &mut self.by, &mut self.face] {
            v.clear();
        }
        for v in [&mut self.t_s, &mut self.duration_s, &mut self.energy_j, &mut self.beam_u, &mut self.beam_v] {
            v.clear();
        }
        for v in &mut self.aim_m {
            v.clear();
        }
        self.run.clear();
        self.group.clear();
        self.radar_index.clear();
        self.roles.clear();
        self.kinds.clear();
    }
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
            cols: Cols::default(),
            first_row: 0,
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
                    self.broken = Some(format!("radar {} refused", r.radar));
                    return;
                }
            },
        };
        let c = &mut self.cols;
        c.run.push(r.run);
        c.radar.push(radar);
        c.radar_index.push(usize::from(radar));
        c.role.push(fixed_index(&Role::LABELS, r.role.as_str()));
        c.by.push(fixed_index(&Requester::LABELS, r.requested_by.as_str()));
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
        let sums_rows = Rows {
            run: &c.run,
            radar: &c.radar,
            role: &c.role,
            requested_by: &c.by,
            t_s: &c.t_s,
            duration_s: &c.duration_s,
            energy_j: &c.energy_j,
        };
        self.pass.rows(&sums_rows).ok_or_else(|| {
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
        let cols = PurposeCols {
            first_row: self.first_row,
            run: &c.run,
            group: &c.group,
            radar: &c.radar_index,
            role: &c.roles,
            kind: &c.kinds,
            t_s: &c.t_s,
            duration_s: &c.duration_s,
            energy_j: &c.energy_j,
            face: &c.face,
            beam_u: &c.beam_u,
            beam_v: &c.beam_v,
            aim_m: [&c.aim_m[0], &c.aim_m[1], &c.aim_m[2]],
        };
        self.purposes.add(&cols, self.interval_s);
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
