//! The multi-target tracker: components composed into a dwell-by-dwell tracker.

use crate::association::{AssociationCost, Associator, GnnAssociator, HypothesisTable};
use crate::deletion::{DeleteReason, Deleter, DeletionConfig, TrackView};
use crate::filter::{FilterPrediction, FilterState, ImmFilter, SingleModelFilter, TrackFilter};
use crate::frame::{Gaussian, StateEcef, TrackFrame};
use crate::gating::{ChiSquareGate, Gater};
use crate::geometry::SensorGeometry;
use crate::initiation::{
    Confirmation, Confirmer, Initiator, MOfN, OnePointInitiator, TwoPointConfig, TwoPointInitiator,
};
use crate::linalg::{Mat3, sandwich};
use crate::measurement::{BistaticRuv, MeasurementConfig, MeasurementModel, PreparedMeasurement};
use crate::motion::{HorizontalTurn, KalmanPredictor, Ncv, Predictor, ProcessNoise};
use crate::policy::{DueInfo, RevisitPolicy, due_tracks, revisit_interval};
use crate::update::EkfUpdater;
use mimo_core::face::FaceFrame;
use mimo_core::geo::Geodetic;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, MeasurementRow, TrackRow, TrackStatus, pack_cov};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::str::FromStr;

/// The built-in trackers, selectable by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TrackerKind {
    /// EKF with a nearly-constant-velocity model (`"default"`).
    #[default]
    Default,
    /// IMM of CV-low and CV-high (optionally plus two coordinated-turn modes) (`"imm"`).
    Imm,
}

impl TrackerKind {
    /// Every kind, in documentation order.
    pub const ALL: [TrackerKind; 2] = [TrackerKind::Default, TrackerKind::Imm];

    /// The name used on the command line and in manifests.
    pub fn as_str(self) -> &'static str {
        match self {
            TrackerKind::Default => "default",
            TrackerKind::Imm => "imm",
        }
    }

    /// Parse `"default"` or `"imm"`.
    pub fn parse(s: &str) -> Option<TrackerKind> {
        TrackerKind::ALL.into_iter().find(|k| k.as_str() == s)
    }
}

impl fmt::Display for TrackerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for TrackerKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        TrackerKind::parse(s).ok_or_else(|| format!("unknown tracker `{s}` (expected one of: default, imm)"))
    }
}

/// IMM configuration (docs/model.md §6.3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ImmConfig {
    /// DWNA σ_a of the quiet CV mode (m/s²). Default 1.
    pub sigma_low_mps2: f64,
    /// DWNA σ_a of the manoeuvre CV mode (m/s²). Default 25.
    pub sigma_high_mps2: f64,
    /// Mean sojourn in the quiet mode (s). Default 60.
    pub sojourn_low_s: f64,
    /// Mean sojourn in the manoeuvre mode (s). Default 15.
    pub sojourn_high_s: f64,
    /// Add two known-rate coordinated-turn modes (±rate, °/s) with σ_a = `sigma_low_mps2`, each
    /// with sojourn `sojourn_high_s`. Default `None` (two CV modes only).
    pub turn_rate_dps: Option<f64>,
    /// Mode probabilities of a new track. Default `None`: the stationary distribution of the
    /// mode chain, μ_i ∝ τ_i (0.8 / 0.2 for the defaults).
    pub initial_mu: Option<Vec<f64>>,
}

impl Default for ImmConfig {
    fn default() -> Self {
        ImmConfig {
            sigma_low_mps2: 1.0,
            sigma_high_mps2: 25.0,
            sojourn_low_s: 60.0,
            sojourn_high_s: 15.0,
            turn_rate_dps: None,
            initial_mu: None,
        }
    }
}

/// Which initiator to use.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum InitiatorConfig {
    /// One-point initiation with a zero-velocity prior.
    OnePoint { velocity_std_mps: f64 },
    /// Two-point differencing.
    TwoPoint(TwoPointConfig),
}

impl Default for InitiatorConfig {
    fn default() -> Self {
        InitiatorConfig::OnePoint { velocity_std_mps: OnePointInitiator::default().velocity_std_mps }
    }
}

/// Which dwells may start tentative tracks from unclaimed detections.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InitiateOn {
    /// Only search dwells (docs/model.md §6.4).
    Search,
    /// Search dwells, and the monostatic channel of any other dwell: a second target that
    /// shows up in a track dwell's beam (a formation opening up) starts its own track at once,
    /// while bistatic channels, whose detections of a tracked target may fail the gate when
    /// the geometry is poor, never start duplicates. Default.
    #[default]
    SearchAndMonostatic,
    /// Any dwell, any channel.
    AnyDwell,
}

/// Configuration of the built-in trackers; every field has a documented default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TrackerConfig {
    /// Which filter: `default` (EKF NCV) or `imm`.
    pub kind: TrackerKind,
    /// Process noise of the default tracker's NCV model. Default DWNA σ_a = 15 m/s², between
    /// the non-manoeuvring (3–5) and manoeuvring (20–30) fighter values of docs/model.md §6.1: in
    /// this crate's checks it holds an n = 3 level turn (27.7 m/s², the standard scenarios'
    /// hardest) at 1 s revisit, where σ_a = 10 loses it, and costs about 5 % of straight-flight
    /// accuracy. Use `imm` for better accuracy on both.
    pub ekf_noise: ProcessNoise,
    /// IMM modes (used when `kind = imm`).
    pub imm: ImmConfig,
    /// How rows become measurements (merged-measurement inflation, variance floors).
    pub measurement: MeasurementConfig,
    /// χ² gate. Default 99.9 % (γ = 16.27).
    pub gate: ChiSquareGate,
    /// GNN cost. Default: likelihood cost with P_D = 0.9 and a P_FA = 1e-6 clutter density.
    pub association: AssociationCost,
    /// Linearizations per update for the first `iekf_first_updates` updates of a track
    /// (iterated EKF). Default 3.
    pub iekf_iterations: u32,
    /// Number of initial updates that use the iterated EKF. Default 3.
    pub iekf_first_updates: u32,
    /// Initiation. Default one-point with σ_v = 300 m/s.
    pub initiator: InitiatorConfig,
    /// Which dwells initiate. Default: search dwells and monostatic channels of any dwell.
    pub initiate_on: InitiateOn,
    /// M-of-N confirmation over looks (the initiating detection is the first look).
    /// Default 2-of-3.
    pub confirmation: MOfN,
    /// Deletion rules.
    pub deletion: DeletionConfig,
    /// Revisit policy (next-due times, confirmation and re-dwell delays).
    pub revisit: RevisitPolicy,
    /// A track predicted within this fraction of a beamwidth of the beam centre of a
    /// non-search look (see [`Look`]) counts a miss when not detected. Default 0.5 (inside the
    /// half-power beam); 0 disables beam-based misses.
    pub beam_miss_fraction: f64,
    /// Let a `merged` measurement also update gated tracks left without a measurement by GNN
    /// (docs/model.md §6.5). Default true.
    pub share_merged: bool,
}

impl Default for TrackerConfig {
    fn default() -> Self {
        TrackerConfig {
            kind: TrackerKind::Default,
            ekf_noise: ProcessNoise::Dwna { sigma_a_mps2: 15.0 },
            imm: ImmConfig::default(),
            measurement: MeasurementConfig::default(),
            gate: ChiSquareGate::default(),
            association: AssociationCost::default(),
            iekf_iterations: 3,
            iekf_first_updates: 3,
            initiator: InitiatorConfig::default(),
            initiate_on: InitiateOn::SearchAndMonostatic,
            confirmation: MOfN::default(),
            deletion: DeletionConfig::default(),
            revisit: RevisitPolicy::default(),
            beam_miss_fraction: 0.5,
            share_merged: true,
        }
    }
}

impl TrackerConfig {
    /// The default configuration of a tracker kind.
    pub fn for_kind(kind: TrackerKind) -> TrackerConfig {
        TrackerConfig { kind, ..TrackerConfig::default() }
    }

    /// Check the configuration; the error names the field and what was expected.
    pub fn validate(&self) -> Result<(), String> {
        let pos = |name: &str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(format!("{name}: expected a positive finite number, got {x}"))
            }
        };
        match self.ekf_noise {
            ProcessNoise::Dwna { sigma_a_mps2 } => pos("ekf_noise.sigma_a_mps2", sigma_a_mps2)?,
            ProcessNoise::Cwna { q_m2ps3 } => pos("ekf_noise.q_m2ps3", q_m2ps3)?,
        }
        pos("imm.sigma_low_mps2", self.imm.sigma_low_mps2)?;
        pos("imm.sigma_high_mps2", self.imm.sigma_high_mps2)?;
        pos("imm.sojourn_low_s", self.imm.sojourn_low_s)?;
        pos("imm.sojourn_high_s", self.imm.sojourn_high_s)?;
        if let Some(r) = self.imm.turn_rate_dps {
            pos("imm.turn_rate_dps", r)?;
        }
        pos("gate.threshold", self.gate.threshold)?;
        if !(self.gate.probability > 0.0 && self.gate.probability < 1.0) {
            return Err(format!("gate.probability: expected a probability in (0, 1), got {}", self.gate.probability));
        }
        if let AssociationCost::Nis { miss_cost } = self.association {
            pos("association.miss_cost", miss_cost)?;
        }
        if let AssociationCost::Likelihood { pd, clutter_density, .. } = self.association {
            pos("association.clutter_density", clutter_density)?;
            if !(pd > 0.0 && pd < 1.0) {
                return Err(format!("association.pd: expected a probability in (0, 1), got {pd}"));
            }
        }
        if self.confirmation.m == 0 || self.confirmation.m > self.confirmation.n {
            return Err("confirmation: expected 1 <= m <= n".into());
        }
        pos("deletion.max_position_trace_m2", self.deletion.max_position_trace_m2)?;
        pos("revisit.t_min_s", self.revisit.t_min_s)?;
        pos("revisit.beamwidth", self.revisit.beamwidth)?;
        pos("revisit.sharpness_v0", self.revisit.sharpness_v0)?;
        if self.revisit.t_max_s < self.revisit.t_min_s {
            return Err("revisit.t_max_s: expected at least revisit.t_min_s".into());
        }
        if !(self.beam_miss_fraction.is_finite() && self.beam_miss_fraction >= 0.0) {
            return Err("beam_miss_fraction: expected a finite number >= 0".into());
        }
        Ok(())
    }
}

/// The components a tracker is made of. Build your own to compose a custom tracker.
pub struct Components {
    pub filter: Box<dyn TrackFilter>,
    pub gater: Box<dyn Gater>,
    pub associator: Box<dyn Associator>,
    pub initiator: Box<dyn Initiator>,
    pub confirmer: Box<dyn Confirmer>,
    pub deleter: Box<dyn Deleter>,
}

impl Components {
    /// The built-in components for a configuration.
    pub fn from_config(cfg: &TrackerConfig) -> Components {
        let filter: Box<dyn TrackFilter> = match cfg.kind {
            TrackerKind::Default => Box::new(SingleModelFilter {
                name: "ekf-ncv".into(),
                predictor: Box::new(KalmanPredictor::new(Ncv { noise: cfg.ekf_noise })),
                updater: Box::new(EkfUpdater::default()),
            }),
            TrackerKind::Imm => {
                let c = &cfg.imm;
                let mut predictors: Vec<Box<dyn Predictor>> = vec![
                    Box::new(KalmanPredictor::new(Ncv::dwna(c.sigma_low_mps2))),
                    Box::new(KalmanPredictor::new(Ncv::dwna(c.sigma_high_mps2))),
                ];
                let mut sojourn_s = vec![c.sojourn_low_s, c.sojourn_high_s];
                if let Some(rate) = c.turn_rate_dps {
                    for sign in [1.0, -1.0] {
                        predictors.push(Box::new(KalmanPredictor::new(HorizontalTurn {
                            omega_radps: sign * rate.to_radians(),
                            noise: ProcessNoise::Dwna { sigma_a_mps2: c.sigma_low_mps2 },
                        })));
                        sojourn_s.push(c.sojourn_high_s);
                    }
                }
                let initial_mu = match &c.initial_mu {
                    Some(mu) => mu.clone(),
                    None => {
                        let s: f64 = sojourn_s.iter().sum();
                        sojourn_s.iter().map(|t| t / s).collect()
                    }
                };
                Box::new(ImmFilter {
                    name: format!("imm-{}", predictors.len()),
                    predictors,
                    sojourn_s,
                    initial_mu,
                    updater: Box::new(EkfUpdater::default()),
                })
            }
        };
        let initiator: Box<dyn Initiator> = match cfg.initiator {
            InitiatorConfig::OnePoint { velocity_std_mps } => Box::new(OnePointInitiator { velocity_std_mps }),
            InitiatorConfig::TwoPoint(c) => Box::new(TwoPointInitiator::new(c)),
        };
        Components {
            filter,
            gater: Box::new(cfg.gate),
            associator: Box::new(GnnAssociator { cost: cfg.association }),
            initiator,
            confirmer: Box::new(cfg.confirmation),
            deleter: Box::new(cfg.deletion.build()),
        }
    }
}

/// A beam of one receive channel in a dwell: which tracks it could have seen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Look {
    pub tx: RadarId,
    pub rx: RadarId,
    pub rx_face: u8,
    /// Receive beam steering direction in the face's sine space.
    pub beam_u: f64,
    pub beam_v: f64,
    /// Equivalent monostatic range window ρ (m) of the channel, if limited.
    pub rho_window_m: Option<(f64, f64)>,
}

/// What the tracker is told about a finished dwell besides its measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct DwellContext {
    pub run: u32,
    /// Dwell time (s) (start or mid-time, as the measurements' `t_s`).
    pub t_s: f64,
    /// Dwell (group) id, for logs.
    pub dwell_id: u64,
    /// Search dwells initiate tracks from unclaimed detections; the other kinds look at tracks.
    pub kind: DwellKind,
    /// Tracks this dwell was aimed at: each one not updated by the dwell counts a miss.
    pub target_tracks: Vec<u64>,
    /// Receive beams of the dwell (optional). For non-search dwells, a track predicted inside a
    /// beam (see [`TrackerConfig::beam_miss_fraction`]) and not updated also counts a miss; this
    /// is how offline replay, which does not know the original tracker's track ids, counts
    /// misses.
    pub looks: Vec<Look>,
}

impl DwellContext {
    /// A search dwell.
    pub fn search(run: u32, dwell_id: u64, t_s: f64) -> DwellContext {
        DwellContext { run, t_s, dwell_id, kind: DwellKind::Search, target_tracks: Vec::new(), looks: Vec::new() }
    }

    /// A dwell aimed at `tracks` (kind `Track`, `Confirm` or `Mimo`).
    pub fn aimed(run: u32, dwell_id: u64, t_s: f64, kind: DwellKind, tracks: Vec<u64>) -> DwellContext {
        DwellContext { run, t_s, dwell_id, kind, target_tracks: tracks, looks: Vec::new() }
    }
}

/// A live track.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    pub id: u64,
    pub status: TrackStatus,
    /// Filter state at `t_s`.
    pub state: FilterState,
    /// Time of the last update (or initiation) (s).
    pub t_s: f64,
    pub t_init_s: f64,
    pub n_updates: u32,
    pub last_meas_id: Option<u64>,
    /// Confirmation looks while tentative (`true` = detected), starting with the initiation.
    pub looks: Vec<bool>,
    pub consecutive_misses: u32,
    /// When the track should next be looked at (s).
    pub next_due_s: f64,
    /// Receiver and face of the last update.
    pub last_face: Option<(RadarId, u8)>,
    pub nis_sum: f64,
    pub nis_count: u32,
}

/// A snapshot of a track for the scheduler.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackInfo {
    pub id: u64,
    pub status: TrackStatus,
    pub t_last_update_s: f64,
    pub n_updates: u32,
    pub consecutive_misses: u32,
    pub next_due_s: f64,
    pub last_face: Option<(RadarId, u8)>,
    /// IMM mode probabilities (`[1.0]` for the EKF).
    pub mode_probabilities: Vec<f64>,
    /// Mean NIS over the track's updates (NaN before the first update).
    pub mean_nis: f64,
}

/// The NIS of one update, for consistency checks (χ²₃ when the filter is consistent).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NisRecord {
    pub run: u32,
    pub t_s: f64,
    pub track_id: u64,
    pub meas_id: u64,
    pub tx: RadarId,
    pub rx: RadarId,
    pub nis: f64,
}

/// A predicted measurement of a track on a channel (scheduler: beam pointing, range windows).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PredictedMeasurement {
    /// Equivalent monostatic range ρ = R_B/2 (m).
    pub rho_m: f64,
    pub u: f64,
    pub v: f64,
    /// Standard deviation of ρ from the track covariance, `√(h P hᵀ)/2` (m).
    pub sigma_rho_m: f64,
    /// `H P Hᵀ` in `(R_B, u, v)` (no measurement noise).
    pub cov: Mat3,
}

/// Counters.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TrackerStats {
    pub dwells: u64,
    pub measurements: u64,
    pub rejected_measurements: u64,
    pub updates: u64,
    pub failed_updates: u64,
    pub jitter_events: u64,
    pub initiated: u64,
    pub confirmed: u64,
    pub deleted: BTreeMap<DeleteReason, u64>,
}

/// A multi-target tracker: filter, gate, GNN association, initiation, M-of-N confirmation and
/// deletion, driven one dwell at a time.
pub struct MultiTargetTracker {
    config: TrackerConfig,
    frame: TrackFrame,
    c: Components,
    tracks: BTreeMap<u64, Track>,
    next_id: u64,
    nis_log: Vec<NisRecord>,
    stats: TrackerStats,
}

impl fmt::Debug for MultiTargetTracker {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("MultiTargetTracker")
            .field("filter", &self.c.filter.name())
            .field("tracks", &self.tracks.len())
            .field("stats", &self.stats)
            .finish()
    }
}

/// Per-track cache of predictions within one channel (usually one time).
struct PredCache {
    entries: Vec<(f64, FilterPrediction)>,
}

impl PredCache {
    fn get(&mut self, filter: &dyn TrackFilter, track: &Track, t_s: f64) -> &FilterPrediction {
        let k = match self.entries.iter().position(|(t, _)| *t == t_s) {
            Some(k) => k,
            None => {
                self.entries.push((t_s, filter.predict(&track.state, t_s - track.t_s)));
                self.entries.len() - 1
            }
        };
        &self.entries[k].1
    }
}

impl MultiTargetTracker {
    /// A built-in tracker tracking in the ENU frame at `centre`.
    pub fn new(config: TrackerConfig, centre: Geodetic) -> MultiTargetTracker {
        let c = Components::from_config(&config);
        MultiTargetTracker::with_components(config, centre, c)
    }

    /// A built-in tracker by name (`"default"`, `"imm"`) with its default configuration.
    pub fn by_name(name: &str, centre: Geodetic) -> Option<MultiTargetTracker> {
        TrackerKind::parse(name).map(|k| MultiTargetTracker::new(TrackerConfig::for_kind(k), centre))
    }

    /// A tracker from custom components. `config` still supplies the measurement handling,
    /// IEKF schedule, revisit policy and the other tracker-level settings.
    pub fn with_components(config: TrackerConfig, centre: Geodetic, components: Components) -> MultiTargetTracker {
        MultiTargetTracker {
            config,
            frame: TrackFrame::new(centre),
            c: components,
            tracks: BTreeMap::new(),
            next_id: 1,
            nis_log: Vec::new(),
            stats: TrackerStats::default(),
        }
    }

    pub fn config(&self) -> &TrackerConfig {
        &self.config
    }

    pub fn frame(&self) -> &TrackFrame {
        &self.frame
    }

    /// Name of the filter (for manifests).
    pub fn filter_name(&self) -> String {
        self.c.filter.name()
    }

    pub fn stats(&self) -> &TrackerStats {
        &self.stats
    }

    /// Every update's NIS so far.
    pub fn nis_log(&self) -> &[NisRecord] {
        &self.nis_log
    }

    /// Take (and clear) the NIS log.
    pub fn take_nis_log(&mut self) -> Vec<NisRecord> {
        std::mem::take(&mut self.nis_log)
    }

    /// A live track.
    pub fn track(&self, id: u64) -> Option<&Track> {
        self.tracks.get(&id)
    }

    /// Snapshots of the live tracks, by id.
    pub fn tracks(&self) -> Vec<TrackInfo> {
        self.tracks
            .values()
            .map(|t| TrackInfo {
                id: t.id,
                status: t.status,
                t_last_update_s: t.t_s,
                n_updates: t.n_updates,
                consecutive_misses: t.consecutive_misses,
                next_due_s: t.next_due_s,
                last_face: t.last_face,
                mode_probabilities: t.state.mu.clone(),
                mean_nis: if t.nis_count > 0 { t.nis_sum / t.nis_count as f64 } else { f64::NAN },
            })
            .collect()
    }

    /// Tracks due for a look by `t_now + lookahead_s`, confirmed first, then by due time.
    pub fn due_tracks(&self, t_now: f64, lookahead_s: f64) -> Vec<u64> {
        let infos: Vec<DueInfo> = self
            .tracks
            .values()
            .map(|t| DueInfo { track_id: t.id, status: t.status, next_due_s: t.next_due_s })
            .collect();
        due_tracks(&infos, t_now, lookahead_s)
    }

    /// The (combined) prediction of a track at `t_s`, in the tracking frame.
    pub fn predict_local(&self, id: u64, t_s: f64) -> Option<Gaussian> {
        let t = self.tracks.get(&id)?;
        if !t_s.is_finite() {
            return None;
        }
        Some(self.c.filter.predict(&t.state, t_s - t.t_s).combined)
    }

    /// The (combined) prediction of a track at `t_s`, in ECEF.
    pub fn predict(&self, id: u64, t_s: f64) -> Option<StateEcef> {
        self.predict_local(id, t_s).map(|g| self.frame.state_to_ecef(&g))
    }

    /// The predicted measurement of a track on channel `tx → rx` (face `rx_face`) at `t_s`.
    pub fn predict_measurement(
        &self,
        id: u64,
        t_s: f64,
        tx: RadarId,
        rx: RadarId,
        rx_face: u8,
        geom: &dyn SensorGeometry,
    ) -> Option<PredictedMeasurement> {
        let g = self.predict_local(id, t_s)?;
        let m = BistaticRuv::from_geometry(&self.frame, geom, tx, rx, rx_face, t_s).ok()?;
        let z = m.h(&g.x);
        let h = m.jacobian(&g.x);
        let cov = sandwich(&h, &g.p);
        let out = PredictedMeasurement {
            rho_m: z[0] / 2.0,
            u: z[1],
            v: z[2],
            sigma_rho_m: cov[0][0].max(0.0).sqrt() / 2.0,
            cov,
        };
        (out.rho_m.is_finite() && out.u.is_finite() && out.v.is_finite()).then_some(out)
    }

    /// Covariance-based revisit interval of a track seen from `face` (docs/model.md §7.1), measured
    /// from its last update.
    pub fn revisit_interval(&self, id: u64, face: &FaceFrame) -> Option<f64> {
        let t = self.tracks.get(&id)?;
        let lf = self.frame.face_to_local(face);
        let filter = &*self.c.filter;
        Some(revisit_interval(&|dt| filter.predict(&t.state, dt).combined, &lf, &self.config.revisit))
    }

    /// Start a track from an external estimate (a cue, or a test). Returns its id and row.
    pub fn spawn_track(
        &mut self,
        run: u32,
        t_s: f64,
        state: &StateEcef,
        status: TrackStatus,
    ) -> Option<(u64, TrackRow)> {
        let g = self.frame.state_from_ecef(state);
        if !g.is_finite() || !t_s.is_finite() || status == TrackStatus::Deleted {
            return None;
        }
        let id = self.next_id;
        self.next_id += 1;
        let track = Track {
            id,
            status,
            state: self.c.filter.init(g),
            t_s,
            t_init_s: t_s,
            n_updates: 0,
            last_meas_id: None,
            looks: vec![true],
            consecutive_misses: 0,
            next_due_s: t_s,
            last_face: None,
            nis_sum: 0.0,
            nis_count: 0,
        };
        let row = self.row_of(run, &track, &track.state.combined(), t_s, status);
        self.tracks.insert(id, track);
        Some((id, row))
    }

    fn row_of(&self, run: u32, t: &Track, g: &Gaussian, t_s: f64, status: TrackStatus) -> TrackRow {
        let e = self.frame.state_to_ecef(g);
        TrackRow {
            run,
            t_s,
            track_id: t.id,
            status,
            x_m: e.pos.x,
            y_m: e.pos.y,
            z_m: e.pos.z,
            vx_mps: e.vel.x,
            vy_mps: e.vel.y,
            vz_mps: e.vel.z,
            cov: pack_cov(&e.cov),
            n_updates: t.n_updates,
            last_meas_id: t.last_meas_id,
        }
    }

    /// Process one finished dwell: associate its measurements (per receive channel, GNN),
    /// update tracks, count misses on the tracks it looked at, initiate tentative tracks from
    /// unclaimed search detections, run confirmation and deletion. Returns one row per track
    /// updated or initiated (its state after the dwell) and one `deleted` row per track ended.
    /// Invalid measurement rows are skipped and counted in [`TrackerStats`].
    pub fn process_dwell(
        &mut self,
        ctx: &DwellContext,
        meas: &[MeasurementRow],
        geom: &dyn SensorGeometry,
    ) -> Vec<TrackRow> {
        let mut rows = Vec::new();
        if !ctx.t_s.is_finite() {
            self.stats.rejected_measurements += meas.len() as u64;
            return rows;
        }
        self.stats.dwells += 1;
        self.stats.measurements += meas.len() as u64;

        // Validate and group by channel; order within a channel by measurement id so that the
        // result never depends on the caller's row order.
        let mut channels: BTreeMap<(RadarId, RadarId), Vec<PreparedMeasurement>> = BTreeMap::new();
        for row in meas {
            match PreparedMeasurement::from_row(row, geom, &self.frame, &self.config.measurement) {
                Ok(pm) => channels.entry((pm.tx, pm.rx)).or_default().push(pm),
                Err(_) => self.stats.rejected_measurements += 1,
            }
        }
        for list in channels.values_mut() {
            list.sort_by(|a, b| a.meas_id.cmp(&b.meas_id).then(a.rx_face.cmp(&b.rx_face)));
        }

        let initiate_on = self.config.initiate_on;
        let may_initiate = |tx: RadarId, rx: RadarId| match initiate_on {
            _ if ctx.kind == DwellKind::Search => true,
            InitiateOn::Search => false,
            InitiateOn::SearchAndMonostatic => tx == rx,
            InitiateOn::AnyDwell => true,
        };
        let mut updated: BTreeSet<u64> = BTreeSet::new();
        let mut new_ids: Vec<u64> = Vec::new();
        for list in channels.values() {
            let init = list.first().is_some_and(|m| may_initiate(m.tx, m.rx));
            self.process_channel(ctx, list, init, &mut updated, &mut new_ids);
        }

        // Looks: explicit targets, plus tracks inside a non-search beam.
        let mut looked: BTreeSet<u64> = ctx.target_tracks.iter().copied().collect();
        if ctx.kind != DwellKind::Search && self.config.beam_miss_fraction > 0.0 {
            looked.extend(self.tracks_in_looks(ctx, geom));
        }

        let mut rejected: BTreeSet<u64> = BTreeSet::new();
        let ids: Vec<u64> = self.tracks.keys().copied().collect();
        for id in ids {
            let is_new = new_ids.contains(&id);
            let hit = updated.contains(&id);
            let Some(track) = self.tracks.get_mut(&id) else { continue };
            if is_new {
                // Initiation may already satisfy M-of-N (two-point initiation).
                if self.c.confirmer.decide(&track.looks) == Confirmation::Confirm {
                    track.status = TrackStatus::Confirmed;
                    self.stats.confirmed += 1;
                }
                track.next_due_s = track.t_s + self.config.revisit.confirm_delay_s;
            } else if hit || looked.contains(&id) {
                if track.status == TrackStatus::Tentative {
                    track.looks.push(hit);
                    match self.c.confirmer.decide(&track.looks) {
                        Confirmation::Confirm => {
                            track.status = TrackStatus::Confirmed;
                            self.stats.confirmed += 1;
                        }
                        Confirmation::Reject => {
                            rejected.insert(id);
                        }
                        Confirmation::Pending => {}
                    }
                }
                if hit {
                    track.consecutive_misses = 0;
                } else {
                    track.consecutive_misses += 1;
                    track.next_due_s = ctx.t_s + self.config.revisit.redwell_delay_s;
                }
            }
            if hit || is_new {
                let next = self.next_due_after_update(id, geom);
                let Some(track) = self.tracks.get_mut(&id) else { continue };
                if let Some(next) = next {
                    track.next_due_s = next;
                }
                let track = &self.tracks[&id];
                let g = track.state.combined();
                rows.push(self.row_of(ctx.run, track, &g, track.t_s, track.status));
            }
        }

        rows.extend(self.delete_pass(ctx.run, ctx.t_s, &rejected));
        rows
    }

    /// Run only the deletion rules at `t_s` (coasting limits, covariance growth); use between
    /// dwells if the scheduler wants tracks to end on time. Returns the `deleted` rows.
    pub fn maintain(&mut self, run: u32, t_s: f64) -> Vec<TrackRow> {
        if !t_s.is_finite() {
            return Vec::new();
        }
        self.delete_pass(run, t_s, &BTreeSet::new())
    }

    fn next_due_after_update(&self, id: u64, geom: &dyn SensorGeometry) -> Option<f64> {
        let t = self.tracks.get(&id)?;
        if t.status != TrackStatus::Confirmed {
            return Some(t.t_s + self.config.revisit.confirm_delay_s);
        }
        let (rx, face) = t.last_face?;
        let f = geom.face(rx, face, t.t_s)?;
        Some(t.t_s + self.revisit_interval(id, &f)?)
    }

    fn tracks_in_looks(&self, ctx: &DwellContext, geom: &dyn SensorGeometry) -> Vec<u64> {
        let theta = self.config.revisit.beamwidth * self.config.beam_miss_fraction;
        let mut out = Vec::new();
        let models: Vec<(Look, BistaticRuv)> = ctx
            .looks
            .iter()
            .filter_map(|l| {
                BistaticRuv::from_geometry(&self.frame, geom, l.tx, l.rx, l.rx_face, ctx.t_s).ok().map(|m| (*l, m))
            })
            .collect();
        for (id, t) in &self.tracks {
            let g = self.c.filter.predict(&t.state, ctx.t_s - t.t_s).combined;
            let p = g.pos();
            for (look, m) in &models {
                let l = crate::linalg::mul_vec(&m.m, &(p - m.rx).to_array());
                if l[2] <= 0.0 {
                    continue;
                }
                let z = m.h_pos(p);
                let (du, dv) = (z[1] - look.beam_u, z[2] - look.beam_v);
                let in_beam = du * du + dv * dv <= theta * theta;
                let in_window = look.rho_window_m.is_none_or(|(lo, hi)| z[0] / 2.0 >= lo && z[0] / 2.0 <= hi);
                if in_beam && in_window {
                    out.push(*id);
                    break;
                }
            }
        }
        out
    }

    fn process_channel(
        &mut self,
        ctx: &DwellContext,
        list: &[PreparedMeasurement],
        may_initiate: bool,
        updated: &mut BTreeSet<u64>,
        new_ids: &mut Vec<u64>,
    ) {
        let ids: Vec<u64> = self.tracks.keys().copied().collect();
        let n_m = list.len();
        let filter = &*self.c.filter;
        let mut caches: Vec<PredCache> = ids.iter().map(|_| PredCache { entries: Vec::new() }).collect();
        let mut table = HypothesisTable::new(ids.len(), n_m);
        for (i, id) in ids.iter().enumerate() {
            let track = &self.tracks[id];
            for (j, m) in list.iter().enumerate() {
                let pred = caches[i].get(filter, track, m.t_s);
                if let Ok(h) = filter.hypothesis(pred, &m.model, &m.z, &m.r)
                    && self.c.gater.accepts(&h)
                {
                    table.set(i, j, Some(h));
                }
            }
        }
        let mut assign = self.c.associator.associate(&table);
        assign.resize(ids.len(), None);
        let mut claimed = vec![false; n_m];
        for j in assign.iter().flatten() {
            if *j < n_m {
                claimed[*j] = true;
            }
        }
        if self.config.share_merged {
            for (i, a) in assign.iter_mut().enumerate() {
                if a.is_some() {
                    continue;
                }
                let best = (0..n_m)
                    .filter(|&j| list[j].merged)
                    .filter_map(|j| table.get(i, j).map(|h| (j, h.nis)))
                    .min_by(|x, y| x.1.total_cmp(&y.1).then(x.0.cmp(&y.0)));
                if let Some((j, _)) = best {
                    *a = Some(j);
                }
            }
        }

        for (i, id) in ids.iter().enumerate() {
            let Some(j) = assign[i].filter(|&j| j < n_m) else { continue };
            let m = &list[j];
            let Some(track) = self.tracks.get(id) else { continue };
            let iterations =
                if track.n_updates < self.config.iekf_first_updates { self.config.iekf_iterations } else { 1 };
            let pred = caches[i].get(filter, track, m.t_s).clone();
            match filter.update(&pred, &m.model, &m.z, &m.r, iterations) {
                Ok(u) if u.state.is_finite() => {
                    let Some(track) = self.tracks.get_mut(id) else { continue };
                    track.state = u.state;
                    track.t_s = m.t_s;
                    track.n_updates += 1;
                    track.last_meas_id = Some(m.meas_id);
                    track.last_face = Some((m.rx, m.rx_face));
                    track.nis_sum += u.innovation.nis;
                    track.nis_count += 1;
                    self.stats.updates += 1;
                    if u.jitter {
                        self.stats.jitter_events += 1;
                    }
                    self.nis_log.push(NisRecord {
                        run: ctx.run,
                        t_s: m.t_s,
                        track_id: *id,
                        meas_id: m.meas_id,
                        tx: m.tx,
                        rx: m.rx,
                        nis: u.innovation.nis,
                    });
                    updated.insert(*id);
                }
                _ => self.stats.failed_updates += 1,
            }
        }

        if !may_initiate {
            return;
        }
        // Unclaimed detections outside every existing track's gate start tentative tracks,
        // strongest first; a detection inside the gate of a track started in this dwell is taken
        // as the same target and skipped.
        let mut cand: Vec<usize> =
            (0..n_m).filter(|&j| !claimed[j] && (0..ids.len()).all(|i| table.get(i, j).is_none())).collect();
        cand.sort_by(|&a, &b| list[b].snr_db.total_cmp(&list[a].snr_db).then(list[a].meas_id.cmp(&list[b].meas_id)));
        for j in cand {
            let m = &list[j];
            let dup = new_ids.iter().any(|nid| {
                self.tracks.get(nid).is_some_and(|t| {
                    let pred = filter.predict(&t.state, m.t_s - t.t_s);
                    filter.hypothesis(&pred, &m.model, &m.z, &m.r).is_ok_and(|h| self.c.gater.accepts(&h))
                })
            });
            if dup {
                continue;
            }
            let Some(init) = self.c.initiator.initiate(m) else { continue };
            let id = self.next_id;
            self.next_id += 1;
            let track = Track {
                id,
                status: TrackStatus::Tentative,
                state: filter.init(init.state),
                t_s: m.t_s,
                t_init_s: m.t_s,
                n_updates: init.meas_ids.len() as u32,
                last_meas_id: Some(m.meas_id),
                looks: init.looks,
                consecutive_misses: 0,
                next_due_s: m.t_s + self.config.revisit.confirm_delay_s,
                last_face: Some((m.rx, m.rx_face)),
                nis_sum: 0.0,
                nis_count: 0,
            };
            self.tracks.insert(id, track);
            self.stats.initiated += 1;
            new_ids.push(id);
        }
    }

    fn delete_pass(&mut self, run: u32, t_s: f64, rejected: &BTreeSet<u64>) -> Vec<TrackRow> {
        let mut rows = Vec::new();
        let mut gone = Vec::new();
        for (id, t) in &self.tracks {
            let g = self.c.filter.predict(&t.state, t_s - t.t_s).combined;
            let reason = if rejected.contains(id) {
                Some(DeleteReason::Unconfirmed)
            } else if !g.is_finite() {
                Some(DeleteReason::Divergence)
            } else {
                self.c.deleter.check(&TrackView {
                    track_id: *id,
                    status: t.status,
                    consecutive_misses: t.consecutive_misses,
                    n_updates: t.n_updates,
                    t_last_update_s: t.t_s,
                    t_s,
                    predicted: &g,
                })
            };
            if let Some(r) = reason {
                // The final row carries the last estimate (extrapolated to the deletion time
                // when it is finite).
                let out = if g.is_finite() { g } else { t.state.combined() };
                rows.push(self.row_of(run, t, &out, t_s, TrackStatus::Deleted));
                gone.push((*id, r));
            }
        }
        for (id, r) in gone {
            self.tracks.remove(&id);
            *self.stats.deleted.entry(r).or_insert(0) += 1;
        }
        rows
    }
}
