//! The measurement rung of the fidelity ladder (docs/model.md §4.8): a channel's detections drawn
//! from the statistics the voltage level produces, without simulating its cells' Δ voltages, its
//! ±W explicit cells or running the ML monopulse estimator.
//!
//! Per channel, the returns of [`crate::dwell`]'s selection (the same returns and fluctuation draws
//! as the voltage level) are grouped: two returns whose `ρ` differ by less than one range cell and
//! whose receive directions differ by less than one beamwidth in `u` and in `v` are one group
//! (single linkage), §2.7's unresolved pair. For each group:
//!
//! 1. **Threshold statistic.** The sum-channel voltage of each cell the group's returns straddle is
//!    `Σ_k = Σ_t a_t·p(kΔR − ρ_t) + n_k`, `n_k ~ CN(0,1)`, with `a_t` the return's fluctuated
//!    amplitude and `p` the §4.1 triangle: given the fluctuation, `2|Σ_k|²` is non-central χ²₂ with
//!    non-centrality `2|Σ_t a_t p_t|²`. It is drawn as that sum (one complex normal per cell), which
//!    is the distribution the voltage level's detector sees, straddle included. The guard cells on
//!    either side are noise conditioned below the threshold (their own crossings, probability
//!    `P_FA` each, are neglected).
//! 2. **Detection** as in [`crate::detect`]: the strongest cell is the peak and it is detected when
//!    `|Σ|² > γ`; its larger neighbour is paired with it, `S = |Σ_{k*}|² + |Σ_{k'}|²`,
//!    `x̂ = A₁/(A₀+A₁)`; a cluster at least three cells wide or the other neighbour crossing sets
//!    the merged flag.
//! 3. **Measurement** = truth + Gaussian error with the covariance the voltage level reports for
//!    those observed statistics (the same functions: [`crate::detect::range_sigma_m`] of `A₀², x̂`,
//!    and the §2.6 ratio variance `(1 + cη²)/(2Sc²)` through the slope of the inverse monopulse
//!    curve at the true ratio, with the same ML bias factor). The reported variances carry the
//!    §4.6 floors (`σ_ρ ≥ 1 m`, `σ_u, σ_v ≥ 1e-4`); the drawn errors do not, as the voltage
//!    level's errors do not. Truth is the return's
//!    `(ρ, u, v)` (receive-face sine space, apparent direction with refraction), or for a group the
//!    power-weighted centroid (weights `|a_t g_Σ|²`). Estimates more than a beamwidth off the beam
//!    are rejected as in the voltage level.
//! 4. **Merged flag** (§2.7): the imaginary parts `η_Q` are drawn as their noise-free value (zero
//!    for one target; the group's noise-free `Σ Im(Δ_k Σ_k*)/S` for several) plus normal noise of
//!    variance `(1 + cη²)/(2S)`, so `T` is χ²₂ for one target and non-central χ²₂ for a group, and
//!    `merged = T > 9.21` or the clustering flags above.
//!
//! False alarms: the §4.4 binomial shortcut over the window's cells outside the groups' cells, on
//! the same stream as the voltage level, detected by [`crate::detect`]. Waveform leakage (§5.3) is
//! not modelled at this rung (the `auto` rung uses the voltage level when it is on).
//!
//! Random draws: one stream per (channel, group), keyed `(dwell keys…, KEY_STATISTICAL, tx, rx,
//! index of the group's first target)`.

use crate::channel::{false_alarm_cells, merge_intervals, open_channel};
use crate::detect::{Cell, MIN_SIGMA_UV, range_f2_observed, range_sigma_m};
use crate::dwell::{Channel, Dwell, Return, Target, channel_info, cn, detect_channel, stream};
use crate::monopulse::{MERGE_T_THRESHOLD, ml_bias_factor};
use crate::pattern::Antenna;
use crate::range::triangle;
use mimo_core::records::PrimitiveRow;
use mimo_core::rng::Stream;
use num_complex::Complex64;

/// Sub-key of the measurement rung's streams ("STAT").
const KEY_STATISTICAL: u64 = 0x5354_4154;

/// Group a channel's returns into unresolved sets: single linkage on `|Δρ| < ΔR`, `|Δu| < θ_u`,
/// `|Δv| < θ_v`. Groups are sorted by their first member, members by index.
pub fn unresolved_groups(rets: &[Return], range_cell_m: f64, theta_u: f64, theta_v: f64) -> Vec<Vec<usize>> {
    let n = rets.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    for a in 0..n {
        for b in a + 1..n {
            let (ra, rb) = (&rets[a], &rets[b]);
            if (ra.rho_m - rb.rho_m).abs() < range_cell_m
                && (ra.u - rb.u).abs() < theta_u
                && (ra.v - rb.v).abs() < theta_v
            {
                let (x, y) = (root(&mut parent, a), root(&mut parent, b));
                parent[x.max(y)] = x.min(y);
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut slot = vec![usize::MAX; n];
    for t in 0..n {
        let r = root(&mut parent, t);
        if slot[r] == usize::MAX {
            slot[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[slot[r]].push(t);
    }
    groups
}

/// One cell of a group: Σ voltage and the noise-free signal voltages.
struct GroupCell {
    k: i64,
    sum: Complex64,
    signal: (Complex64, Complex64, Complex64),
}

/// The channel `(j → i)` at the measurement rung: its [`Channel`] (cells: the false-alarm cells
/// only) and its primitives.
pub(crate) fn measure_channel(
    d: &Dwell,
    j: usize,
    i: usize,
    returns: &[Vec<Vec<Return>>],
    targets: &[Target],
) -> (Channel, Vec<PrimitiveRow>) {
    let tx = &d.transmitters[j];
    let rx = &d.receivers[i];
    let dr = rx.params.range_cell_m();
    let rets = &returns[j][i];
    let mut ch = open_channel(d, j, i, returns);
    let Some((kmin, kmax)) = ch.window else { return (ch, Vec::new()) };
    let mut segs = Vec::new();
    let mut out = Vec::new();
    // Most channels (every empty search dwell) have no return: no antenna, no groups.
    let ant = (!rets.is_empty()).then(|| Antenna::new(rx.params, d.fidelity.pattern));
    let groups = ant.as_ref().map_or_else(Vec::new, |a| unresolved_groups(rets, dr, a.theta_u(), a.theta_v()));
    for g in &groups {
        let k_lo = g.iter().map(|&t| (rets[t].rho_m / dr).floor() as i64).min().unwrap_or(0);
        let k_hi = g.iter().map(|&t| (rets[t].rho_m / dr).floor() as i64 + 1).max().unwrap_or(0);
        let (a, b) = ((k_lo - 1).max(kmin), (k_hi + 1).min(kmax));
        if a > b {
            continue;
        }
        segs.push((a, b));
        let first = targets.get(rets[g[0]].target).map_or(0, |t| u64::from(t.index));
        let mut s = stream(d, &[KEY_STATISTICAL, tx.radar.0 as u64, rx.radar.0 as u64, first]);
        if let Some(ant) = &ant
            && let Some(p) = group_primitive(d, i, j, rets, g, (a, b), (k_lo, k_hi), ant, &mut s, targets)
        {
            out.push(p);
        }
    }
    // False alarms over the rest of the window (§4.4), detected as at the voltage level.
    let segs = if segs.len() > 1 { merge_intervals(segs) } else { segs };
    let fa = false_alarm_cells(d, j, i, (kmin, kmax), &segs);
    ch.shortcut_cells = fa.shortcut_cells;
    ch.false_alarms = fa.false_alarms;
    if !fa.cells.is_empty() {
        ch.cells = fa.cells;
        ch.cells.sort_unstable_by_key(|c: &Cell| c.k);
        out.extend(detect_channel(d, &ch, targets));
    }
    (ch, out)
}

#[allow(clippy::too_many_arguments)]
fn group_primitive(
    d: &Dwell,
    i: usize,
    j: usize,
    rets: &[Return],
    g: &[usize],
    cells_ab: (i64, i64),
    signal_ab: (i64, i64),
    ant: &Antenna,
    s: &mut Stream,
    targets: &[Target],
) -> Option<PrimitiveRow> {
    let rx = &d.receivers[i];
    let info = channel_info(d, j, i, ant);
    let (dr, gamma) = (info.range_cell_m, info.threshold);
    // 1. The Σ voltages of the straddled cells and their guard cells.
    let cells = group_cells(rets, g, cells_ab, signal_ab, dr, gamma, s);
    // 2. Detection.
    let pw: Vec<f64> = cells.iter().map(|c| c.sum.norm_sqr()).collect();
    let peak = detect_peak(&pw, gamma)?;
    let (m, nb) = (peak.m, peak.nb);
    let a0 = pw[m].sqrt();
    let a1 = nb.map_or(0.0, |x| pw[x].sqrt());
    let s_obs = (pw[m] + nb.map_or(0.0, |x| pw[x])).max(f64::MIN_POSITIVE);
    let x_hat = if a0 + a1 > 0.0 { a1 / (a0 + a1) } else { 0.0 };

    // 3. Truth (power-weighted centroid of the group) and the reported covariance.
    let (rho, u, v) = group_centroid(rets, g);
    let c = ml_bias_factor(rx.predicted_snr);
    let (eta_a, eta_e) = ant.ratio(u - rx.beam_u, v - rx.beam_v);
    let vq_a = (1.0 + c * eta_a * eta_a) / (2.0 * s_obs);
    let vq_e = (1.0 + c * eta_e * eta_e) / (2.0 * s_obs);
    let (su, sv) = ant.offset_slope(eta_a, eta_e);
    // The errors follow the estimator's spread; the reported variances carry the floors, as at the
    // voltage level (whose errors do not know about the floors either).
    let spread_u = su * su * vq_a / (c * c);
    let spread_v = sv * sv * vq_e / (c * c);
    let spread_r = range_f2_observed(pw[m], x_hat).sqrt() * dr / (2.0 * pw[m]).sqrt();
    let var_u = spread_u.max(MIN_SIGMA_UV * MIN_SIGMA_UV);
    let var_v = spread_v.max(MIN_SIGMA_UV * MIN_SIGMA_UV);
    let sig_r = range_sigma_m(pw[m], x_hat, dr);
    let rho_hat = rho + spread_r * s.normal();
    let u_hat = u + spread_u.sqrt() * s.normal();
    let v_hat = v + spread_v.sqrt() * s.normal();
    if !((u_hat - rx.beam_u).abs() <= ant.theta_u() && (v_hat - rx.beam_v).abs() <= ant.theta_v()) {
        return None;
    }
    // 4. The imaginary-part statistic (§2.7).
    let (qa, qe) = if g.len() > 1 { imaginary_parts(&cells, m, nb) } else { (0.0, 0.0) };
    let eta_qa = qa / s_obs + vq_a.sqrt() * s.normal();
    let eta_qe = qe / s_obs + vq_e.sqrt() * s.normal();
    let t_stat = eta_qa * eta_qa / vq_a + eta_qe * eta_qe / vq_e;
    let merged = t_stat > MERGE_T_THRESHOLD || peak.wide || peak.other_crosses;
    let k_peak = cells[m].k;
    Some(PrimitiveRow {
        range_cell: k_peak,
        range_m: rho_hat,
        u: u_hat,
        v: v_hat,
        snr_db: 10.0 * s_obs.log10(),
        eta_q: t_stat,
        merged,
        var_range_m2: sig_r * sig_r,
        var_u,
        var_v,
        target_hint: dominant_target(rets, g, k_peak, dr, targets),
        ..info.channel_columns()
    })
}

/// The Σ, Δaz and Δel signal voltages of cells `cells_ab` of a group, and each cell's Σ voltage
/// with noise: signal plus noise in the straddled cells `signal_ab`, noise conditioned below the
/// threshold `gamma` in the guard cells.
fn group_cells(
    rets: &[Return],
    g: &[usize],
    cells_ab: (i64, i64),
    signal_ab: (i64, i64),
    dr: f64,
    gamma: f64,
    s: &mut Stream,
) -> Vec<GroupCell> {
    let below = 1.0 - (-gamma).exp();
    let mut cells: Vec<GroupCell> = Vec::with_capacity((cells_ab.1 - cells_ab.0 + 1) as usize);
    for k in cells_ab.0..=cells_ab.1 {
        let mut sig = (Complex64::default(), Complex64::default(), Complex64::default());
        for &t in g {
            let p = triangle(k as f64 * dr - rets[t].rho_m, dr);
            sig.0 += rets[t].sum * p;
            sig.1 += rets[t].az * p;
            sig.2 += rets[t].el * p;
        }
        let sum = if k >= signal_ab.0 && k <= signal_ab.1 {
            sig.0 + cn(s)
        } else {
            // A guard cell: noise conditioned below the threshold.
            let p2 = -(1.0 - s.uniform() * below).ln();
            Complex64::from_polar(p2.sqrt(), s.phase())
        };
        cells.push(GroupCell { k, sum, signal: sig });
    }
    cells
}

/// The detection of a group's cells.
struct Peak {
    /// The strongest cell.
    m: usize,
    /// Its stronger neighbour.
    nb: Option<usize>,
    /// Three or more consecutive cells cross the threshold.
    wide: bool,
    /// The weaker neighbour crosses the threshold too.
    other_crosses: bool,
}

/// The strongest of the cell powers `pw` (the first on ties, as the detector's local-maximum
/// rule) if it crosses the threshold `gamma`.
fn detect_peak(pw: &[f64], gamma: f64) -> Option<Peak> {
    let mut m = 0;
    for (n, &p) in pw.iter().enumerate() {
        if p > pw[m] {
            m = n;
        }
    }
    if pw[m] <= gamma {
        return None;
    }
    let left = m.checked_sub(1);
    let right = (m + 1 < pw.len()).then_some(m + 1);
    let (nb, other) = match (left, right) {
        (Some(l), Some(r)) if pw[r] > pw[l] => (Some(r), Some(l)),
        (Some(l), Some(r)) => (Some(l), Some(r)),
        (l, r) => (l.or(r), None),
    };
    let (mut c0, mut c1) = (m, m);
    while c0 > 0 && pw[c0 - 1] > gamma {
        c0 -= 1;
    }
    while c1 + 1 < pw.len() && pw[c1 + 1] > gamma {
        c1 += 1;
    }
    Some(Peak { m, nb, wide: c1 - c0 + 1 >= 3, other_crosses: other.is_some_and(|o| pw[o] > gamma) })
}

/// The power-weighted centroid `(ρ, u, v)` of a group's returns.
fn group_centroid(rets: &[Return], g: &[usize]) -> (f64, f64, f64) {
    let (mut wsum, mut rho, mut u, mut v) = (0.0, 0.0, 0.0, 0.0);
    for &t in g {
        let w = rets[t].sum.norm_sqr().max(f64::MIN_POSITIVE);
        wsum += w;
        rho += w * rets[t].rho_m;
        u += w * rets[t].u;
        v += w * rets[t].v;
    }
    (rho / wsum, u / wsum, v / wsum)
}

/// The noise-free imaginary parts of Δaz·Σ* and Δel·Σ* over the peak cell and its neighbour.
fn imaginary_parts(cells: &[GroupCell], m: usize, nb: Option<usize>) -> (f64, f64) {
    let (mut qa, mut qe) = (0.0, 0.0);
    for n in std::iter::once(m).chain(nb) {
        let (ss, sa, se) = cells[n].signal;
        qa += (sa * ss.conj()).im;
        qe += (se * ss.conj()).im;
    }
    (qa, qe)
}

/// The dominant target of the peak cell `k_peak`, which names the primitive.
fn dominant_target(rets: &[Return], g: &[usize], k_peak: i64, dr: f64, targets: &[Target]) -> Option<String> {
    g.iter()
        .map(|&t| (t, rets[t].sum.norm_sqr() * triangle(k_peak as f64 * dr - rets[t].rho_m, dr).powi(2)))
        .filter(|&(_, p)| p > 0.0)
        .fold(None, |best: Option<(usize, f64)>, x| if best.is_none_or(|b| x.1 > b.1) { Some(x) } else { best })
        .and_then(|(t, _)| targets.get(rets[t].target).map(|x| x.id.to_string()))
}
