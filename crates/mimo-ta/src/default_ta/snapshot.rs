//! One scheduling pass's view of the radars and tracks at its instant (docs/model.md §7.1–§7.5).
//!
//! A pass plans every due track at the same time with the same tracker state, so the radars'
//! faces, the heights of their sites and of the aim points (for the 4/3-earth horizon test,
//! docs/model.md §1.7) and the tracks' predicted positions are the same for every plan of the
//! pass: each is computed once, on first use, and kept until the pass ends. The horizon test
//! converts heights only when cheap lower bounds of them cannot already show the look visible.
//! Every value and answer is the one the direct computation gives, bit for bit.

use super::near_index::NearIndex;
use crate::geometry::ShipGeometry;
use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::geo::{height_lower_bound_m, surely_visible_effective_earth};
use mimo_core::ids::RadarId;
use mimo_radar::energy::{PairEnd, PairPrediction, predict_pair_seen};
use mimo_radar::geometry::{height_m, visible_with_heights};
use mimo_track::{MultiTargetTracker, TrackDue};
use std::cell::{Cell, OnceCell, RefCell};
use std::collections::BTreeMap;

/// The radars and tracks at one scheduling instant, each part computed once.
pub struct Snapshot<'a> {
    /// The tracker (unchanged during the pass).
    pub tracker: &'a MultiTargetTracker,
    /// The ships.
    pub geom: &'a ShipGeometry,
    /// The instant of the pass (s).
    pub t_s: f64,
    ids: &'a [RadarId],
    faces: OnceCell<Vec<Vec<FaceFrame>>>,
    /// Heights above the ellipsoid (m) of the points seen so far, by their coordinates' bits.
    heights_m: RefCell<Vec<([u64; 3], f64)>>,
    positions_ecef: RefCell<BTreeMap<u64, Option<DVec3>>>,
    /// The tracks' position balls in their grid, kept across passes by the caller
    /// ([`Snapshot::with_index`]).
    index: Option<&'a RefCell<NearIndex>>,
    /// Whether the index was brought to the pass's instant.
    refreshed: Cell<bool>,
}

/// Slack of the direction test on unit vectors (far above their rounding).
const DIRECTION_SLACK: f64 = 1e-9;

impl<'a> Snapshot<'a> {
    /// The view at `t_s` of the radars `ids` (`geom.ids()`); nothing is computed yet.
    pub fn new(tracker: &'a MultiTargetTracker, geom: &'a ShipGeometry, ids: &'a [RadarId], t_s: f64) -> Snapshot<'a> {
        Snapshot {
            tracker,
            geom,
            t_s,
            ids,
            faces: OnceCell::new(),
            heights_m: RefCell::new(Vec::new()),
            positions_ecef: RefCell::new(BTreeMap::new()),
            index: None,
            refreshed: Cell::new(false),
        }
    }

    /// The same view, keeping the tracks' position balls in `index` (renewed when stale, kept
    /// for later passes; the caller marks the tracks its dwells changed).
    pub fn with_index(self, index: &'a RefCell<NearIndex>) -> Snapshot<'a> {
        Snapshot { index: Some(index), ..self }
    }

    /// Whether the predicted position at the pass's instant of the track `due` may lie, seen
    /// from `site`, within `dr_m` of range `r0_m` and within `da` of the direction `u0` (a unit
    /// vector; the distance of unit vectors): `false` only when the track's position ball shows
    /// that it cannot. A point of a ball of radius `ρ` around `c` is within `ρ` of `c`'s range,
    /// and, when `|c − site| ≥ 2ρ`, its direction within `asin(ρ/|c − site|) ≤ 1.05 ρ/|c − site|`
    /// of `c`'s.
    pub fn may_be_near(&self, due: &TrackDue, site: DVec3, r0_m: f64, u0: DVec3, dr_m: f64, da: f64) -> bool {
        let Some((centre, radius_m)) = self.ball(due) else { return true };
        let dc = centre - site;
        let rc = dc.length();
        if (rc - r0_m).abs() > dr_m + radius_m {
            return false;
        }
        if !(rc > 0.0 && rc >= 2.0 * radius_m) {
            return true;
        }
        (dc / rc - u0).length() <= da + 1.05 * radius_m / rc + DIRECTION_SLACK
    }

    /// The tracks (of any status) whose predicted position at the pass's instant may lie within
    /// `dist_m` of `point`, by id: every track except those whose position ball is farther
    /// ([`NearIndex`], made at the first query of the pass).
    pub fn near(&self, point: DVec3, dist_m: f64) -> Vec<u64> {
        let Some(index) = self.index else { return self.tracker.track_dues().map(|d| d.id).collect() };
        let mut index = index.borrow_mut();
        if !self.refreshed.replace(true) {
            index.refresh(self.tracker, self.t_s);
        }
        index.near(point, dist_m)
    }

    /// The centre and radius of the kept position ball of the track `due` at the pass's instant
    /// (made anew when missing or stale), if the caller keeps balls and the tracker offers one.
    fn ball(&self, due: &TrackDue) -> Option<(DVec3, f64)> {
        self.index?.borrow_mut().ball(self.tracker, due, self.t_s)
    }

    /// Every radar id, in order.
    pub fn ids(&self) -> &[RadarId] {
        self.ids
    }

    /// Every radar's faces at the pass's instant, in the order of [`Snapshot::ids`].
    pub fn faces(&self) -> &[Vec<FaceFrame>] {
        self.faces.get_or_init(|| self.ids.iter().map(|&r| self.geom.faces_at(r, self.t_s)).collect())
    }

    /// Radar `r`'s faces at the pass's instant (empty for a radar the run does not have).
    pub fn faces_of(&self, r: RadarId) -> &[FaceFrame] {
        match self.ids.iter().position(|&x| x == r) {
            Some(k) => &self.faces()[k],
            None => &[],
        }
    }

    /// Height above the ellipsoid of an ECEF point (m), [`height_m`]'s value.
    pub fn height_m(&self, p: DVec3) -> f64 {
        let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        if let Some(&(_, h)) = self.heights_m.borrow().iter().find(|(k, _)| *k == key) {
            return h;
        }
        let h = height_m(p);
        self.heights_m.borrow_mut().push((key, h));
        h
    }

    /// A track's predicted position at the pass's instant, ECEF
    /// ([`MultiTargetTracker::predict_position`]).
    pub fn position(&self, id: u64) -> Option<DVec3> {
        if let Some(&p) = self.positions_ecef.borrow().get(&id) {
            return p;
        }
        let p = self.tracker.predict_position(id, self.t_s);
        self.positions_ecef.borrow_mut().insert(id, p);
        p
    }

    /// [`mimo_radar::energy::predict_pair`] of radars `tx → rx` (their faces at the pass's
    /// instant) for a target at `p`, with the horizon test on the kept heights.
    pub fn pair(&self, tx: RadarId, rx: RadarId, p: DVec3, rcs_m2: f64) -> Option<PairPrediction> {
        let t = PairEnd { params: self.geom.params(tx)?, faces: self.faces_of(tx) };
        let r = PairEnd { params: self.geom.params(rx)?, faces: self.faces_of(rx) };
        let p_lo_m = height_lower_bound_m(p);
        predict_pair_seen(t, r, p, rcs_m2, |site| {
            // Heights are converted only when their bounds leave the horizon test open.
            surely_visible_effective_earth(site, height_lower_bound_m(site), p, p_lo_m)
                || visible_with_heights(site, self.height_m(site), p, self.height_m(p))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::default_ta::fixture::minute_of_scenario_7;
    use mimo_core::records::TrackStatus;
    use mimo_radar::energy::predict_pair;

    /// Every kept value is the direct computation's, bit for bit: faces, heights, the pair
    /// predictions of every radar pair and the predicted positions of every live track, on the
    /// default test article's tracker after a minute of scenario 7.
    #[test]
    fn kept_values_are_the_direct_ones() {
        let (ta, geom) = minute_of_scenario_7();
        let tracker = ta.tracker().expect("started");
        let t_s = 60.4;
        let ids = geom.ids();
        let snap = Snapshot::new(tracker, &geom, &ids, t_s);
        let live: Vec<u64> =
            tracker.tracks().iter().filter(|t| t.status != TrackStatus::Deleted).map(|t| t.id).collect();
        assert!(live.len() >= 4, "{} live tracks", live.len());
        let mut pairs = 0;
        for _ in 0..2 {
            // The second pass answers from what the first kept.
            for &id in &live {
                let direct = tracker.predict(id, t_s).expect("prediction").pos;
                let kept = snap.position(id).expect("position");
                assert_eq!(kept.to_array().map(f64::to_bits), direct.to_array().map(f64::to_bits));
                assert_eq!(snap.height_m(kept).to_bits(), height_m(kept).to_bits());
                for &tx in snap.ids() {
                    for &rx in snap.ids() {
                        let (pt, pr) = (geom.params(tx).expect("tx"), geom.params(rx).expect("rx"));
                        let (ft, fr) = (geom.faces_at(tx, t_s), geom.faces_at(rx, t_s));
                        assert_eq!(snap.faces_of(tx), ft.as_slice());
                        let direct = predict_pair(
                            PairEnd { params: pt, faces: &ft },
                            PairEnd { params: pr, faces: &fr },
                            kept,
                            1.0,
                        );
                        assert_eq!(snap.pair(tx, rx, kept, 1.0), direct);
                        pairs += usize::from(direct.is_some());
                    }
                }
            }
        }
        assert!(pairs > 0, "no pair sees any track");
        assert_eq!(snap.position(u64::MAX), None);
    }
}
