//! The resolved scenario: plain data, serde both ways, so that a run manifest holds the whole
//! scenario and a run can be repeated from it.
//!
//! The flight definitions ([`Formation`], [`Aircraft`]) have the same shape as in the scenario
//! TOML files; [`Scenario`] adds the resolved ships (with their full radar parameters) and the
//! resolved target list. See `scenarios/README.md` for the file format.

use mimo_core::geo::Geodetic;
use mimo_core::ids::RadarId;
use mimo_core::params::{Fidelity, RadarParams};
use mimo_core::polarimetry::Polarimetry;
use serde::{Deserialize, Serialize};

/// Default scenario duration (s), as in the seed paper.
pub const DEFAULT_DURATION_S: f64 = 1000.0;
/// Default height of a ship's array centre above the ellipsoid (m), docs/model.md §1.3.
pub const DEFAULT_ARRAY_HEIGHT_M: f64 = 20.0;
/// Default time over which a manoeuvre ramps its acceleration (or climb rate) up and down (s).
pub const DEFAULT_RAMP_S: f64 = 1.0;

/// A fully resolved scenario: what `mimo simulate` runs and what its manifest records.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Short name, e.g. `scenario-7`.
    pub name: String,
    /// One-line description.
    #[serde(default)]
    pub description: String,
    /// Length of the run (s).
    pub duration_s: f64,
    /// Modelling switches.
    #[serde(default)]
    pub fidelity: Fidelity,
    /// The ships, `R1`, `R2`, … in order (`ships[i].id.index() == i`).
    pub ships: Vec<Ship>,
    /// The targets in scenario order (the order of truth rows at one time).
    pub targets: Vec<Target>,
    /// Formations flying the targets that belong to one (only their present members).
    #[serde(default)]
    pub formations: Vec<Formation>,
    /// Single aircraft.
    #[serde(default)]
    pub aircraft: Vec<Aircraft>,
    /// Registration biases of the radars (docs/model.md §5.5); off by default, and then not
    /// written into a manifest.
    #[serde(default, skip_serializing_if = "crate::biases::Biases::is_off")]
    pub biases: crate::biases::Biases,
    /// The links between the ships and the test article (docs/model.md §5.6); perfect by
    /// default, and then not written into a manifest.
    #[serde(default, skip_serializing_if = "crate::links::Links::is_off")]
    pub links: crate::links::Links,
}

/// A ship and its radar. The ship steams straight (along the great circle through its start
/// point in the direction of its start heading) at constant speed, or stays put when
/// `speed_mps` is 0.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ship {
    /// `R1`, `R2`, …
    #[serde(with = "radar_id_string")]
    pub id: RadarId,
    /// Latitude of the array centre at t = 0 (deg).
    pub lat_deg: f64,
    /// Longitude of the array centre at t = 0 (deg).
    pub lon_deg: f64,
    /// Height of the array centre above the WGS-84 ellipsoid (m).
    pub array_height_m: f64,
    /// Heading at t = 0, clockwise from north (deg). Face azimuths are relative to it.
    pub heading_deg: f64,
    /// Speed over ground (m/s); 0 for a stationary ship.
    pub speed_mps: f64,
    /// The radar, fully resolved (every parameter explicit).
    pub radar: RadarParams,
}

/// A target of the scenario, with the properties that do not depend on time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Target {
    /// `F-1`…`F-4`, `A`, `B`, `C` in the standard scenarios.
    pub id: String,
    /// Aircraft type name, e.g. `fighter` or `airliner`.
    pub kind: String,
    /// Mean radar cross-section (m²); the fluctuation model is `fidelity.swerling`.
    pub rcs_m2: f64,
    /// What the trajectory must stay within (checked when trajectories are built).
    pub envelope: Envelope,
    /// Polarimetric statistics used with `fidelity.polarization` (docs/model.md §3.5), from the
    /// aircraft type and scaled with `rcs_m2`; `None` is the default model for `rcs_m2`.
    #[serde(default)]
    pub polarimetry: Option<Polarimetry>,
}

/// Speed and acceleration limits of an aircraft type.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Envelope {
    /// Minimum speed (m/s, 3-D, relative to the earth).
    pub min_speed_mps: f64,
    /// Maximum speed (m/s).
    pub max_speed_mps: f64,
    /// Maximum magnitude of the kinematic acceleration relative to the earth, gravity excluded
    /// (units of g0 = 9.80665 m/s²).
    pub max_accel_g: f64,
}

/// An aircraft type in the scenario files (`[aircraft_types.NAME]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AircraftType {
    /// Mean RCS (m²).
    pub rcs_m2: f64,
    /// Minimum speed (m/s, 3-D, relative to the earth).
    pub min_speed_mps: f64,
    /// Maximum speed (m/s, 3-D, relative to the earth).
    pub max_speed_mps: f64,
    /// Maximum kinematic acceleration relative to the earth, gravity excluded (g0 = 9.80665 m/s²).
    pub max_accel_g: f64,
    /// Polarimetric statistics (`[aircraft_types.NAME.polarimetry]`, docs/model.md §3.5), used
    /// only with `fidelity.polarization`; absent, the default model for `rcs_m2`.
    #[serde(default)]
    pub polarimetry: Option<Polarimetry>,
}

impl AircraftType {
    /// The type's envelope.
    pub fn envelope(&self) -> Envelope {
        Envelope { min_speed_mps: self.min_speed_mps, max_speed_mps: self.max_speed_mps, max_accel_g: self.max_accel_g }
    }
}

/// A point given in degrees and metres above the WGS-84 ellipsoid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatLonAlt {
    /// WGS-84 geodetic latitude (deg, north positive).
    pub lat_deg: f64,
    /// Longitude (deg, east positive).
    pub lon_deg: f64,
    /// Height above the WGS-84 ellipsoid (m).
    pub alt_m: f64,
}

impl LatLonAlt {
    /// As a [`Geodetic`] (radians).
    pub fn to_geodetic(self) -> Geodetic {
        Geodetic::from_deg(self.lat_deg, self.lon_deg, self.alt_m)
    }
}

/// A position in a formation's moving frame: metres ahead of, to the right of and above the
/// reference point, in the local horizontal frame of the reference heading (docs/model.md §8.2).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Offset {
    /// Ahead of the reference point, along its heading (m).
    #[serde(default)]
    pub along_m: f64,
    /// To the right of the reference point, horizontal (m).
    #[serde(default)]
    pub right_m: f64,
    /// Above the reference point, local vertical (m).
    #[serde(default)]
    pub up_m: f64,
}

impl std::ops::Sub for Offset {
    type Output = Offset;
    fn sub(self, o: Offset) -> Offset {
        Offset { along_m: self.along_m - o.along_m, right_m: self.right_m - o.right_m, up_m: self.up_m - o.up_m }
    }
}

/// A formation: a reference path flown per docs/model.md §8.1, members at offsets from it, smooth
/// changes of those offsets (crossovers), and optionally a split into sub-groups that fly on
/// their own.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Formation {
    /// Name, unique among formations.
    pub name: String,
    /// Aircraft type of the members (a key of `aircraft_types`).
    #[serde(rename = "type")]
    pub kind: String,
    /// Reference point at t = 0.
    pub start: LatLonAlt,
    /// Reference heading at t = 0, clockwise from north (deg).
    pub heading_deg: f64,
    /// Reference horizontal speed at t = 0 (m/s).
    pub speed_mps: f64,
    /// The aircraft and their offsets at t = 0.
    pub members: Vec<Member>,
    /// Manoeuvres of the reference path, in time order; straight (geodesic), level flight at
    /// constant speed in between.
    #[serde(default)]
    pub manoeuvres: Vec<Manoeuvre>,
    /// Smooth offset changes, in time order.
    #[serde(default)]
    pub crossovers: Vec<Crossover>,
    /// Optional break-up into groups.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<Split>,
}

/// A formation member.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Member {
    /// Target id.
    pub id: String,
    /// Offset ahead of the reference point at t = 0 (m).
    #[serde(default)]
    pub along_m: f64,
    /// Offset to the right of the reference point at t = 0 (m).
    #[serde(default)]
    pub right_m: f64,
    /// Offset above the reference point at t = 0 (m).
    #[serde(default)]
    pub up_m: f64,
    /// Mean RCS (m²) if different from the type's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rcs_m2: Option<f64>,
}

impl Member {
    /// The member's offset at t = 0.
    pub fn offset(&self) -> Offset {
        Offset { along_m: self.along_m, right_m: self.right_m, up_m: self.up_m }
    }
}

/// One manoeuvre of a reference path. Manoeuvres start at absolute times, must not overlap, and
/// ramp their acceleration (or climb rate) up smoothly over `ramp_s` (cubic smoothstep) and
/// down over `ramp_s` at the end, so accelerations never step, not even for a formation's
/// outer aircraft. Their durations follow from the other parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Manoeuvre {
    /// A level coordinated turn through `turn_deg` (positive = right) at load factor
    /// `load_factor` (lateral acceleration g0·√(n² − 1)), at constant speed. A turn too small
    /// to reach full load factor uses a lower peak.
    Turn {
        /// Start time (s since scenario start).
        at_s: f64,
        /// Heading change (deg, positive = right).
        turn_deg: f64,
        /// Load factor n at full turn rate (> 1).
        load_factor: f64,
        /// Time over which the lateral acceleration ramps up, and again down (s); default 1 s.
        #[serde(default = "default_ramp")]
        ramp_s: f64,
    },
    /// A climb or descent to `to_alt_m` at vertical speed `rate_mps` (> 0), ramped over
    /// `ramp_s`; horizontal speed is unchanged.
    Climb {
        /// Start time (s since scenario start).
        at_s: f64,
        /// Altitude to reach, above the WGS-84 ellipsoid (m); of the reference point in a formation.
        to_alt_m: f64,
        /// Vertical speed at full rate (m/s, > 0; up or down follows from `to_alt_m`).
        rate_mps: f64,
        /// Time over which the vertical speed ramps up, and again down (s); default 1 s.
        #[serde(default = "default_ramp")]
        ramp_s: f64,
    },
    /// A change of horizontal speed to `to_mps` at acceleration `accel_mps2` (> 0).
    Speed {
        /// Start time (s since scenario start).
        at_s: f64,
        /// Horizontal speed to reach (m/s).
        to_mps: f64,
        /// Longitudinal acceleration at full rate (m/s², > 0; its sign follows from `to_mps`).
        accel_mps2: f64,
        /// Time over which the longitudinal acceleration ramps up, and again down (s); default 1 s.
        #[serde(default = "default_ramp")]
        ramp_s: f64,
    },
}

fn default_ramp() -> f64 {
    DEFAULT_RAMP_S
}

impl Manoeuvre {
    /// Start time (s).
    pub fn at_s(&self) -> f64 {
        match self {
            Manoeuvre::Turn { at_s, .. } | Manoeuvre::Climb { at_s, .. } | Manoeuvre::Speed { at_s, .. } => *at_s,
        }
    }

    /// Ramp time (s).
    pub fn ramp_s(&self) -> f64 {
        match self {
            Manoeuvre::Turn { ramp_s, .. } | Manoeuvre::Climb { ramp_s, .. } | Manoeuvre::Speed { ramp_s, .. } => {
                *ramp_s
            }
        }
    }

    /// `turn`, `climb` or `speed`.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Manoeuvre::Turn { .. } => "turn",
            Manoeuvre::Climb { .. } => "climb",
            Manoeuvre::Speed { .. } => "speed",
        }
    }
}

/// A smooth change of some members' offsets over `[start_s, start_s + duration_s]` with the
/// quintic smoothstep s(x) = 10x³ − 15x⁴ + 6x⁵ (zero rate and acceleration at both ends), plus an
/// optional vertical pass `pass_up_m · sin²(πx)` for deconfliction (docs/model.md §8.2). When two
/// sides trade places it is a crossover.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Crossover {
    /// Start time of the change (s since scenario start).
    pub start_s: f64,
    /// Duration of the change, T_x (s).
    pub duration_s: f64,
    /// The members that move, each at most once.
    pub moves: Vec<Move>,
}

/// One member's part in a [`Crossover`]: its offsets at the end (unchanged where omitted) and its
/// vertical pass height.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Move {
    /// Id of the member that moves.
    pub id: String,
    /// Offset ahead of the reference point at the end (m); unchanged if `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub along_m: Option<f64>,
    /// Offset to the right of the reference point at the end (m); unchanged if `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub right_m: Option<f64>,
    /// Offset above the reference point at the end (m); unchanged if `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up_m: Option<f64>,
    /// Height of the sin² bump flown during the change (m); 0 for none.
    #[serde(default)]
    pub pass_up_m: f64,
}

/// A break-up of a formation (or group) at `at_s` into groups, each with its own reference path
/// that starts where the group's reference point was, with the same heading and speed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Split {
    /// Time of the break-up (s since scenario start).
    pub at_s: f64,
    /// The groups; every member goes to exactly one.
    pub groups: Vec<Group>,
}

/// A group after a [`Split`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Group {
    /// Name (for messages and plots).
    pub name: String,
    /// Member ids, taken from the parent group.
    pub members: Vec<String>,
    /// The group's reference point as an offset in the parent's frame at the split. Resolved
    /// scenarios always carry it; in a file it defaults to the centroid of the members' offsets
    /// at the split, so removing a member from a scenario never moves the others.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<Offset>,
    /// Manoeuvres of the group's reference path after the split, in time order.
    #[serde(default)]
    pub manoeuvres: Vec<Manoeuvre>,
    /// Offset changes among the group's members after the split, in time order.
    #[serde(default)]
    pub crossovers: Vec<Crossover>,
    /// Optional further break-up of this group.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<Split>,
}

/// A single aircraft flying its own path (docs/model.md §8.1, §8.3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Aircraft {
    /// Target id.
    pub id: String,
    /// Aircraft type (a key of `aircraft_types`).
    #[serde(rename = "type")]
    pub kind: String,
    /// Position at t = 0.
    pub start: LatLonAlt,
    /// Heading at t = 0, clockwise from north (deg).
    pub heading_deg: f64,
    /// Horizontal speed at t = 0 (m/s).
    pub speed_mps: f64,
    /// Manoeuvres in time order; straight (geodesic), level flight at constant speed in between.
    #[serde(default)]
    pub manoeuvres: Vec<Manoeuvre>,
    /// Mean RCS (m²) if different from the type's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rcs_m2: Option<f64>,
}

mod radar_id_string {
    use mimo_core::ids::RadarId;
    use serde::{Deserialize, Deserializer, Serializer, de::Error};

    pub fn serialize<S: Serializer>(id: &RadarId, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(id)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<RadarId, D::Error> {
        let s = String::deserialize(d)?;
        RadarId::parse(&s).ok_or_else(|| D::Error::custom(format!("expected a radar id R1, R2, …, got `{s}`")))
    }
}
