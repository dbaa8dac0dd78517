//! Hypotheses and data association (docs/model.md §6.5).
//!
//! The tracker fills a [`HypothesisTable`] (one row per track, one column per measurement of one
//! receive channel, `None` outside the gate) and an [`Associator`] turns it into at most one
//! measurement per track and one track per measurement. [`GnnAssociator`] is the global nearest
//! neighbour: an exact rectangular assignment with a per-track miss option
//! ([`mimo_core::assign::assign_with_miss`]), with either the simple NIS cost or the likelihood
//! cost. [`GreedyAssociator`] is the cheap local alternative (and the foil in tests).

use serde::{Deserialize, Serialize};

/// A track–measurement pairing's statistics. For a single Gaussian prediction `nis = νᵀ S⁻¹ ν`
/// and `ln_det_2pi_s = ln |2π S|`; in general `nis` is the gating statistic and
/// `nis + ln_det_2pi_s = −2 ln` (measurement likelihood), which is what the likelihood cost uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hypothesis {
    /// Normalized innovation squared d² = νᵀS⁻¹ν.
    pub nis: f64,
    /// ln|2πS|, for likelihood costs.
    pub ln_det_2pi_s: f64,
}

/// Gated hypotheses of one channel: `entries[t · n_meas + m]`.
#[derive(Debug, Clone, PartialEq)]
pub struct HypothesisTable {
    /// Number of tracks (rows).
    pub n_tracks: usize,
    /// Number of measurements (columns).
    pub n_meas: usize,
    /// Row-major gated hypotheses; `None` outside the gate.
    pub entries: Vec<Option<Hypothesis>>,
}

impl HypothesisTable {
    /// An empty (all-ungated) table.
    pub fn new(n_tracks: usize, n_meas: usize) -> HypothesisTable {
        HypothesisTable { n_tracks, n_meas, entries: vec![None; n_tracks * n_meas] }
    }

    /// The hypothesis of track `t` and measurement `m`.
    pub fn get(&self, t: usize, m: usize) -> Option<Hypothesis> {
        self.entries[t * self.n_meas + m]
    }

    /// Set the hypothesis of track `t` and measurement `m`.
    pub fn set(&mut self, t: usize, m: usize, h: Option<Hypothesis>) {
        self.entries[t * self.n_meas + m] = h;
    }
}

/// The association family.
pub trait Associator: Send + Sync {
    /// The measurement index assigned to each track (`None` = missed).
    fn associate(&self, table: &HypothesisTable) -> Vec<Option<usize>>;

    /// Marginal association probabilities, for soft (JPDA) association; `None` (the default)
    /// means the tracker updates each track with its [`Associator::associate`] measurement only.
    fn probabilities(&self, _table: &HypothesisTable) -> Option<crate::jpda::AssociationProbabilities> {
        None
    }
}

/// Cost of a track–measurement pairing and of a miss.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum AssociationCost {
    /// `c = d²`, miss cost `miss_cost` (usually the gate threshold).
    Nis {
        /// Cost of leaving a track without a measurement.
        miss_cost: f64,
    },
    /// `c = d² + ln|2πS| − 2 ln(P_D/λ_FA)`, miss cost `−2 ln(1 − P_D P_G)`, with `λ_FA` the
    /// false-alarm density in measurement space (per m of R_B per unit u per unit v).
    Likelihood {
        /// Detection probability P_D.
        pd: f64,
        /// False-alarm density λ_FA in measurement space.
        clutter_density: f64,
        /// Gate probability P_G.
        gate_probability: f64,
    },
}

impl Default for AssociationCost {
    fn default() -> Self {
        // λ_FA: P_FA = 1e-6 per cell of 2ΔR ≈ 60 m in R_B and a beam of θ² = 0.0252² in u–v.
        AssociationCost::Likelihood {
            pd: 0.9,
            clutter_density: 1e-6 / (60.0 * 0.0252 * 0.0252),
            gate_probability: 0.999,
        }
    }
}

impl AssociationCost {
    /// Cost of a gated pairing.
    pub fn pair_cost(&self, h: &Hypothesis) -> f64 {
        match *self {
            AssociationCost::Nis { .. } => h.nis,
            AssociationCost::Likelihood { pd, clutter_density, .. } => {
                h.nis + h.ln_det_2pi_s - 2.0 * (pd / clutter_density).ln()
            }
        }
    }

    /// Cost of leaving a track unassigned.
    pub fn miss_cost(&self) -> f64 {
        match *self {
            AssociationCost::Nis { miss_cost } => miss_cost,
            AssociationCost::Likelihood { pd, gate_probability, .. } => {
                -2.0 * (1.0 - pd * gate_probability).max(1e-12).ln()
            }
        }
    }
}

/// Global nearest neighbour: the assignment minimizing the total cost, exactly.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct GnnAssociator {
    /// The pairing and miss costs.
    pub cost: AssociationCost,
}

impl Associator for GnnAssociator {
    fn associate(&self, table: &HypothesisTable) -> Vec<Option<usize>> {
        let (n, m) = (table.n_tracks, table.n_meas);
        if n == 0 {
            return Vec::new();
        }
        if m == 0 {
            return vec![None; n];
        }
        let cost: Vec<f64> = table
            .entries
            .iter()
            .map(|e| match e {
                Some(h) => {
                    let c = self.cost.pair_cost(h);
                    if c.is_finite() { c } else { f64::INFINITY }
                }
                None => f64::INFINITY,
            })
            .collect();
        // A non-finite miss cost (a bad configuration) would make the assignment infeasible;
        // treat it as "never miss when a gated measurement exists".
        let mc = self.cost.miss_cost();
        let mc = if mc.is_finite() { mc } else { 1e9 };
        // A track with no finite pairing can only miss, and leaves the others' assignment as it
        // is (docs/decisions/0043-pregate-and-gnn-over-gating-tracks.md): solve for the others alone.
        let rows: Vec<usize> = (0..n).filter(|&t| cost[t * m..(t + 1) * m].iter().any(|c| c.is_finite())).collect();
        let mut out = vec![None; n];
        if rows.is_empty() {
            return out;
        }
        if rows.len() == n {
            return mimo_core::assign::assign_with_miss(&cost, n, m, &vec![mc; n]);
        }
        let sub: Vec<f64> = rows.iter().flat_map(|&t| cost[t * m..(t + 1) * m].iter().copied()).collect();
        let sol = mimo_core::assign::assign_with_miss(&sub, rows.len(), m, &vec![mc; rows.len()]);
        for (&t, a) in rows.iter().zip(sol) {
            out[t] = a;
        }
        out
    }
}

/// Greedy nearest neighbour: repeatedly take the cheapest remaining gated pair (ties broken by
/// track then measurement index). Not globally optimal.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct GreedyAssociator {
    /// The pairing and miss costs.
    pub cost: AssociationCost,
}

impl Associator for GreedyAssociator {
    fn associate(&self, table: &HypothesisTable) -> Vec<Option<usize>> {
        let (n, m) = (table.n_tracks, table.n_meas);
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for t in 0..n {
            for j in 0..m {
                if let Some(h) = table.get(t, j) {
                    let c = self.cost.pair_cost(&h);
                    if c.is_finite() && c < self.cost.miss_cost() {
                        pairs.push((c, t, j));
                    }
                }
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let mut out = vec![None; n];
        let mut used = vec![false; m];
        for (_, t, j) in pairs {
            if out[t].is_none() && !used[j] {
                out[t] = Some(j);
                used[j] = true;
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(d2: &[&[f64]]) -> HypothesisTable {
        let n = d2.len();
        let m = d2[0].len();
        let mut t = HypothesisTable::new(n, m);
        for (i, row) in d2.iter().enumerate() {
            for (j, &x) in row.iter().enumerate() {
                if x.is_finite() {
                    t.set(i, j, Some(Hypothesis { nis: x, ln_det_2pi_s: 0.0 }));
                }
            }
        }
        t
    }

    #[test]
    fn gnn_is_globally_optimal_where_greedy_is_not() {
        // Track 0 is nearest to measurement 0, but taking it leaves track 1 only measurement 1,
        // outside its gate. The global optimum pairs 0–1 and 1–0.
        let inf = f64::INFINITY;
        let t = table(&[&[0.64, 1.96], &[1.44, inf]]);
        let cost = AssociationCost::Nis { miss_cost: 11.34 };
        let gnn = GnnAssociator { cost }.associate(&t);
        let greedy = GreedyAssociator { cost }.associate(&t);
        assert_eq!(gnn, vec![Some(1), Some(0)]);
        assert_eq!(greedy, vec![Some(0), None]);
    }

    #[test]
    fn gnn_prefers_miss_when_cheaper_and_handles_empty() {
        let t = table(&[&[9.0], &[1.0]]);
        let cost = AssociationCost::Nis { miss_cost: 5.0 };
        assert_eq!(GnnAssociator { cost }.associate(&t), vec![None, Some(0)]);
        assert_eq!(GnnAssociator { cost }.associate(&HypothesisTable::new(2, 0)), vec![None, None]);
        assert!(GnnAssociator { cost }.associate(&HypothesisTable::new(0, 3)).is_empty());
    }

    /// Tracks with nothing in their gate are left out of the assignment; the others' result
    /// is the full problem's (a hand-made case with a tie between two measurements).
    #[test]
    fn gnn_without_the_empty_rows_is_the_full_assignment() {
        let inf = f64::INFINITY;
        let t = table(&[&[inf, inf, inf], &[2.0, 2.0, inf], &[inf, inf, inf], &[1.0, 3.0, 5.0], &[inf, 4.0, 4.0]]);
        let cost = AssociationCost::Nis { miss_cost: 11.34 };
        let out = GnnAssociator { cost }.associate(&t);
        assert_eq!(out, vec![None, Some(1), None, Some(0), Some(2)]);
        // The same as solving the full matrix with its miss options.
        let full: Vec<f64> = t.entries.iter().map(|e| e.map_or(inf, |h| h.nis)).collect();
        let direct = mimo_core::assign::assign_with_miss(&full, 5, 3, &[11.34; 5]);
        assert_eq!(out, direct);
        assert_eq!(GnnAssociator { cost }.associate(&table(&[&[inf], &[inf]])), vec![None, None]);
    }

    #[test]
    fn likelihood_cost_prefers_the_sharper_track() {
        // Same d² but track 1 has a much smaller |S|: it wins the single measurement.
        let mut t = HypothesisTable::new(2, 1);
        t.set(0, 0, Some(Hypothesis { nis: 2.0, ln_det_2pi_s: 10.0 }));
        t.set(1, 0, Some(Hypothesis { nis: 2.0, ln_det_2pi_s: -5.0 }));
        let out = GnnAssociator::default().associate(&t);
        assert_eq!(out, vec![None, Some(0)]);
    }
}
