//! One run's dwells as the page needs them, read from the dwells table one chunk at a time
//! (`mimo_store::table_chunks`).
//!
//! The page does not draw the radars' own search dwells, which are over 90 % of the rows. It
//! needs four things from the table:
//! * each part's kind, for the measurements made in it: 16 bytes a part;
//! * the transmitting parts' time and energy, in file order, for the energy panel: 24 bytes a part;
//! * the search parts' start times, for the note on what the page leaves out: 8 bytes a part;
//! * the test article's parts, whole, for its beams.
//!
//! A whole row takes about 120 bytes, so the rows no longer decide `mimo plot`'s memory.

use mimo_core::records::{DwellKind, DwellRow, Requester};
use mimo_store::StoreError;
use mimo_store::table_chunks::TableChunks;
use std::path::Path;

/// A transmitting part: what the energy per interval adds up.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Transmit {
    t_s: f64,
    energy_j: f64,
    by_ta: bool,
}

/// What the page keeps of a run's dwells.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DwellDigest {
    /// `(dwell_id, kind)` of every part, sorted by id once read.
    kinds: Vec<(u64, DwellKind)>,
    /// The transmitting parts, in file order.
    transmits: Vec<Transmit>,
    /// Start times of the search parts.
    search_t_s: Vec<f64>,
    /// The parts the test article requested, in file order.
    pub ta_parts: Vec<DwellRow>,
}

impl DwellDigest {
    /// Read a dwells file, checked as every read of the table is (its rules included).
    pub fn read(path: &Path) -> Result<DwellDigest, StoreError> {
        let mut chunks = TableChunks::<DwellRow>::open(path)?;
        let mut out = DwellDigest { kinds: Vec::with_capacity(chunks.num_rows()), ..DwellDigest::default() };
        while let Some(rows) = chunks.next_chunk()? {
            out.extend(&rows);
        }
        out.finish();
        Ok(out)
    }

    /// Add rows, in file order; [`Self::finish`] once all are in.
    pub fn extend(&mut self, rows: &[DwellRow]) {
        for d in rows {
            self.kinds.push((d.dwell_id, d.kind));
            if d.role.transmits() {
                self.transmits.push(Transmit {
                    t_s: d.t_s,
                    energy_j: d.energy_j,
                    by_ta: d.requested_by == Requester::Ta,
                });
            }
            if d.kind == DwellKind::Search {
                self.search_t_s.push(d.t_s);
            }
            if d.requested_by == Requester::Ta {
                self.ta_parts.push(d.clone());
            }
        }
    }

    /// Sort the kinds by dwell id, for [`Self::kind_of`].
    pub fn finish(&mut self) {
        self.kinds.sort_unstable_by_key(|&(id, _)| id);
    }

    /// The kind of dwell part `dwell_id`, if the table has it.
    pub fn kind_of(&self, dwell_id: u64) -> Option<DwellKind> {
        self.kinds.binary_search_by_key(&dwell_id, |&(id, _)| id).ok().map(|i| self.kinds[i].1)
    }

    /// Energy emitted per scoring interval `j = ⌊t/Δ⌋ + 1` (J): all transmit parts, and those the
    /// test article requested. Interval `j` is closed by scoring time `t_j = jΔ`; the result has
    /// one entry per `j = 1 … n`. Added in file order.
    pub fn energy_per_interval(&self, interval_s: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
        let mut all = vec![0.0; n];
        let mut ta = vec![0.0; n];
        for d in &self.transmits {
            let j = (d.t_s / interval_s).floor();
            if j >= 0.0 && (j as usize) < n {
                all[j as usize] += d.energy_j;
                if d.by_ta {
                    ta[j as usize] += d.energy_j;
                }
            }
        }
        (all, ta)
    }

    /// How many search parts start within `[t0, t1]` (s).
    pub fn search_parts_within(&self, t0: f64, t1: f64) -> usize {
        self.search_t_s.iter().filter(|&&t| t >= t0 && t <= t1).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::ids::RadarId;
    use mimo_core::records::Role;

    fn part(dwell_id: u64, t_s: f64, role: Role, kind: DwellKind, by: Requester, energy_j: f64) -> DwellRow {
        DwellRow {
            run: 0,
            dwell_id,
            group_id: dwell_id,
            radar: RadarId(1),
            role,
            kind,
            requested_by: by,
            t_s,
            duration_s: 0.01,
            pulse_width_s: 1e-4,
            n_pulses: 2,
            peak_power_w: if energy_j > 0.0 { energy_j / 2e-4 } else { 0.0 },
            energy_j,
            waveform: 0,
            face: 0,
            beam_u: 0.0,
            beam_v: 0.0,
            aim_x_m: 1.0,
            aim_y_m: 2.0,
            aim_z_m: 3.0,
        }
    }

    /// The sizes the module's docs give for what is kept of a part.
    #[test]
    fn a_kept_part_takes_the_bytes_the_docs_say() {
        assert_eq!(std::mem::size_of::<(u64, DwellKind)>(), 16);
        assert_eq!(std::mem::size_of::<Transmit>(), 24);
    }

    /// A hand-made run: energy per 1-s interval, kinds, search count and the test article's parts.
    #[test]
    fn a_hand_made_runs_digest_and_its_file_round_trip() {
        use DwellKind::{Mimo, Search, Track};
        use Requester::{Radar, Ta};
        let rows = vec![
            part(1, 0.2, Role::Txrx, Search, Radar, 10.0),
            part(2, 0.7, Role::Txrx, Track, Ta, 4.0),
            part(3, 1.5, Role::Tx, Mimo, Ta, 6.0),
            part(4, 1.5, Role::Rx, Mimo, Ta, 0.0),
            part(5, 2.5, Role::Txrx, Search, Radar, 10.0),
            // Beyond the last interval: not counted in the energy.
            part(6, 3.5, Role::Txrx, Search, Radar, 10.0),
        ];
        let mut d = DwellDigest::default();
        d.extend(&rows[3..]);
        d.extend(&rows[..3]);
        d.finish();
        assert_eq!(d.kind_of(2), Some(Track));
        assert_eq!(d.kind_of(4), Some(Mimo));
        assert_eq!(d.kind_of(7), None);
        let (all, ta) = d.energy_per_interval(1.0, 3);
        assert_eq!(all, [14.0, 6.0, 10.0]);
        assert_eq!(ta, [4.0, 6.0, 0.0]);
        assert_eq!(d.search_parts_within(0.0, 2.5), 2);
        assert_eq!(d.search_parts_within(0.3, 10.0), 2);
        let ids: Vec<u64> = d.ta_parts.iter().map(|p| p.dwell_id).collect();
        assert_eq!(ids, [4, 2, 3]);

        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("run-0000.parquet");
        mimo_store::write_table(&path, &rows).expect("write");
        let read = DwellDigest::read(&path).expect("read");
        assert_eq!(read.ta_parts.iter().map(|p| p.dwell_id).collect::<Vec<_>>(), [2, 3, 4]);
        assert_eq!(read.energy_per_interval(1.0, 3), (all, ta));
        assert_eq!(read.kinds, d.kinds);
    }
}
