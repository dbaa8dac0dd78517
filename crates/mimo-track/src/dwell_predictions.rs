//! Predictions made during one dwell, kept for its other channels and its deletion pass
//! (docs/model.md §6.5).
//!
//! Each receive channel of a dwell gates every track against its measurements, so a MIMO dwell
//! with several channels predicted each track once per channel, and the deletion pass after the
//! dwell predicted it once more. A prediction is a pure function of the track's state, the time
//! of that state and the time predicted to, so one made from the same state (bit for bit) to the
//! same time is the same prediction: the store hands it back instead of computing it again, and
//! the tracks are the same, bit for bit. An interacting-multiple-model prediction (mixing, one
//! prediction per mode, the combination) is the costly case.

use crate::filter::{FilterPrediction, FilterState};
use std::collections::BTreeMap;

/// The state a track's predictions were made from.
#[derive(Debug, Clone)]
pub(crate) struct Basis {
    /// Time of the state (s).
    pub t_s: f64,
    /// The state itself.
    pub state: FilterState,
}

impl Basis {
    /// Whether `t_s` and `state` are this basis, bit for bit (so that a prediction made from it
    /// is the one they would give).
    pub(crate) fn is(&self, t_s: f64, state: &FilterState) -> bool {
        let bits =
            |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        self.t_s.to_bits() == t_s.to_bits()
            && bits(&self.state.mu, &state.mu)
            && self.state.modes.len() == state.modes.len()
            && self
                .state
                .modes
                .iter()
                .zip(&state.modes)
                .all(|(a, b)| bits(&a.x, &b.x) && a.p.iter().zip(&b.p).all(|(ra, rb)| bits(ra, rb)))
    }
}

/// Predictions by track, made in the current dwell.
#[derive(Debug, Default)]
pub(crate) struct DwellPredictions {
    by_track: BTreeMap<u64, (Basis, Vec<(f64, FilterPrediction)>)>,
}

impl DwellPredictions {
    /// Forget everything (a new dwell).
    pub(crate) fn clear(&mut self) {
        self.by_track.clear();
    }

    /// Take the predictions of track `id` made from `state` at `t_s` (none if it changed since).
    pub(crate) fn take(
        &mut self,
        id: u64,
        t_s: f64,
        state: &FilterState,
    ) -> Option<(Basis, Vec<(f64, FilterPrediction)>)> {
        match self.by_track.remove(&id) {
            Some((basis, entries)) if basis.is(t_s, state) => Some((basis, entries)),
            _ => None,
        }
    }

    /// Keep the predictions of track `id` made from `basis` (replacing older ones).
    pub(crate) fn put(&mut self, id: u64, basis: Basis, entries: Vec<(f64, FilterPrediction)>) {
        self.by_track.insert(id, (basis, entries));
    }

    /// The prediction of track `id` from `state` at `t_s` to `to_s`, if one was made.
    pub(crate) fn find(&self, id: u64, t_s: f64, state: &FilterState, to_s: f64) -> Option<&FilterPrediction> {
        let (basis, entries) = self.by_track.get(&id)?;
        if !basis.is(t_s, state) {
            return None;
        }
        entries.iter().find(|(t, _)| t.to_bits() == to_s.to_bits()).map(|(_, p)| p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Gaussian;
    use crate::linalg::identity;

    fn state(x0: f64) -> FilterState {
        let mut g = Gaussian { x: [0.0; 6], p: identity() };
        g.x[0] = x0;
        FilterState { modes: vec![g, g], mu: vec![0.5, 0.5] }
    }

    fn pred(x0: f64) -> FilterPrediction {
        let g = state(x0).modes[0];
        FilterPrediction { modes: vec![g, g], cbar: vec![0.5, 0.5], combined: g }
    }

    #[test]
    fn a_prediction_is_found_only_from_the_same_state_and_times() {
        let mut store = DwellPredictions::default();
        store.put(7, Basis { t_s: 10.0, state: state(1.0) }, vec![(12.5, pred(3.0))]);
        assert_eq!(store.find(7, 10.0, &state(1.0), 12.5), Some(&pred(3.0)));
        // Another target time, another state time, another state, another track.
        assert!(store.find(7, 10.0, &state(1.0), 12.0).is_none());
        assert!(store.find(7, 10.5, &state(1.0), 12.5).is_none());
        assert!(store.find(7, 10.0, &state(1.0 + 1e-12), 12.5).is_none());
        assert!(store.find(8, 10.0, &state(1.0), 12.5).is_none());
        // −0 and +0 are different bits: not the same state.
        assert!(store.find(7, 10.0, &state(1.0), 12.5).is_some());
        let mut z = state(1.0);
        z.modes[1].x[3] = -0.0;
        assert!(store.find(7, 10.0, &z, 12.5).is_none());
        // Taking moves the entries out; a changed state takes nothing.
        assert!(store.take(7, 10.0, &state(2.0)).is_none());
        store.put(7, Basis { t_s: 10.0, state: state(1.0) }, vec![(12.5, pred(3.0))]);
        let (b, e) = store.take(7, 10.0, &state(1.0)).expect("same state");
        assert!(b.is(10.0, &state(1.0)));
        assert_eq!(e.len(), 1);
        assert!(store.find(7, 10.0, &state(1.0), 12.5).is_none());
        store.put(7, b, e);
        store.clear();
        assert!(store.find(7, 10.0, &state(1.0), 12.5).is_none());
    }
}
