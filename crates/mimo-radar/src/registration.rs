//! Registration biases as a real radar carries them (docs/model.md §5.5).
//!
//! The simulated face frames are the frames the radars (and the test article) believe in. A
//! radar with biases `b` measures in a physical frame that differs: the direction it reports for
//! a physical direction cosine pair `(u, v)` is `(u + b_u, v + b_v)`, then turned clockwise about
//! the local vertical by the heading bias `b_ψ` ([`reported_direction`]); it steers a beam it
//! believes at `(u_b, v_b)` along the inverse ([`physical_beam`]). A range sum carries both
//! radars' range biases (`ρ' = ρ + (b_r,tx + b_r,rx)/2`). The reported variances are unchanged.

use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::ids::RadarId;
use mimo_core::records::PrimitiveRow;
use mimo_core::registration::RadarBias;

/// WGS-84 semi-major axis (m) and first eccentricity squared (docs/model.md §1.1).
const A_M: f64 = 6_378_137.0;
const E2: f64 = 6.694_379_990_141_317e-3;

/// The local vertical at a face's centre, written in the face frame: the ellipsoid normal, whose
/// direction at the array's few metres of height differs from the surface point's by < 1e-8 rad.
pub fn up_in_face(frame: &FaceFrame) -> DVec3 {
    let p = frame.origin_ecef;
    let b2 = A_M * A_M * (1.0 - E2);
    let normal = DVec3::new(p.x / (A_M * A_M), p.y / (A_M * A_M), p.z / b2).normalize();
    frame.face_from_ecef * normal
}

/// `d` turned by `angle_rad` about the unit axis `k` (right-handed, Rodrigues).
fn rotate(d: DVec3, k: DVec3, angle_rad: f64) -> DVec3 {
    let (s, c) = angle_rad.sin_cos();
    d * c + k.cross(d) * s + k * (k.dot(d) * (1.0 - c))
}

/// The unit vector of direction cosines `(u, v)` in front of the face, if there is one.
fn front(u: f64, v: f64) -> Option<DVec3> {
    let q = 1.0 - u * u - v * v;
    (q > 0.0).then(|| DVec3::new(u, v, q.sqrt()))
}

/// The direction a radar with biases `b` reports for the physical direction cosines `(u, v)` of
/// a face whose local vertical is `up_face`: `None` when the biased direction leaves the front
/// of the face (only for biases far beyond the bounds' typical use).
pub fn reported_direction(u: f64, v: f64, up_face: DVec3, b: &RadarBias) -> Option<(f64, f64)> {
    let d = front(u + b.u, v + b.v)?;
    // Clockwise seen from above (azimuth grows) is a negative right-handed turn about the up axis.
    let r = rotate(d, up_face, -b.heading_deg.to_radians());
    (r.z > 0.0).then_some((r.x, r.y))
}

/// Where a radar with biases `b` physically points a beam it believes steered at `(u_b, v_b)`:
/// the inverse of [`reported_direction`], so that a target the radar reports at the beam centre
/// is at its physical centre. The believed direction is kept if the inverse leaves the face.
pub fn physical_beam(u_b: f64, v_b: f64, up_face: DVec3, b: &RadarBias) -> (f64, f64) {
    let Some(d) = front(u_b, v_b) else { return (u_b, v_b) };
    let r = rotate(d, up_face, b.heading_deg.to_radians());
    let (u, v) = (r.x - b.u, r.y - b.v);
    if r.z > 0.0 && u * u + v * v < 1.0 { (u, v) } else { (u_b, v_b) }
}

/// Give a dwell's primitives the biases of their radars: each range the mean of its transmitter's
/// and receiver's range biases, each direction the receiver's angle and heading biases
/// ([`reported_direction`]; `up_face(rx, face)` is the receiving face's vertical). A primitive
/// whose biased direction leaves its face is dropped.
pub fn bias_primitives(
    primitives: &mut Vec<PrimitiveRow>,
    biases: &[RadarBias],
    up_face: impl Fn(RadarId, u8) -> Option<DVec3>,
) {
    let zero = RadarBias::default();
    let of = |r: RadarId| biases.get(r.index()).unwrap_or(&zero);
    primitives.retain_mut(|p| {
        let (tx, rx) = (of(p.tx), of(p.rx));
        p.range_m += 0.5 * (tx.range_m + rx.range_m);
        let Some(up) = up_face(p.rx, p.rx_face) else { return true };
        match reported_direction(p.u, p.v, up, rx) {
            Some((u, v)) => {
                (p.u, p.v) = (u, v);
                true
            }
            None => false,
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::geo::Geodetic;

    fn face() -> FaceFrame {
        FaceFrame::new(Geodetic::from_deg(43.0, 7.0, 20.0), 45f64.to_radians(), 15f64.to_radians())
    }

    #[test]
    fn heading_bias_turns_a_target_clockwise_by_the_bias() {
        // A target 100 km out at azimuth 60° (east of the 45° boresight), on the horizon plane.
        let f = face();
        let site = Geodetic::from_deg(43.0, 7.0, 20.0);
        let enu_to_ecef = mimo_core::geo::enu_from_ecef(site.lat_rad, site.lon_rad).transpose();
        let at = |az_deg: f64| {
            let a = f64::to_radians(az_deg);
            f.to_sine(f.origin_ecef + enu_to_ecef * DVec3::new(a.sin(), a.cos(), 0.05) * 1e5)
        };
        let (t, want) = (at(60.0), at(60.5));
        let b = RadarBias { heading_deg: 0.5, ..RadarBias::default() };
        let (u, v) = reported_direction(t.u, t.v, up_in_face(&f), &b).expect("in front");
        // Within 1e-9 (a micro-radian's thousandth): the ECEF round trip at 100 km leaves ~1e-10.
        assert!((u - want.u).abs() < 1e-9 && (v - want.v).abs() < 1e-9, "{u} {v} vs {want:?}");
        // And the turn is the bias, not nothing: half a degree moves u by ~4e-3.
        assert!((u - t.u).abs() > 1e-3, "{u} vs {}", t.u);
    }

    #[test]
    fn physical_beam_inverts_the_reported_direction() {
        let up = up_in_face(&face());
        let b = RadarBias { range_m: 5.0, u: 2e-3, v: -1e-3, heading_deg: -0.3 };
        for (ub, vb) in [(0.0, 0.0), (0.5, -0.2), (-0.6, 0.4)] {
            let (pu, pv) = physical_beam(ub, vb, up, &b);
            let (u, v) = reported_direction(pu, pv, up, &b).expect("in front");
            assert!((u - ub).abs() < 1e-13 && (v - vb).abs() < 1e-13);
        }
    }

    #[test]
    fn a_bistatic_range_carries_half_of_both_radars_range_bias() {
        let p = PrimitiveRow {
            run: 0,
            dwell_id: 0,
            t_s: 0.0,
            rx: RadarId(1),
            tx: RadarId(0),
            rx_face: 0,
            range_cell: 0,
            range_m: 50_000.0,
            u: 0.1,
            v: 0.2,
            snr_db: 20.0,
            eta_q: 0.0,
            merged: false,
            beam_u: 0.1,
            beam_v: 0.2,
            var_range_m2: 1.0,
            var_u: 1e-6,
            var_v: 1e-6,
            target_hint: None,
        };
        let biases = [
            RadarBias { range_m: 10.0, u: 0.5, ..RadarBias::default() },
            RadarBias { range_m: 30.0, u: 1e-3, ..RadarBias::default() },
        ];
        let mut ps = vec![p];
        bias_primitives(&mut ps, &biases, |_, _| Some(DVec3::new(0.0, 1.0, 0.0)));
        // ρ + (10 + 30)/2; u carries the receiver's bias only, not the transmitter's 0.5.
        assert_eq!(ps[0].range_m, 50_020.0);
        assert!((ps[0].u - 0.101).abs() < 1e-15 && ps[0].v == 0.2);
        assert_eq!(ps[0].var_range_m2, 1.0);
    }
}
