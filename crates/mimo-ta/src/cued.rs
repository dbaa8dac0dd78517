//! The truth-cued fixed schedule: a stand-in test article that forms no tracks.
//!
//! Every `period_s` it aims one dwell at every target that some radar can see, from the radar
//! with the best predicted SNR, with pulses sized for P_D = 0.9; every `mimo_every`-th cycle
//! the dwell is a MIMO dwell (the best radar transmits, every radar that can steer at the target
//! receives). It reads truth, which a real test article never may: it exists to record and check
//! the radar model's output before (or without) a tracker, and the manifest says so (`schedule`).
//! It is therefore built with the engine's [`World`], unlike every other test article.

use mimo_core::records::DwellKind;
use mimo_radar::energy::{PairEnd, predict_pair, pulses_for, required_snr_sw1, straddle_loss};
use mimo_sim::World;
use mimo_sim::messages::{DwellReport, DwellRequest, Reply, Request, StartInfo, Subscription, TxOrder};
use mimo_sim::test_article::{TaFault, TestArticle};
use serde::{Deserialize, Serialize};

/// Settings of the cued schedule.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CuedConfig {
    /// Time between looks at every target (s). Default 1.
    pub period_s: f64,
    /// Every this many cycles the looks are MIMO dwells (0: never). Default 5.
    pub mimo_every: u32,
}

impl Default for CuedConfig {
    fn default() -> Self {
        CuedConfig { period_s: 1.0, mimo_every: 5 }
    }
}

/// The truth-cued schedule.
pub struct Cued<'w> {
    world: &'w World,
    cfg: CuedConfig,
    cycle: u32,
}

impl<'w> Cued<'w> {
    /// The schedule over `world`'s truth.
    pub fn new(world: &'w World, cfg: CuedConfig) -> Cued<'w> {
        Cued { world, cfg, cycle: 0 }
    }
}

impl TestArticle for Cued<'_> {
    fn name(&self) -> &str {
        "cued"
    }
    fn config(&self) -> serde_json::Value {
        serde_json::json!({"period_s": self.cfg.period_s, "mimo_every": self.cfg.mimo_every, "reads_truth": true})
    }
    fn subscription(&self) -> Subscription {
        Subscription { dwells: mimo_sim::messages::DwellFilter::Own, ..Subscription::default() }
    }
    fn on_start(&mut self, _start: &StartInfo) -> Result<Reply, TaFault> {
        self.cycle = 0;
        Ok(Reply::requests(vec![Request::WakeAt(self.cfg.period_s)]))
    }
    fn on_dwell(&mut self, _report: &DwellReport) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_wake(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        self.cycle += 1;
        let mimo = self.cfg.mimo_every > 0 && self.cycle.is_multiple_of(self.cfg.mimo_every);
        let w = self.world;
        let mut out = vec![Request::WakeAt(t_s + self.cfg.period_s)];
        for tgt in w.targets_at(t_s) {
            // Best monostatic radar.
            let mut best: Option<(mimo_core::ids::RadarId, f64)> = None;
            let mut seers = Vec::new();
            for r in w.radar_ids() {
                let faces = w.faces_at(r, t_s);
                let radar = PairEnd { params: w.params(r), faces: &faces };
                if let Some(pp) = predict_pair(radar, radar, tgt.pos_ecef, tgt.rcs_m2) {
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
                earliest_s: t_s,
                aim_ecef: tgt.pos_ecef,
                transmitters: vec![TxOrder { radar: tx, n_pulses: n }],
                receivers,
                window_half_m: 1000.0,
                predicted_snr: Some(snr1 * f64::from(n)),
                tag: vec![u64::from(tgt.index)],
            }));
        }
        Ok(Reply::requests(out))
    }
}
