//! The tracks one receive channel reached: those with a pair that passed the pre-gate, with
//! their gated hypotheses and their predictions (docs/model.md §6.5, §6.8).
//!
//! A channel gates every track, but in a raid nearly every track is far from its few
//! measurements and is rejected by the pre-gate without a prediction. Such a track gates nothing:
//! for JPDA it is a cluster of its own that misses for sure, so it changes no association
//! probability and no track. The association then runs on the reached tracks alone (a table of
//! reached tracks × measurements), so a channel's association cost follows the tracks near its
//! measurements rather than all tracks; the hard (GNN) path, whose partner rules may look at a
//! track that gated nothing, gets the full table back ([`widen`]).

use crate::association::{Hypothesis, HypothesisTable};

/// The reached tracks of one channel, built track by track ([`Reached::gate`],
/// [`Reached::push_row`]) and closed with [`Reached::finish`].
#[derive(Debug)]
pub(crate) struct Reached<C> {
    /// Index (in the channel's track list) of each reached track, increasing.
    pub(crate) rows: Vec<usize>,
    /// Each reached track's predictions.
    pub(crate) caches: Vec<C>,
    /// The gated hypotheses: one row per reached track (filled by [`Reached::finish`]).
    pub(crate) table: HypothesisTable,
    /// Which measurements lie inside an existing track's resolution cell or exclusion gate.
    pub(crate) near: Vec<bool>,
    /// The current track's row (all `None` between tracks).
    row: Vec<Option<Hypothesis>>,
}

impl<C> Reached<C> {
    /// Nothing reached yet, for a channel of `n_meas` measurements.
    pub(crate) fn new(n_meas: usize) -> Reached<C> {
        Reached {
            rows: Vec::new(),
            caches: Vec::new(),
            table: HypothesisTable { n_tracks: 0, n_meas, entries: Vec::new() },
            near: vec![false; n_meas],
            row: vec![None; n_meas],
        }
    }

    /// The current track gates measurement `j` with hypothesis `h`.
    pub(crate) fn gate(&mut self, j: usize, h: Hypothesis) {
        self.row[j] = Some(h);
    }

    /// Close the current track, index `i` of the channel's list, as reached with `cache`. A track
    /// that is not reached is simply not pushed (it gated nothing).
    pub(crate) fn push_row(&mut self, i: usize, cache: C) {
        self.rows.push(i);
        self.caches.push(cache);
        self.table.entries.extend_from_slice(&self.row);
        self.row.iter_mut().for_each(|e| *e = None);
    }

    /// The finished record.
    pub(crate) fn finish(mut self) -> Reached<C> {
        self.table.n_tracks = self.rows.len();
        self
    }
}

/// The table and caches of every one of `n_tracks` tracks from those of the reached ones (`rows`
/// their indices): a track not reached has no gated hypothesis and an empty cache.
pub(crate) fn widen<C: Default>(
    table: HypothesisTable,
    caches: Vec<C>,
    rows: &[usize],
    n_tracks: usize,
) -> (HypothesisTable, Vec<C>) {
    let n_meas = table.n_meas;
    let mut full = HypothesisTable::new(n_tracks, n_meas);
    let mut all: Vec<C> = (0..n_tracks).map(|_| C::default()).collect();
    for (k, (&i, cache)) in rows.iter().zip(caches).enumerate() {
        for j in 0..n_meas {
            full.set(i, j, table.get(k, j));
        }
        all[i] = cache;
    }
    (full, all)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::association::{Associator, GnnAssociator};
    use crate::jpda::JpdaAssociator;
    use mimo_core::rng::Stream;

    /// A random channel: `n` tracks, `m` measurements; each track is reached with probability
    /// one half, and a reached track gates each measurement with probability `p_gate`.
    fn scene(s: &mut Stream, n: usize, m: usize, p_gate: f64) -> (HypothesisTable, Reached<u64>) {
        let mut full = HypothesisTable::new(n, m);
        let mut r = Reached::new(m);
        for i in 0..n {
            if s.uniform() < 0.5 {
                continue;
            }
            for j in 0..m {
                if s.uniform() < p_gate {
                    let h = Hypothesis { nis: 12.0 * s.uniform(), ln_det_2pi_s: 10.0 + 5.0 * s.uniform() };
                    full.set(i, j, Some(h));
                    r.gate(j, h);
                }
            }
            r.push_row(i, i as u64 + 1);
        }
        (full, r.finish())
    }

    #[test]
    fn widening_the_reached_tracks_gives_the_full_table_back() {
        let mut s = Stream::new(11, &[2]);
        for _ in 0..200 {
            let (n, m) = (1 + (s.uniform() * 12.0) as usize, (s.uniform() * 6.0) as usize);
            let (full, r) = scene(&mut s, n, m, 0.4);
            assert_eq!(r.table.n_tracks, r.rows.len());
            assert!(r.rows.windows(2).all(|w| w[0] < w[1]));
            let (wide, caches) = widen(r.table, r.caches, &r.rows, n);
            assert_eq!(wide, full);
            for (i, c) in caches.iter().enumerate() {
                assert_eq!(*c, if r.rows.contains(&i) { i as u64 + 1 } else { 0 });
            }
        }
    }

    #[test]
    fn jpda_on_the_reached_tracks_gives_each_of_them_the_full_tables_probabilities() {
        let jpda = JpdaAssociator::default();
        let mut s = Stream::new(11, &[3]);
        let mut compared = 0;
        for _ in 0..300 {
            let (n, m) = (1 + (s.uniform() * 10.0) as usize, (s.uniform() * 5.0) as usize);
            let (full, r) = scene(&mut s, n, m, 0.5);
            let all = jpda.probabilities(&full);
            let some = jpda.probabilities(&r.table);
            for (k, &i) in r.rows.iter().enumerate() {
                assert_eq!(some.beta[k], all.beta[i], "track {i} of {n}, {m} measurements");
                compared += 1;
            }
            // A track not reached misses for sure.
            for i in (0..n).filter(|i| !r.rows.contains(i)) {
                assert_eq!(all.beta[i][m], 1.0);
            }
        }
        assert!(compared > 500);
    }

    #[test]
    fn gnn_on_the_reached_tracks_assigns_as_on_the_full_table() {
        let gnn = GnnAssociator::default();
        let mut s = Stream::new(11, &[4]);
        for _ in 0..300 {
            let (n, m) = (1 + (s.uniform() * 10.0) as usize, (s.uniform() * 6.0) as usize);
            let (full, r) = scene(&mut s, n, m, 0.5);
            let all = gnn.associate(&full);
            let some = gnn.associate(&r.table);
            for (k, &i) in r.rows.iter().enumerate() {
                assert_eq!(some[k], all[i]);
            }
        }
    }
}
