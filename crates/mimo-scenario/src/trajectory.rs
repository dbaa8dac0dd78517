//! Truth trajectories: every target integrated once at [`STEP_S`], then evaluated at any time
//! by cubic Hermite interpolation of ECEF position and velocity.

use crate::epoch_balls::{Ball, EpochBalls};
use crate::error::ScenarioError;
use crate::flight::{
    Controls, Ctx, OffsetTrack, RefNode, RefState, STEP_S, compile_offsets, direction_of, heading_of, member_state,
    node, rk4,
};
use crate::model::{Crossover, Group, Manoeuvre, Offset, Scenario, Split};
use glam::DVec3;
use mimo_core::G0_MPS2;
use mimo_core::geo::{Geodetic, ecef_to_geodetic, enu_from_ecef};
use mimo_core::records::TruthRow;
use std::collections::HashMap;

/// Trajectories are integrated this long past the scenario's end (s), so that a dwell that
/// starts just before the end can still be evaluated by interpolation.
pub const MARGIN_S: f64 = 2.0;

/// A target's truth at one time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TargetState {
    /// ECEF position (m).
    pub pos_ecef: DVec3,
    /// ECEF velocity (m/s).
    pub vel_ecef: DVec3,
    /// The same position as latitude, longitude and height above the ellipsoid.
    pub geodetic: Geodetic,
    /// Mean RCS (m²).
    pub rcs_m2: f64,
}

/// Every target's trajectory, sampled at [`STEP_S`] from t = 0 to the scenario's end plus
/// [`MARGIN_S`]. Build with [`Scenario::build_trajectories`]. Cheap to query at any time:
/// between samples the position is the cubic Hermite interpolant of the sampled positions and
/// velocities (error well below a millimetre here); before t = 0 and after the last sample the
/// target moves on at its end velocity.
#[derive(Debug, Clone)]
pub struct Trajectories {
    duration_s: f64,
    ids: Vec<String>,
    rcs: Vec<f64>,
    pos: Vec<Vec<DVec3>>,
    vel: Vec<Vec<DVec3>>,
    /// Made on the first [`Trajectories::balls_at`] (only the simulator's quiet dwells ask).
    balls: std::sync::OnceLock<EpochBalls>,
}

fn first_node_at_or_after(t: f64) -> usize {
    ((t / STEP_S) - 1e-7).ceil().max(0.0) as usize
}

/// A group of aircraft flying one reference path.
struct GroupView<'a> {
    members: Vec<(String, Offset)>,
    manoeuvres: &'a [Manoeuvre],
    crossovers: &'a [Crossover],
    split: Option<&'a Split>,
}

struct Builder {
    n_nodes: usize,
    index: HashMap<String, usize>,
    pos: Vec<Vec<DVec3>>,
    vel: Vec<Vec<DVec3>>,
}

impl Builder {
    /// Fly one group from `t_begin` (state `y0`, horizontal speed `v0`), filling nodes from
    /// `k_first` on, then its split groups.
    fn fly(
        &mut self,
        g: &GroupView<'_>,
        t_begin: f64,
        k_first: usize,
        y0: RefState,
        v0: f64,
        ctx: &Ctx,
    ) -> Result<(), ScenarioError> {
        let controls = Controls::compile(g.manoeuvres, t_begin, v0, y0.alt, ctx)?;
        let tracks = compile_offsets(&g.members, g.crossovers, t_begin, ctx)?;
        let slots: Vec<Option<usize>> = g.members.iter().map(|(id, _)| self.index.get(id).copied()).collect();
        let k_end = g.split.map_or(self.n_nodes, |s| first_node_at_or_after(s.at_s)).min(self.n_nodes);
        let (mut t, mut y) = (t_begin, y0);
        for k in k_first..k_end {
            let tk = k as f64 * STEP_S;
            if tk > t {
                y = rk4(&controls, t, y, tk - t);
                t = tk;
            }
            let nd = node(&controls, tk, y);
            for (slot, track) in slots.iter().zip(&tracks) {
                if let Some(i) = *slot {
                    let (o, od) = track.at(tk);
                    let (p, v) = member_state(&nd, o, od);
                    self.pos[i][k] = p;
                    self.vel[i][k] = v;
                }
            }
        }
        let Some(split) = g.split else {
            return Ok(());
        };
        if k_end >= self.n_nodes {
            return Ok(());
        }
        let ts = split.at_s;
        if ts > t {
            y = rk4(&controls, t, y, ts - t);
        }
        let nd = node(&controls, ts, y);
        for (gi, child) in split.groups.iter().enumerate() {
            let (y_child, view) = child_group(g, child, &tracks, &nd, ts);
            let c = ctx.sub(&format!("split.groups[{gi}]"));
            self.fly(&view, ts, k_end, y_child, nd.v, &c)?;
        }
        Ok(())
    }
}

/// The state of a group after a split at `ts` (reference node `nd`) and its members with their
/// offsets in its own frame, taken from their actual positions so that positions are exactly
/// continuous across the split.
fn child_group<'a>(
    g: &GroupView<'_>,
    child: &'a Group,
    tracks: &[OffsetTrack],
    nd: &RefNode,
    ts: f64,
) -> (RefState, GroupView<'a>) {
    let dir = direction_of(nd);
    let offsets: Vec<Offset> = child
        .members
        .iter()
        .filter_map(|id| {
            let q = g.members.iter().position(|(m, _)| m == id)?;
            Some(tracks[q].at(ts).0)
        })
        .collect();
    let reference = child.reference.unwrap_or_else(|| centroid(&offsets));
    let (p_ref, _) = member_state(nd, reference, Offset::default());
    let geo = ecef_to_geodetic(p_ref);
    let psi = heading_of(geo, dir);
    let y_child = RefState { lat: geo.lat_rad, lon: geo.lon_rad, alt: geo.alt_m, psi };
    let enu = enu_from_ecef(geo.lat_rad, geo.lon_rad);
    let (sp, cp) = psi.sin_cos();
    let members = child
        .members
        .iter()
        .zip(&offsets)
        .map(|(id, o)| {
            let d = enu * (member_state(nd, *o, Offset::default()).0 - p_ref);
            let rel = Offset { along_m: d.x * sp + d.y * cp, right_m: d.x * cp - d.y * sp, up_m: d.z };
            (id.clone(), rel)
        })
        .collect();
    let view = GroupView {
        members,
        manoeuvres: &child.manoeuvres,
        crossovers: &child.crossovers,
        split: child.split.as_ref(),
    };
    (y_child, view)
}

/// Mean of offsets (the default reference point of a group after a split).
pub(crate) fn centroid(offsets: &[Offset]) -> Offset {
    let n = offsets.len().max(1) as f64;
    Offset {
        along_m: offsets.iter().map(|o| o.along_m).sum::<f64>() / n,
        right_m: offsets.iter().map(|o| o.right_m).sum::<f64>() / n,
        up_m: offsets.iter().map(|o| o.up_m).sum::<f64>() / n,
    }
}

impl Scenario {
    /// Integrate every target's trajectory over `[0, duration_s + MARGIN_S]` and check it
    /// against its aircraft type's envelope (speed and acceleration, evaluated at every
    /// sample). Deterministic: no randomness is involved. Takes a few milliseconds per target
    /// for a 1000 s scenario.
    pub fn build_trajectories(&self) -> Result<Trajectories, ScenarioError> {
        self.validate()?;
        let n_nodes = first_node_at_or_after(self.duration_s + MARGIN_S) + 1;
        let n_targets = self.targets.len();
        let mut b = Builder {
            n_nodes,
            index: self.targets.iter().enumerate().map(|(i, t)| (t.id.clone(), i)).collect(),
            pos: vec![vec![DVec3::NAN; n_nodes]; n_targets],
            vel: vec![vec![DVec3::NAN; n_nodes]; n_targets],
        };
        let ctx = Ctx::new("scenario", "");
        for (i, f) in self.formations.iter().enumerate() {
            let view = GroupView {
                members: f.members.iter().map(|m| (m.id.clone(), m.offset())).collect(),
                manoeuvres: &f.manoeuvres,
                crossovers: &f.crossovers,
                split: f.split.as_ref(),
            };
            let y0 = start_state(f.start.to_geodetic(), f.heading_deg);
            b.fly(&view, 0.0, 0, y0, f.speed_mps, &ctx.sub(&format!("formations[{i}]")))?;
        }
        for (i, a) in self.aircraft.iter().enumerate() {
            let view = GroupView {
                members: vec![(a.id.clone(), Offset::default())],
                manoeuvres: &a.manoeuvres,
                crossovers: &[],
                split: None,
            };
            let y0 = start_state(a.start.to_geodetic(), a.heading_deg);
            b.fly(&view, 0.0, 0, y0, a.speed_mps, &ctx.sub(&format!("aircraft[{i}]")))?;
        }
        let traj = Trajectories {
            duration_s: self.duration_s,
            ids: self.targets.iter().map(|t| t.id.clone()).collect(),
            rcs: self.targets.iter().map(|t| t.rcs_m2).collect(),
            balls: std::sync::OnceLock::new(),
            pos: b.pos,
            vel: b.vel,
        };
        for (i, target) in self.targets.iter().enumerate() {
            traj.check_envelope(i, target)?;
        }
        Ok(traj)
    }
}

fn start_state(g: Geodetic, heading_deg: f64) -> RefState {
    RefState { lat: g.lat_rad, lon: g.lon_rad, alt: g.alt_m, psi: heading_deg.to_radians() }
}

impl Trajectories {
    fn check_envelope(&self, i: usize, target: &crate::model::Target) -> Result<(), ScenarioError> {
        let env = target.envelope;
        let (pos, vel) = (&self.pos[i], &self.vel[i]);
        let fail = |k: usize, what: String| ScenarioError::Envelope {
            target: target.id.clone(),
            t_s: k as f64 * STEP_S,
            what,
        };
        for (k, (p, v)) in pos.iter().zip(vel).enumerate() {
            if !(p.is_finite() && v.is_finite()) {
                return Err(fail(k, "its position is undefined (is it a member of a flight?)".into()));
            }
            let speed = v.length();
            if speed < env.min_speed_mps - 1e-6 || speed > env.max_speed_mps + 1e-6 {
                return Err(fail(
                    k,
                    format!("speed {speed:.1} m/s outside [{}, {}] m/s", env.min_speed_mps, env.max_speed_mps),
                ));
            }
        }
        let limit = env.max_accel_g * G0_MPS2;
        for k in 1..vel.len().saturating_sub(1) {
            let a = ((vel[k + 1] - vel[k - 1]) / (2.0 * STEP_S)).length();
            if a > limit {
                return Err(fail(
                    k,
                    format!("acceleration {:.2} g above max_accel_g {}", a / G0_MPS2, env.max_accel_g),
                ));
            }
        }
        Ok(())
    }

    /// Number of targets.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True when there are no targets (never for a validated scenario).
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// Target ids in scenario order.
    pub fn ids(&self) -> &[String] {
        &self.ids
    }

    /// Index of a target id.
    pub fn index_of(&self, id: &str) -> Option<usize> {
        self.ids.iter().position(|x| x == id)
    }

    /// The scenario duration the trajectories were built for (s).
    pub fn duration_s(&self) -> f64 {
        self.duration_s
    }

    /// Sample spacing of the stored trajectory (s).
    pub fn step_s(&self) -> f64 {
        STEP_S
    }

    /// ECEF position and velocity of target `i` at `t_s`. Panics if `i >= self.len()`.
    pub fn pos_vel_at(&self, i: usize, t_s: f64) -> (DVec3, DVec3) {
        let (pos, vel) = (&self.pos[i], &self.vel[i]);
        let last = pos.len() - 1;
        let t_last = last as f64 * STEP_S;
        if t_s <= 0.0 {
            return (pos[0] + vel[0] * t_s, vel[0]);
        }
        if t_s >= t_last {
            return (pos[last] + vel[last] * (t_s - t_last), vel[last]);
        }
        let h = self.segment(i, t_s);
        let s2 = h.s * h.s;
        let v = (h.p0 * (6.0 * s2 - 6.0 * h.s)
            + h.m0 * (3.0 * s2 - 4.0 * h.s + 1.0)
            + h.p1 * (6.0 * h.s - 6.0 * s2)
            + h.m1 * (3.0 * s2 - 2.0 * h.s))
            / STEP_S;
        (h.position(), v)
    }

    /// ECEF position of target `i` at `t_s` (m). Panics if `i >= self.len()`. The position half of
    /// [`Self::pos_vel_at`] (the same expression, so the same value): the engine asks for every
    /// target's position at every dwell and needs no velocity.
    pub fn position_at(&self, i: usize, t_s: f64) -> DVec3 {
        let last = self.pos[i].len() - 1;
        if t_s <= 0.0 || t_s >= last as f64 * STEP_S {
            return self.pos_vel_at(i, t_s).0;
        }
        self.segment(i, t_s).position()
    }

    /// The cubic Hermite segment of target `i` holding `t_s`, for `0 < t_s < t_last`.
    fn segment(&self, i: usize, t_s: f64) -> Hermite {
        let (pos, vel) = (&self.pos[i], &self.vel[i]);
        let k = ((t_s / STEP_S).floor() as usize).min(pos.len() - 2);
        Hermite {
            s: (t_s - k as f64 * STEP_S) / STEP_S,
            p0: pos[k],
            p1: pos[k + 1],
            m0: vel[k] * STEP_S,
            m1: vel[k + 1] * STEP_S,
        }
    }

    /// For every target (in order), a ball that holds it at `t_s` and at every other time of the
    /// same one-second epoch (see [`EpochBalls`]); `None` outside the sampled span.
    pub fn balls_at(&self, t_s: f64) -> Option<&[Ball]> {
        self.balls.get_or_init(|| EpochBalls::new(&self.pos, &self.vel)).balls_at(t_s)
    }

    /// Mean RCS of target `i` (m²). Panics if `i >= self.len()`.
    pub fn rcs_m2(&self, i: usize) -> f64 {
        self.rcs[i]
    }

    /// Full state of target `i` at `t_s`. Panics if `i >= self.len()`.
    pub fn state_at(&self, i: usize, t_s: f64) -> TargetState {
        let (pos_ecef, vel_ecef) = self.pos_vel_at(i, t_s);
        TargetState { pos_ecef, vel_ecef, geodetic: ecef_to_geodetic(pos_ecef), rcs_m2: self.rcs[i] }
    }

    /// Truth table rows for Monte Carlo run `run`, sampled at `rate_hz` from t = 0 to the
    /// scenario's end inclusive (times are `j / rate_hz`), ordered by time, then by target in
    /// scenario order. Empty if `rate_hz` is not a positive finite number.
    pub fn truth_rows(&self, run: u32, rate_hz: f64) -> Vec<TruthRow> {
        self.truth_rows_of_steps(run, rate_hz, 0..self.truth_steps(rate_hz))
    }

    /// The number of truth sample times over the run at `rate_hz` (0 for a rate that is not a
    /// finite positive number): the steps `j` of [`Trajectories::truth_rows_of_steps`].
    pub fn truth_steps(&self, rate_hz: f64) -> usize {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return 0;
        }
        (self.duration_s * rate_hz + 1e-9).floor() as usize + 1
    }

    /// The truth rows of sample times `j / rate_hz` for `j` in `steps`, in the order of
    /// [`Trajectories::truth_rows`]: consecutive ranges give that table piece by piece, so a
    /// writer can stream it with memory that does not grow with the run's duration.
    pub fn truth_rows_of_steps(&self, run: u32, rate_hz: f64, steps: std::ops::Range<usize>) -> Vec<TruthRow> {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return Vec::new();
        }
        let mut rows = Vec::with_capacity(steps.len() * self.len());
        for j in steps {
            let t = j as f64 / rate_hz;
            for (i, id) in self.ids.iter().enumerate() {
                let s = self.state_at(i, t);
                rows.push(TruthRow {
                    run,
                    t_s: t,
                    target: id.clone(),
                    x_m: s.pos_ecef.x,
                    y_m: s.pos_ecef.y,
                    z_m: s.pos_ecef.z,
                    vx_mps: s.vel_ecef.x,
                    vy_mps: s.vel_ecef.y,
                    vz_mps: s.vel_ecef.z,
                    lat_deg: s.geodetic.lat_deg(),
                    lon_deg: s.geodetic.lon_deg(),
                    alt_m: s.geodetic.alt_m,
                    rcs_m2: s.rcs_m2,
                });
            }
        }
        rows
    }
}

/// One cubic Hermite segment between two truth samples: end points, end tangents (velocity ×
/// step) and the normalised time `s ∈ [0, 1)` within it.
struct Hermite {
    s: f64,
    p0: DVec3,
    p1: DVec3,
    m0: DVec3,
    m1: DVec3,
}

impl Hermite {
    fn position(&self) -> DVec3 {
        let (s, s2) = (self.s, self.s * self.s);
        let s3 = s2 * s;
        self.p0 * (2.0 * s3 - 3.0 * s2 + 1.0)
            + self.m0 * (s3 - 2.0 * s2 + s)
            + self.p1 * (3.0 * s2 - 2.0 * s3)
            + self.m1 * (s3 - s2)
    }
}
