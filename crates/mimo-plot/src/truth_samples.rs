//! One run's truth as the page needs it: each target's sample times, ECEF positions and
//! velocities, read from the truth table one chunk at a time (`mimo_store::table_chunks`).
//!
//! The page draws truth paths ([`crate::objects::truth_paths`]) from these, and counts the
//! samples in its window. A sample takes 56 bytes here. A truth row read whole takes about three
//! times that, with its target id a string of its own. That difference decides `mimo plot`'s memory
//! on a raid, whose truth is most of its rows (10 Hz × every aircraft).

use glam::DVec3;
use mimo_core::records::TruthRow;
use mimo_store::StoreError;
use mimo_store::table_chunks::TableChunks;
use std::collections::BTreeMap;
use std::path::Path;

/// One target's truth samples, in the order of the file's rows.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TargetSamples {
    /// Sample times (s).
    pub t_s: Vec<f64>,
    /// Positions, ECEF (m).
    pub pos_m: Vec<DVec3>,
    /// Velocities, ECEF (m/s).
    pub vel_mps: Vec<DVec3>,
}

/// The truth samples of one run, by target id.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TruthSamples {
    /// Each target's samples.
    pub by_target: BTreeMap<String, TargetSamples>,
}

impl TruthSamples {
    /// Read a truth file, checked as every read of the table is (its rules included).
    pub fn read(path: &Path) -> Result<TruthSamples, StoreError> {
        let mut chunks = TableChunks::<TruthRow>::open(path)?;
        let mut out = TruthSamples::default();
        while let Some(rows) = chunks.next_chunk()? {
            out.extend(&rows);
        }
        Ok(out)
    }

    /// Add rows, in order.
    pub fn extend(&mut self, rows: &[TruthRow]) {
        // The truth is written one row per target per sample time, so the target changes every
        // row: the entry is looked up by name each time, without allocating.
        for r in rows {
            let s = match self.by_target.get_mut(r.target.as_str()) {
                Some(s) => s,
                None => self.by_target.entry(r.target.clone()).or_default(),
            };
            s.t_s.push(r.t_s);
            s.pos_m.push(DVec3::new(r.x_m, r.y_m, r.z_m));
            s.vel_mps.push(DVec3::new(r.vx_mps, r.vy_mps, r.vz_mps));
        }
    }

    /// How many samples, of every target, lie within `[t0, t1]` (s).
    pub fn count_within(&self, t0: f64, t1: f64) -> usize {
        self.by_target.values().map(|s| s.t_s.iter().filter(|&&t| t >= t0 && t <= t1).count()).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(t_s: f64, target: &str, x: f64) -> TruthRow {
        TruthRow {
            run: 0,
            t_s,
            target: target.into(),
            x_m: x,
            y_m: 2.0 * x,
            z_m: 3.0 * x,
            vx_mps: -x,
            vy_mps: 0.5,
            vz_mps: 0.0,
            lat_deg: 0.0,
            lon_deg: 0.0,
            alt_m: 0.0,
            rcs_m2: 1.0,
        }
    }

    #[test]
    fn rows_go_to_their_target_in_order_and_a_file_round_trips() {
        let rows = vec![row(0.0, "B", 1.0), row(0.0, "A", 2.0), row(0.1, "B", 3.0), row(0.1, "A", 4.0)];
        let mut s = TruthSamples::default();
        s.extend(&rows[..3]);
        s.extend(&rows[3..]);
        assert_eq!(s.by_target.keys().collect::<Vec<_>>(), ["A", "B"]);
        let b = &s.by_target["B"];
        assert_eq!(b.t_s, [0.0, 0.1]);
        assert_eq!(b.pos_m, [DVec3::new(1.0, 2.0, 3.0), DVec3::new(3.0, 6.0, 9.0)]);
        assert_eq!(b.vel_mps[1], DVec3::new(-3.0, 0.5, 0.0));
        assert_eq!(s.count_within(0.05, 1.0), 2);
        assert_eq!(s.count_within(0.0, 0.1), 4);

        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("run-0000.parquet");
        mimo_store::write_table(&path, &rows).expect("write");
        assert_eq!(TruthSamples::read(&path).expect("read"), s);
    }
}
