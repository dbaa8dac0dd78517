//! The default test article under a power budget (docs/model.md §7.6): which looks come first,
//! what each detection's confirmation is worth, and planning only the looks the budget admits.

use super::config::ResourceConfig;
use super::hold::HeldTracks;
use super::planner;
use super::power::{LookClass, PowerLedger, admits, evidence_nats, evidence_share};
use super::snapshot::Snapshot;
use crate::geometry::ShipGeometry;
use mimo_core::ids::RadarId;
use mimo_core::records::{TrackRow, TrackStatus};
use mimo_radar::energy::dwell_energy_j;
use mimo_sim::messages::{DwellReport, DwellRequest};
use mimo_track::TrackDue;
use std::collections::BTreeMap;

/// The power budget's state during a run.
#[derive(Debug, Clone)]
pub struct Afford {
    /// Energy each radar may spend per window, `P_B·W` (J).
    capacity_j: f64,
    /// The window `W` (s).
    window_s: f64,
    ledger: PowerLedger,
    /// Evidence (nats) of each tentative track's strongest detection.
    evidence: BTreeMap<u64, f64>,
    /// Counts the times energy left the window: only then can a refused look fit.
    freed: u64,
    /// Looks refused, by track: the `freed` count and the track's updates at the refusal.
    refused: BTreeMap<u64, (u64, u32)>,
    /// The confirmed tracks the budget holds (docs/model.md §7.6, rule 4); `None` when
    /// `hold_tracks` is off.
    hold: Option<HeldTracks>,
}

impl Afford {
    /// The budget of `cfg`, or `None` when it has none (unlimited).
    pub fn of(cfg: &ResourceConfig) -> Option<Afford> {
        let p = cfg.power_budget_w?;
        Some(Afford {
            capacity_j: p * cfg.power_window_s,
            window_s: cfg.power_window_s,
            ledger: PowerLedger::default(),
            evidence: BTreeMap::new(),
            freed: 0,
            refused: BTreeMap::new(),
            hold: cfg.hold_tracks.then(HeldTracks::default),
        })
    }

    /// Book a finished dwell: a test-article dwell's transmit energy (`ta`), and the evidence of
    /// the detections that started or updated tentative tracks (`rows`, the tracker's rows for
    /// this dwell; a confirmed or deleted track's evidence is forgotten).
    pub fn on_dwell(&mut self, report: &DwellReport, ta: bool, rows: &[TrackRow], geom: &ShipGeometry) {
        if ta {
            let tx: Vec<(RadarId, f64)> = report
                .parts
                .iter()
                .filter(|p| p.transmits)
                .filter_map(|p| geom.params(p.radar).map(|q| (p.radar, dwell_energy_j(q, p.n_pulses))))
                .collect();
            self.ledger.report(report.tag.first().copied(), report.end_s - report.duration_s, &tx);
        }
        for r in rows {
            if r.status == TrackStatus::Deleted {
                self.refused.remove(&r.track_id);
            }
            if r.status != TrackStatus::Confirmed
                && let Some(h) = &mut self.hold
            {
                h.forget(r.track_id);
            }
            if r.status != TrackStatus::Tentative {
                self.evidence.remove(&r.track_id);
                continue;
            }
            let e = r
                .last_meas_id
                .and_then(|id| report.measurements.iter().find(|m| m.meas_id == id))
                .and_then(|m| geom.params(m.rx).map(|q| evidence_nats(m.snr_db, q.pfa)))
                .unwrap_or(0.0);
            let kept = self.evidence.entry(r.track_id).or_insert(e);
            *kept = kept.max(e);
        }
    }

    /// Start a scheduling pass at `now`: forget dwells that left the window.
    pub fn begin_pass(&mut self, now: f64) {
        if self.ledger.prune(now, self.window_s) {
            self.freed += 1;
        }
    }

    /// The priority class of a look at `info`.
    pub fn class_of(&self, info: &TrackDue) -> LookClass {
        match info.status {
            TrackStatus::Confirmed => LookClass::Maintenance,
            _ => LookClass::Confirmation { evidence_nats: self.evidence.get(&info.id).copied().unwrap_or(0.0) },
        }
    }

    /// Put looks in the order the budget serves them: confirmed tracks first (in the order of
    /// `dues`, the tracker's, so that group looks form as without a budget), then tentative
    /// tracks, strongest detection first; and choose the tracks the budget holds.
    pub fn order(&mut self, dues: &mut [TrackDue]) {
        if let Some(h) = &mut self.hold {
            let confirmed: Vec<u64> =
                dues.iter().filter(|d| d.status == TrackStatus::Confirmed).map(|d| d.id).collect();
            h.choose(&confirmed, self.capacity_j / self.window_s);
        }
        let key = |d: &TrackDue| match self.class_of(d) {
            LookClass::Maintenance => (0, 0.0),
            LookClass::Confirmation { evidence_nats } => (1, -evidence_nats),
        };
        dues.sort_by(|a, b| {
            let (ka, kb) = (key(a), key(b));
            ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
        });
    }

    /// [`planner::plan`] within the budget: the planner's look if its transmitter can pay for
    /// it; otherwise the look the planner makes without that radar as a transmitter, and so on;
    /// `None` when no radar can (the look waits). Radars that cannot pay for a one-pulse look are
    /// left out from the start. A look refused once is not planned again until energy has left
    /// the window or the track was updated (admissions only add load). An admitted look is
    /// booked as requested.
    pub fn plan(
        &mut self,
        rm: &ResourceConfig,
        snap: &Snapshot<'_>,
        info: &TrackDue,
        over_budget: &[RadarId],
        busy_rx: &[RadarId],
        trouble: bool,
    ) -> Option<(DwellRequest, bool)> {
        let class = self.class_of(info);
        if self.refused.get(&info.id) == Some(&(self.freed, info.n_updates)) {
            return None;
        }
        let mut starved: Vec<RadarId> = snap
            .ids()
            .iter()
            .copied()
            .filter(|&r| {
                let one = snap.geom.params(r).map_or(f64::INFINITY, |p| dwell_energy_j(p, 1));
                !admits(self.capacity_j, self.ledger.load(r), one, class)
            })
            .collect();
        let unheld = class == LookClass::Maintenance && self.hold.as_ref().is_some_and(|h| !h.is_held(info.id));
        let planned = self.first_affordable(snap, info, class, unheld, &mut starved, |starved| {
            planner::plan(rm, snap, info, over_budget, starved, busy_rx, trouble)
        });
        match planned {
            Some(_) => self.refused.remove(&info.id),
            None => self.refused.insert(info.id, (self.freed, info.n_updates)),
        };
        planned
    }

    /// The first look `plan_with` makes, given the radars that may not transmit, whose
    /// transmitter can pay for it: each look refused adds its transmitter to `starved` and asks
    /// again; `None` when every radar is starved or the planner finds no look. A look at a track
    /// the budget does not hold (`unheld`) must also leave the held tracks' reserve. An admitted
    /// look is booked for track `info` as requested.
    fn first_affordable(
        &mut self,
        snap: &Snapshot<'_>,
        info: &TrackDue,
        class: LookClass,
        unheld: bool,
        starved: &mut Vec<RadarId>,
        plan_with: impl Fn(&[RadarId]) -> Option<(DwellRequest, bool)>,
    ) -> Option<(DwellRequest, bool)> {
        if starved.len() == snap.ids().len() {
            return None;
        }
        loop {
            let (mut req, unresolved) = plan_with(starved)?;
            let tx = *req.transmitters.first()?;
            let params = snap.geom.params(tx.radar)?;
            let load = self.ledger.load(tx.radar);
            let reserve_j = match (&self.hold, unheld) {
                (Some(h), true) => h.reserve_gap_j(tx.radar, self.window_s, load.maintenance_j),
                _ => 0.0,
            };
            if self.hold.is_some() {
                // A look larger than any window of this budget can hold is cut to the largest
                // that one can (docs/model.md §7.6, rule 4): fewer pulses, a lower chance of
                // detection, but a look.
                let most_j = self.most_for(class) - reserve_j;
                fit_pulses(&mut req, dwell_energy_j(params, 1), most_j);
            }
            let n_pulses = req.transmitters.first()?.n_pulses;
            let energy_j = dwell_energy_j(params, n_pulses.min(params.max_pulses));
            if admits(self.capacity_j - reserve_j, load, energy_j, class) {
                self.ledger.request(info.id, tx.radar, energy_j, class);
                if class == LookClass::Maintenance
                    && let Some(h) = &mut self.hold
                {
                    h.note_look(info.id, tx.radar, energy_j, snap.t_s - info.t_last_update_s);
                }
                return Some((req, unresolved));
            }
            starved.push(tx.radar);
        }
    }

    /// The most energy one look of `class` may ever take in a window: the capacity for a look
    /// at a confirmed track, the share its evidence earns for a confirmation.
    fn most_for(&self, class: LookClass) -> f64 {
        match class {
            LookClass::Maintenance => self.capacity_j,
            LookClass::Confirmation { evidence_nats } => evidence_share(evidence_nats) * self.capacity_j,
        }
    }

    /// When a waiting look should be planned again: the next time a radar's oldest dwell leaves
    /// the window (`None`: only pending dwells hold the budget, and their reports wake the
    /// test article).
    pub fn next_release_s(&self) -> Option<f64> {
        self.ledger.next_release_s(self.window_s)
    }
}

/// Cut the pulses of `req`'s transmitter so that the look takes at most `most_j` at `pulse_j` a
/// pulse, when it would take more and one pulse fits; a monostatic look's predicted SNR scales
/// with its pulses.
fn fit_pulses(req: &mut DwellRequest, pulse_j: f64, most_j: f64) {
    let Some(tx) = req.transmitters.first_mut() else { return };
    if pulse_j.is_nan() || pulse_j <= 0.0 || f64::from(tx.n_pulses) * pulse_j <= most_j || most_j < pulse_j {
        return;
    }
    let n = ((most_j / pulse_j).floor() as u32).max(1);
    if let Some(snr) = &mut req.predicted_snr {
        *snr *= f64::from(n) / f64::from(tx.n_pulses.max(1));
    }
    tx.n_pulses = n;
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::DVec3;
    use mimo_core::records::DwellKind;
    use mimo_sim::messages::TxOrder;

    fn look(n_pulses: u32, predicted_snr: Option<f64>) -> DwellRequest {
        DwellRequest {
            kind: DwellKind::Track,
            earliest_s: 0.0,
            aim_ecef: DVec3::ZERO,
            transmitters: vec![TxOrder { radar: RadarId(0), n_pulses }],
            receivers: vec![RadarId(0)],
            window_half_m: 1000.0,
            predicted_snr,
            tag: vec![1],
        }
    }

    /// A 16-pulse look of 1-J pulses under a 10-J window is cut to 10 pulses, its predicted SNR
    /// with it; a look that fits, or a window that cannot hold one pulse, is left alone.
    #[test]
    fn a_look_larger_than_the_window_is_cut_to_fit() {
        let mut req = look(16, Some(32.0));
        fit_pulses(&mut req, 1.0, 10.0);
        assert_eq!(req.transmitters[0].n_pulses, 10);
        assert_eq!(req.predicted_snr, Some(20.0));
        let mut fits = look(8, None);
        fit_pulses(&mut fits, 1.0, 10.0);
        assert_eq!(fits.transmitters[0].n_pulses, 8);
        let mut none = look(4, Some(8.0));
        fit_pulses(&mut none, 1.0, 0.5);
        assert_eq!((none.transmitters[0].n_pulses, none.predicted_snr), (4, Some(8.0)));
        let mut edge = look(16, None);
        fit_pulses(&mut edge, 1.0, 2.5);
        assert_eq!(edge.transmitters[0].n_pulses, 2);
    }
}
