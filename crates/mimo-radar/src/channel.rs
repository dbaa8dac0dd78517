//! One Tx→Rx channel's simulated cells (docs/model.md §2.4, §4.4, §5.3): noise and target
//! voltages in the cells around each return, the binomial false-alarm shortcut for the rest of the
//! window, and waveform leakage from the other transmitters.

use crate::detect::{Cell, Source};
use crate::dwell::{Channel, Dwell, KEY_FALSE_ALARM, KEY_LEAKAGE, KEY_NOISE, LEAKAGE_FLOOR, Return, cn, stream};
use crate::range::{cell_window, triangle};
use mimo_core::ids::RadarId;
use mimo_core::{SPEED_OF_LIGHT_MPS, db_to_lin};
use num_complex::Complex64;
use std::collections::BTreeSet;

/// Merge closed integers intervals (sorted output, disjoint, non-adjacent merged too).
pub(crate) fn merge_intervals(mut iv: Vec<(i64, i64)>) -> Vec<(i64, i64)> {
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

/// Channel `(j → i)` with its returns and cell window (§4.4, §5.2) and no cells yet: where both
/// rungs of the ladder (docs/model.md §4.8) start.
pub(crate) fn open_channel(d: &Dwell, j: usize, i: usize, returns: &[Vec<Vec<Return>>]) -> Channel {
    let tx = &d.transmitters[j];
    let rx = &d.receivers[i];
    let (lo, hi) = rx.window.limits(tx.frame.origin_ecef, rx.frame.origin_ecef);
    let window = cell_window(lo, hi, rx.params.range_cell_m());
    Channel {
        tx: j,
        rx: i,
        window,
        cells: Vec::new(),
        returns: returns[j][i].clone(),
        shortcut_cells: 0,
        false_alarms: 0,
    }
}

/// Simulate one channel's cells.
pub(crate) fn simulate_channel(d: &Dwell, j: usize, i: usize, returns: &[Vec<Vec<Return>>]) -> Channel {
    let rets = &returns[j][i];
    let mut ch = open_channel(d, j, i, returns);
    let Some((kmin, kmax)) = ch.window else { return ch };
    let leaks = leakage(d, j, i, returns, (kmin, kmax));
    let segs = explicit_segments(d, i, rets, &leaks, (kmin, kmax));
    let mut cells = explicit_cells(d, j, i, rets, &leaks, &segs);

    // False alarms in the remaining noise-only cells (§4.4).
    if !d.simulate_all_cells {
        let fa = false_alarm_cells(d, j, i, (kmin, kmax), &segs);
        ch.shortcut_cells = fa.shortcut_cells;
        ch.false_alarms = fa.false_alarms;
        if !fa.cells.is_empty() {
            cells.extend(fa.cells);
            cells.sort_unstable_by_key(|c| c.k);
        }
    }
    ch.cells = cells;
    ch
}

/// The echo of another transmitter's waveform leaking into channel `(j → i)` (§5.3): cells
/// `k0..=k1` get noise of standard deviations `sd` (Σ, Δaz, Δel).
struct Leak {
    target: usize,
    k0: i64,
    k1: i64,
    sd: [f64; 3],
    tx: RadarId,
}

/// The leaks into channel `(j → i)` within `window` from the other transmitters' echoes, when the
/// waveform isolation is modelled.
fn leakage(d: &Dwell, j: usize, i: usize, returns: &[Vec<Vec<Return>>], window: (i64, i64)) -> Vec<Leak> {
    let (kmin, kmax) = window;
    let dr = d.receivers[i].params.range_cell_m();
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
    leaks
}

/// The explicitly simulated cells of receiver `i`'s `window`, as merged segments: the whole
/// window, or `explicit_cells_each_side` cells around each return and the leaks' cells.
fn explicit_segments(d: &Dwell, i: usize, rets: &[Return], leaks: &[Leak], window: (i64, i64)) -> Vec<(i64, i64)> {
    let (kmin, kmax) = window;
    let dr = d.receivers[i].params.range_cell_m();
    let w = i64::from(d.fidelity.explicit_cells_each_side);
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
        for l in leaks {
            iv.push((l.k0, l.k1));
        }
    }
    merge_intervals(iv)
}

/// The cells of the segments `segs` of channel `(j → i)`, sorted: noise, then the returns'
/// voltages and the leaks.
fn explicit_cells(d: &Dwell, j: usize, i: usize, rets: &[Return], leaks: &[Leak], segs: &[(i64, i64)]) -> Vec<Cell> {
    let tx = &d.transmitters[j];
    let rx = &d.receivers[i];
    let dr = rx.params.range_cell_m();
    // Noise in the explicit cells.
    let mut noise = stream(d, &[KEY_NOISE, tx.radar.0 as u64, rx.radar.0 as u64]);
    let explicit: i64 = segs.iter().map(|&(a, b)| b - a + 1).sum();
    let mut cells = Vec::with_capacity(explicit as usize + 8);
    for &(a, b) in segs {
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
    for l in leaks {
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
    cells
}

/// What the §4.4 shortcut drew in the noise-only cells of a channel's window.
pub(crate) struct FalseAlarms {
    /// Cells of the window outside `segs` (handled by the shortcut).
    pub shortcut_cells: u64,
    /// Threshold crossings drawn among them.
    pub false_alarms: u64,
    /// The crossing cells and their neighbours (noise conditioned below the threshold), unsorted.
    pub cells: Vec<Cell>,
}

/// The §4.4 false-alarm shortcut over the cells of `[kmin, kmax]` outside the explicit segments
/// `segs` (sorted, disjoint), on the channel `(j → i)`'s false-alarm stream.
pub(crate) fn false_alarm_cells(d: &Dwell, j: usize, i: usize, window: (i64, i64), segs: &[(i64, i64)]) -> FalseAlarms {
    let tx = &d.transmitters[j];
    let rx = &d.receivers[i];
    let (kmin, kmax) = window;
    let explicit: i64 = segs.iter().map(|&(a, b)| b - a + 1).sum();
    let m = (kmax - kmin + 1 - explicit).max(0) as u64;
    let mut fa = stream(d, &[KEY_FALSE_ALARM, tx.radar.0 as u64, rx.radar.0 as u64]);
    let n_fa = fa.binomial(m, rx.params.pfa);
    let mut extra: Vec<Cell> = Vec::new();
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
                for &(a, b) in segs {
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
        extra.reserve(3 * fa_cells.len());
        for &k in &fa_cells {
            let amp = (gamma + fa.exp1()).sqrt();
            let sum = Complex64::from_polar(amp, fa.phase());
            extra.push(Cell { k, sum, az: cn(&mut fa), el: cn(&mut fa), source: None });
        }
        for &k in &fa_cells {
            for n in [k - 1, k + 1] {
                if n < kmin || n > kmax || in_segments(segs, n) || !taken.insert(n) {
                    continue;
                }
                // Noise conditioned below threshold: |Σ|² ~ Exp(1) truncated to [0, γ).
                let p2 = -(1.0 - fa.uniform() * below).ln();
                let sum = Complex64::from_polar(p2.sqrt(), fa.phase());
                extra.push(Cell { k: n, sum, az: cn(&mut fa), el: cn(&mut fa), source: None });
            }
        }
    }
    FalseAlarms { shortcut_cells: m, false_alarms: n_fa, cells: extra }
}
