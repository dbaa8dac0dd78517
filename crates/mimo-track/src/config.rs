//! The built-in trackers' configuration: which filter, and every tracker-level setting with its
//! documented default, and the check of a configuration (docs/model.md §6).

use crate::association::AssociationCost;
use crate::deletion::DeletionConfig;
use crate::gating::ChiSquareGate;
use crate::initiation::{MOfN, OnePointInitiator, TwoPointConfig};
use crate::measurement::MeasurementConfig;
use crate::motion::ProcessNoise;
use crate::partner::PartnerUpdate;
use crate::policy::RevisitPolicy;
use serde::{Deserialize, Serialize};
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
    type Err = TrackerConfigError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        TrackerKind::parse(s).ok_or_else(|| TrackerConfigError::UnknownKind {
            name: s.to_string(),
            known: TrackerKind::ALL.map(TrackerKind::as_str).join(", "),
        })
    }
}

/// A tracker configuration that cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TrackerConfigError {
    /// A field's value is out of range; `field` is its dotted path (`gate.probability`).
    #[error("{field}: expected {expected}, got {got}")]
    BadValue {
        /// Dotted path of the field.
        field: String,
        /// What the field must hold.
        expected: String,
        /// The value found.
        got: String,
    },
    /// An unknown tracker kind.
    #[error("unknown tracker `{name}` (expected one of: {known})")]
    UnknownKind {
        /// The name asked for.
        name: String,
        /// The known names.
        known: String,
    },
}

fn bad(field: &str, expected: &str, got: impl fmt::Display) -> TrackerConfigError {
    TrackerConfigError::BadValue { field: field.to_string(), expected: expected.to_string(), got: got.to_string() }
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
    OnePoint {
        /// Standard deviation of the zero-velocity prior (m/s).
        velocity_std_mps: f64,
    },
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

/// How measurements are assigned to tracks within one receive channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AssociationMethod {
    /// Global nearest neighbour: at most one measurement per track (docs/model.md §6.5). Default.
    #[default]
    Gnn,
    /// Joint probabilistic data association: every gated measurement updates a track with its
    /// marginal probability (docs/model.md §6.8).
    Jpda,
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
    /// Association method: `gnn` (default) or `jpda`.
    pub association_method: AssociationMethod,
    /// JPDA limits (used when `association_method = jpda`; its P_D, P_G and clutter density
    /// come from `association`).
    pub jpda: JpdaLimits,
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
    /// Where a detection may not start a track: near an existing track.
    pub initiation_exclusion: InitiationExclusion,
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
    /// With `share_merged`, move a track that shares a `merged` measurement with the track GNN
    /// gave it to by that track's correction instead of pulling it onto the measurement, so
    /// that an unresolved group keeps its members' relative geometry (docs/model.md §6.5).
    /// Default false.
    pub merged_group_update: bool,
    /// Let a track GNN left without a measurement share the measurement of another track whose
    /// resolution cell it is in, moving by that track's correction (docs/model.md §6.5). Off by
    /// default.
    pub partner_update: PartnerUpdate,
    /// Under JPDA, let a return inside a track's gate start a track when every track that gates
    /// it prefers another return and gives it `β` below this (docs/model.md §6.4,
    /// [`crate::second_return`]); 0, the default, disables.
    pub second_return_max_beta: f64,
}

/// A detection never starts a track when it lies, for some existing track, inside the track's
/// predicted resolution cell or inside a wide exclusion gate (docs/model.md §6.4): an
/// unresolved or gate-missing return of a tracked target is not a new target. Off by default
/// (it cost the GNN default completeness on scenario 7,
/// docs/decisions/0026-formation-measures-as-options.md); on in the JPDA
/// built-ins ([`InitiationExclusion::resolution_cell`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct InitiationExclusion {
    /// NIS below which a detection belongs to a track (0, the default, disables; the JPDA
    /// built-ins use χ²₃ 99.999 % = 25.9).
    pub nis: f64,
    /// Range resolution ΔR (m of ρ): the cell is `|ΔR_B| ≤ 2ΔR`. Default 30 m.
    pub range_cell_m: f64,
    /// Half-width of the cell in angle, as a fraction of the beamwidth (`revisit.beamwidth`).
    /// Default 0 (no cell); the JPDA built-ins use 0.5.
    pub beam_fraction: f64,
}

impl Default for InitiationExclusion {
    fn default() -> Self {
        InitiationExclusion { nis: 0.0, range_cell_m: 30.0, beam_fraction: 0.0 }
    }
}

impl InitiationExclusion {
    /// The exclusion the JPDA built-ins use: the resolution cell (ΔR = 30 m, half a beamwidth)
    /// and a χ²₃ 99.999 % gate (NIS 25.9).
    pub fn resolution_cell() -> InitiationExclusion {
        InitiationExclusion { nis: 25.9, range_cell_m: 30.0, beam_fraction: 0.5 }
    }
}

/// Limits of the JPDA enumeration (docs/model.md §6.8).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct JpdaLimits {
    /// Largest number of joint events enumerated in one cluster; a larger cluster falls back to
    /// the GNN assignment. Default 20 000.
    pub max_events: usize,
    /// Association probabilities below this are dropped. Default 0.01.
    pub min_probability: f64,
}

impl Default for JpdaLimits {
    fn default() -> Self {
        JpdaLimits { max_events: 20_000, min_probability: 0.01 }
    }
}

impl Default for TrackerConfig {
    fn default() -> Self {
        TrackerConfig {
            kind: TrackerKind::Default,
            ekf_noise: ProcessNoise::Dwna { sigma_a_mps2: 15.0 },
            imm: ImmConfig::default(),
            measurement: MeasurementConfig::default(),
            gate: ChiSquareGate::default(),
            association_method: AssociationMethod::Gnn,
            jpda: JpdaLimits::default(),
            association: AssociationCost::default(),
            iekf_iterations: 3,
            iekf_first_updates: 3,
            initiator: InitiatorConfig::default(),
            initiate_on: InitiateOn::SearchAndMonostatic,
            initiation_exclusion: InitiationExclusion::default(),
            confirmation: MOfN::default(),
            deletion: DeletionConfig::default(),
            revisit: RevisitPolicy::default(),
            beam_miss_fraction: 0.5,
            share_merged: true,
            merged_group_update: false,
            partner_update: PartnerUpdate::default(),
            second_return_max_beta: 0.0,
        }
    }
}

impl TrackerConfig {
    /// The default configuration of a tracker kind.
    pub fn for_kind(kind: TrackerKind) -> TrackerConfig {
        TrackerConfig { kind, ..TrackerConfig::default() }
    }

    /// Check the configuration; the error names the field and what was expected.
    pub fn validate(&self) -> Result<(), TrackerConfigError> {
        let pos = |name: &str, x: f64| {
            if x.is_finite() && x > 0.0 { Ok(()) } else { Err(bad(name, "a positive finite number", x)) }
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
            return Err(bad("gate.probability", "a probability in (0, 1)", self.gate.probability));
        }
        if let AssociationCost::Nis { miss_cost } = self.association {
            pos("association.miss_cost", miss_cost)?;
        }
        if let AssociationCost::Likelihood { pd, clutter_density, .. } = self.association {
            pos("association.clutter_density", clutter_density)?;
            if !(pd > 0.0 && pd < 1.0) {
                return Err(bad("association.pd", "a probability in (0, 1)", pd));
            }
        }
        let e = &self.initiation_exclusion;
        for (name, x) in [
            ("initiation_exclusion.nis", e.nis),
            ("initiation_exclusion.range_cell_m", e.range_cell_m),
            ("initiation_exclusion.beam_fraction", e.beam_fraction),
            ("partner_update.range_sum_m", self.partner_update.range_sum_m),
            ("partner_update.beam_fraction", self.partner_update.beam_fraction),
        ] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(bad(name, "a finite number >= 0", x));
            }
        }
        if self.jpda.max_events == 0 {
            return Err(bad("jpda.max_events", "at least 1", self.jpda.max_events));
        }
        if !(self.jpda.min_probability >= 0.0 && self.jpda.min_probability < 1.0) {
            return Err(bad("jpda.min_probability", "a number in [0, 1)", self.jpda.min_probability));
        }
        if self.confirmation.m == 0 || self.confirmation.m > self.confirmation.n {
            let got = format!("m = {}, n = {}", self.confirmation.m, self.confirmation.n);
            return Err(bad("confirmation", "1 <= m <= n", got));
        }
        pos("deletion.max_position_trace_m2", self.deletion.max_position_trace_m2)?;
        pos("revisit.t_min_s", self.revisit.t_min_s)?;
        pos("revisit.beamwidth", self.revisit.beamwidth)?;
        pos("revisit.sharpness_v0", self.revisit.sharpness_v0)?;
        if self.revisit.t_max_s < self.revisit.t_min_s {
            return Err(bad("revisit.t_max_s", "at least revisit.t_min_s", self.revisit.t_max_s));
        }
        if !(0.0..=1.0).contains(&self.second_return_max_beta) {
            return Err(bad("second_return_max_beta", "a probability in [0, 1]", self.second_return_max_beta));
        }
        if !(self.beam_miss_fraction.is_finite() && self.beam_miss_fraction >= 0.0) {
            return Err(bad("beam_miss_fraction", "a finite number >= 0", self.beam_miss_fraction));
        }
        Ok(())
    }
}
