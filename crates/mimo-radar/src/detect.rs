//! Detection, range centroiding and the measurement variances (docs/model.md §2.5–§2.7, §4.3, §4.5,
//! §4.6); the ML monopulse estimator itself is in [`crate::monopulse`].
//!
//! Input: the simulated cells of one Tx→Rx channel, sorted by cell index (cells that were not
//! simulated are noise below threshold by construction, §4.4). Output: one [`PrimitiveRow`] per
//! local maximum of every cluster of threshold crossings.
//!
//! * Threshold `|Σ_k|² > γ = −ln P_FA` (§4.3); clusters are runs of adjacent crossing cells (§4.5).
//! * Each local maximum `k*` is paired with its **larger neighbour** `k'` even below threshold.
//!   Range: `ρ̂ = ρ_{k*} ± ΔR·A₁/(A₀+A₁)` (§4.5 with `δ_s = ΔR`).
//! * Angles: `η̂ = Σ_k Re(Δ_k Σ_k*) / S`, `S = Σ_k |Σ_k|²` over `{k*, k'}` (§2.5). When the
//!   dwell carries a predicted mean SNR `R̄ ≤ 20 dB`, the Rayleigh ML bias is removed by dividing by
//!   `c = R̄/(1+R̄)`; above 20 dB (bias < 1 %) or without a prediction it is skipped. The truth is
//!   never used for it.
//! * Variances (§2.6, §4.6) from the **observed** `S`: `var(η̂) = (1 + c η̂²)/(2 S c²)` (the
//!   deterministic form when `c = 1`), mapped through the slope of the inverse monopulse curve;
//!   `σ_ρ = f·ΔR/√(2A₀²)` where `f` is recalibrated by Monte Carlo against the *observed*
//!   `A₀²` and centroid offset `x̂ = A₁/(A₀+A₁)` (the §4.6 table is against the mean SNR; read at
//!   `A₀²` it overstates the variance ~1.5× at 20 dB and the range NEES drops to 0.75). Floors
//!   `σ_u, σ_v ≥ 1e-4` and `σ_ρ ≥ 1 m`.
//! * Merged flag (§2.7): `T = η_Qa²/var_a + η_Qe²/var_e > χ²₂(0.99) = 9.21`, or a cluster at least 3
//!   cells wide, or the other neighbour of the peak also crossing.
//! * Estimates with `|û − u_b| > θ_u` or `|v̂ − v_b| > θ_v` lie outside the linear region of the
//!   monopulse curve and are rejected (no primitive).
//! * Option `two_target` (§4.9): clusters one sub-threshold cell apart form a region, and a region
//!   whose two-target fit ([`crate::two_target`]) passes the order test is reported as the two
//!   members instead of its local maxima.

use crate::monopulse::{MERGE_T_THRESHOLD, ml_bias_factor, monopulse};
use crate::pattern::Antenna;
use crate::two_target;
use mimo_core::ids::RadarId;
use mimo_core::records::PrimitiveRow;
use num_complex::Complex64;

/// Floor on the reported `σ_u`, `σ_v` (§4.6).
pub const MIN_SIGMA_UV: f64 = 1e-4;
/// Floor on the reported `σ_ρ` (m) (§4.6).
pub const MIN_SIGMA_RANGE_M: f64 = 1.0;

/// Which target contributed most power to a simulated cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Source {
    /// Index of the target in the dwell's target slice.
    pub target: usize,
    /// Its mean power in the Σ channel of this cell (linear SNR, fluctuation included).
    pub power: f64,
}

/// One simulated range cell of one channel: the three monopulse voltages.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    /// Cell index `k` (`ρ_k = k·ΔR`).
    pub k: i64,
    /// Sum-channel voltage Σ_k (noise power normalised to 1).
    pub sum: Complex64,
    /// Azimuth difference-channel voltage Δa_k.
    pub az: Complex64,
    /// Elevation difference-channel voltage Δe_k.
    pub el: Complex64,
    /// The dominant target contribution, `None` for noise-only cells.
    pub source: Option<Source>,
}

/// Two-point range centroid (§4.5, `δ_s = ΔR`): `ρ̂ = ρ_{k*} + dir·ΔR·A₁/(A₀+A₁)` where `dir` is
/// the side of the larger neighbour (+1, −1, or 0 when there is none).
pub fn range_centroid(rho_peak_m: f64, dir: f64, a0: f64, a1: f64, range_cell_m: f64) -> f64 {
    let tot = a0 + a1;
    if tot > 0.0 && dir != 0.0 { rho_peak_m + dir * range_cell_m * a1 / tot } else { rho_peak_m }
}

/// §4.6's Monte Carlo table of `f = RMS·√(2·SNR)/ΔR` for the two-point estimator against the
/// target's **mean** peak SNR (dB): RMS 0.234, 0.177, 0.094, 0.045, 0.0225 ΔR at 13, 16, 20, 25,
/// 30 dB (a steady target at a uniform offset between samples, detected). Use it to *predict* range
/// accuracy from a predicted SNR.
const RANGE_F_MEAN_SNR: [(f64, f64); 5] = [(13.0, 1.478), (16.0, 1.579), (20.0, 1.329), (25.0, 1.132), (30.0, 1.006)];

/// Recalibrated reported-variance table for the observed two-point statistics (§4.6 allows
/// recalibration by Monte Carlo): `f² = E[(ρ̂−ρ)²]·2S/ΔR²` against the observed peak-cell power
/// `S = A₀²` (rows, dB, bin centres [`RANGE_VAR_S_DB`]) and the centroid offset `x̂ = A₁/(A₀+A₁)`
/// (columns, bin centres 0.05 … 0.45). Monte Carlo: 2·10⁷ draws of a Swerling 1 target with mean
/// SNR log-uniform over 8–35 dB, uniform offset between samples, detected (peak `|Σ|² > γ`), peak
/// plus larger neighbour. Why two dimensions: the error depends strongly on where the target lies
/// between the samples — small `x̂` suffers the Rician bias of a noise-level neighbour, `x̂ ≈ 0.2–0.3`
/// at low SNR the choice of the wrong neighbour — and the observed `x̂` tells that. Read with
/// `S` alone (or with the §4.6 table at `A₀²`, which overstates the variance ~1.5× at 20 dB), the
/// mean range NEES depends on the target's SNR distribution by ±25 %; with this table it stays
/// within 0.97–1.11 for Swerling 0 and 1 targets of fixed mean SNR from 13 to 27 dB.
const RANGE_VAR_S_DB: [f64; 11] = [12.0, 14.0, 16.0, 18.0, 20.0, 22.0, 24.0, 26.0, 28.5, 31.5, 34.5];
const RANGE_VAR_F2: [[f64; 5]; 11] = [
    [0.898, 1.566, 2.206, 1.299, 0.241],
    [1.023, 1.950, 2.244, 0.685, 0.183],
    [1.282, 2.370, 1.798, 0.332, 0.170],
    [1.612, 2.643, 1.011, 0.263, 0.163],
    [2.045, 2.560, 0.522, 0.249, 0.159],
    [2.505, 2.055, 0.399, 0.245, 0.158],
    [2.832, 1.335, 0.379, 0.240, 0.157],
    [2.888, 0.799, 0.368, 0.236, 0.157],
    [2.590, 0.595, 0.363, 0.236, 0.158],
    [2.176, 0.564, 0.361, 0.236, 0.158],
    [1.792, 0.558, 0.364, 0.241, 0.161],
];

/// Linear interpolation weights of `x` on sorted bin centres (clamped at the ends).
fn bracket(centres: &[f64], x: f64) -> (usize, usize, f64) {
    let n = centres.len();
    if x.is_nan() || x <= centres[0] {
        return (0, 0, 0.0);
    }
    if x >= centres[n - 1] {
        return (n - 1, n - 1, 0.0);
    }
    let i = centres.partition_point(|&c| c <= x) - 1;
    (i, i + 1, (x - centres[i]) / (centres[i + 1] - centres[i]))
}

/// `f²(S, x̂)` of the reported range variance, bilinear in (dB, `x̂`) between bin centres.
pub fn range_f2_observed(s_peak: f64, x_hat: f64) -> f64 {
    const X_CENTRES: [f64; 5] = [0.05, 0.15, 0.25, 0.35, 0.45];
    let db = 10.0 * s_peak.max(1e-12).log10();
    let (i0, i1, ws) = bracket(&RANGE_VAR_S_DB, db);
    let (j0, j1, wx) = bracket(&X_CENTRES, x_hat.clamp(0.0, 0.5));
    let row = |i: usize| RANGE_VAR_F2[i][j0] * (1.0 - wx) + RANGE_VAR_F2[i][j1] * wx;
    row(i0) * (1.0 - ws) + row(i1) * ws
}

fn interp_db(table: &[(f64, f64)], s_lin: f64) -> f64 {
    let db = 10.0 * s_lin.max(1e-12).log10();
    if db <= table[0].0 {
        return table[0].1;
    }
    for w in table.windows(2) {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        if db <= x1 {
            return y0 + (y1 - y0) * (db - x0) / (x1 - x0);
        }
    }
    table[table.len() - 1].1
}

/// §4.6's `f` against the mean peak SNR (linear), interpolated in dB, constant outside the table.
pub fn range_f_factor_mean_snr(snr: f64) -> f64 {
    interp_db(&RANGE_F_MEAN_SNR, snr)
}

/// Predicted range standard deviation (m) of a return of mean peak SNR `snr` (§4.6 table), floored
/// at 1 m.
pub fn range_sigma_predicted_m(snr: f64, range_cell_m: f64) -> f64 {
    let s = snr.max(1e-12);
    (range_f_factor_mean_snr(s) * range_cell_m / (2.0 * s).sqrt()).max(MIN_SIGMA_RANGE_M)
}

/// Reported range standard deviation (m) from the observed peak-cell power `S = A₀²` and the
/// centroid offset `x̂ = A₁/(A₀+A₁)`: `σ_ρ = √f²(S, x̂)·ΔR/√(2S)`, floored at 1 m (§4.6, recalibrated).
pub fn range_sigma_m(s_peak: f64, x_hat: f64, range_cell_m: f64) -> f64 {
    let s = s_peak.max(1e-12);
    (range_f2_observed(s, x_hat).sqrt() * range_cell_m / (2.0 * s).sqrt()).max(MIN_SIGMA_RANGE_M)
}

/// Everything about a channel the detector needs besides its cells.
#[derive(Debug, Clone, Copy)]
pub struct ChannelInfo<'a> {
    /// Monte Carlo run index.
    pub run: u32,
    /// The receiver's dwell id.
    pub dwell_id: u64,
    /// Time stamped on the primitives: the dwell mid-time (s).
    pub t_s: f64,
    /// Receiving radar.
    pub rx: RadarId,
    /// Transmitting radar (whose waveform this channel is matched to).
    pub tx: RadarId,
    /// Receiving face index.
    pub rx_face: u8,
    /// Receiver beam steering direction.
    pub beam_u: f64,
    /// Receiver beam steering direction, v (sine space).
    pub beam_v: f64,
    /// The receiver's antenna (monopulse curve).
    pub antenna: &'a Antenna,
    /// Range cell `ΔR` = sample spacing (m).
    pub range_cell_m: f64,
    /// Threshold `γ` on `|Σ|²`.
    pub threshold: f64,
    /// Predicted mean SNR of the return the dwell aims at (for the ML bias factor), if any.
    pub predicted_snr: Option<f64>,
    /// Fit two targets to each region of crossings (`fidelity.two_target`, docs/model.md §4.9).
    pub two_target: bool,
}

impl ChannelInfo<'_> {
    /// A primitives row holding the columns the channel fixes (its key and beam steering
    /// direction), with zero estimate columns: the base of a struct update in which the caller
    /// sets every estimate column.
    pub(crate) fn channel_columns(&self) -> PrimitiveRow {
        PrimitiveRow {
            run: self.run,
            dwell_id: self.dwell_id,
            t_s: self.t_s,
            rx: self.rx,
            tx: self.tx,
            rx_face: self.rx_face,
            range_cell: 0,
            range_m: 0.0,
            u: 0.0,
            v: 0.0,
            snr_db: 0.0,
            eta_q: 0.0,
            merged: false,
            beam_u: self.beam_u,
            beam_v: self.beam_v,
            var_range_m2: 0.0,
            var_u: 0.0,
            var_v: 0.0,
            target_hint: None,
        }
    }
}

/// Detect, centroid and estimate DOA on one channel's cells (sorted by `k`, unique). `hint` maps
/// a target index of [`Source`] to its id.
pub fn detect(cells: &[Cell], info: &ChannelInfo, hint: &dyn Fn(usize) -> Option<String>) -> Vec<PrimitiveRow> {
    let mut out = Vec::new();
    let gamma = info.threshold;
    let n = cells.len();
    let c = ml_bias_factor(info.predicted_snr);
    // Clusters [i, j): runs of adjacent crossing cells (§4.5).
    let mut clusters: Vec<(usize, usize)> = Vec::new();
    let mut i = 0;
    while i < n {
        if cells[i].sum.norm_sqr() <= gamma {
            i += 1;
            continue;
        }
        let mut j = i + 1;
        while j < n && cells[j].k == cells[j - 1].k + 1 && cells[j].sum.norm_sqr() > gamma {
            j += 1;
        }
        clusters.push((i, j));
        i = j;
    }
    let mut ci = 0;
    while ci < clusters.len() {
        // With the two-target option, clusters one sub-threshold cell apart form one region (§4.9).
        let mut cj = ci + 1;
        while info.two_target
            && cj < clusters.len()
            && clusters[cj].0 == clusters[cj - 1].1 + 1
            && cells[clusters[cj].0].k == cells[clusters[cj - 1].1 - 1].k + 2
            && cells[clusters[cj - 1].1].k == cells[clusters[cj - 1].1 - 1].k + 1
        {
            cj += 1;
        }
        let mut region = Vec::new();
        let mut peak: Option<usize> = None;
        for &(i, j) in &clusters[ci..cj] {
            let wide = j - i >= 3;
            for m in i..j {
                let p = cells[m].sum.norm_sqr();
                let left_ok = m == i || p > cells[m - 1].sum.norm_sqr();
                let right_ok = m + 1 == j || p >= cells[m + 1].sum.norm_sqr();
                if left_ok && right_ok {
                    if peak.is_none_or(|q| p > cells[q].sum.norm_sqr()) {
                        peak = Some(m);
                    }
                    if let Some(row) = primitive(cells, m, wide, c, info, hint) {
                        region.push(row);
                    }
                }
            }
        }
        let (first, last) = (clusters[ci].0, clusters[cj - 1].1 - 1);
        if info.two_target
            && let Some(peak) = peak
            && let Some(pair) = two_target::split(samples(cells, first, last), cells[peak].k, c, info, hint)
        {
            region = pair.to_vec();
        }
        out.extend(region);
        ci = cj;
    }
    out
}

/// The cells `first..=last` and one adjacent cell each side (two for a one-cell region), as far
/// as they were simulated (§4.9).
fn samples(cells: &[Cell], first: usize, last: usize) -> &[Cell] {
    let margin = if cells[last].k > cells[first].k { 1 } else { 2 };
    let (mut lo, mut hi) = (first, last);
    for _ in 0..margin {
        if lo > 0 && cells[lo - 1].k + 1 == cells[lo].k {
            lo -= 1;
        }
        if hi + 1 < cells.len() && cells[hi + 1].k == cells[hi].k + 1 {
            hi += 1;
        }
    }
    &cells[lo..=hi]
}

fn primitive(
    cells: &[Cell],
    m: usize,
    wide: bool,
    c: f64,
    info: &ChannelInfo,
    hint: &dyn Fn(usize) -> Option<String>,
) -> Option<PrimitiveRow> {
    let peak = &cells[m];
    let left = (m > 0 && cells[m - 1].k == peak.k - 1).then(|| &cells[m - 1]);
    let right = cells.get(m + 1).filter(|r| r.k == peak.k + 1);
    let (nb, other, dir) = match (left, right) {
        (Some(l), Some(r)) => {
            if r.sum.norm_sqr() > l.sum.norm_sqr() {
                (Some(r), Some(l), 1.0)
            } else {
                (Some(l), Some(r), -1.0)
            }
        }
        (Some(l), None) => (Some(l), None, -1.0),
        (None, Some(r)) => (Some(r), None, 1.0),
        (None, None) => (None, None, 0.0),
    };
    let a0 = peak.sum.norm();
    let a1 = nb.map_or(0.0, |x| x.sum.norm());
    let rho_peak = peak.k as f64 * info.range_cell_m;
    let rho = range_centroid(rho_peak, dir, a0, a1, info.range_cell_m);
    let mut samples = [(peak.sum, peak.az, peak.el); 2];
    let used = if let Some(x) = nb {
        samples[1] = (x.sum, x.az, x.el);
        2
    } else {
        1
    };
    let mp = monopulse(&samples[..used], c);
    let ant = info.antenna;
    let (du, dv) = ant.offset_from_ratio(mp.eta_a, mp.eta_e);
    if !(du.abs() <= ant.theta_u() && dv.abs() <= ant.theta_v()) {
        return None;
    }
    let (su, sv) = ant.offset_slope(mp.eta_a, mp.eta_e);
    let var_u = (su * su * mp.var_a).max(MIN_SIGMA_UV * MIN_SIGMA_UV);
    let var_v = (sv * sv * mp.var_e).max(MIN_SIGMA_UV * MIN_SIGMA_UV);
    let x_hat = if a0 + a1 > 0.0 { a1 / (a0 + a1) } else { 0.0 };
    let sig_r = range_sigma_m(a0 * a0, x_hat, info.range_cell_m);
    let other_crosses = other.is_some_and(|o| o.sum.norm_sqr() > info.threshold);
    let merged = mp.t_stat > MERGE_T_THRESHOLD || wide || other_crosses;
    Some(PrimitiveRow {
        range_cell: peak.k,
        range_m: rho,
        u: info.beam_u + du,
        v: info.beam_v + dv,
        snr_db: 10.0 * mp.s.log10(),
        eta_q: mp.t_stat,
        merged,
        var_range_m2: sig_r * sig_r,
        var_u,
        var_v,
        target_hint: peak.source.and_then(|s| hint(s.target)),
        ..info.channel_columns()
    })
}
