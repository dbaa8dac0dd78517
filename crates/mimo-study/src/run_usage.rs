//! A study run's transmit usage (docs/design.md §6): the totals and per-interval sums of its
//! transmitting dwells, summed in dwell order as the run makes them, from which the study's
//! energy and dwell-time metrics come.

use mimo_core::records::{DwellRow, Requester, Role};

/// A run's transmit usage, summed in dwell order (so the sums never depend on how a dataframe
/// engine splits its work): totals and, per scoring interval, the sums the per-object figures
/// divide (docs/design.md §6: only transmitting participations cost; interval
/// `j = floor(t_s / interval_s) + 1`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunUsage {
    /// Dwell time, energy, TA dwell time, TA energy over the run.
    pub totals: [f64; 4],
    /// The same per interval, indexed by `j` (index 0 unused; an interval with no transmit dwell
    /// holds zeros).
    pub per_interval: Vec<[f64; 4]>,
}

impl RunUsage {
    /// Sum a run's dwell rows.
    pub fn of(dwells: &[DwellRow], interval_s: f64) -> RunUsage {
        let mut u = RunUsage::default();
        for d in dwells {
            u.add(d, interval_s);
        }
        u
    }

    /// Add the run's next dwell row (in the run's order; a receive-only row costs nothing).
    pub fn add(&mut self, d: &DwellRow, interval_s: f64) {
        if d.role == Role::Rx {
            return;
        }
        let ta = d.requested_by == Requester::Ta;
        let add = [d.duration_s, d.energy_j, if ta { d.duration_s } else { 0.0 }, if ta { d.energy_j } else { 0.0 }];
        let j = (d.t_s / interval_s).floor() as u32 as usize + 1;
        if self.per_interval.len() <= j {
            self.per_interval.resize(j + 1, [0.0; 4]);
        }
        let slot = &mut self.per_interval[j];
        for i in 0..4 {
            self.totals[i] += add[i];
            slot[i] += add[i];
        }
    }

    /// Σ over intervals `j` with `N[j] > 0` of `sum[j][i] / N[j]`, `N[j]` the objects scorable
    /// at the end of interval `j` (`n_scorable[j − 1]`); `None` if no interval has one.
    pub fn per_object(&self, i: usize, n_scorable: &[u32]) -> Option<f64> {
        let mut total = None;
        for (j, n) in n_scorable.iter().enumerate() {
            if *n > 0 {
                let s = self.per_interval.get(j + 1).map_or(0.0, |v| v[i]);
                *total.get_or_insert(0.0) += s / f64::from(*n);
            }
        }
        total
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::ids::RadarId;

    fn dwell(t_s: f64, role: Role, by: Requester, duration_s: f64, energy_j: f64) -> DwellRow {
        DwellRow {
            run: 0,
            dwell_id: 0,
            group_id: 0,
            radar: RadarId(1),
            role,
            kind: mimo_core::records::DwellKind::Track,
            requested_by: by,
            t_s,
            duration_s,
            pulse_width_s: 1e-6,
            n_pulses: 1,
            peak_power_w: 1.0,
            energy_j,
            waveform: 0,
            face: 0,
            beam_u: 0.0,
            beam_v: 0.0,
            aim_x_m: 0.0,
            aim_y_m: 0.0,
            aim_z_m: 0.0,
        }
    }

    #[test]
    fn usage_counts_transmitters_per_interval() {
        let d = [
            dwell(0.2, Role::Txrx, Requester::Radar, 0.01, 100.0),
            dwell(0.7, Role::Tx, Requester::Ta, 0.02, 300.0),
            dwell(0.7, Role::Rx, Requester::Ta, 0.02, 999.0), // receiving costs nothing
            dwell(1.5, Role::Txrx, Requester::Ta, 0.04, 500.0),
            dwell(2.5, Role::Txrx, Requester::Ta, 0.04, 700.0),
        ];
        let u = RunUsage::of(&d, 1.0);
        let want = [0.11, 1600.0, 0.1, 1500.0];
        assert!(u.totals.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12), "{:?}", u.totals);
        // Two objects scorable at 1 s, none at 2 s, four at 3 s.
        let per = u.per_object(1, &[2, 0, 4]).expect("defined");
        assert!((per - (400.0 / 2.0 + 700.0 / 4.0)).abs() < 1e-12, "{per}");
        assert_eq!(u.per_object(1, &[0, 0]), None);
    }
}
