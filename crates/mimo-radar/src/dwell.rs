//! Dwell evaluation: complex monopulse voltages per Tx→Rx channel and range cell, and their
//! detection (docs/model.md §2.4, §3, §4.2–§4.4, §5.2, §5.3).
//!
//! A dwell has one or more transmitters (each with its own orthogonal waveform) and one or more
//! receivers; receiver `i` runs one matched filter per transmitter `j`, giving the channel
//! `(j → i)`. A monostatic dwell is one radar in both lists.
//!
//! Cost follows targets, not cells:
//! * a target is evaluated in a channel only if it is in front of both faces, above both radars'
//!   4/3-earth horizons, the bistatic angle is at most 150°, its two-way pattern power is at least
//!   [`PATTERN_FLOOR`] of the peak and its pattern-weighted mean SNR at least [`SNR_FLOOR`]
//!   (−10 dB); everything else is never looked at again;
//! * cells within `±W` (`fidelity.explicit_cells_each_side`) of each target return are simulated
//!   explicitly: noise `CN(0,1)` in Σ, Δa, Δe plus the triangle-weighted target voltages, several
//!   targets adding as voltages (§2.7);
//! * the remaining `M` noise-only cells of the receiver's window are handled by the §4.4 shortcut:
//!   `K ~ Binomial(M, P_FA)` distinct cells chosen uniformly, `|Σ|² = γ + Exp(1)` with uniform
//!   phase, `Δa, Δe ~ CN(0,1)`, and their two neighbours drawn as noise *conditioned below γ*
//!   (exactly the distribution of a non-crossing noise cell), so detection works the same way on
//!   false alarms as on targets;
//! * voltages are turned into [`VoltageRow`]s only when `record_voltages` is set. They then hold the
//!   simulated cells only; all other cells of the window are noise below threshold.
//!
//! Random draws come from streams keyed by the dwell's `(seed, keys…)` plus (purpose, tx radar,
//! rx radar[, target]): a target's fluctuation on a pair never depends on the other targets, and
//! channels have independent noise (ideal orthogonality). With `fidelity.waveform_isolation_db =
//! Some(I)`, every other transmitter's echoes leak into a channel as noise-like `CN` terms of
//! per-cell power `|Σ_{ij',t}|²·10^{−I/10}` (and likewise in Δa, Δe) over `±τc/2` of the target's
//! `ρ` (§5.3); leakage below 1e-3 of the noise power is ignored.

use crate::detect::{Cell, ChannelInfo, Source, detect};
use crate::equation::snr1;
use crate::fluctuation::draw_zeta;
use crate::geometry::{Bistatic, bistatic, height_m, refracted_direction, visible_with_heights};
use crate::pattern::{Antenna, Gains};
use crate::range::{cell_window, triangle};
use mimo_core::face::FaceFrame;
use mimo_core::ids::RadarId;
use mimo_core::params::{Fidelity, RadarParams};
use mimo_core::records::{PrimitiveRow, VoltageRow};
use mimo_core::rng::{Stream, domain};
use mimo_core::{DVec3, SPEED_OF_LIGHT_MPS, db_to_lin};
use num_complex::Complex64;
use std::collections::BTreeSet;

/// Two-way pattern power (relative to the peak) below which a target is not evaluated.
pub const PATTERN_FLOOR: f64 = 1e-4;
/// Pattern-weighted mean SNR (linear, −10 dB) below which a target is not evaluated.
pub const SNR_FLOOR: f64 = 0.1;
/// Leakage power (relative to the noise) below which waveform leakage is ignored.
pub const LEAKAGE_FLOOR: f64 = 1e-3;

/// Sub-keys appended to the dwell's stream keys.
const KEY_NOISE: u64 = domain::DWELL;
const KEY_RCS: u64 = domain::RCS;
const KEY_FALSE_ALARM: u64 = domain::FALSE_ALARM;
const KEY_LEAKAGE: u64 = 0x4C45_414B;

/// A transmitter of the dwell.
#[derive(Debug, Clone, Copy)]
pub struct Transmitter<'a> {
    pub radar: RadarId,
    pub params: &'a RadarParams,
    /// The transmitting face; its origin is the array centre (site) position.
    pub frame: FaceFrame,
    /// Beam steering direction in the face's sine space.
    pub beam_u: f64,
    pub beam_v: f64,
    /// Pulses coherently integrated (SNR = `n_pulses · SNR₁`; 0 transmits nothing).
    pub n_pulses: u32,
    /// Orthogonal waveform index (informational: channels are told apart by transmitter).
    pub waveform: u32,
}

/// A receiver of the dwell.
#[derive(Debug, Clone, Copy)]
pub struct Receiver<'a> {
    pub radar: RadarId,
    /// The receiver's dwell part id: primitives and voltages carry it.
    pub dwell_id: u64,
    pub params: &'a RadarParams,
    /// Receiving face index (reported in the primitives) and its frame.
    pub face: u8,
    pub frame: FaceFrame,
    /// Σ/Δ beam steering direction in the face's sine space.
    pub beam_u: f64,
    pub beam_v: f64,
    /// Range window of the receiver's channels (§4.4, §5.2).
    pub window: RangeWindow,
    /// The scheduler's predicted mean SNR (linear, summed over the cells used) of the return this
    /// dwell aims at, for the ML monopulse bias factor (§2.5). `None` for search dwells.
    pub predicted_snr: Option<f64>,
}

/// The range window a receiver processes, in equivalent monostatic range `ρ = R_B/2`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RangeWindow {
    /// The same `[ρ_min, ρ_max]` (m) in every channel: search dwells use the whole instrumented
    /// range.
    Fixed { rho_min_m: f64, rho_max_m: f64 },
    /// Per channel `(j → i)`: `ρ_ji(aim) ± half_width_m`, with `ρ_ji` the equivalent range of the
    /// aim point for that transmitter and this receiver (§5.2: track and MIMO dwells use
    /// `half_width = max(5σ_ρ, 1 km)`).
    AroundAim { aim_ecef: DVec3, half_width_m: f64 },
}

impl RangeWindow {
    /// `[ρ_min, ρ_max]` of the channel from a transmitter at `tx` to a receiver at `rx` (ECEF).
    pub fn limits(&self, tx: DVec3, rx: DVec3) -> (f64, f64) {
        match *self {
            RangeWindow::Fixed { rho_min_m, rho_max_m } => (rho_min_m, rho_max_m),
            RangeWindow::AroundAim { aim_ecef, half_width_m } => {
                let rho = 0.5 * ((aim_ecef - tx).length() + (aim_ecef - rx).length());
                (rho - half_width_m, rho + half_width_m)
            }
        }
    }
}

/// A target at the dwell mid-time.
#[derive(Debug, Clone, Copy)]
pub struct Target<'a> {
    /// Truth id, copied into `target_hint`.
    pub id: &'a str,
    /// Stable index of the target in the scenario (keys its fluctuation stream).
    pub index: u32,
    pub pos_ecef: DVec3,
    /// Mean RCS `σ̄` (m²).
    pub rcs_m2: f64,
}

/// One dwell to evaluate.
#[derive(Debug, Clone, Copy)]
pub struct Dwell<'a> {
    pub run: u32,
    /// Time stamped on the primitives (s).
    pub t_s: f64,
    /// Stream seed and keys of this dwell, e.g. `[run, group_id]`; they must differ between dwells.
    pub seed: u64,
    pub keys: &'a [u64],
    pub transmitters: &'a [Transmitter<'a>],
    pub receivers: &'a [Receiver<'a>],
    pub fidelity: &'a Fidelity,
    /// Materialize [`VoltageRow`]s.
    pub record_voltages: bool,
    /// Simulate every cell of the window explicitly instead of the §4.4 shortcut (reference mode
    /// for tests and full voltage recordings; cost grows with the window).
    pub simulate_all_cells: bool,
}

/// A target's return in one channel, before noise and range sampling.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Return {
    /// Index into the dwell's target slice.
    pub target: usize,
    /// Equivalent monostatic range `ρ = R_B/2` (m).
    pub rho_m: f64,
    /// Bistatic geometry.
    pub geometry: Bistatic,
    /// Mean SNR at the beam peak, `N_p·SNR₁` with scan loss (linear, no pattern, no straddle).
    pub peak_snr: f64,
    /// Two-way pattern power `g_Σtx² g_Σrx²`.
    pub pattern_power: f64,
    /// True receive direction cosines of the target and the noise-free monopulse ratios.
    pub u: f64,
    pub v: f64,
    pub eta_a: f64,
    pub eta_e: f64,
    /// Complex amplitudes (fluctuation included) of Σ, Δa, Δe before the range response.
    pub sum: Complex64,
    pub az: Complex64,
    pub el: Complex64,
}

/// One Tx→Rx channel's simulated samples.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    /// Indices into the dwell's transmitter and receiver slices.
    pub tx: usize,
    pub rx: usize,
    /// Cell window `[k_min, k_max]`, `None` if empty.
    pub window: Option<(i64, i64)>,
    /// Simulated cells, sorted by index.
    pub cells: Vec<Cell>,
    /// Target returns evaluated in this channel.
    pub returns: Vec<Return>,
    /// Cells of the window handled by the false-alarm shortcut.
    pub shortcut_cells: u64,
    /// False alarms drawn by the shortcut.
    pub false_alarms: u64,
}

/// Everything a dwell produces.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DwellOutput {
    pub channels: Vec<Channel>,
    pub primitives: Vec<PrimitiveRow>,
    /// Empty unless `record_voltages`.
    pub voltages: Vec<VoltageRow>,
}

/// How one radar face sees one target.
#[derive(Debug, Clone, Copy)]
struct Look {
    range_m: f64,
    u: f64,
    v: f64,
    gains: Gains,
}

fn stream(d: &Dwell, extra: &[u64]) -> Stream {
    // The keys on the stack when they fit (every dwell does): no heap allocation per stream.
    let n = d.keys.len() + extra.len();
    let mut buf = [0u64; 12];
    if n <= buf.len() {
        buf[..d.keys.len()].copy_from_slice(d.keys);
        buf[d.keys.len()..n].copy_from_slice(extra);
        return Stream::new(d.seed, &buf[..n]);
    }
    let mut k = Vec::with_capacity(n);
    k.extend_from_slice(d.keys);
    k.extend_from_slice(extra);
    Stream::new(d.seed, &k)
}

fn cn(s: &mut Stream) -> Complex64 {
    let (re, im) = s.cn01();
    Complex64::new(re, im)
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
        let hs = *site_h.get_or_insert_with(|| height_m(frame.origin_ecef));
        let ht = heights.target(targets, t);
        if !visible_with_heights(frame.origin_ecef, hs, tg.pos_ecef, ht) {
            out.push(None);
            continue;
        }
        out.push(Some(Look { range_m: s.range_m, u, v, gains: g }));
    }
    out
}

/// The returns of every target in every channel, indexed `[tx][rx]`.
fn all_returns(d: &Dwell, targets: &[Target]) -> Vec<Vec<Vec<Return>>> {
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
    // A receiver that is also a transmitter with the same face and beam (every monostatic dwell,
    // so every search dwell) sees the targets exactly as that transmitter does: its looks are
    // copied, not recomputed (the same function of the same inputs, so the same values).
    let rx_looks: Vec<Vec<Option<Look>>> = d
        .receivers
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
                    looks(&rx.frame, &ant, rx.beam_u, rx.beam_v, targets, &mut heights, fid.refraction)
                }
            }
        })
        .collect();
    let mut out = Vec::with_capacity(d.transmitters.len());
    for (j, tx) in d.transmitters.iter().enumerate() {
        let w_tx = (1.0 - tx.beam_u * tx.beam_u - tx.beam_v * tx.beam_v).max(0.0).sqrt();
        let lambda = tx.params.wavelength_m();
        let mut per_rx = Vec::with_capacity(d.receivers.len());
        for (i, rx) in d.receivers.iter().enumerate() {
            let w_rx = (1.0 - rx.beam_u * rx.beam_u - rx.beam_v * rx.beam_v).max(0.0).sqrt();
            let mut rets = Vec::new();
            for (t, tg) in targets.iter().enumerate() {
                let (Some(lt), Some(lr)) = (tx_looks[j][t], rx_looks[i][t]) else { continue };
                let gt = lt.gains.sum;
                let gr = lr.gains;
                let rx_pow = (gr.sum * gr.sum).max(gr.az * gr.az).max(gr.el * gr.el);
                let pattern = gt * gt * rx_pow;
                if pattern < PATTERN_FLOOR {
                    continue;
                }
                let geo = bistatic(tx.frame.origin_ecef, rx.frame.origin_ecef, tg.pos_ecef);
                if !geo.usable() {
                    continue;
                }
                if !(tg.rcs_m2 > 0.0 && tg.rcs_m2.is_finite()) {
                    continue;
                }
                let peak =
                    f64::from(tx.n_pulses) * snr1(tx.params, rx.params, w_tx, w_rx, tg.rcs_m2, lt.range_m, lr.range_m);
                if (peak * pattern).is_nan() || peak * pattern < SNR_FLOOR {
                    continue;
                }
                let mut s = stream(d, &[KEY_RCS, tx.radar.0 as u64, rx.radar.0 as u64, u64::from(tg.index)]);
                let zeta = draw_zeta(fid.swerling, &mut s);
                let carrier = Complex64::from_polar(1.0, -std::f64::consts::TAU * (geo.r_b_m / lambda).fract());
                let a = zeta * carrier * (peak.sqrt() * gt);
                let (eta_a, eta_e) = if gr.sum != 0.0 { (gr.az / gr.sum, gr.el / gr.sum) } else { (0.0, 0.0) };
                rets.push(Return {
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
                });
            }
            per_rx.push(rets);
        }
        out.push(per_rx);
    }
    out
}

/// Merge closed integers intervals (sorted output, disjoint, non-adjacent merged too).
fn merge_intervals(mut iv: Vec<(i64, i64)>) -> Vec<(i64, i64)> {
    iv.sort_unstable();
    let mut out: Vec<(i64, i64)> = Vec::with_capacity(iv.len());
    for (a, b) in iv {
        match out.last_mut() {
            Some(last) if a <= last.1 + 1 => last.1 = last.1.max(b),
            _ => out.push((a, b)),
        }
    }
    out
}

fn in_segments(segs: &[(i64, i64)], k: i64) -> bool {
    let i = segs.partition_point(|&(_, b)| b < k);
    i < segs.len() && segs[i].0 <= k
}

fn add_source(c: &mut Cell, target: usize, power: f64) {
    if c.source.is_none_or(|s| power > s.power) {
        c.source = Some(Source { target, power });
    }
}

/// Simulate one channel's cells.
fn simulate_channel(d: &Dwell, j: usize, i: usize, returns: &[Vec<Vec<Return>>]) -> Channel {
    let tx = &d.transmitters[j];
    let rx = &d.receivers[i];
    let dr = rx.params.range_cell_m();
    let rets = &returns[j][i];
    let (lo, hi) = rx.window.limits(tx.frame.origin_ecef, rx.frame.origin_ecef);
    let window = cell_window(lo, hi, dr);
    let mut ch =
        Channel { tx: j, rx: i, window, cells: Vec::new(), returns: rets.clone(), shortcut_cells: 0, false_alarms: 0 };
    let Some((kmin, kmax)) = window else { return ch };
    let w = i64::from(d.fidelity.explicit_cells_each_side);

    // Leakage from the other transmitters' echoes (§5.3).
    struct Leak {
        target: usize,
        k0: i64,
        k1: i64,
        sd: [f64; 3],
        tx: RadarId,
    }
    let mut leaks = Vec::new();
    if let Some(iso_db) = d.fidelity.waveform_isolation_db {
        let f = db_to_lin(-iso_db);
        for (jj, other) in d.transmitters.iter().enumerate() {
            if jj == j {
                continue;
            }
            let half = other.params.pulse_width_s * SPEED_OF_LIGHT_MPS / 2.0;
            for r in &returns[jj][i] {
                let p = [r.sum.norm_sqr() * f, r.az.norm_sqr() * f, r.el.norm_sqr() * f];
                if p.iter().all(|&x| x < LEAKAGE_FLOOR) {
                    continue;
                }
                let k0 = (((r.rho_m - half) / dr).floor() as i64).max(kmin);
                let k1 = (((r.rho_m + half) / dr).ceil() as i64).min(kmax);
                if k0 <= k1 {
                    leaks.push(Leak { target: r.target, k0, k1, sd: p.map(f64::sqrt), tx: other.radar });
                }
            }
        }
    }

    let mut iv = Vec::with_capacity(rets.len() + leaks.len());
    if d.simulate_all_cells {
        iv.push((kmin, kmax));
    } else {
        for r in rets {
            let k0 = (r.rho_m / dr).floor() as i64;
            let (a, b) = ((k0 - w).max(kmin), (k0 + 1 + w).min(kmax));
            if a <= b {
                iv.push((a, b));
            }
        }
        for l in &leaks {
            iv.push((l.k0, l.k1));
        }
    }
    let segs = merge_intervals(iv);

    // Noise in the explicit cells.
    let mut noise = stream(d, &[KEY_NOISE, tx.radar.0 as u64, rx.radar.0 as u64]);
    let explicit: i64 = segs.iter().map(|&(a, b)| b - a + 1).sum();
    let mut cells = Vec::with_capacity(explicit as usize + 8);
    for &(a, b) in &segs {
        for k in a..=b {
            cells.push(Cell { k, sum: cn(&mut noise), az: cn(&mut noise), el: cn(&mut noise), source: None });
        }
    }
    // Target voltages (§4.2): triangle-weighted, several targets add as voltages.
    for r in rets {
        let k0 = (r.rho_m / dr).floor() as i64;
        for k in [k0, k0 + 1] {
            let p = triangle(k as f64 * dr - r.rho_m, dr);
            if p <= 0.0 {
                continue;
            }
            if let Ok(idx) = cells.binary_search_by_key(&k, |c| c.k) {
                let c = &mut cells[idx];
                c.sum += r.sum * p;
                c.az += r.az * p;
                c.el += r.el * p;
                add_source(c, r.target, r.sum.norm_sqr() * p * p);
            }
        }
    }
    for l in &leaks {
        let mut s = stream(d, &[KEY_LEAKAGE, tx.radar.0 as u64, rx.radar.0 as u64, l.tx.0 as u64, l.target as u64]);
        for k in l.k0..=l.k1 {
            if let Ok(idx) = cells.binary_search_by_key(&k, |c| c.k) {
                let c = &mut cells[idx];
                c.sum += cn(&mut s) * l.sd[0];
                c.az += cn(&mut s) * l.sd[1];
                c.el += cn(&mut s) * l.sd[2];
                add_source(c, l.target, l.sd[0] * l.sd[0]);
            }
        }
    }

    // False alarms in the remaining noise-only cells (§4.4).
    if !d.simulate_all_cells {
        let m = (kmax - kmin + 1 - explicit).max(0) as u64;
        ch.shortcut_cells = m;
        let mut fa = stream(d, &[KEY_FALSE_ALARM, tx.radar.0 as u64, rx.radar.0 as u64]);
        let n_fa = fa.binomial(m, rx.params.pfa);
        ch.false_alarms = n_fa;
        if n_fa > 0 {
            let gamma = rx.params.threshold();
            // Floyd's algorithm: n_fa distinct uniform indices in [0, m).
            let mut chosen: BTreeSet<u64> = BTreeSet::new();
            for top in (m - n_fa)..m {
                let t = fa.below(top + 1);
                if !chosen.insert(t) {
                    chosen.insert(top);
                }
            }
            // Map to cell indices (ascending), skipping the explicit segments.
            let fa_cells: Vec<i64> = chosen
                .iter()
                .map(|&p| {
                    let mut k = kmin + p as i64;
                    for &(a, b) in &segs {
                        if k >= a {
                            k += b - a + 1;
                        } else {
                            break;
                        }
                    }
                    k
                })
                .collect();
            let below = 1.0 - (-gamma).exp();
            let mut taken: BTreeSet<i64> = fa_cells.iter().copied().collect();
            let mut extra: Vec<Cell> = Vec::with_capacity(3 * fa_cells.len());
            for &k in &fa_cells {
                let amp = (gamma + fa.exp1()).sqrt();
                let sum = Complex64::from_polar(amp, fa.phase());
                extra.push(Cell { k, sum, az: cn(&mut fa), el: cn(&mut fa), source: None });
            }
            for &k in &fa_cells {
                for n in [k - 1, k + 1] {
                    if n < kmin || n > kmax || in_segments(&segs, n) || !taken.insert(n) {
                        continue;
                    }
                    // Noise conditioned below threshold: |Σ|² ~ Exp(1) truncated to [0, γ).
                    let p2 = -(1.0 - fa.uniform() * below).ln();
                    let sum = Complex64::from_polar(p2.sqrt(), fa.phase());
                    extra.push(Cell { k: n, sum, az: cn(&mut fa), el: cn(&mut fa), source: None });
                }
            }
            cells.extend(extra);
            cells.sort_unstable_by_key(|c| c.k);
        }
    }
    ch.cells = cells;
    ch
}

/// Simulate every channel of a dwell (no detection).
pub fn simulate(d: &Dwell, targets: &[Target]) -> Vec<Channel> {
    let returns = all_returns(d, targets);
    let mut out = Vec::with_capacity(d.transmitters.len() * d.receivers.len());
    for j in 0..d.transmitters.len() {
        for i in 0..d.receivers.len() {
            out.push(simulate_channel(d, j, i, &returns));
        }
    }
    out
}

/// Detect on one simulated channel of a dwell.
pub fn detect_channel(d: &Dwell, ch: &Channel, targets: &[Target]) -> Vec<PrimitiveRow> {
    let tx = &d.transmitters[ch.tx];
    let rx = &d.receivers[ch.rx];
    let ant = Antenna::new(rx.params, d.fidelity.pattern);
    let info = ChannelInfo {
        run: d.run,
        dwell_id: rx.dwell_id,
        t_s: d.t_s,
        rx: rx.radar,
        tx: tx.radar,
        rx_face: rx.face,
        beam_u: rx.beam_u,
        beam_v: rx.beam_v,
        antenna: &ant,
        range_cell_m: rx.params.range_cell_m(),
        threshold: rx.params.threshold(),
        predicted_snr: rx.predicted_snr,
    };
    let hint = |t: usize| targets.get(t).map(|x| x.id.to_string());
    detect(&ch.cells, &info, &hint)
}

/// Voltage rows of one simulated channel.
pub fn voltage_rows(d: &Dwell, ch: &Channel) -> Vec<VoltageRow> {
    let tx = &d.transmitters[ch.tx];
    let rx = &d.receivers[ch.rx];
    let dr = rx.params.range_cell_m();
    ch.cells
        .iter()
        .map(|c| VoltageRow {
            run: d.run,
            dwell_id: rx.dwell_id,
            rx: rx.radar,
            tx: tx.radar,
            range_cell: c.k,
            range_m: c.k as f64 * dr,
            sum_i: c.sum.re,
            sum_q: c.sum.im,
            az_i: c.az.re,
            az_q: c.az.im,
            el_i: c.el.re,
            el_q: c.el.im,
        })
        .collect()
}

/// Evaluate a dwell: simulate every channel, detect, and (if asked) materialize voltages.
pub fn evaluate(d: &Dwell, targets: &[Target]) -> DwellOutput {
    let channels = simulate(d, targets);
    let mut primitives = Vec::new();
    let mut voltages = Vec::new();
    for ch in &channels {
        primitives.extend(detect_channel(d, ch, targets));
        if d.record_voltages {
            voltages.extend(voltage_rows(d, ch));
        }
    }
    DwellOutput { channels, primitives, voltages }
}
