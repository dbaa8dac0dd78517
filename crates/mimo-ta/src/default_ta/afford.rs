//! The default test article under a power budget (docs/model.md §7.6): which looks come first,
//! what each detection's confirmation is worth, and planning only the looks the budget admits.

use super::config::ResourceConfig;
use super::planner;
use super::power::{LookClass, PowerLedger, admits, evidence_nats};
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
    /// tracks, strongest detection first.
    pub fn order(&self, dues: &mut [TrackDue]) {
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
        let planned = self.first_affordable(snap, info.id, class, &mut starved, |starved| {
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
    /// again; `None` when every radar is starved or the planner finds no look. An admitted look
    /// is booked for track `track_id` as requested.
    fn first_affordable(
        &mut self,
        snap: &Snapshot<'_>,
        track_id: u64,
        class: LookClass,
        starved: &mut Vec<RadarId>,
        plan_with: impl Fn(&[RadarId]) -> Option<(DwellRequest, bool)>,
    ) -> Option<(DwellRequest, bool)> {
        if starved.len() == snap.ids().len() {
            return None;
        }
        loop {
            let (req, unresolved) = plan_with(starved)?;
            let tx = *req.transmitters.first()?;
            let params = snap.geom.params(tx.radar)?;
            let energy_j = dwell_energy_j(params, tx.n_pulses.min(params.max_pulses));
            if admits(self.capacity_j, self.ledger.load(tx.radar), energy_j, class) {
                self.ledger.request(track_id, tx.radar, energy_j, class);
                return Some((req, unresolved));
            }
            starved.push(tx.radar);
        }
    }

    /// When a waiting look should be planned again: the next time a radar's oldest dwell leaves
    /// the window (`None`: only pending dwells hold the budget, and their reports wake the
    /// test article).
    pub fn next_release_s(&self) -> Option<f64> {
        self.ledger.next_release_s(self.window_s)
    }
}
