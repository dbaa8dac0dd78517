//! # mimo-radar
//!
//! The radar model of `mimo`: from targets and a dwell to complex monopulse voltages, detection
//! primitives and measurements. Pure functions, no I/O, no global state; every random draw comes
//! from a [`mimo_core::rng::Stream`] keyed by the caller's `(seed, keys…)`.
//!
//! | module | does | docs/model.md |
//! |---|---|---|
//! | [`geometry`] | face choice and scan limit, scan loss `G0·w^α_s`, 4/3-earth horizon, optional refraction, bistatic ranges and angle, bistatic `(R_B,u,v)` ⇄ ECEF, measurement Jacobians | §1.4–§1.8, §5.1, §5.4 |
//! | [`equation`] | radar range equation, bistatic and monostatic | §3.1, §3.3 |
//! | [`pattern`] | Gaussian (A) and uniform-aperture (B) Σ/Δ voltage patterns, monopulse curve and its inverse | §2.1–§2.3, §2.5 |
//! | [`fluctuation`] | Swerling 0/1/3 voltage draws | §3.2 |
//! | [`polarization`] | polarimetric scattering matrix, Jones vectors, the β rotation (option) | §3.5 |
//! | [`range`] | `ρ = R_B/2`, cell grid, triangular response, straddle loss | §4.1 |
//! | [`dwell`] | per-channel voltages: explicit cells near returns, §4.4 false-alarm shortcut, waveform leakage | §2.4, §2.7, §4.2, §4.4, §5.2, §5.3 |
//! | [`detect`] | threshold, clusters, two-point range centroid, ML monopulse, variances, merged flag | §2.5–§2.7, §4.3, §4.5, §4.6 |
//! | [`two_target`] | option: two point targets fitted to a wide cluster (joint-bin range and angles, order test, Fisher covariance) | §4.9 |
//! | [`ladder`] | which rung of the fidelity ladder evaluates a channel (`voltage`, `measurement`, `auto`) | §4.8 |
//! | [`statistical`] | the measurement rung: detections drawn from the voltage level's statistics, no cells | §4.8 |
//! | [`measure`] | primitives → measurements (the only implementation, used online and offline) | §4.5 |
//! | [`quiet`] | a monostatic dwell that no target reaches and whose false-alarm draw is zero, recognised without building its vectors | §4.4, §4.7 |
//! | [`registration`] | registration biases carried as a radar carries them: biased ranges and directions, beams steered through the biases | §5.5 |
//! | [`energy`] | predicted SNR, required SNR, pointing/straddle loss, pulses per dwell, dwell time and energy | §7.2, §7.3 |
//!
//! ## Flow of one dwell
//!
//! ```text
//! Dwell{transmitters, receivers, windows, fidelity, stream keys} + targets at mid-dwell
//!   └─ dwell::simulate     per (tx→rx) channel: returns of the targets that matter, explicit
//!                          cells (noise + voltages), false alarms by the shortcut
//!   └─ dwell::detect_channel → PrimitiveRow (ρ̂, û, v̂, S, T, merged, variances, target_hint)
//!   └─ measure::measurements_from_primitives → MeasurementRow
//! ```
//! [`dwell::evaluate`] does the first two for all channels (and the voltage rows when asked), each
//! channel at its rung of the fidelity ladder ([`ladder`], docs/model.md §4.8): the flow above is
//! the `voltage` rung; at the `measurement` rung [`statistical`] draws the primitives from the
//! statistics the voltage rung produces, without cells.
//!
//! ## Conventions and decisions
//!
//! * Voltages are normalized so that noise is `CN(0,1)` in every channel and cell; `|a|²` of a
//!   signal amplitude is its SNR. SW0/SW1/SW3 targets give one complex sample per cell per dwell
//!   with SNR `N_p·SNR₁` (coherent integration, no integration loss).
//! * Cells: `ρ_k = k·ΔR` with `ΔR = c/(2B)` of the receiver, sample spacing `δ_s = ΔR`.
//! * For a bistatic pair the loss `L` is the mean (in dB) of the two radars' losses, `P_t`, `τ`, `λ`
//!   the transmitter's and the noise figure the receiver's.
//! * The ML monopulse bias factor `c = R̄/(1+R̄)` uses the dwell's *predicted* SNR
//!   ([`dwell::Receiver::predicted_snr`]), never the truth, and is skipped above 20 dB or without a
//!   prediction (search).
//! * Monopulse estimates more than one beamwidth off the beam are rejected (§2.5).
//! * Range windows ([`dwell::RangeWindow`]) are either fixed (search: the whole instrumented range)
//!   or centred per channel on the aim point's `ρ_ji` (track and MIMO dwells, §5.2), since the
//!   same aim point has a different equivalent range for each transmitter.
//! * The reported range variance is recalibrated (§4.6 allows it): the §4.6 table gives the
//!   estimator's RMS against the *mean* SNR (reproduced by a test within 10 %), but the reported
//!   variance must be computed from what was *observed*; [`detect::range_sigma_m`] uses a Monte
//!   Carlo table in the observed `A₀²` and centroid offset `x̂`, which keeps the range NEES near 1
//!   (0.97–1.11) whatever the target's SNR distribution. [`detect::range_sigma_predicted_m`]
//!   keeps the §4.6 table for predictions from a predicted SNR.
//! * A bistatic channel's cell size is the receiver's `ΔR` (all waveforms share the bandwidth).
//! * `n_pulses = 0` transmits nothing; targets with a non-finite position or a non-positive RCS and
//!   empty or non-finite windows are skipped, never a panic.
//! * Polarization (§3.5) is an option (`fidelity.polarization`, off by default): each radar has a
//!   transmit and a receive linear polarization and each target a Gaussian scattering matrix; the
//!   matrix voltage replaces the Swerling draw and the pair's mean RCS replaces `σ̄`. Off, every
//!   radar is co-polarized and the echo is the Swerling draw on `σ̄`.
//! * Refraction (§1.8, off by default) bends the direction used for both patterns (so the measured
//!   `û, v̂` are apparent directions); ranges stay geometric.
#![warn(missing_docs)]

mod channel;
pub mod detect;
pub mod dwell;
pub mod energy;
pub mod equation;
pub mod fluctuation;
pub mod geometry;
pub mod ladder;
pub mod measure;
pub mod monopulse;
pub mod pattern;
pub mod polarization;
pub mod quiet;
pub mod range;
pub mod reach;
pub mod registration;
mod returns;
pub mod statistical;
pub mod two_target;

pub use detect::{Cell, Source};
pub use dwell::{Channel, Dwell, DwellOutput, RangeWindow, Receiver, Target, Transmitter, evaluate};
pub use measure::measurements_from_primitives;
pub use monopulse::Monopulse;
pub use pattern::{Antenna, Gains};
