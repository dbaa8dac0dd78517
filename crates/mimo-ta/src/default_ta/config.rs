//! Configuration of the default test article: the tracker's and the resource manager's.

use super::search_manager::SearchManagerConfig;
use mimo_track::TrackerConfig;
use serde::{Deserialize, Serialize};

/// Settings of the default test article's resource manager (docs/model.md §7).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ResourceConfig {
    /// Detection probability each track look is sized for. Default 0.9.
    pub pd_target: f64,
    /// Detection probability the confirmation looks of a tentative track are sized for until it
    /// is seen again (without doubling on a miss); once a tentative track has been seen again,
    /// looks are sized for `pd_target`. Default 0.9: the built-in test articles confirm on 2 of
    /// 2 looks, so a real target's one confirmation look must rarely miss (0.7 with 2-of-2 lost
    /// the scenario-7 guard run, docs/decisions/0028-confirmation-revisit-group-looks.md).
    pub confirm_pd: f64,
    /// RCS assumed when sizing dwells (m²): the fighters' 2 m², so airliners are over-served.
    pub assumed_rcs_m2: f64,
    /// Pointing error the energy budget allows for, in beamwidths (V₀). Default 0.2.
    pub pointing_sharpness: f64,
    /// Use MIMO dwells for confirmed tracks seen by more than one radar. Default true; false is
    /// a conventional phased-array network (monostatic dwells only).
    pub mimo: bool,
    /// Smallest half-width of a track dwell's range window (m). Default 1000.
    pub min_window_half_m: f64,
    /// Range window half-width in predicted range standard deviations. Default 5.
    pub window_sigmas: f64,
    /// Largest share of a radar's timeline over the last `budget_window_s` that the test
    /// article's dwells (track, confirmation, MIMO; transmitting or receiving) may take before
    /// the radar stops being asked for more than the looks it must transmit, so that its
    /// background search keeps running (docs/model.md §7.3). Default 1 (off); 0.9 keeps every
    /// search stop of scenario 7 under 10 s at a cost in breaks (docs/decisions/0026-formation-measures-as-options.md).
    pub max_ta_share: f64,
    /// Window of the timeline budget (s). Default 8.
    pub budget_window_s: f64,
    /// Stop re-dwelling on pairs the radar cannot resolve (docs/model.md §7.2): a confirmed
    /// track whose last look missed or returned a merged measurement while another track is
    /// predicted in the same resolution cell from the transmitter gets no energy doubling, and
    /// its next look waits `unresolved_revisit_s`. Default true.
    pub unresolved_hold: bool,
    /// Range part of the resolution cell, in range cells. Default 1000, so that in effect only
    /// the angle counts: on scenario 7 the pairs R1 thrashed on share its beam but not its
    /// range cell, and 1.5 cells left the thrashing in place (docs/decisions/0027-hold-beam-sharing-tracks.md).
    pub unresolved_range_cells: f64,
    /// Angular part of the resolution cell, as a fraction of the narrower beamwidth. Default 0.5.
    pub unresolved_beam_fraction: f64,
    /// Shortest time between looks at a track held as unresolved (s). Default 2.
    pub unresolved_revisit_s: f64,
    /// Search protection under load (docs/model.md §7.3): a radar whose test-article dwells
    /// (transmitting or receiving) took at least this share of the last `rx_busy_window_s` is
    /// not asked to receive for another radar's MIMO dwell, so that its background search keeps
    /// at least about the rest of its timeline (it still transmits its own looks). Default 0.5:
    /// no radar of the standard scenarios comes near it (at most 0.21 over 8 s on scenario 7),
    /// while a raid of 64 aircraft drove the receivers to 0.9-1 and search to a fifth of the
    /// timeline (docs/decisions/0251-search-protection-under-load.md). 1 turns it off.
    pub rx_busy_share: f64,
    /// Window of `rx_busy_share` (s). Default 8, about one low-band search frame (§7.4).
    pub rx_busy_window_s: f64,
    /// Group looks (docs/model.md §7.2): a dwell planned for one confirmed track also serves
    /// every other confirmed track due within `group_lookahead_s` whose predicted position is
    /// within `group_beam_fraction` of the narrower beamwidth of the aim point seen from the
    /// transmitter and within `group_radius_m` of it; those tracks get no dwell of their own and
    /// the range window is widened to hold them. Default true
    /// (docs/decisions/0028-confirmation-revisit-group-looks.md).
    pub group_looks: bool,
    /// Angular radius of a group look, as a fraction of the narrower beamwidth. Default 0.25.
    pub group_beam_fraction: f64,
    /// Largest distance between the aim point and a track served by the same look (m).
    /// Default 1500.
    pub group_radius_m: f64,
    /// How early a track may be looked at as a member of another track's group look (s).
    /// Default 1.
    pub group_lookahead_s: f64,
    /// Average transmit power (W) each radar may spend on the test article's own dwells over any
    /// `power_window_s` window (docs/model.md §7.6); background search is not charged. Looks at
    /// confirmed tracks come first, then confirmations by the strength of their detection; a
    /// request that does not fit waits. Default `None`: unlimited.
    pub power_budget_w: Option<f64>,
    /// Window of `power_budget_w` (s). Default 10.
    pub power_window_s: f64,
    /// Under a power budget, hold the confirmed tracks the budget can pay for, cheapest first,
    /// and give the others only what the held tracks leave (docs/model.md §7.6, rule 4), instead
    /// of stretching every track's revisit alike. Default true; no effect without a budget.
    pub hold_tracks: bool,
}

impl Default for ResourceConfig {
    fn default() -> Self {
        ResourceConfig {
            pd_target: 0.9,
            confirm_pd: 0.9,
            assumed_rcs_m2: 2.0,
            pointing_sharpness: 0.2,
            mimo: true,
            min_window_half_m: 1000.0,
            window_sigmas: 5.0,
            max_ta_share: 1.0,
            budget_window_s: 8.0,
            unresolved_hold: true,
            unresolved_range_cells: 1000.0,
            unresolved_beam_fraction: 0.5,
            unresolved_revisit_s: 2.0,
            rx_busy_share: 0.5,
            rx_busy_window_s: 8.0,
            group_looks: true,
            group_beam_fraction: 0.25,
            group_radius_m: 1500.0,
            group_lookahead_s: 1.0,
            power_budget_w: None,
            power_window_s: 10.0,
            hold_tracks: true,
        }
    }
}

impl ResourceConfig {
    /// Check the values; the error names the key and what was expected.
    pub fn validate(&self) -> Result<(), (String, String)> {
        let prob = |k: &str, x: f64| {
            if x > 0.0 && x < 1.0 { Ok(()) } else { Err((k.to_string(), format!("a probability in (0, 1), got {x}"))) }
        };
        let pos = |k: &str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err((k.to_string(), format!("a positive finite number, got {x}")))
            }
        };
        prob("resource_manager.pd_target", self.pd_target)?;
        prob("resource_manager.confirm_pd", self.confirm_pd)?;
        pos("resource_manager.assumed_rcs_m2", self.assumed_rcs_m2)?;
        pos("resource_manager.pointing_sharpness", self.pointing_sharpness)?;
        pos("resource_manager.min_window_half_m", self.min_window_half_m)?;
        pos("resource_manager.window_sigmas", self.window_sigmas)?;
        pos("resource_manager.budget_window_s", self.budget_window_s)?;
        pos("resource_manager.unresolved_range_cells", self.unresolved_range_cells)?;
        pos("resource_manager.unresolved_beam_fraction", self.unresolved_beam_fraction)?;
        pos("resource_manager.unresolved_revisit_s", self.unresolved_revisit_s)?;
        pos("resource_manager.rx_busy_window_s", self.rx_busy_window_s)?;
        pos("resource_manager.group_beam_fraction", self.group_beam_fraction)?;
        pos("resource_manager.group_radius_m", self.group_radius_m)?;
        pos("resource_manager.power_window_s", self.power_window_s)?;
        if let Some(p) = self.power_budget_w
            && !(p.is_finite() && p > 0.0)
        {
            return Err((
                "resource_manager.power_budget_w".into(),
                format!("a power in watts, positive and finite, got {p}"),
            ));
        }
        if !(self.group_lookahead_s.is_finite() && self.group_lookahead_s >= 0.0) {
            return Err((
                "resource_manager.group_lookahead_s".into(),
                format!("a non-negative finite number, got {}", self.group_lookahead_s),
            ));
        }
        if !(self.rx_busy_share > 0.0 && self.rx_busy_share <= 1.0) {
            return Err((
                "resource_manager.rx_busy_share".into(),
                format!("a share in (0, 1], got {}", self.rx_busy_share),
            ));
        }
        if !(self.max_ta_share > 0.0 && self.max_ta_share <= 1.0) {
            return Err((
                "resource_manager.max_ta_share".into(),
                format!("a share in (0, 1], got {}", self.max_ta_share),
            ));
        }
        Ok(())
    }
}

/// Check the optional settings of a merged configuration before it is parsed: an optional number
/// takes any JSON value when merged (its default is `null`), so one that is not a number is named
/// here with its key path rather than by the parser.
pub fn check_optional_numbers(merged: &serde_json::Value) -> Result<(), (String, String)> {
    let optional = [
        ("resource_manager", "power_budget_w", "a power in watts, positive and finite"),
        ("search_manager", "held_share", "a share in [0, 1]"),
        ("search_manager", "frame_period_s", "a positive finite time (s)"),
    ];
    for (section, key, expected) in optional {
        match merged.get(section).and_then(|r| r.get(key)) {
            None | Some(serde_json::Value::Null | serde_json::Value::Number(_)) => {}
            Some(v) => return Err((format!("{section}.{key}"), format!("{expected}, got {v}"))),
        }
    }
    Ok(())
}

/// The whole configuration of the default test article, as recorded in the manifest and as
/// `--ta-config` / `--set` address it (`tracker.kind`, `resource_manager.mimo`, …).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct DefaultTaConfig {
    /// The multi-target tracker.
    pub tracker: TrackerConfig,
    /// The resource manager (scheduling and energy).
    pub resource_manager: ResourceConfig,
    /// Online registration of the radars (docs/model.md §6.9); off by default.
    pub registration: crate::registration::RegistrationConfig,
    /// The search manager (background search of every radar, docs/model.md §7.4).
    pub search_manager: SearchManagerConfig,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_holds_unresolved_tracks_and_bad_hold_settings_are_named() {
        let d = ResourceConfig::default();
        assert!(d.unresolved_hold && d.rx_busy_share == 0.5 && d.rx_busy_window_s == 8.0);
        assert!(d.validate().is_ok());
        let bad = |f: &dyn Fn(&mut ResourceConfig)| {
            let mut c = ResourceConfig::default();
            f(&mut c);
            c.validate().err().map(|(k, _)| k)
        };
        assert_eq!(bad(&|c| c.rx_busy_share = 0.0).as_deref(), Some("resource_manager.rx_busy_share"));
        assert_eq!(bad(&|c| c.rx_busy_share = 1.5).as_deref(), Some("resource_manager.rx_busy_share"));
        assert_eq!(bad(&|c| c.unresolved_revisit_s = -1.0).as_deref(), Some("resource_manager.unresolved_revisit_s"));
        assert_eq!(
            bad(&|c| c.unresolved_beam_fraction = f64::NAN).as_deref(),
            Some("resource_manager.unresolved_beam_fraction")
        );
    }
}
