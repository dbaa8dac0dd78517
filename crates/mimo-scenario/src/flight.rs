//! Flight kinematics (docs/model.md §8.1, §8.2): manoeuvre schedules, the RK4 integration of a
//! reference path on the WGS-84 ellipsoid, formation offsets and the exact member state.

use crate::error::ScenarioError;
use crate::model::{Crossover, Manoeuvre, Offset};
use glam::DVec3;
use mimo_core::G0_MPS2;
use mimo_core::geo::{Geodetic, enu_from_ecef, meridian_radius_m, prime_vertical_radius_m};

/// Integration step and sample spacing of every trajectory (s). docs/model.md §8.1 asks for
/// dt ≤ 0.05 s.
pub const STEP_S: f64 = 0.05;

/// Where in which file a definition lives, for error messages.
#[derive(Debug, Clone)]
pub(crate) struct Ctx {
    pub file: String,
    pub path: String,
}

impl Ctx {
    pub fn new(file: &str, path: impl Into<String>) -> Ctx {
        Ctx { file: file.to_string(), path: path.into() }
    }

    /// A context for a sub-field (`a.b`) or element (`a[3]`).
    pub fn sub(&self, part: &str) -> Ctx {
        let path = if self.path.is_empty() {
            part.to_string()
        } else if part.starts_with('[') {
            format!("{}{part}", self.path)
        } else {
            format!("{}.{part}", self.path)
        };
        Ctx { file: self.file.clone(), path }
    }

    /// An [`ScenarioError::Invalid`] for `field` under this context.
    pub fn err(&self, field: &str, expected: impl Into<String>) -> ScenarioError {
        let f = if field.is_empty() { self.path.clone() } else { self.sub(field).path };
        ScenarioError::invalid(&self.file, f, expected)
    }
}

/// Cubic smoothstep S(x) = 3x² − 2x³ on [0, 1] and its integral from 0.
fn ramp_shape(x: f64) -> (f64, f64) {
    let x = x.clamp(0.0, 1.0);
    let x2 = x * x;
    (x2 * (3.0 - 2.0 * x), x2 * x * (1.0 - 0.5 * x))
}

/// Normalized trapezoid pulse: a smooth ramp up over `ramp` (cubic smoothstep, so the pulse's
/// own rate of change is continuous and a formation's outer aircraft never see an acceleration
/// step), `plateau` at 1, and the mirror-image ramp down. Returns (value, integral from 0) at
/// `tau` after its start. Each ramp contributes `ramp / 2` to the integral, as a linear ramp
/// would.
fn trapezoid(tau: f64, ramp: f64, plateau: f64) -> (f64, f64) {
    if tau <= 0.0 {
        (0.0, 0.0)
    } else if tau < ramp {
        let (g, f) = ramp_shape(tau / ramp);
        (g, f * ramp)
    } else if tau < ramp + plateau {
        (1.0, ramp / 2.0 + (tau - ramp))
    } else if tau < 2.0 * ramp + plateau {
        let u = tau - ramp - plateau;
        let (g, f) = ramp_shape(u / ramp);
        (1.0 - g, ramp / 2.0 + plateau + u - f * ramp)
    } else {
        (0.0, ramp + plateau)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Channel {
    /// Lateral acceleration a⊥ (m/s²), positive to the right.
    Lateral,
    /// Longitudinal acceleration (m/s²).
    Longitudinal,
    /// Vertical speed ḣ (m/s).
    Vertical,
}

#[derive(Debug, Clone, Copy)]
struct Pulse {
    start: f64,
    ramp: f64,
    plateau: f64,
    amp: f64,
    channel: Channel,
    /// Horizontal speed when the pulse starts.
    v_before: f64,
    /// Altitude when the pulse starts (reference path, before any offsets).
    h_before: f64,
}

impl Pulse {
    fn end(&self) -> f64 {
        self.start + 2.0 * self.ramp + self.plateau
    }
}

/// Commanded horizontal speed, lateral acceleration and climb rate at one time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Command {
    pub speed_mps: f64,
    pub lateral_mps2: f64,
    pub climb_mps: f64,
}

/// The control schedule of one reference path: piecewise-linear (trapezoidal) pulses.
#[derive(Debug, Clone)]
pub(crate) struct Controls {
    v0: f64,
    h0: f64,
    pulses: Vec<Pulse>,
}

impl Controls {
    /// Turn manoeuvres into pulses. `t_begin`, `v0`, `h0`: when the path starts, its horizontal
    /// speed and altitude then. Checks that manoeuvres start at or after `t_begin`, are in time
    /// order and do not overlap.
    pub fn compile(
        manoeuvres: &[Manoeuvre],
        t_begin: f64,
        v0: f64,
        h0: f64,
        ctx: &Ctx,
    ) -> Result<Controls, ScenarioError> {
        let mut pulses: Vec<Pulse> = Vec::with_capacity(manoeuvres.len());
        let (mut v, mut h) = (v0, h0);
        let mut free_from = t_begin;
        for (i, m) in manoeuvres.iter().enumerate() {
            let c = ctx.sub(&format!("manoeuvres[{i}]"));
            let at = m.at_s();
            let ramp = m.ramp_s();
            if !(at.is_finite() && at >= free_from - 1e-9) {
                let why = if i == 0 {
                    format!("a start time at or after {free_from} s (when this path begins), got {at}")
                } else {
                    format!(
                        "a start time at or after {free_from:.3} s, when manoeuvre {} ends \
                         (manoeuvres are in time order and do not overlap), got {at}",
                        i - 1
                    )
                };
                return Err(c.err("at_s", why));
            }
            if !(ramp.is_finite() && ramp > 0.0 && ramp <= 60.0) {
                return Err(c.err("ramp_s", format!("a ramp time in (0, 60] s, got {ramp}")));
            }
            let (v_before, h_before) = (v, h);
            let (channel, amp, plateau) = match *m {
                Manoeuvre::Turn { turn_deg, load_factor, .. } => {
                    if !(turn_deg.is_finite() && turn_deg.abs() <= 3600.0) {
                        let why = format!("a turn angle within ±3600°, got {turn_deg}");
                        return Err(c.err("turn_deg", why));
                    }
                    if !(load_factor.is_finite() && load_factor > 1.0 && load_factor <= 12.0) {
                        let why = format!("a load factor n in (1, 12], got {load_factor}");
                        return Err(c.err("load_factor", why));
                    }
                    let dpsi = turn_deg.to_radians().abs();
                    let a = G0_MPS2 * (load_factor * load_factor - 1.0).sqrt();
                    let (a, p) = full_or_reduced(dpsi * v, a, ramp);
                    (Channel::Lateral, a.copysign(turn_deg), p)
                }
                Manoeuvre::Climb { to_alt_m, rate_mps, .. } => {
                    if !(to_alt_m.is_finite() && (-100.0..=30_000.0).contains(&to_alt_m)) {
                        let why = format!("an altitude between -100 and 30000 m, got {to_alt_m}");
                        return Err(c.err("to_alt_m", why));
                    }
                    if !(rate_mps.is_finite() && rate_mps > 0.0 && rate_mps <= 300.0) {
                        let why = format!("a climb rate in (0, 300] m/s, got {rate_mps}");
                        return Err(c.err("rate_mps", why));
                    }
                    let dh = to_alt_m - h;
                    let (r, p) = full_or_reduced(dh.abs(), rate_mps, ramp);
                    h = to_alt_m;
                    (Channel::Vertical, r.copysign(dh), p)
                }
                Manoeuvre::Speed { to_mps, accel_mps2, .. } => {
                    if !(to_mps.is_finite() && to_mps > 0.0 && to_mps <= 1500.0) {
                        let why = format!("a speed in (0, 1500] m/s, got {to_mps}");
                        return Err(c.err("to_mps", why));
                    }
                    if !(accel_mps2.is_finite() && accel_mps2 > 0.0 && accel_mps2 <= 200.0) {
                        let why = format!("an acceleration in (0, 200] m/s², got {accel_mps2}");
                        return Err(c.err("accel_mps2", why));
                    }
                    let dv = to_mps - v;
                    let (a, p) = full_or_reduced(dv.abs(), accel_mps2, ramp);
                    v = to_mps;
                    (Channel::Longitudinal, a.copysign(dv), p)
                }
            };
            let pulse = Pulse { start: at, ramp, plateau, amp, channel, v_before, h_before };
            free_from = pulse.end();
            pulses.push(pulse);
        }
        Ok(Controls { v0, h0, pulses })
    }

    /// The commands at time `t`.
    pub fn eval(&self, t: f64) -> Command {
        let mut cmd = Command { speed_mps: self.v0, lateral_mps2: 0.0, climb_mps: 0.0 };
        for p in &self.pulses {
            if t < p.start {
                break;
            }
            let (g, f) = trapezoid(t - p.start, p.ramp, p.plateau);
            match p.channel {
                Channel::Lateral => cmd.lateral_mps2 = p.amp * g,
                Channel::Longitudinal => cmd.speed_mps = p.v_before + p.amp * f,
                Channel::Vertical => cmd.climb_mps = p.amp * g,
            }
        }
        cmd
    }

    /// Altitude of the reference path at `t` implied by the climbs alone (exact up to the
    /// integrator's rounding).
    pub fn altitude(&self, t: f64) -> f64 {
        let mut h = self.h0;
        for p in self.pulses.iter().filter(|p| p.channel == Channel::Vertical) {
            if t < p.start {
                break;
            }
            h = p.h_before + p.amp * trapezoid(t - p.start, p.ramp, p.plateau).1;
        }
        h
    }

    /// When the last manoeuvre ends (or `None`).
    pub fn last_end(&self) -> Option<f64> {
        self.pulses.last().map(Pulse::end)
    }
}

/// A trapezoid pulse of peak `peak` and ramps `ramp` whose integral is `total`: the plateau
/// length, or a lower peak with no plateau when `total` is too small for the full peak.
fn full_or_reduced(total: f64, peak: f64, ramp: f64) -> (f64, f64) {
    let plateau = total / peak - ramp;
    if plateau >= 0.0 { (peak, plateau) } else { (total / ramp, 0.0) }
}

/// Quintic smoothstep s(x) and its derivative.
fn smoothstep(x: f64) -> (f64, f64) {
    let x = x.clamp(0.0, 1.0);
    let x2 = x * x;
    (x2 * x * (10.0 - 15.0 * x + 6.0 * x2), 30.0 * x2 * (1.0 - 2.0 * x + x2))
}

#[derive(Debug, Clone, Copy)]
struct Change {
    start: f64,
    duration: f64,
    from: Offset,
    to: Offset,
    pass_up: f64,
}

/// A member's offset over time.
#[derive(Debug, Clone)]
pub(crate) struct OffsetTrack {
    base: Offset,
    changes: Vec<Change>,
}

impl OffsetTrack {
    /// The offset and its rate at `t`.
    pub fn at(&self, t: f64) -> (Offset, Offset) {
        let mut o = self.base;
        for c in &self.changes {
            if t >= c.start + c.duration {
                o = c.to;
                continue;
            }
            if t <= c.start {
                break;
            }
            let x = (t - c.start) / c.duration;
            let (s, ds) = smoothstep(x);
            let (sp, cp) = (std::f64::consts::PI * x).sin_cos();
            let bump = sp * sp;
            let dbump = 2.0 * sp * cp * std::f64::consts::PI;
            let k = ds / c.duration;
            let pos = Offset {
                along_m: c.from.along_m + (c.to.along_m - c.from.along_m) * s,
                right_m: c.from.right_m + (c.to.right_m - c.from.right_m) * s,
                up_m: c.from.up_m + (c.to.up_m - c.from.up_m) * s + c.pass_up * bump,
            };
            let rate = Offset {
                along_m: (c.to.along_m - c.from.along_m) * k,
                right_m: (c.to.right_m - c.from.right_m) * k,
                up_m: (c.to.up_m - c.from.up_m) * k + c.pass_up * dbump / c.duration,
            };
            return (pos, rate);
        }
        (o, Offset::default())
    }
}

/// Compile the crossovers of a group into one offset track per member (same order as
/// `members`). Checks times, overlaps and member ids.
pub(crate) fn compile_offsets(
    members: &[(String, Offset)],
    crossovers: &[Crossover],
    t_begin: f64,
    ctx: &Ctx,
) -> Result<Vec<OffsetTrack>, ScenarioError> {
    let mut tracks: Vec<OffsetTrack> =
        members.iter().map(|(_, o)| OffsetTrack { base: *o, changes: Vec::new() }).collect();
    let mut current: Vec<Offset> = members.iter().map(|(_, o)| *o).collect();
    let mut free_from = t_begin;
    for (i, x) in crossovers.iter().enumerate() {
        let c = ctx.sub(&format!("crossovers[{i}]"));
        if !(x.start_s.is_finite() && x.start_s >= free_from - 1e-9) {
            return Err(c.err(
                "start_s",
                format!(
                    "a start time at or after {free_from} s (crossovers are in time order, do \
                     not overlap, and start after their group forms), got {}",
                    x.start_s
                ),
            ));
        }
        if !(x.duration_s.is_finite() && x.duration_s >= 1.0 && x.duration_s <= 3600.0) {
            return Err(c.err("duration_s", format!("a duration in [1, 3600] s, got {}", x.duration_s)));
        }
        if x.moves.is_empty() {
            return Err(c.err("moves", "at least one move"));
        }
        free_from = x.start_s + x.duration_s;
        let mut seen = Vec::new();
        for (j, mv) in x.moves.iter().enumerate() {
            let cm = c.sub(&format!("moves[{j}]"));
            let Some(q) = members.iter().position(|(id, _)| *id == mv.id) else {
                let ids: Vec<&str> = members.iter().map(|(id, _)| id.as_str()).collect();
                return Err(cm.err("id", format!("a member of this group ({}), got `{}`", ids.join(", "), mv.id)));
            };
            if seen.contains(&q) {
                return Err(cm.err("id", format!("each member at most once per crossover, `{}` repeats", mv.id)));
            }
            seen.push(q);
            for (name, v) in [("along_m", mv.along_m), ("right_m", mv.right_m), ("up_m", mv.up_m)] {
                if let Some(v) = v
                    && !(v.is_finite() && v.abs() <= 100_000.0)
                {
                    return Err(cm.err(name, format!("an offset within ±100 km, got {v}")));
                }
            }
            if !(mv.pass_up_m.is_finite() && mv.pass_up_m.abs() <= 10_000.0) {
                return Err(cm.err("pass_up_m", format!("a pass height within ±10000 m, got {}", mv.pass_up_m)));
            }
            let from = current[q];
            let to = Offset {
                along_m: mv.along_m.unwrap_or(from.along_m),
                right_m: mv.right_m.unwrap_or(from.right_m),
                up_m: mv.up_m.unwrap_or(from.up_m),
            };
            current[q] = to;
            tracks[q].changes.push(Change {
                start: x.start_s,
                duration: x.duration_s,
                from,
                to,
                pass_up: mv.pass_up_m,
            });
        }
    }
    Ok(tracks)
}

/// The integrated state of a reference path: geodetic position and heading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RefState {
    pub lat: f64,
    pub lon: f64,
    pub alt: f64,
    /// Heading, clockwise from north (rad).
    pub psi: f64,
}

/// A reference-path sample: state, commands and rates.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RefNode {
    pub s: RefState,
    pub v: f64,
    pub lat_dot: f64,
    pub lon_dot: f64,
    pub alt_dot: f64,
    pub psi_dot: f64,
}

fn rates(cmd: Command, y: RefState) -> [f64; 4] {
    let m = meridian_radius_m(y.lat) + y.alt;
    let n = prime_vertical_radius_m(y.lat) + y.alt;
    let (sp, cp) = y.psi.sin_cos();
    let (sl, cl) = y.lat.sin_cos();
    let v = cmd.speed_mps;
    [
        v * cp / m,
        v * sp / (n * cl),
        cmd.climb_mps,
        // Lateral acceleration turns the path; with none it follows a geodesic, whose heading
        // drifts by sin ψ tan φ / N per metre.
        cmd.lateral_mps2 / v + v * sp * sl / (cl * n),
    ]
}

fn add(y: RefState, k: [f64; 4], h: f64) -> RefState {
    RefState { lat: y.lat + h * k[0], lon: y.lon + h * k[1], alt: y.alt + h * k[2], psi: y.psi + h * k[3] }
}

/// One classical RK4 step of size `h` from `t`.
pub(crate) fn rk4(c: &Controls, t: f64, y: RefState, h: f64) -> RefState {
    let k1 = rates(c.eval(t), y);
    let k2 = rates(c.eval(t + h / 2.0), add(y, k1, h / 2.0));
    let k3 = rates(c.eval(t + h / 2.0), add(y, k2, h / 2.0));
    let k4 = rates(c.eval(t + h), add(y, k3, h));
    let mut k = [0.0; 4];
    for i in 0..4 {
        k[i] = (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) / 6.0;
    }
    add(y, k, h)
}

/// The sample at `t` of state `y`.
pub(crate) fn node(c: &Controls, t: f64, y: RefState) -> RefNode {
    let cmd = c.eval(t);
    let r = rates(cmd, y);
    RefNode { s: y, v: cmd.speed_mps, lat_dot: r[0], lon_dot: r[1], alt_dot: r[2], psi_dot: r[3] }
}

/// ECEF position and velocity of a point at `offset` (changing at `rate`) from a reference
/// sample, in the reference's local horizontal frame (docs/model.md §8.2), differentiated exactly
/// (including the rotation of the local frame along the path).
pub(crate) fn member_state(n: &RefNode, o: Offset, rate: Offset) -> (DVec3, DVec3) {
    let RefState { lat, lon, alt, psi } = n.s;
    let (sl, cl) = lat.sin_cos();
    let (so, co) = lon.sin_cos();
    let (sp, cp) = psi.sin_cos();
    // ENU axes in ECEF.
    let e = DVec3::new(-so, co, 0.0);
    let nn = DVec3::new(-sl * co, -sl * so, cl);
    let u = DVec3::new(cl * co, cl * so, sl);
    // Their time derivatives.
    let (ld, od) = (n.lat_dot, n.lon_dot);
    let e_dot = DVec3::new(-co, -so, 0.0) * od;
    let n_dot = DVec3::new(-cl * co, -cl * so, -sl) * ld + DVec3::new(sl * so, -sl * co, 0.0) * od;
    let u_dot = DVec3::new(-sl * co, -sl * so, cl) * ld + DVec3::new(-cl * so, cl * co, 0.0) * od;
    // Offset in ENU: along t̂ = (sin ψ, cos ψ, 0), right ĉ = (cos ψ, −sin ψ, 0), up.
    let x_e = o.along_m * sp + o.right_m * cp;
    let x_n = o.along_m * cp - o.right_m * sp;
    let x_u = o.up_m;
    // d/dt of the ENU offset: heading rotation plus the offset's own rate.
    let xd_e = n.psi_dot * (o.along_m * cp - o.right_m * sp) + rate.along_m * sp + rate.right_m * cp;
    let xd_n = n.psi_dot * (-o.along_m * sp - o.right_m * cp) + rate.along_m * cp - rate.right_m * sp;
    let xd_u = rate.up_m;
    let g = Geodetic { lat_rad: lat, lon_rad: lon, alt_m: alt };
    let p_ref = g.to_ecef();
    let v_ref = e * (n.v * sp) + nn * (n.v * cp) + u * n.alt_dot;
    let p = p_ref + e * x_e + nn * x_n + u * x_u;
    let v = v_ref + e_dot * x_e + n_dot * x_n + u_dot * x_u + e * xd_e + nn * xd_n + u * xd_u;
    (p, v)
}

/// Heading (rad) at geodetic point `at` of a horizontal direction given in ECEF.
pub(crate) fn heading_of(at: Geodetic, dir_ecef: DVec3) -> f64 {
    let enu = enu_from_ecef(at.lat_rad, at.lon_rad) * dir_ecef;
    enu.x.atan2(enu.y)
}

/// Horizontal unit direction (ECEF) of heading `psi` at the reference sample.
pub(crate) fn direction_of(n: &RefNode) -> DVec3 {
    let (sl, cl) = n.s.lat.sin_cos();
    let (so, co) = n.s.lon.sin_cos();
    let (sp, cp) = n.s.psi.sin_cos();
    DVec3::new(-so, co, 0.0) * sp + DVec3::new(-sl * co, -sl * so, cl) * cp
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trapezoid_integrates_to_area() {
        let (r, p) = (1.5, 4.0);
        let n = 100_000;
        let total = 2.0 * r + p;
        let h = total / n as f64;
        let mut sum = 0.0;
        for i in 0..n {
            sum += trapezoid((i as f64 + 0.5) * h, r, p).0 * h;
        }
        assert!((sum - (r + p)).abs() < 1e-6);
        for &tau in &[0.3, 1.5, 3.0, 5.5, 6.9, 7.5] {
            let (_, f) = trapezoid(tau, r, p);
            let m = 20_000;
            let hh = tau / m as f64;
            let num: f64 = (0..m).map(|i| trapezoid((i as f64 + 0.5) * hh, r, p).0 * hh).sum();
            assert!((f - num).abs() < 1e-6, "tau {tau}: {f} vs {num}");
        }
    }

    #[test]
    fn smoothstep_ends_are_flat() {
        let (s0, d0) = smoothstep(0.0);
        let (s1, d1) = smoothstep(1.0);
        assert_eq!((s0, d0), (0.0, 0.0));
        assert!((s1 - 1.0).abs() < 1e-15 && d1.abs() < 1e-12);
        assert!((smoothstep(0.5).1 - 1.875).abs() < 1e-12);
    }

    #[test]
    fn turn_pulse_turns_through_the_angle() {
        let m = [Manoeuvre::Turn { at_s: 10.0, turn_deg: -90.0, load_factor: 3.0, ramp_s: 2.0 }];
        let c = Controls::compile(&m, 0.0, 250.0, 6000.0, &Ctx::new("t", "x")).expect("valid");
        let end = c.last_end().expect("one pulse");
        let n = 200_000;
        let h = (end - 10.0) / n as f64;
        let turned: f64 = (0..n).map(|i| c.eval(10.0 + (i as f64 + 0.5) * h).lateral_mps2 / 250.0 * h).sum();
        assert!((turned.to_degrees() + 90.0).abs() < 1e-6, "{}", turned.to_degrees());
        assert!(c.eval(9.0).lateral_mps2 == 0.0 && c.eval(end + 0.1).lateral_mps2 == 0.0);
    }

    #[test]
    fn overlapping_manoeuvres_are_rejected() {
        let m = [
            Manoeuvre::Turn { at_s: 10.0, turn_deg: 90.0, load_factor: 2.0, ramp_s: 1.0 },
            Manoeuvre::Speed { at_s: 12.0, to_mps: 300.0, accel_mps2: 5.0, ramp_s: 1.0 },
        ];
        let e = Controls::compile(&m, 0.0, 250.0, 6000.0, &Ctx::new("f.toml", "aircraft[0]")).expect_err("overlap");
        let msg = e.to_string();
        assert!(msg.contains("f.toml: aircraft[0].manoeuvres[1].at_s"), "{msg}");
    }
}
