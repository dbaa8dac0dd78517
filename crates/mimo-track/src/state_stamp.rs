//! Which state a track is in, without copying it (docs/model.md §6.4, §6.5).
//!
//! A track's state changes only in an update, which counts `n_updates` and sets `t_s`, and track
//! ids are never reused; so a track's id, update count and time name its state. What is computed
//! from a state and kept for later (a deletion certificate, a dwell's predictions) carries a
//! [`StateStamp`] and is reused only while the track still matches it. Debug builds (so every
//! test) also keep the state and assert, bit for bit, that a match means the same state.

#[cfg(debug_assertions)]
use crate::filter::FilterState;
use crate::tracker::Track;

/// The state a track was in when something was computed from it.
#[derive(Debug, Clone)]
pub(crate) struct StateStamp {
    /// Time of the state (s).
    t_s: f64,
    /// The track's update count at that state.
    n_updates: u32,
    /// The state itself (debug builds: the promise above is checked).
    #[cfg(debug_assertions)]
    state: FilterState,
}

impl StateStamp {
    /// The stamp of `track` as it is now.
    pub(crate) fn of(track: &Track) -> StateStamp {
        StateStamp {
            t_s: track.t_s,
            n_updates: track.n_updates,
            #[cfg(debug_assertions)]
            state: track.state.clone(),
        }
    }

    /// Whether `track` (the same id) is still in the stamped state.
    pub(crate) fn matches(&self, track: &Track) -> bool {
        let same = self.t_s.to_bits() == track.t_s.to_bits() && self.n_updates == track.n_updates;
        #[cfg(debug_assertions)]
        debug_assert!(!same || same_bits(&self.state, &track.state), "track {} changed without an update", track.id);
        same
    }
}

/// Bit-for-bit equality of two states.
#[cfg(debug_assertions)]
fn same_bits(a: &FilterState, b: &FilterState) -> bool {
    let bits = |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
    bits(&a.mu, &b.mu)
        && a.modes.len() == b.modes.len()
        && a.modes.iter().zip(&b.modes).all(|(p, q)| bits(&p.x, &q.x) && p.p.iter().zip(&q.p).all(|(r, s)| bits(r, s)))
}
