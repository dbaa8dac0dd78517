//! Joint probabilistic data association (docs/model.md §6.8).
//!
//! [`JpdaAssociator`] turns a channel's [`HypothesisTable`] into marginal association
//! probabilities `β_tj` (and `β_t0`, no measurement) by enumerating the feasible joint events of
//! each cluster of tracks that share gated measurements. [`combine`] then merges the
//! per-measurement posteriors of one track into one state by moment matching, which for a
//! Kalman update with a common gain is exactly the PDA update with its spread-of-means term.

use crate::association::{AssociationCost, Associator, GnnAssociator, HypothesisTable};
use crate::filter::{FilterPrediction, FilterState, moment_match};
use crate::frame::Gaussian;
use serde::{Deserialize, Serialize};

/// JPDA over one receive channel with a Poisson clutter model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct JpdaAssociator {
    /// Detection probability P_D, gate probability P_G and clutter density λ (the likelihood
    /// cost's parameters).
    pub cost: AssociationCost,
    /// Largest number of joint events enumerated in one cluster; a larger cluster falls back to
    /// the GNN assignment (β = 1 on the assigned measurement). Default 20 000.
    pub max_events: usize,
    /// Association probabilities below this are dropped (and the rest renormalized), so that
    /// far-fetched pairings do not cost an update. Default 0.01.
    pub min_probability: f64,
}

impl Default for JpdaAssociator {
    fn default() -> Self {
        JpdaAssociator { cost: AssociationCost::default(), max_events: 20_000, min_probability: 0.01 }
    }
}

/// Marginal association probabilities of one channel: `beta[t][j]` for measurement `j`, and
/// `beta[t][n_meas]` for "no measurement" (each row sums to 1).
#[derive(Debug, Clone, PartialEq)]
pub struct AssociationProbabilities {
    /// One row per track, `n_meas + 1` columns.
    pub beta: Vec<Vec<f64>>,
}

impl JpdaAssociator {
    /// ln of the likelihood ratio of pairing `(t, j)` against clutter: `−c/2` with the
    /// likelihood cost `c = d² + ln|2πS| − 2 ln(P_D/λ)`.
    fn log_pair(&self, table: &HypothesisTable, t: usize, j: usize) -> Option<f64> {
        let h = table.get(t, j)?;
        let c = self.cost.pair_cost(&h);
        c.is_finite().then_some(-0.5 * c)
    }

    /// The marginal association probabilities of every track of the table.
    pub fn probabilities(&self, table: &HypothesisTable) -> AssociationProbabilities {
        let (n, m) = (table.n_tracks, table.n_meas);
        let mut beta = vec![vec![0.0; m + 1]; n];
        let log_miss = -0.5 * self.cost.miss_cost();
        let members = clusters(table);
        // The GNN assignment is the fallback of a cluster with too many (or no) joint events.
        let mut gnn: Option<Vec<Option<usize>>> = None;
        let mut tracks: Vec<usize> = Vec::new();
        let mut options: Vec<(usize, f64)> = Vec::new();
        let mut starts: Vec<usize> = Vec::new();
        let mut used = vec![false; m];
        let mut choice: Vec<usize> = Vec::new();
        for cluster in &members {
            // A track that gates nothing misses for sure (its only event, β = 1 on "none").
            if let [t] = cluster[..]
                && log_miss.is_finite()
                && (0..m).all(|j| table.get(t, j).is_none())
            {
                beta[t][m] = 1.0;
                continue;
            }
            tracks.clear();
            tracks.extend_from_slice(cluster);
            // Each track's options, one after another: "none", then its gated measurements.
            options.clear();
            starts.clear();
            for &t in &tracks {
                starts.push(options.len());
                options.push((m, log_miss));
                options.extend((0..m).filter_map(|j| self.log_pair(table, t, j).map(|l| (j, l))));
            }
            starts.push(options.len());
            choice.clear();
            choice.resize(tracks.len(), 0);
            let mut ev = Enumeration { options: &options, starts: &starts, used: &mut used, choice: &mut choice };
            // Pass 1: how many joint events, and the largest log weight. Pass 2 (below) visits
            // the same events in the same order, so the sums are those of one stored list.
            let mut count = 0usize;
            let mut top = f64::NEG_INFINITY;
            let limit = self.max_events;
            let complete = ev.walk(0, 0.0, &mut |_, l| {
                if count >= limit {
                    return false;
                }
                count += 1;
                top = top.max(l);
                true
            });
            if !complete || count == 0 {
                let gnn = gnn.get_or_insert_with(|| GnnAssociator { cost: self.cost }.associate(table));
                for &t in &tracks {
                    beta[t][gnn.get(t).copied().flatten().filter(|&j| j < m).unwrap_or(m)] = 1.0;
                }
                continue;
            }
            let mut total = 0.0;
            ev.walk(0, 0.0, &mut |choice, l| {
                let w = (l - top).exp();
                total += w;
                for (k, &t) in tracks.iter().enumerate() {
                    beta[t][options[starts[k] + choice[k]].0] += w;
                }
                true
            });
            self.normalize(&mut beta, &tracks, total);
        }
        AssociationProbabilities { beta }
    }

    /// Divide the rows of `tracks` by the cluster's `total` weight, drop the probabilities below
    /// `min_probability` and renormalize each row to 1.
    fn normalize(&self, beta: &mut [Vec<f64>], tracks: &[usize], total: f64) {
        for &t in tracks {
            let m = beta[t].len() - 1;
            let row = &mut beta[t];
            row.iter_mut().for_each(|b| *b /= total);
            for b in row.iter_mut().take(m) {
                if *b < self.min_probability {
                    *b = 0.0;
                }
            }
            let s: f64 = row.iter().sum();
            row.iter_mut().for_each(|b| *b /= s);
        }
    }
}

/// The clusters of a table: tracks connected through shared gated measurements, each in
/// increasing track order, numbered in order of their first track. A sweep over the gated pairs
/// (each track's row and each measurement's column once), so that a channel's cost follows its
/// gated pairs rather than tracks × tracks.
fn clusters(table: &HypothesisTable) -> Vec<Vec<usize>> {
    let (n, m) = (table.n_tracks, table.n_meas);
    let rows: Vec<Vec<usize>> = (0..n).map(|t| (0..m).filter(|&j| table.get(t, j).is_some()).collect()).collect();
    let mut cols: Vec<Vec<usize>> = vec![Vec::new(); m];
    for (t, row) in rows.iter().enumerate() {
        row.iter().for_each(|&j| cols[j].push(t));
    }
    let mut cluster = vec![usize::MAX; n];
    let mut col_done = vec![false; m];
    let mut members: Vec<Vec<usize>> = Vec::new();
    let mut stack = Vec::new();
    for start in 0..n {
        if cluster[start] != usize::MAX {
            continue;
        }
        let c = members.len();
        let mut these = vec![start];
        cluster[start] = c;
        stack.push(start);
        while let Some(t) = stack.pop() {
            for &j in &rows[t] {
                if std::mem::replace(&mut col_done[j], true) {
                    continue;
                }
                for &u in &cols[j] {
                    if cluster[u] == usize::MAX {
                        cluster[u] = c;
                        these.push(u);
                        stack.push(u);
                    }
                }
            }
        }
        these.sort_unstable();
        members.push(these);
    }
    members
}

/// Depth-first enumeration of the feasible joint events of one cluster: each track takes one of
/// its options (a gated measurement not taken by another track, or none). Track `k`'s options are
/// `options[starts[k]..starts[k + 1]]`; an event is handed to the visitor as each track's option
/// index and the event's log weight, in a fixed order, without being stored.
struct Enumeration<'a> {
    options: &'a [(usize, f64)],
    starts: &'a [usize],
    used: &'a mut [bool],
    choice: &'a mut [usize],
}

impl Enumeration<'_> {
    /// Visit every event from track `k` on; `false` when the visitor stopped the walk.
    fn walk(&mut self, k: usize, log_w: f64, visit: &mut impl FnMut(&[usize], f64) -> bool) -> bool {
        if k == self.choice.len() {
            return visit(&*self.choice, log_w);
        }
        let first = self.starts[k];
        for o in 0..(self.starts[k + 1] - first) {
            let (j, l) = self.options[first + o];
            let real = j < self.used.len();
            if real && self.used[j] {
                continue;
            }
            if real {
                self.used[j] = true;
            }
            self.choice[k] = o;
            let go_on = self.walk(k + 1, log_w + l, visit);
            if real {
                self.used[j] = false;
            }
            if !go_on {
                return false;
            }
        }
        true
    }
}

impl Associator for JpdaAssociator {
    /// The most probable measurement of each track (for callers that want one).
    fn associate(&self, table: &HypothesisTable) -> Vec<Option<usize>> {
        let m = table.n_meas;
        self.probabilities(table)
            .beta
            .iter()
            .map(|row| {
                let (j, _) = row.iter().enumerate().fold((m, -1.0), |a, (j, &b)| if b > a.1 { (j, b) } else { a });
                (j < m).then_some(j)
            })
            .collect()
    }

    fn probabilities(&self, table: &HypothesisTable) -> Option<AssociationProbabilities> {
        Some(JpdaAssociator::probabilities(self, table))
    }
}

/// The state of a track after a JPDA update: the mixture of the prediction (weight `beta0`) and
/// the per-measurement posteriors `(β_j, state_j)`, moment-matched mode by mode. Mode `i`'s
/// probability is `Σ_j β_j μ_ij` (with `μ_i0 = c̄_i`), its estimate the β·μ-weighted moment
/// match of the mode's estimates; for one mode this is the PDA update `x = x̄ + K Σ β_j ν_j`,
/// `P = β₀ P̄ + (1 − β₀) P_c + K (Σ β_j ν_j ν_jᵀ − ν νᵀ) Kᵀ`.
pub fn combine(pred: &FilterPrediction, beta0: f64, posteriors: &[(f64, FilterState)]) -> FilterState {
    let n_modes = pred.modes.len();
    let mut mu = vec![0.0; n_modes];
    let mut modes = Vec::with_capacity(n_modes);
    for (i, mu_i) in mu.iter_mut().enumerate() {
        let mut w: Vec<f64> = vec![beta0 * pred.cbar[i]];
        let mut g: Vec<Gaussian> = vec![pred.modes[i]];
        for (b, s) in posteriors {
            w.push(b * s.mu[i]);
            g.push(s.modes[i]);
        }
        let total: f64 = w.iter().sum();
        *mu_i = total;
        if total > 0.0 {
            w.iter_mut().for_each(|x| *x /= total);
            modes.push(moment_match(&w, &g));
        } else {
            modes.push(pred.modes[i]);
        }
    }
    let s: f64 = mu.iter().sum();
    if s > 0.0 {
        mu.iter_mut().for_each(|x| *x /= s);
    }
    FilterState { modes, mu }
}
