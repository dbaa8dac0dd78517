//! Which targets each Tx→Rx channel of a dwell sees, and how strongly (docs/model.md §3, §5.2):
//! a target is kept only if it is in front of both faces, above both radars' 4/3-earth horizons,
//! within the bistatic-angle limit and above the pattern and SNR floors of [`crate::dwell`]; the
//! rest is never looked at again.

use crate::dwell::{Dwell, KEY_RCS, PATTERN_FLOOR, Return, SNR_FLOOR, Target, stream};
use crate::equation::snr1;
use crate::fluctuation::draw_zeta;
use crate::geometry::{bistatic, height_m, refracted_direction, visible_with_heights};
use crate::pattern::{Antenna, Gains};
use crate::polarization::{draw_scattering, effective_voltage, jones_in_target_basis, mean_rcs_m2};
use mimo_core::face::FaceFrame;
use mimo_core::geo::{height_lower_bound_m, surely_visible_effective_earth};
use mimo_core::polarimetry::Polarimetry;
use num_complex::Complex64;

/// How one radar face sees one target.
#[derive(Debug, Clone, Copy)]
struct Look {
    range_m: f64,
    u: f64,
    v: f64,
    gains: Gains,
}

/// Lazily computed heights above the ellipsoid.
struct Heights {
    targets: Vec<Option<f64>>,
}

impl Heights {
    fn target(&mut self, targets: &[Target], t: usize) -> f64 {
        *self.targets[t].get_or_insert_with(|| height_m(targets[t].pos_ecef))
    }
}

/// How a face steered at `(bu, bv)` sees each target (None: behind, beyond the pattern floor or
/// below the horizon).
fn looks(
    frame: &FaceFrame,
    ant: &Antenna,
    bu: f64,
    bv: f64,
    targets: &[Target],
    heights: &mut Heights,
    refraction: bool,
) -> Vec<Option<Look>> {
    let mut site_h: Option<f64> = None;
    let mut site_lo: Option<f64> = None;
    let mut out = Vec::with_capacity(targets.len());
    for (t, tg) in targets.iter().enumerate() {
        let s = frame.to_sine(tg.pos_ecef);
        let (u, v, w) = if refraction {
            let d = frame.face_from_ecef * refracted_direction(frame.origin_ecef, tg.pos_ecef);
            (d.x, d.y, d.z)
        } else {
            (s.u, s.v, s.w)
        };
        if !(w > 0.0 && s.range_m > 0.0) {
            out.push(None);
            continue;
        }
        let g = ant.gains(u - bu, v - bv);
        let p = g.sum * g.sum;
        let pmax = p.max(g.az * g.az).max(g.el * g.el);
        if pmax < PATTERN_FLOOR {
            out.push(None);
            continue;
        }
        // Cheap lower bounds of the heights settle most horizon tests; the heights themselves
        // (an iterative ECEF → geodetic conversion each) only the rest, with the same answer.
        let surely = surely_visible_effective_earth(
            frame.origin_ecef,
            *site_lo.get_or_insert_with(|| height_lower_bound_m(frame.origin_ecef)),
            tg.pos_ecef,
            height_lower_bound_m(tg.pos_ecef),
        );
        if !surely
            && !visible_with_heights(
                frame.origin_ecef,
                *site_h.get_or_insert_with(|| height_m(frame.origin_ecef)),
                tg.pos_ecef,
                heights.target(targets, t),
            )
        {
            out.push(None);
            continue;
        }
        out.push(Some(Look { range_m: s.range_m, u, v, gains: g }));
    }
    out
}

/// The returns of every target in every channel, indexed `[tx][rx]`.
pub(crate) fn all_returns(d: &Dwell, targets: &[Target]) -> Vec<Vec<Vec<Return>>> {
    let fid = d.fidelity;
    let mut heights = Heights { targets: vec![None; targets.len()] };
    let tx_looks: Vec<Vec<Option<Look>>> = d
        .transmitters
        .iter()
        .map(|tx| {
            let ant = Antenna::new(tx.params, fid.pattern);
            looks(&tx.frame, &ant, tx.beam_u, tx.beam_v, targets, &mut heights, fid.refraction)
        })
        .collect();
    let rx_looks = receiver_looks(d, &tx_looks, targets, &mut heights);
    let mut out = Vec::with_capacity(d.transmitters.len());
    for (j, tx_j) in tx_looks.iter().enumerate() {
        let mut per_rx = Vec::with_capacity(d.receivers.len());
        for (i, rx_i) in rx_looks.iter().enumerate() {
            let mut rets = Vec::new();
            for (t, tg) in targets.iter().enumerate() {
                let (Some(lt), Some(lr)) = (tx_j[t], rx_i[t]) else { continue };
                if let Some(r) = target_return(d, (j, i), (t, tg), (lt, lr)) {
                    rets.push(r);
                }
            }
            per_rx.push(rets);
        }
        out.push(per_rx);
    }
    out
}

/// Each receiver's looks at the targets. A receiver that is also a transmitter with the same face
/// and beam (every monostatic dwell, so every search dwell) sees the targets exactly as that
/// transmitter does: its looks are copied, not recomputed (the same function of the same inputs,
/// so the same values).
fn receiver_looks(
    d: &Dwell,
    tx_looks: &[Vec<Option<Look>>],
    targets: &[Target],
    heights: &mut Heights,
) -> Vec<Vec<Option<Look>>> {
    let fid = d.fidelity;
    d.receivers
        .iter()
        .map(|rx| {
            let same = d.transmitters.iter().position(|tx| {
                tx.radar == rx.radar
                    && std::ptr::eq(tx.params, rx.params)
                    && tx.frame == rx.frame
                    && tx.beam_u == rx.beam_u
                    && tx.beam_v == rx.beam_v
            });
            match same {
                Some(j) => tx_looks[j].clone(),
                None => {
                    let ant = Antenna::new(rx.params, fid.pattern);
                    looks(&rx.frame, &ant, rx.beam_u, rx.beam_v, targets, heights, fid.refraction)
                }
            }
        })
        .collect()
}

/// The return of target `t` in channel `(j → i)`, seen by the transmitter's look `lt` and the
/// receiver's look `lr`; `None` when a floor drops it or its geometry or RCS is unusable.
fn target_return(
    d: &Dwell,
    (j, i): (usize, usize),
    (t, tg): (usize, &Target),
    (lt, lr): (Look, Look),
) -> Option<Return> {
    let fid = d.fidelity;
    let (tx, rx) = (&d.transmitters[j], &d.receivers[i]);
    let w_tx = (1.0 - tx.beam_u * tx.beam_u - tx.beam_v * tx.beam_v).max(0.0).sqrt();
    let w_rx = (1.0 - rx.beam_u * rx.beam_u - rx.beam_v * rx.beam_v).max(0.0).sqrt();
    let lambda = tx.params.wavelength_m();
    let gt = lt.gains.sum;
    let gr = lr.gains;
    let rx_pow = (gr.sum * gr.sum).max(gr.az * gr.az).max(gr.el * gr.el);
    let pattern = gt * gt * rx_pow;
    if pattern < PATTERN_FLOOR {
        return None;
    }
    let geo = bistatic(tx.frame.origin_ecef, rx.frame.origin_ecef, tg.pos_ecef);
    if !geo.usable() {
        return None;
    }
    if !(tg.rcs_m2 > 0.0 && tg.rcs_m2.is_finite()) {
        return None;
    }
    // With polarization (§3.5) the pair sees the mean RCS of its polarizations, and the
    // echo is the scattering-matrix voltage normalized to unit mean power.
    let polar = fid.polarization.then(|| {
        let pm = tg.pol.unwrap_or_else(|| Polarimetry::default_for(tg.rcs_m2));
        let f = jones_in_target_basis(tx.params.tx_polarization_deg, pm.rotation_deg);
        let g = jones_in_target_basis(rx.params.rx_polarization_deg, pm.rotation_deg);
        let mono = tx.radar == rx.radar;
        (pm, f, g, mono, mean_rcs_m2(&pm, mono, g, f))
    });
    let rcs_m2 = polar.map_or(tg.rcs_m2, |p| p.4);
    if rcs_m2.is_nan() || rcs_m2 <= 0.0 {
        return None;
    }
    let peak = f64::from(tx.n_pulses) * snr1(tx.params, rx.params, w_tx, w_rx, rcs_m2, lt.range_m, lr.range_m);
    if (peak * pattern).is_nan() || peak * pattern < SNR_FLOOR {
        return None;
    }
    let mut s = stream(d, &[KEY_RCS, tx.radar.0 as u64, rx.radar.0 as u64, u64::from(tg.index)]);
    let zeta = match polar {
        Some((pm, f, g, mono, mean)) => effective_voltage(&draw_scattering(&pm, mono, &mut s), g, f) / mean.sqrt(),
        None => draw_zeta(fid.swerling, &mut s),
    };
    let carrier = Complex64::from_polar(1.0, -std::f64::consts::TAU * (geo.r_b_m / lambda).fract());
    let a = zeta * carrier * (peak.sqrt() * gt);
    let (eta_a, eta_e) = if gr.sum != 0.0 { (gr.az / gr.sum, gr.el / gr.sum) } else { (0.0, 0.0) };
    Some(Return {
        target: t,
        rho_m: geo.rho_m(),
        geometry: geo,
        peak_snr: peak,
        pattern_power: gt * gt * gr.sum * gr.sum,
        u: lr.u,
        v: lr.v,
        eta_a,
        eta_e,
        sum: a * gr.sum,
        az: a * gr.az,
        el: a * gr.el,
    })
}
