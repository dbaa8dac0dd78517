//! What a dwell's energy was spent on (docs/design.md §6, "Usage by purpose"): the purposes,
//! the radars' beams as the rule sees them, and the rule deciding whether a truth object was in
//! a look's beam and range window.
//!
//! **The rule.** A transmit part of a look (a `dwells` row with role `tx` or `txrx` and kind
//! `confirm`, `track` or `mimo`) *holds a truth* at the look's mid-time `t = t_s + duration_s / 2`
//! (when the radar model evaluates it, docs/model.md §4.2) when the truth's position `p` there
//!
//! 1. is in front of the transmitter's face (`w > 0`) and inside the 3 dB footprint of its beam,
//!    `(2Δu/θ_u)² + (2Δv/θ_v)² ≤ 1` with `(Δu, Δv)` the truth's direction cosines in that face
//!    minus the row's `(beam_u, beam_v)` and `θ` the half-power beamwidths of the radar's
//!    pattern model (docs/model.md §2.1–§2.3). The pattern depends on `(Δu, Δv)` alone, so the
//!    footprint broadens off broadside by itself and is never widened on top (§1.5);
//! 2. and, for at least one receiver of the look (the transmitter itself when it receives, or
//!    another part of the same `group_id` with role `rx` or `txrx`), is inside that receiver's 3 dB
//!    footprint in the same way, with its equivalent range on that channel
//!    `ρ = (‖p − t‖ + ‖p − r‖) / 2` (transmitter and receiver array centres; the plain range when
//!    they are one radar, docs/model.md §4.1, §5.2) within [`RANGE_WINDOW_HALF_M`] of the aim
//!    point's `ρ` on the same channel.
//!
//! Everything is the geometry of the dwell itself: visibility (horizon, minimum range, bistatic
//! angle) and detection are not asked, so a look at a real object that it could not see is still
//! spent on that object, as a track on a present truth is never spurious (§6).

use glam::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::params::{PatternModel, RadarParams};
use mimo_core::records::DwellKind;
use std::collections::BTreeMap;

/// Half-width of the range window the rule takes around the aim point's equivalent range (m):
/// the smallest window the default test article asks for (docs/model.md §5.2,
/// `w = max(5σ_ρ, 1 km)`), so that a truth counted in it is inside that test article's window.
pub const RANGE_WINDOW_HALF_M: f64 = 1000.0;

mimo_core::label_enum! {
    /// What a transmit dwell row was spent on; the labels are the `purpose` column of
    /// `score_usage_by_purpose` and the keys of `summary.json`.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
    pub enum Purpose {
        /// Kind `search`, whoever requested it.
        Search = "search",
        /// Kind `confirm` holding a truth.
        ConfirmTrue = "confirm_true",
        /// Kind `confirm` holding none.
        ConfirmFalse = "confirm_false",
        /// Kind `track` or `mimo` holding a truth.
        Track = "track",
        /// Kind `track` or `mimo` holding none (a track following no object).
        TrackFalse = "track_false",
    }
}

impl Purpose {
    /// The name written in tables and JSON.
    pub fn name(self) -> &'static str {
        self.as_str()
    }

    /// Index in [`Purpose::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// The purpose of a look of `kind` (`confirm`, `track`, `mimo`) that holds a truth or not;
    /// `None` for `search` (which needs no geometry).
    pub fn of_look(kind: DwellKind, holds_truth: bool) -> Option<Purpose> {
        match (kind, holds_truth) {
            (DwellKind::Confirm, true) => Some(Purpose::ConfirmTrue),
            (DwellKind::Confirm, false) => Some(Purpose::ConfirmFalse),
            (DwellKind::Track | DwellKind::Mimo, true) => Some(Purpose::Track),
            (DwellKind::Track | DwellKind::Mimo, false) => Some(Purpose::TrackFalse),
            (DwellKind::Search, _) => None,
        }
    }
}

/// A radar's faces over time: face `face` at `t_s` (`None` for a face the radar does not have).
pub type FaceAt = Box<dyn Fn(f64, u8) -> Option<FaceFrame> + Send + Sync>;

struct RadarBeams {
    theta_u: f64,
    theta_v: f64,
    face_at: FaceAt,
}

/// The radars' faces and beamwidths the rule needs, by radar id. A look part of a radar or face
/// it does not know holds no truth.
#[derive(Default)]
pub struct BeamGeometry {
    radars: BTreeMap<String, RadarBeams>,
}

impl std::fmt::Debug for BeamGeometry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BeamGeometry").field("radars", &self.radars.keys().collect::<Vec<_>>()).finish()
    }
}

impl BeamGeometry {
    /// Geometry that knows no radar: every look holds no truth (for tests of the other metrics).
    pub fn none() -> BeamGeometry {
        BeamGeometry::default()
    }

    /// Add radar `radar` (`R1`, …) with `params` under pattern `model` and its faces over time.
    pub fn with_radar(mut self, radar: &str, params: &RadarParams, model: PatternModel, face_at: FaceAt) -> Self {
        let (theta_u, theta_v) = params.half_power_beamwidths(model);
        self.radars.insert(radar.to_string(), RadarBeams { theta_u, theta_v, face_at });
        self
    }

    /// Radar `radar`'s face `face` at `t_s` with its beamwidths.
    pub(crate) fn face(&self, radar: &str, face: u8, t_s: f64) -> Option<(FaceFrame, f64, f64)> {
        let r = self.radars.get(radar)?;
        Some(((r.face_at)(t_s, face)?, r.theta_u, r.theta_v))
    }
}

/// One radar's part in a look, as the rule needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LookPart {
    /// The face used, at the look's mid-time.
    pub frame: FaceFrame,
    /// Half-power beamwidths in sine space.
    pub theta_u: f64,
    /// Half-power beamwidth along v.
    pub theta_v: f64,
    /// Beam centre in the face's sine space.
    pub beam_u: f64,
    /// Beam centre, v.
    pub beam_v: f64,
    /// Whether the part receives (role `rx` or `txrx`).
    pub receives: bool,
}

impl LookPart {
    /// Is `p` (ECEF) in front of the face and inside the beam's 3 dB footprint?
    pub fn in_footprint(&self, p: DVec3) -> bool {
        let s = self.frame.to_sine(p);
        if s.w.is_nan() || s.w <= 0.0 {
            return false;
        }
        let a = 2.0 * (s.u - self.beam_u) / self.theta_u;
        let b = 2.0 * (s.v - self.beam_v) / self.theta_v;
        a * a + b * b <= 1.0
    }
}

/// Equivalent range `(‖p − t‖ + ‖p − r‖) / 2` of `p` on the channel from `tx` to `rx`.
fn rho(tx: &LookPart, rx: &LookPart, p: DVec3) -> f64 {
    0.5 * ((p - tx.frame.origin_ecef).length() + (p - rx.frame.origin_ecef).length())
}

/// Does transmitter `tx` of a look aimed at `aim` (ECEF) hold a truth at `p` (ECEF), with
/// `receivers` the look's receiving parts (see the module docs)?
pub fn holds_truth(tx: &LookPart, receivers: &[LookPart], aim: DVec3, p: DVec3) -> bool {
    tx.in_footprint(p)
        && receivers
            .iter()
            .any(|rx| rx.in_footprint(p) && (rho(tx, rx, p) - rho(tx, rx, aim)).abs() <= RANGE_WINDOW_HALF_M)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::geo::Geodetic;

    const THETA: f64 = 0.0252;

    fn part(lat: f64, lon: f64, az_deg: f64, beam_u: f64, beam_v: f64) -> LookPart {
        let frame = FaceFrame::new(Geodetic::from_deg(lat, lon, 20.0), az_deg.to_radians(), 15f64.to_radians());
        LookPart { frame, theta_u: THETA, theta_v: THETA, beam_u, beam_v, receives: true }
    }

    /// A monostatic look at (u, v) = (0.1, 0.05), aim 100 km out.
    fn mono() -> (LookPart, DVec3) {
        let p = part(36.0, -70.0, 45.0, 0.1, 0.05);
        (p, p.frame.from_ruv(100_000.0, 0.1, 0.05))
    }

    #[test]
    fn a_truth_at_the_beam_centre_and_aim_range_is_held() {
        let (tx, aim) = mono();
        assert!(holds_truth(&tx, &[tx], aim, aim));
    }

    #[test]
    fn the_footprint_edge_is_half_a_beamwidth_in_sine_space() {
        let (tx, aim) = mono();
        let at = |du: f64, dv: f64| tx.frame.from_ruv(100_000.0, 0.1 + du, 0.05 + dv);
        let h = THETA / 2.0;
        for (du, dv) in [
            (h, 0.0),
            (-h, 0.0),
            (0.0, h),
            (0.0, -h),
            (h * std::f64::consts::FRAC_1_SQRT_2, h * std::f64::consts::FRAC_1_SQRT_2),
        ] {
            assert!(holds_truth(&tx, &[tx], aim, at(0.999 * du, 0.999 * dv)), "just inside at ({du}, {dv})");
            assert!(!holds_truth(&tx, &[tx], aim, at(1.001 * du, 1.001 * dv)), "just outside at ({du}, {dv})");
        }
        // The footprint is fixed in sine space: off broadside it covers more angle, as the pattern.
        let far = part(36.0, -70.0, 45.0, 0.8, 0.0);
        let p_in = far.frame.from_ruv(100_000.0, 0.8 + 0.999 * h, 0.0);
        assert!(far.in_footprint(p_in));
    }

    #[test]
    fn the_range_window_is_a_kilometre_each_side_of_the_aim() {
        let (tx, aim) = mono();
        let at = |r: f64| tx.frame.from_ruv(r, 0.1, 0.05);
        assert!(holds_truth(&tx, &[tx], aim, at(100_000.0 + 999.0)));
        assert!(holds_truth(&tx, &[tx], aim, at(100_000.0 - 999.0)));
        assert!(!holds_truth(&tx, &[tx], aim, at(100_000.0 + 1001.0)));
        assert!(!holds_truth(&tx, &[tx], aim, at(100_000.0 - 1001.0)));
    }

    #[test]
    fn a_truth_behind_the_face_is_not_held() {
        let (tx, aim) = mono();
        // The mirror image of the beam centre through the face centre: same |u|, |v|, w < 0.
        let behind = tx.frame.origin_ecef - (aim - tx.frame.origin_ecef);
        let s = tx.frame.to_sine(behind);
        assert!(s.w < 0.0);
        assert!(!tx.in_footprint(behind));
        // With the sign of u and v flipped it would sit on the beam centre if w were ignored.
        let flipped = LookPart { beam_u: -0.1, beam_v: -0.05, ..tx };
        assert!(((s.u + 0.1).abs() < 1e-9) && ((s.v + 0.05).abs() < 1e-9));
        assert!(!flipped.in_footprint(behind));
    }

    #[test]
    fn a_mimo_part_uses_the_bistatic_range_and_both_beams() {
        use mimo_core::geo::{ecef_to_geodetic, enu_from_ecef};
        // Transmitter R1 looking north-east; receiver 150 km south-east of the aim point, looking
        // back at it, so that the bistatic angle at the aim point is near 90°.
        let tx0 = part(36.0, -70.0, 45.0, 0.0, 0.0);
        let aim = tx0.frame.from_ruv(120_000.0, 0.05, 0.03);
        let g = ecef_to_geodetic(aim);
        let se = 132f64.to_radians();
        let east_north = enu_from_ecef(g.lat_rad, g.lon_rad).transpose() * DVec3::new(se.sin(), se.cos(), 0.0);
        let site = ecef_to_geodetic(aim + east_north * 150_000.0);
        let rx_site = Geodetic { alt_m: 20.0, ..site };
        let rx_frame = FaceFrame::new(rx_site, 312f64.to_radians(), 15f64.to_radians());
        let steer = |frame: FaceFrame, receives: bool| {
            let s = frame.to_sine(aim);
            assert!(s.w > 0.5, "the aim point is in front of the face");
            LookPart { frame, theta_u: THETA, theta_v: THETA, beam_u: s.u, beam_v: s.v, receives }
        };
        let tx = steer(tx0.frame, false);
        let rx = steer(rx_frame, true);
        assert!(holds_truth(&tx, &[rx], aim, aim));
        // 1.2 km further along the transmitter's line of sight: outside a 1-km monostatic window,
        // but the bistatic ρ grows by only about 1.2 km · (1 + cos β) / 2.
        let dir = (aim - tx.frame.origin_ecef).normalize();
        let p = aim + dir * 1200.0;
        let d_rho = rho(&tx, &rx, p) - rho(&tx, &rx, aim);
        assert!(d_rho > 400.0 && d_rho < 900.0, "dρ {d_rho}");
        assert!(rx.in_footprint(p) && tx.in_footprint(p));
        assert!(holds_truth(&tx, &[rx], aim, p), "inside the bistatic window");
        let tx_rx = LookPart { receives: true, ..tx };
        assert!(!holds_truth(&tx_rx, &[tx_rx], aim, p), "outside the monostatic one");
        // Either channel may hold it: the look with both receivers does.
        assert!(holds_truth(&tx_rx, &[tx_rx, rx], aim, p));
        // Beyond the bistatic window too.
        let q = aim + dir * 2500.0;
        assert!(rho(&tx, &rx, q) - rho(&tx, &rx, aim) > RANGE_WINDOW_HALF_M);
        assert!(!holds_truth(&tx, &[rx], aim, q));
        // A receiver whose beam points elsewhere has no echo of it: no channel holds the truth.
        let rx_away = LookPart { beam_u: rx.beam_u + THETA, ..rx };
        assert!(!holds_truth(&tx, &[rx_away], aim, aim));
        // Nor does a look without receivers.
        assert!(!holds_truth(&tx, &[], aim, aim));
    }

    #[test]
    fn purposes_of_looks() {
        assert_eq!(Purpose::of_look(DwellKind::Confirm, true), Some(Purpose::ConfirmTrue));
        assert_eq!(Purpose::of_look(DwellKind::Confirm, false), Some(Purpose::ConfirmFalse));
        assert_eq!(Purpose::of_look(DwellKind::Mimo, true), Some(Purpose::Track));
        assert_eq!(Purpose::of_look(DwellKind::Track, false), Some(Purpose::TrackFalse));
        assert_eq!(Purpose::of_look(DwellKind::Search, true), None);
        let names: Vec<&str> = Purpose::ALL.iter().map(|p| p.name()).collect();
        assert_eq!(names, ["search", "confirm_true", "confirm_false", "track", "track_false"]);
        assert!(Purpose::ALL.iter().enumerate().all(|(i, p)| p.index() == i));
    }
}
