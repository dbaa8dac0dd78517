//! Second returns under soft (JPDA) association (docs/model.md §6.4, §6.8): when one track's gate
//! holds two returns of a channel and the track prefers the other one, the less probable return
//! is taken to be a second target (the other aircraft of a pair the two-target estimator split,
//! docs/model.md §4.9) and may start a track, although it lies inside an existing track's gate.
//!
//! Under GNN a track claims one measurement and the rest of its gate is left to initiation only
//! outside every gate; JPDA claims nothing, so without this rule a young track with a wide gate
//! sitting on a pair keeps the pair's second aircraft from ever starting its own track.

use crate::association::HypothesisTable;

/// Which measurements of a channel are second returns: gated by at least one track, and for every
/// track that gates it, that track's most probable measurement (`β`, ties to the lower index) is
/// another one and this one's `β` is below `max_beta`.
///
/// `beta[t][j]` are the marginal association probabilities of track `t` (`n_meas + 1` columns,
/// the last for "no measurement").
pub fn second_returns(table: &HypothesisTable, beta: &[Vec<f64>], max_beta: f64) -> Vec<bool> {
    let (n, m) = (table.n_tracks, table.n_meas);
    let best: Vec<Option<usize>> = (0..n)
        .map(|t| {
            let row = beta.get(t)?;
            (0..m)
                .filter(|&j| row.get(j).is_some_and(|&b| b > 0.0))
                .max_by(|&a, &b| row[a].total_cmp(&row[b]).then(b.cmp(&a)))
        })
        .collect();
    (0..m)
        .map(|j| {
            let mut gated = false;
            for t in (0..n).filter(|&t| table.get(t, j).is_some()) {
                gated = true;
                let b = beta.get(t).and_then(|row| row.get(j)).copied().unwrap_or(0.0);
                if best[t].is_none_or(|k| k == j) || b >= max_beta {
                    return false;
                }
            }
            gated
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::association::Hypothesis;

    fn table(n: usize, m: usize, gated: &[(usize, usize)]) -> HypothesisTable {
        let mut t = HypothesisTable::new(n, m);
        for &(i, j) in gated {
            t.set(i, j, Some(Hypothesis { nis: 1.0, ln_det_2pi_s: 0.0 }));
        }
        t
    }

    #[test]
    fn the_less_probable_of_two_returns_in_one_gate_is_a_second_return() {
        let t = table(1, 2, &[(0, 0), (0, 1)]);
        let beta = vec![vec![0.8, 0.15, 0.05]];
        assert_eq!(second_returns(&t, &beta, 0.5), vec![false, true]);
        // A probable second return (β ≥ max_beta) stays the track's.
        let beta = vec![vec![0.45, 0.44, 0.11]];
        assert_eq!(second_returns(&t, &beta, 0.4), vec![false, false]);
    }

    #[test]
    fn a_return_some_track_prefers_or_no_track_gates_is_not_a_second_return() {
        // Track 0 prefers 0, track 1 prefers 1; 1 is in both gates. Measurement 2 is gated by no
        // track (ordinary initiation decides about it).
        let t = table(2, 3, &[(0, 0), (0, 1), (1, 1)]);
        let beta = vec![vec![0.7, 0.2, 0.0, 0.1], vec![0.0, 0.9, 0.0, 0.1]];
        assert_eq!(second_returns(&t, &beta, 0.5), vec![false, false, false]);
    }
}
