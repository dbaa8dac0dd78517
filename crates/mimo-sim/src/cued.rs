//! The truth-cued fixed schedule: a stand-in test article that forms no tracks.
//!
//! Every `period_s` it aims one dwell at every target that some radar can see, from the radar
//! with the best predicted SNR, with pulses sized for P_D = 0.9; every `mimo_every`-th cycle
//! the dwell is a MIMO dwell (the best radar transmits, every radar that can steer at the target
//! receives). It reads truth, which a real TA never may: it exists to record and check the radar
//! model's output before (or without) a tracker, and the manifest says so (`schedule`).

use crate::ta::{DwellReport, DwellRequest, Request, TaContext, TestArticle, TxOrder};
use crate::world::World;
use mimo_core::records::{DwellKind, TrackRow};
use mimo_radar::energy::{predict_pair, pulses_for, required_snr_sw1, straddle_loss};

/// The truth-cued schedule.
pub struct Cued<'w> {
    world: &'w World,
    pub period_s: f64,
    pub mimo_every: u32,
    cycle: u32,
}

impl<'w> Cued<'w> {
    pub fn new(world: &'w World) -> Cued<'w> {
        Cued { world, period_s: 1.0, mimo_every: 5, cycle: 0 }
    }
}

impl TestArticle for Cued<'_> {
    fn name(&self) -> &str {
        "cued"
    }
    fn config(&self) -> serde_json::Value {
        serde_json::json!({"period_s": self.period_s, "mimo_every": self.mimo_every, "reads_truth": true})
    }
    fn start(&mut self, _ctx: &TaContext) -> Vec<Request> {
        vec![Request::WakeAt(self.period_s)]
    }
    fn on_dwell(&mut self, _ctx: &TaContext, _report: &DwellReport) -> Vec<Request> {
        Vec::new()
    }
    fn on_wake(&mut self, ctx: &TaContext, t_s: f64) -> Vec<Request> {
        self.cycle += 1;
        let mimo = self.mimo_every > 0 && self.cycle.is_multiple_of(self.mimo_every);
        let w = self.world;
        let mut out = vec![Request::WakeAt(t_s + self.period_s)];
        for tgt in w.targets_at(ctx.t_s) {
            // Best monostatic radar.
            let mut best: Option<(mimo_core::ids::RadarId, f64)> = None;
            let mut seers = Vec::new();
            for r in w.radar_ids() {
                let p = w.params(r);
                let faces = w.faces_at(r, ctx.t_s);
                if let Some(pp) = predict_pair(p, &faces, p, &faces, tgt.pos_ecef, tgt.rcs_m2) {
                    seers.push(r);
                    if best.is_none_or(|(_, s)| pp.snr1 > s) {
                        best = Some((r, pp.snr1));
                    }
                }
            }
            let Some((tx, snr1)) = best else { continue };
            let p = w.params(tx);
            let n = pulses_for(required_snr_sw1(0.9, p.pfa), snr1, straddle_loss(), p.max_pulses);
            let receivers = if mimo { seers } else { vec![tx] };
            out.push(Request::Dwell(DwellRequest {
                kind: if mimo { DwellKind::Mimo } else { DwellKind::Track },
                earliest_s: ctx.t_s,
                aim_ecef: tgt.pos_ecef,
                transmitters: vec![TxOrder { radar: tx, n_pulses: n }],
                receivers,
                window_half_m: 1000.0,
                predicted_snr: Some(snr1 * f64::from(n)),
                tag: vec![u64::from(tgt.index)],
            }));
        }
        out
    }
    fn take_track_rows(&mut self) -> Vec<TrackRow> {
        Vec::new()
    }
}
