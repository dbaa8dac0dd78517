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

use crate::channel::simulate_channel;
use crate::detect::{Cell, ChannelInfo, detect};
use crate::geometry::Bistatic;
use crate::ladder::{Rung, channel_rung};
use crate::pattern::Antenna;
use crate::returns::all_returns;
use crate::statistical::measure_channel;
use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::ids::RadarId;
use mimo_core::params::{Fidelity, RadarParams};
use mimo_core::records::{PrimitiveRow, VoltageRow};
use mimo_core::rng::{Stream, domain};
use num_complex::Complex64;

/// Two-way pattern power (relative to the peak) below which a target is not evaluated.
pub const PATTERN_FLOOR: f64 = 1e-4;
/// Pattern-weighted mean SNR (linear, −10 dB) below which a target is not evaluated.
pub const SNR_FLOOR: f64 = 0.1;
/// Leakage power (relative to the noise) below which waveform leakage is ignored.
pub const LEAKAGE_FLOOR: f64 = 1e-3;

/// Sub-keys appended to the dwell's stream keys.
pub(crate) const KEY_NOISE: u64 = domain::DWELL;
pub(crate) const KEY_RCS: u64 = domain::RCS;
pub(crate) const KEY_FALSE_ALARM: u64 = domain::FALSE_ALARM;
pub(crate) const KEY_LEAKAGE: u64 = 0x4C45_414B;

/// A transmitter of the dwell.
#[derive(Debug, Clone, Copy)]
pub struct Transmitter<'a> {
    /// The transmitting radar.
    pub radar: RadarId,
    /// Its radar parameters (power, bandwidth, losses).
    pub params: &'a RadarParams,
    /// The transmitting face; its origin is the array centre (site) position.
    pub frame: FaceFrame,
    /// Beam steering direction in the face's sine space.
    pub beam_u: f64,
    /// Beam steering direction, v (sine space).
    pub beam_v: f64,
    /// Pulses coherently integrated (SNR = `n_pulses · SNR₁`; 0 transmits nothing).
    pub n_pulses: u32,
    /// Orthogonal waveform index (informational: channels are told apart by transmitter).
    pub waveform: u32,
}

/// A receiver of the dwell.
#[derive(Debug, Clone, Copy)]
pub struct Receiver<'a> {
    /// The receiving radar.
    pub radar: RadarId,
    /// The receiver's dwell part id: primitives and voltages carry it.
    pub dwell_id: u64,
    /// Its radar parameters (noise figure, bandwidth, losses).
    pub params: &'a RadarParams,
    /// Receiving face index (reported in the primitives) and its frame.
    pub face: u8,
    /// The receiving face's frame (origin at the array centre).
    pub frame: FaceFrame,
    /// Σ/Δ beam steering direction in the face's sine space.
    pub beam_u: f64,
    /// Σ/Δ beam steering direction, v (sine space).
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
    Fixed {
        /// Window start (m).
        rho_min_m: f64,
        /// Window end (m).
        rho_max_m: f64,
    },
    /// Per channel `(j → i)`: `ρ_ji(aim) ± half_width_m`, with `ρ_ji` the equivalent range of the
    /// aim point for that transmitter and this receiver (§5.2: track and MIMO dwells use
    /// `half_width = max(5σ_ρ, 1 km)`).
    AroundAim {
        /// The aim point, ECEF (m).
        aim_ecef: DVec3,
        /// Half width of the window in ρ (m).
        half_width_m: f64,
    },
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
    /// Position at the dwell mid-time, ECEF (m).
    pub pos_ecef: DVec3,
    /// Mean RCS `σ̄` (m²).
    pub rcs_m2: f64,
    /// Polarimetric statistics, used with `fidelity.polarization` (docs/model.md §3.5); `None`
    /// takes the default model for `rcs_m2`.
    pub pol: Option<mimo_core::polarimetry::Polarimetry>,
}

/// One dwell to evaluate.
#[derive(Debug, Clone, Copy)]
pub struct Dwell<'a> {
    /// Monte Carlo run index.
    pub run: u32,
    /// Time stamped on the primitives (s).
    pub t_s: f64,
    /// Stream seed and keys of this dwell, e.g. `[run, group_id]`; they must differ between dwells.
    pub seed: u64,
    /// The dwell's stream keys (see `seed`).
    pub keys: &'a [u64],
    /// Transmitters, each with its own orthogonal waveform.
    pub transmitters: &'a [Transmitter<'a>],
    /// Receivers; receiver `i` forms one channel per transmitter.
    pub receivers: &'a [Receiver<'a>],
    /// Fidelity switches (Swerling case, pattern model, explicit cells, waveform isolation).
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
    /// True receive direction cosine v of the target.
    pub v: f64,
    /// Noise-free monopulse ratio in azimuth.
    pub eta_a: f64,
    /// Noise-free monopulse ratio in elevation.
    pub eta_e: f64,
    /// Complex amplitudes (fluctuation included) of Σ, Δa, Δe before the range response.
    pub sum: Complex64,
    /// Complex amplitude of Δa before the range response.
    pub az: Complex64,
    /// Complex amplitude of Δe before the range response.
    pub el: Complex64,
}

/// One Tx→Rx channel's simulated samples.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    /// Indices into the dwell's transmitter and receiver slices.
    pub tx: usize,
    /// Index into the dwell's receiver slice.
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
    /// Every Tx→Rx channel's simulated cells and returns.
    pub channels: Vec<Channel>,
    /// Detections with their ML monopulse estimates (docs/model.md §4).
    pub primitives: Vec<PrimitiveRow>,
    /// Empty unless `record_voltages`.
    pub voltages: Vec<VoltageRow>,
}

pub(crate) fn stream(d: &Dwell, extra: &[u64]) -> Stream {
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

pub(crate) fn cn(s: &mut Stream) -> Complex64 {
    let (re, im) = s.cn01();
    Complex64::new(re, im)
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

/// What the detector needs of channel (transmitter `j`, receiver `i`) of a dwell, with the
/// receiver's antenna `ant`.
pub(crate) fn channel_info<'a>(d: &Dwell, j: usize, i: usize, ant: &'a Antenna) -> ChannelInfo<'a> {
    let tx = &d.transmitters[j];
    let rx = &d.receivers[i];
    ChannelInfo {
        run: d.run,
        dwell_id: rx.dwell_id,
        t_s: d.t_s,
        rx: rx.radar,
        tx: tx.radar,
        rx_face: rx.face,
        beam_u: rx.beam_u,
        beam_v: rx.beam_v,
        antenna: ant,
        range_cell_m: rx.params.range_cell_m(),
        threshold: rx.params.threshold(),
        predicted_snr: rx.predicted_snr,
        two_target: d.fidelity.two_target,
    }
}

/// Detect on one simulated channel of a dwell.
pub fn detect_channel(d: &Dwell, ch: &Channel, targets: &[Target]) -> Vec<PrimitiveRow> {
    let ant = Antenna::new(d.receivers[ch.rx].params, d.fidelity.pattern);
    let info = channel_info(d, ch.tx, ch.rx, &ant);
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

/// Evaluate a dwell: every channel at its rung of the fidelity ladder (docs/model.md §4.8) —
/// simulate and detect at the voltage level, or draw from its statistics at the measurement
/// level — and (if asked) materialize voltages.
pub fn evaluate(d: &Dwell, targets: &[Target]) -> DwellOutput {
    let returns = all_returns(d, targets);
    let mut channels = Vec::with_capacity(d.transmitters.len() * d.receivers.len());
    let mut primitives = Vec::new();
    let mut voltages = Vec::new();
    for j in 0..d.transmitters.len() {
        for i in 0..d.receivers.len() {
            let ch = match channel_rung(d, i, &returns[j][i]) {
                Rung::Voltage => {
                    let ch = simulate_channel(d, j, i, &returns);
                    primitives.extend(detect_channel(d, &ch, targets));
                    ch
                }
                Rung::Measurement => {
                    let (ch, prims) = measure_channel(d, j, i, &returns, targets);
                    primitives.extend(prims);
                    ch
                }
            };
            if d.record_voltages {
                voltages.extend(voltage_rows(d, &ch));
            }
            channels.push(ch);
        }
    }
    DwellOutput { channels, primitives, voltages }
}
