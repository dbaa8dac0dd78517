//! Predictions made during one dwell, kept for its other channels and its deletion pass
//! (docs/model.md §6.5).
//!
//! Each receive channel of a dwell gates every track against its measurements, so a MIMO dwell
//! with several channels predicted each track once per channel, and the deletion pass after the
//! dwell predicted it once more. A prediction is a pure function of the track's state, the time
//! of that state and the time predicted to, so one made from the same state to the same time is
//! the same prediction: the store hands it back instead of computing it again, and the tracks are
//! the same, bit for bit. An interacting-multiple-model prediction (mixing, one prediction per
//! mode, the combination) is the costly case.
//!
//! The predictions are kept with the track's [`StateStamp`] and handed back only while the track
//! still matches it.

use crate::filter::FilterPrediction;
use crate::state_stamp::StateStamp;
use crate::tracker::Track;

/// A track's predictions in one dwell: `(time predicted to, prediction)`.
pub(crate) type Entries = Vec<(f64, FilterPrediction)>;

/// Predictions by track, made in the current dwell (a map by id: a raid holds hundreds of
/// tracks, and every channel looks each one up).
#[derive(Debug, Default)]
pub(crate) struct DwellPredictions {
    by_track: crate::track_balls::IdMap<(StateStamp, Entries)>,
}

impl DwellPredictions {
    /// Forget everything (a new dwell).
    pub(crate) fn clear(&mut self) {
        self.by_track.clear();
    }

    /// Take the predictions of `track` made from its current state (none if it changed since).
    pub(crate) fn take(&mut self, track: &Track) -> Option<(StateStamp, Entries)> {
        let (basis, entries) = self.by_track.remove(&track.id)?;
        basis.matches(track).then_some((basis, entries))
    }

    /// Keep the predictions of track `id` made from `basis` (replacing older ones).
    pub(crate) fn put(&mut self, id: u64, basis: StateStamp, entries: Entries) {
        self.by_track.insert(id, (basis, entries));
    }

    /// The prediction of `track` from its current state to `to_s`, if one was made.
    pub(crate) fn find(&self, track: &Track, to_s: f64) -> Option<&FilterPrediction> {
        let (basis, entries) = self.by_track.get(&track.id)?;
        if !basis.matches(track) {
            return None;
        }
        entries.iter().find(|(t, _)| t.to_bits() == to_s.to_bits()).map(|(_, p)| p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::FilterState;
    use crate::frame::Gaussian;
    use crate::linalg::identity;

    fn track(id: u64, t_s: f64, n_updates: u32) -> Track {
        let g = Gaussian { x: [0.0; 6], p: identity() };
        Track::confirmed_for_test(id, FilterState { modes: vec![g, g], mu: vec![0.5, 0.5] }, t_s, n_updates)
    }

    fn pred(x0: f64) -> FilterPrediction {
        let mut g = Gaussian { x: [0.0; 6], p: identity() };
        g.x[0] = x0;
        FilterPrediction { modes: vec![g, g], cbar: vec![0.5, 0.5], combined: g }
    }

    #[test]
    fn a_prediction_is_found_only_from_the_same_state_and_times() {
        let mut store = DwellPredictions::default();
        let t = track(7, 10.0, 3);
        store.put(7, StateStamp::of(&t), vec![(12.5, pred(3.0))]);
        assert_eq!(store.find(&t, 12.5), Some(&pred(3.0)));
        // Another target time, another state time, another update, another track.
        assert!(store.find(&t, 12.0).is_none());
        assert!(store.find(&track(7, 10.5, 3), 12.5).is_none());
        assert!(store.find(&track(7, 10.0, 4), 12.5).is_none());
        assert!(store.find(&track(8, 10.0, 3), 12.5).is_none());
        // Taking moves the entries out; a changed track takes nothing.
        assert!(store.take(&track(7, 11.0, 4)).is_none());
        store.put(7, StateStamp::of(&t), vec![(12.5, pred(3.0))]);
        let (b, e) = store.take(&t).expect("same state");
        assert!(b.matches(&t));
        assert_eq!(e.len(), 1);
        assert!(store.find(&t, 12.5).is_none());
        store.put(7, b, e);
        // Putting again replaces; clearing forgets.
        store.put(7, StateStamp::of(&t), vec![(12.5, pred(4.0))]);
        assert_eq!(store.find(&t, 12.5), Some(&pred(4.0)));
        store.clear();
        assert!(store.find(&t, 12.5).is_none());
    }

    /// Debug builds catch a state that changed without an update.
    #[test]
    #[cfg(debug_assertions)]
    #[should_panic(expected = "changed without an update")]
    fn a_state_changed_without_an_update_is_caught() {
        let mut store = DwellPredictions::default();
        let t = track(7, 10.0, 3);
        store.put(7, StateStamp::of(&t), vec![(12.5, pred(3.0))]);
        let mut moved = t.clone();
        moved.state.modes[0].x[0] = -0.0;
        let _ = store.find(&moved, 12.5);
    }
}
