//! Two-target (joint-bin) range–angle estimator for an unresolved pair (docs/model.md §4.9),
//! an option of the voltage rung (`fidelity.two_target`).
//!
//! Model (§4.1–§4.2): over the samples `k ∈ K` of a region of crossings (its cells and one cell
//! each side, two for a one-cell region), `Σ_k = a₁ p(k − x₁) + a₂ p(k − x₂) + n_k` with `p(d) = max(0, 1 − |d|)` and the
//! delays `x_i = ρ_i/ΔR` in cells; likewise `Δa_k`, `Δe_k` with amplitudes `b_i`. For given delays
//! the amplitudes are a linear least-squares solve `â = (HᵀH)⁻¹Hᵀ Σ` (`H` real, `n × 2`), so the
//! sum-channel residual `r₂(x₁, x₂) = ‖Σ‖² − ΣᴴH(HᵀH)⁻¹HᵀΣ` depends on the delays only; it is
//! minimised on a grid of [`GRID_STEP_CELLS`] and refined by a compass search down to
//! [`REFINE_STEP_CELLS`]. The one-target residual `r₁(x)` is minimised the same way.
//!
//! * **Order test:** the pair is kept when `Λ = 2(r₁ − r₂)` (twice the log-likelihood ratio for
//!   `CN(0,1)` noise) exceeds [`ORDER_THRESHOLD`] and each `|â_i|²` is at least
//!   [`AMPLITUDE_FLOOR_FRACTION`]`·γ`; the threshold was set by Monte Carlo so that a lone Swerling
//!   0 target at 20 dB splits in well under 1 % of detections (`tests/two_target.rs`).
//! * **Angles:** `η_i = Re(b_i/a_i)/c` per axis with the dwell's ML bias factor `c` (§2.5), mapped
//!   through the antenna's inverse monopulse curve exactly as for one target. Variance
//!   `(1 + cη²)·G_ii/(2|â_i|²c²)`, `G = (HᵀH)⁻¹` (the LS covariance of `b_i` and `a_i`), i.e. §2.6
//!   with `S` replaced by the pair member's effective SNR `|â_i|²/G_ii`.
//! * **Range variance:** the inverse Fisher information of the sum-channel model in
//!   `(x₁, x₂, Re a₁, Im a₁, Re a₂, Im a₂)`, `J = 2 Re(DᴴD)` with `∂μ_k/∂x_i = a_i sgn(k − x_i)`,
//!   times [`RANGE_VARIANCE_INFLATION`] (Monte Carlo calibration), floored like §4.6; the angle
//!   variances likewise carry [`ANGLE_VARIANCE_INFLATION`].

use crate::detect::{Cell, ChannelInfo, MIN_SIGMA_RANGE_M, MIN_SIGMA_UV};
use crate::monopulse::MERGE_T_THRESHOLD;
use mimo_core::records::PrimitiveRow;
use num_complex::Complex64;

/// Threshold on `Λ = 2(r₁ − r₂)`: keep two targets above it (Monte Carlo, §4.9).
pub const ORDER_THRESHOLD: f64 = 16.0;
/// Each fitted peak amplitude must reach this fraction of the detection threshold `γ` in `|â_i|²`.
pub const AMPLITUDE_FLOOR_FRACTION: f64 = 0.5;
/// The two delays are at least this far apart (cells): closer, the fit is ill-conditioned.
pub const MIN_SEPARATION_CELLS: f64 = 0.5;
/// Coarse grid step of the delay search (cells).
pub const GRID_STEP_CELLS: f64 = 0.1;
/// Final step of the compass refinement (cells).
pub const REFINE_STEP_CELLS: f64 = 1e-3;
/// Factor on the Fisher range variance (Monte Carlo calibration of the reported `σ_ρ`, §4.9).
pub const RANGE_VARIANCE_INFLATION: f64 = 2.2;
/// Factor on the LS angle variances (Monte Carlo calibration, §4.9): delay errors leak the other
/// target's difference voltage into `b̂_i`.
pub const ANGLE_VARIANCE_INFLATION: f64 = 1.45;

/// The column of `H` for a delay `x` (cells, absolute): up to two samples `(index in K, weight)`.
fn column(x: f64, k_lo: i64, n: usize) -> [(usize, f64); 2] {
    let k0 = x.floor();
    let f = x - k0;
    let mut col = [(0, 0.0); 2];
    for (slot, (k, w)) in [(k0 as i64, 1.0 - f), (k0 as i64 + 1, f)].into_iter().enumerate() {
        let idx = k - k_lo;
        if idx >= 0 && (idx as usize) < n {
            col[slot] = (idx as usize, w);
        }
    }
    col
}

fn dot(col: &[(usize, f64); 2], y: &[Complex64]) -> Complex64 {
    col.iter().map(|&(i, w)| y[i] * w).sum()
}

fn gram(c1: &[(usize, f64); 2], c2: &[(usize, f64); 2]) -> f64 {
    let mut s = 0.0;
    for &(i, w) in c1 {
        for &(j, v) in c2 {
            if i == j {
                s += w * v;
            }
        }
    }
    s
}

/// `(HᵀH)⁻¹` of two columns, or `None` when singular.
fn inverse_gram(c1: &[(usize, f64); 2], c2: &[(usize, f64); 2]) -> Option<[[f64; 2]; 2]> {
    let (g11, g12, g22) = (gram(c1, c1), gram(c1, c2), gram(c2, c2));
    let det = g11 * g22 - g12 * g12;
    if det <= 1e-9 * (g11 * g22).max(1e-300) || !det.is_finite() {
        return None;
    }
    Some([[g22 / det, -g12 / det], [-g12 / det, g11 / det]])
}

/// LS amplitudes of two columns on `y`.
fn amplitudes(g: &[[f64; 2]; 2], c1: &[(usize, f64); 2], c2: &[(usize, f64); 2], y: &[Complex64]) -> [Complex64; 2] {
    let (z1, z2) = (dot(c1, y), dot(c2, y));
    [z1 * g[0][0] + z2 * g[0][1], z1 * g[1][0] + z2 * g[1][1]]
}

/// Energy of `y` captured by the two-column model (`‖y‖² − r₂`), or −∞ when singular.
fn captured2(x1: f64, x2: f64, k_lo: i64, y: &[Complex64]) -> f64 {
    let (c1, c2) = (column(x1, k_lo, y.len()), column(x2, k_lo, y.len()));
    let Some(g) = inverse_gram(&c1, &c2) else { return f64::NEG_INFINITY };
    let (z1, z2) = (dot(&c1, y), dot(&c2, y));
    let a = amplitudes(&g, &c1, &c2, y);
    (z1.conj() * a[0] + z2.conj() * a[1]).re
}

/// Energy captured by one column (`‖y‖² − r₁`).
fn captured1(x: f64, k_lo: i64, y: &[Complex64]) -> f64 {
    let c = column(x, k_lo, y.len());
    let e = gram(&c, &c);
    if e <= 0.0 { f64::NEG_INFINITY } else { dot(&c, y).norm_sqr() / e }
}

/// Best one-target delay and its captured energy over `[lo, hi]` (cells).
fn fit_one(lo: f64, hi: f64, k_lo: i64, y: &[Complex64]) -> (f64, f64) {
    let mut best = (lo, f64::NEG_INFINITY);
    let steps = ((hi - lo) / GRID_STEP_CELLS).round() as i64;
    for s in 0..=steps {
        let x = lo + s as f64 * GRID_STEP_CELLS;
        let e = captured1(x, k_lo, y);
        if e > best.1 {
            best = (x, e);
        }
    }
    let mut step = GRID_STEP_CELLS / 2.0;
    while step >= REFINE_STEP_CELLS {
        let mut moved = true;
        while moved {
            moved = false;
            for x in [best.0 - step, best.0 + step] {
                if (lo..=hi).contains(&x) {
                    let e = captured1(x, k_lo, y);
                    if e > best.1 {
                        best = (x, e);
                        moved = true;
                    }
                }
            }
        }
        step /= 2.0;
    }
    best
}

/// Best two-target delays `(x₁ < x₂)` and captured energy over `[lo, hi]` (cells).
fn fit_two(lo: f64, hi: f64, k_lo: i64, y: &[Complex64]) -> Option<(f64, f64, f64)> {
    let ok = |x1: f64, x2: f64| x1 >= lo && x2 <= hi && x2 - x1 >= MIN_SEPARATION_CELLS;
    let mut best: Option<(f64, f64, f64)> = None;
    let steps = ((hi - lo) / GRID_STEP_CELLS).round() as i64;
    for s1 in 0..=steps {
        let x1 = lo + s1 as f64 * GRID_STEP_CELLS;
        for s2 in s1 + 1..=steps {
            let x2 = lo + s2 as f64 * GRID_STEP_CELLS;
            if !ok(x1, x2) {
                continue;
            }
            let e = captured2(x1, x2, k_lo, y);
            if best.is_none_or(|b| e > b.2) {
                best = Some((x1, x2, e));
            }
        }
    }
    let mut b = best?;
    let mut step = GRID_STEP_CELLS / 2.0;
    while step >= REFINE_STEP_CELLS {
        let mut moved = true;
        while moved {
            moved = false;
            for (d1, d2) in [(-step, 0.0), (step, 0.0), (0.0, -step), (0.0, step), (step, step), (-step, -step)] {
                let (x1, x2) = (b.0 + d1, b.1 + d2);
                if ok(x1, x2) {
                    let e = captured2(x1, x2, k_lo, y);
                    if e > b.2 {
                        b = (x1, x2, e);
                        moved = true;
                    }
                }
            }
        }
        step /= 2.0;
    }
    b.2.is_finite().then_some(b)
}

/// Inverse of a small symmetric positive-definite matrix by Gauss–Jordan, `None` if singular.
fn invert<const N: usize>(mut m: [[f64; N]; N]) -> Option<[[f64; N]; N]> {
    let mut inv = [[0.0; N]; N];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for c in 0..N {
        let p = (c..N).max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs()))?;
        if m[p][c].abs() < 1e-12 {
            return None;
        }
        m.swap(c, p);
        inv.swap(c, p);
        let d = m[c][c];
        for j in 0..N {
            m[c][j] /= d;
            inv[c][j] /= d;
        }
        for r in 0..N {
            if r != c {
                let f = m[r][c];
                if f != 0.0 {
                    for j in 0..N {
                        m[r][j] -= f * m[c][j];
                        inv[r][j] -= f * inv[c][j];
                    }
                }
            }
        }
    }
    Some(inv)
}

/// Cramér–Rao variances of the delays `(x₁, x₂)` (cells²) of the sum-channel model at the
/// estimate, amplitudes unknown (§4.9).
fn delay_variances(x: [f64; 2], a: [Complex64; 2], k_lo: i64, n: usize) -> Option<[f64; 2]> {
    // Columns of D (complex, length n): ∂μ/∂x_i, ∂μ/∂Re a_i = h_i, ∂μ/∂Im a_i = j h_i.
    let mut d = vec![[Complex64::new(0.0, 0.0); 6]; n];
    for i in 0..2 {
        for (idx, w) in column(x[i], k_lo, n) {
            if w > 0.0 {
                let k = k_lo + idx as i64;
                let sgn = (k as f64 - x[i]).signum();
                d[idx][i] = a[i] * sgn;
                d[idx][2 + 2 * i] += Complex64::new(w, 0.0);
                d[idx][3 + 2 * i] += Complex64::new(0.0, w);
            }
        }
    }
    let mut j = [[0.0; 6]; 6];
    for row in &d {
        for p in 0..6 {
            for q in 0..6 {
                j[p][q] += 2.0 * (row[p].conj() * row[q]).re;
            }
        }
    }
    let inv = invert(j)?;
    (inv[0][0] > 0.0 && inv[1][1] > 0.0).then_some([inv[0][0], inv[1][1]])
}

/// Result of a two-target fit on one region of crossings (cell units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairFit {
    /// Delays `x_i = ρ_i/ΔR` (cells, absolute), `x₁ < x₂`.
    pub x_cells: [f64; 2],
    /// Sum-channel amplitudes `â_i` (peak voltage of each target).
    pub sum: [Complex64; 2],
    /// Azimuth difference-channel amplitudes `b̂_i`.
    pub az: [Complex64; 2],
    /// Elevation difference-channel amplitudes.
    pub el: [Complex64; 2],
    /// Diagonal of `G = (HᵀH)⁻¹` at the estimate.
    pub g_diag: [f64; 2],
    /// Cramér–Rao delay variances (cells²), before inflation and floors.
    pub var_x_cells2: [f64; 2],
    /// Order statistic `Λ = 2(r₁ − r₂)`.
    pub order_stat: f64,
    /// Energy of each target in the samples, `|â_i|²‖h_i‖²`.
    pub energy: [f64; 2],
}

/// Fit one and two targets to contiguous samples `cells` (consecutive `k`, at least 4) and return
/// the two-target fit, whatever the order test says (the caller applies it with [`accept`]).
pub fn fit_pair(cells: &[Cell]) -> Option<PairFit> {
    let n = cells.len();
    if n < 4 || cells.windows(2).any(|w| w[1].k != w[0].k + 1) {
        return None;
    }
    let k_lo = cells[0].k;
    let sum: Vec<Complex64> = cells.iter().map(|c| c.sum).collect();
    let (lo, hi) = (k_lo as f64, (k_lo + n as i64 - 1) as f64);
    let (_, e1) = fit_one(lo, hi, k_lo, &sum);
    let (x1, x2, e2) = fit_two(lo, hi, k_lo, &sum)?;
    let (c1, c2) = (column(x1, k_lo, n), column(x2, k_lo, n));
    let g = inverse_gram(&c1, &c2)?;
    let a = amplitudes(&g, &c1, &c2, &sum);
    let az: Vec<Complex64> = cells.iter().map(|c| c.az).collect();
    let el: Vec<Complex64> = cells.iter().map(|c| c.el).collect();
    let var = delay_variances([x1, x2], a, k_lo, n)?;
    Some(PairFit {
        x_cells: [x1, x2],
        sum: a,
        az: amplitudes(&g, &c1, &c2, &az),
        el: amplitudes(&g, &c1, &c2, &el),
        g_diag: [g[0][0], g[1][1]],
        var_x_cells2: var,
        order_stat: 2.0 * (e2 - e1),
        energy: [a[0].norm_sqr() * gram(&c1, &c1), a[1].norm_sqr() * gram(&c2, &c2)],
    })
}

/// Whether the order test can pass at all, from the one-target fit alone: the two-target fit
/// captures at most all the samples' energy (`r₂ ≥ 0`), so `Λ = 2(r₁ − r₂) ≤ 2r₁`. A region whose
/// one-target residual leaves `2r₁` under [`ORDER_THRESHOLD`] (a lone target or a false alarm:
/// `2r₁` is then about twice the noise energy of the other samples) is never split, and the
/// two-delay search is skipped. The margin covers rounding in the captured energies, so the
/// answer is exactly the full test's.
fn may_pass_order_test(cells: &[Cell]) -> bool {
    let n = cells.len();
    if n < 4 || cells.windows(2).any(|w| w[1].k != w[0].k + 1) {
        return true; // fit_pair answers these
    }
    let sum: Vec<Complex64> = cells.iter().map(|c| c.sum).collect();
    let total: f64 = sum.iter().map(|y| y.norm_sqr()).sum();
    let k_lo = cells[0].k;
    let (lo, hi) = (k_lo as f64, (k_lo + n as i64 - 1) as f64);
    let (_, e1) = fit_one(lo, hi, k_lo, &sum);
    2.0 * (total - e1) + 1e-9 * total >= ORDER_THRESHOLD
}

/// The order test (§4.9): `Λ` above [`ORDER_THRESHOLD`] and each `|â_i|² ≥` the amplitude floor.
pub fn accept(fit: &PairFit, threshold: f64) -> bool {
    fit.order_stat > ORDER_THRESHOLD && fit.sum.iter().all(|a| a.norm_sqr() >= AMPLITUDE_FLOOR_FRACTION * threshold)
}

/// Two primitives from the samples `cells` (a region of crossings and its neighbours, consecutive `k`)
/// when the pair passes the order test and both estimates lie in the monopulse's linear region;
/// `None` keeps the one-target primitives. Both carry `range_cell = peak_k` (the convention that
/// keeps them apart in [`crate::measure`]); `merged` is the imaginary-part test of each (§2.7).
pub fn split(
    cells: &[Cell],
    peak_k: i64,
    c: f64,
    info: &ChannelInfo,
    hint: &dyn Fn(usize) -> Option<String>,
) -> Option<[PrimitiveRow; 2]> {
    if !may_pass_order_test(cells) {
        return None;
    }
    let fit = fit_pair(cells)?;
    if !accept(&fit, info.threshold) {
        return None;
    }
    let ant = info.antenna;
    let dr = info.range_cell_m;
    let row = |i: usize| -> Option<PrimitiveRow> {
        let a = fit.sum[i];
        let s_eff = a.norm_sqr() / fit.g_diag[i];
        let ra = fit.az[i] / a;
        let re = fit.el[i] / a;
        let (eta_a, eta_e) = (ra.re / c, re.re / c);
        let (du, dv) = ant.offset_from_ratio(eta_a, eta_e);
        if !(du.abs() <= ant.theta_u() && dv.abs() <= ant.theta_v()) {
            return None;
        }
        let vq_a = (1.0 + c * eta_a * eta_a) / (2.0 * s_eff);
        let vq_e = (1.0 + c * eta_e * eta_e) / (2.0 * s_eff);
        let t_stat = ra.im * ra.im / vq_a + re.im * re.im / vq_e;
        let (su, sv) = ant.offset_slope(eta_a, eta_e);
        let var_u = (su * su * vq_a / (c * c) * ANGLE_VARIANCE_INFLATION).max(MIN_SIGMA_UV * MIN_SIGMA_UV);
        let var_v = (sv * sv * vq_e / (c * c) * ANGLE_VARIANCE_INFLATION).max(MIN_SIGMA_UV * MIN_SIGMA_UV);
        let var_r =
            (fit.var_x_cells2[i] * RANGE_VARIANCE_INFLATION * dr * dr).max(MIN_SIGMA_RANGE_M * MIN_SIGMA_RANGE_M);
        let near = fit.x_cells[i].round() as i64;
        let source = cells
            .iter()
            .find(|cell| cell.k == near)
            .and_then(|cell| cell.source)
            .or_else(|| cells.iter().filter_map(|cell| cell.source).max_by(|p, q| p.power.total_cmp(&q.power)));
        Some(PrimitiveRow {
            range_cell: peak_k,
            range_m: fit.x_cells[i] * dr,
            u: info.beam_u + du,
            v: info.beam_v + dv,
            snr_db: 10.0 * fit.energy[i].max(1e-12).log10(),
            eta_q: t_stat,
            merged: t_stat > MERGE_T_THRESHOLD,
            var_range_m2: var_r,
            var_u,
            var_v,
            target_hint: source.and_then(|s| hint(s.target)),
            ..info.channel_columns()
        })
    };
    Some([row(0)?, row(1)?])
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::rng::Stream;

    /// Random regions (noise, one target or two, 4–7 samples, 0–30 dB): whenever the cheap bound
    /// says the order test cannot pass, the full fit agrees; and the bound prunes most lone
    /// targets and noise (else it would save nothing).
    #[test]
    fn the_order_bound_never_rejects_a_pair_the_full_test_accepts() {
        let mut rng = Stream::new(7, &[0x0b0d]);
        let (mut lone, mut lone_pruned) = (0, 0);
        for trial in 0..6000 {
            let n = 4 + (rng.uniform() * 4.0) as usize;
            let k_lo = 100i64;
            let targets = trial % 3; // 0: noise, 1: one target, 2: two
            let mut cells: Vec<Cell> = (0..n)
                .map(|i| {
                    let (s, a, e) = (rng.cn01(), rng.cn01(), rng.cn01());
                    Cell {
                        k: k_lo + i as i64,
                        sum: Complex64::new(s.0, s.1),
                        az: Complex64::new(a.0, a.1),
                        el: Complex64::new(e.0, e.1),
                        source: None,
                    }
                })
                .collect();
            for _ in 0..targets {
                let x = k_lo as f64 + 0.5 + rng.uniform() * (n as f64 - 2.0);
                let amp =
                    Complex64::from_polar(10f64.powf(rng.uniform() * 1.5), 2.0 * std::f64::consts::PI * rng.uniform());
                for c in &mut cells {
                    let w = (1.0 - (c.k as f64 - x).abs()).max(0.0);
                    c.sum += amp * w;
                    c.az += amp * w * 0.3;
                }
            }
            let pruned = !may_pass_order_test(&cells);
            if targets < 2 {
                lone += 1;
                lone_pruned += usize::from(pruned);
            }
            if pruned && let Some(fit) = fit_pair(&cells) {
                assert!(fit.order_stat <= ORDER_THRESHOLD, "trial {trial}: pruned but Λ = {}", fit.order_stat);
            }
        }
        assert!(lone_pruned * 2 > lone, "the bound pruned only {lone_pruned} of {lone} lone regions");
    }
}
