//! Which confirmed tracks a power budget holds (docs/model.md §7.6, rule 4): under a budget too
//! small for every track, the default test article keeps the tracks it can pay for instead of
//! stretching every track's revisit until all of them are lost.
//!
//! Each confirmed track's *maintenance power* is the energy of its last look divided by the time
//! that look came after the track's previous update, `p = E / max(Δt, Δt_min)`, at the radar that
//! transmitted it. At each scheduling pass the tracks are taken cheapest first — a track held at
//! the previous pass counts at [`INCUMBENT_DISCOUNT`] of its power, so that two tracks of nearly
//! equal cost do not swap places from pass to pass — and a track is *held* while its radar's held
//! power stays within the budget `P_B` (a track that does not fit does not stop a cheaper one
//! after it). A track not yet looked at since its confirmation has no power yet and is held.
//!
//! A look at a held track is admitted by the usual rule (`L + E ≤ C`). A look at a track that is
//! not held may use only what the held tracks leave: its radar's capacity less the part of the
//! held tracks' reserve `W·Σp` that the window's maintenance `M` has not spent yet,
//! `L + E + max(0, W·Σp − M) ≤ C`. A budget that holds every track reserves nothing beyond what
//! the rule without holding admits, so a budget no window reaches is still no budget.

use mimo_core::ids::RadarId;
use std::collections::{BTreeMap, BTreeSet};

/// A track held at the previous pass is ranked at this fraction of its maintenance power.
pub const INCUMBENT_DISCOUNT: f64 = 0.8;

/// Shortest interval a look's energy is spread over when its maintenance power is estimated (s):
/// a re-look just after an update does not make its track look unaffordable.
pub const MIN_INTERVAL_S: f64 = 1.0;

/// The held set of a power budget and what it reserves.
#[derive(Debug, Clone, Default)]
pub struct HeldTracks {
    /// Each confirmed track's maintenance power at its last look: (transmitter, W).
    rates: BTreeMap<u64, (RadarId, f64)>,
    /// The tracks held at the last pass.
    held: BTreeSet<u64>,
    /// Power reserved per radar for the held tracks at the last pass (W).
    reserved_w: BTreeMap<RadarId, f64>,
}

impl HeldTracks {
    /// Note an admitted look at confirmed track `id`: `energy_j` transmitted by `radar`,
    /// `interval_s` after the track's previous update.
    pub fn note_look(&mut self, id: u64, radar: RadarId, energy_j: f64, interval_s: f64) {
        let p = energy_j / interval_s.max(MIN_INTERVAL_S);
        if p.is_finite() {
            self.rates.insert(id, (radar, p));
        }
    }

    /// Forget a track (deleted, or no longer confirmed).
    pub fn forget(&mut self, id: u64) {
        self.rates.remove(&id);
        self.held.remove(&id);
    }

    /// Choose the held set among the confirmed tracks `confirmed` under `budget_w` per radar
    /// (module docs). Deterministic: ties by track id.
    pub fn choose(&mut self, confirmed: &[u64], budget_w: f64) {
        let mut ranked: Vec<(f64, u64)> = confirmed
            .iter()
            .map(|&id| {
                let p = self.rates.get(&id).map_or(0.0, |&(_, p)| p);
                let discount = if self.held.contains(&id) { INCUMBENT_DISCOUNT } else { 1.0 };
                (p * discount, id)
            })
            .collect();
        ranked.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        self.held.clear();
        self.reserved_w.clear();
        for (_, id) in ranked {
            let Some(&(radar, p)) = self.rates.get(&id) else {
                self.held.insert(id);
                continue;
            };
            let reserved = self.reserved_w.entry(radar).or_insert(0.0);
            if *reserved + p <= budget_w {
                *reserved += p;
                self.held.insert(id);
            }
        }
    }

    /// Whether track `id` was held at the last [`Self::choose`].
    pub fn is_held(&self, id: u64) -> bool {
        self.held.contains(&id)
    }

    /// Energy (J) a look at a track that is not held must leave to `radar`'s held tracks over a
    /// window of `window_s` whose maintenance has committed `maintenance_j`:
    /// `max(0, W·Σp − M)`.
    pub fn reserve_gap_j(&self, radar: RadarId, window_s: f64, maintenance_j: f64) -> f64 {
        let reserved = self.reserved_w.get(&radar).copied().unwrap_or(0.0);
        (reserved * window_s - maintenance_j).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const R1: RadarId = RadarId(0);
    const R2: RadarId = RadarId(1);

    /// Tracks of 0.4, 0.5 and 0.7 W at R1 under a 1 W budget: the two cheapest are held (0.9 W),
    /// the third does not fit; a 0.05-W track after it still does. R2's track is held on R2's own
    /// budget.
    #[test]
    fn the_cheapest_tracks_that_fit_are_held() {
        let mut h = HeldTracks::default();
        h.note_look(1, R1, 7.0, 10.0); // 0.7 W
        h.note_look(2, R1, 2.0, 4.0); // 0.5 W
        h.note_look(3, R1, 0.4, 0.2); // 0.4 W: the interval is floored at 1 s
        h.note_look(4, R1, 0.5, 10.0); // 0.05 W
        h.note_look(5, R2, 9.0, 10.0); // 0.9 W at R2
        h.choose(&[1, 2, 3, 4, 5, 6], 1.0);
        let held: Vec<u64> = (1..=6).filter(|&id| h.is_held(id)).collect();
        assert_eq!(held, vec![2, 3, 4, 5, 6], "track 6 has no look yet and is held");
        // R1 reserves 0.95 W: over a 10-s window 9.5 J, less the maintenance already spent.
        assert!((h.reserve_gap_j(R1, 10.0, 0.0) - 9.5).abs() < 1e-9);
        assert!((h.reserve_gap_j(R1, 10.0, 6.0) - 3.5).abs() < 1e-9);
        assert_eq!(h.reserve_gap_j(R1, 10.0, 12.0), 0.0);
        assert!((h.reserve_gap_j(R2, 10.0, 0.0) - 9.0).abs() < 1e-9);
        // A budget for everything holds everything.
        h.choose(&[1, 2, 3, 4, 5], 2.0);
        assert!((1..=5).all(|id| h.is_held(id)));
    }

    /// The admission of a look at a track the budget does not hold (docs/model.md §7.6, rule 4):
    /// a 0.8-W budget holds tracks of 0.3 and 0.4 W but not a second 0.4-W one; over a 10-J
    /// window the held tracks reserve 7 J, of which the window's maintenance has committed 3 J,
    /// so 4 J stay reserved. With 3 J committed, an unheld 3-J look fits (3 + 3 + 4 = 10), a
    /// 3.5-J one does not, and a held 3.5-J look does.
    #[test]
    fn a_track_the_budget_does_not_hold_leaves_the_held_reserve() {
        use crate::default_ta::power::{Load, LookClass, admits};
        let mut h = HeldTracks::default();
        h.note_look(1, R1, 4.0, 10.0); // 0.4 W
        h.note_look(2, R1, 4.0, 10.0); // 0.4 W
        h.note_look(3, R1, 3.0, 10.0); // 0.3 W: 0.3 + 0.4 fit, the second 0.4 does not
        h.choose(&[1, 2, 3], 0.8);
        assert!(h.is_held(1) && !h.is_held(2) && h.is_held(3));
        // Reserve: the held 0.3 + 0.4 = 0.7 W.
        let (cap_j, window_s) = (10.0, 10.0);
        let load = Load { total_j: 3.0, maintenance_j: 3.0 };
        let gap = h.reserve_gap_j(R1, window_s, load.maintenance_j);
        assert!((gap - 4.0).abs() < 1e-9, "{gap}");
        let m = LookClass::Maintenance;
        assert!(admits(cap_j - gap, load, 3.0, m));
        assert!(!admits(cap_j - gap, load, 3.5, m));
        assert!(admits(cap_j, load, 3.5, m), "a held track's look is admitted by the plain rule");
        // Once the held tracks' maintenance has spent their reserve, nothing more is kept back.
        let spent = Load { total_j: 7.0, maintenance_j: 7.0 };
        assert_eq!(h.reserve_gap_j(R1, window_s, spent.maintenance_j), 0.0);
        assert!(admits(cap_j, spent, 3.0, m));
    }

    /// A held track keeps its place against a newcomer up to 25 % cheaper (0.8 of its power),
    /// not against one that is much cheaper.
    #[test]
    fn a_held_track_keeps_its_place_against_a_slightly_cheaper_one() {
        let mut h = HeldTracks::default();
        h.note_look(1, R1, 10.0, 10.0); // 1.0 W
        h.choose(&[1], 1.0);
        assert!(h.is_held(1));
        h.note_look(2, R1, 9.0, 10.0); // 0.9 W: 0.8·1.0 = 0.8 ranks first
        h.choose(&[1, 2], 1.0);
        assert!(h.is_held(1) && !h.is_held(2));
        h.note_look(3, R1, 7.0, 10.0); // 0.7 W < 0.8 W: takes the place
        h.choose(&[1, 2, 3], 1.0);
        assert!(h.is_held(3) && !h.is_held(1) && !h.is_held(2));
        // Forgotten tracks are neither held nor ranked.
        h.forget(3);
        h.choose(&[1, 2], 1.0);
        assert!(!h.is_held(3));
        assert!(h.is_held(2), "0.9 W ranks before 1.0 W when neither was held");
    }
}
