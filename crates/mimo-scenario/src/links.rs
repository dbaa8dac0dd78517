//! The links between the ships and the test article (`[links]`, docs/model.md §5.6): per ship, a
//! delay (and a jitter) for a dwell report to reach the test article and for a dwell order to
//! reach the radar.
//!
//! ```toml
//! [links]
//! delay_s = 0.5                # every ship's, 0–60 s; 0 (the default) is a perfect link
//! jitter_s = 0.1               # 0 ≤ jitter ≤ delay: each message takes delay ± jitter
//! [links.ships.R3]             # one ship's own link
//! delay_s = 2.0
//! ```

use crate::error::ScenarioError;
use crate::flight::Ctx;
use mimo_core::ids::RadarId;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The largest link delay (s): a minute, beyond any tactical data link's latency.
pub const MAX_DELAY_S: f64 = 60.0;

/// One ship's link.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShipLink {
    /// Mean time a message takes (s).
    #[serde(default)]
    pub delay_s: f64,
    /// Half-width of the uniform spread about the delay (s), at most the delay.
    #[serde(default)]
    pub jitter_s: f64,
}

impl ShipLink {
    fn validate(&self, ctx: &Ctx) -> Result<(), ScenarioError> {
        let d = self.delay_s;
        if !(d.is_finite() && (0.0..=MAX_DELAY_S).contains(&d)) {
            return Err(ctx.err("delay_s", format!("a delay in [0, {MAX_DELAY_S}] s, got {d}")));
        }
        let j = self.jitter_s;
        if !(j.is_finite() && (0.0..=d).contains(&j)) {
            return Err(ctx.err("jitter_s", format!("a jitter in [0, delay_s = {d}] s, got {j}")));
        }
        Ok(())
    }

    /// A message's travel time for a uniform draw `x` in [0, 1).
    pub fn travel_s(&self, x: f64) -> f64 {
        self.delay_s + self.jitter_s * (2.0 * x - 1.0)
    }
}

/// The `[links]` table of a scenario.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Links {
    /// Every ship's delay (s), unless it has its own.
    #[serde(default)]
    pub delay_s: f64,
    /// Every ship's jitter (s), unless it has its own.
    #[serde(default)]
    pub jitter_s: f64,
    /// Links of single ships, by radar id (`R1`, …).
    #[serde(default)]
    pub ships: BTreeMap<String, ShipLink>,
}

impl Links {
    /// Every link perfect: messages arrive when sent (the engine then runs as without links).
    pub fn is_off(&self) -> bool {
        self.delay_s == 0.0 && self.ships.values().all(|l| l.delay_s == 0.0)
    }

    /// Ship `r`'s link.
    pub fn of(&self, r: RadarId) -> ShipLink {
        self.ships.get(&r.to_string()).copied().unwrap_or(ShipLink { delay_s: self.delay_s, jitter_s: self.jitter_s })
    }

    /// Every ship's delay set to `delay_s` (a study's stress), jitters kept within it.
    pub fn set_delay(&mut self, delay_s: f64) {
        self.delay_s = delay_s;
        self.jitter_s = self.jitter_s.min(delay_s);
        for l in self.ships.values_mut() {
            l.delay_s = delay_s;
            l.jitter_s = l.jitter_s.min(delay_s);
        }
    }

    /// Every value checked, for a scenario of `n_radars` ships; `ctx` is the `[links]` table.
    pub(crate) fn validate(&self, n_radars: usize, ctx: &Ctx) -> Result<(), ScenarioError> {
        ShipLink { delay_s: self.delay_s, jitter_s: self.jitter_s }.validate(ctx)?;
        for (id, l) in &self.ships {
            let at = ctx.sub("ships").sub(id);
            match RadarId::parse(id) {
                Some(r) if r.index() < n_radars => l.validate(&at)?,
                _ => {
                    let last = RadarId(n_radars.saturating_sub(1) as u8);
                    return Err(at.err("", format!("a ship of the scenario (R1…{last}), got `{id}`")));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_links_name_the_key_and_the_range() {
        let ctx = Ctx::new("s.toml", "links");
        let e = Links { delay_s: -1.0, ..Links::default() }.validate(2, &ctx).expect_err("negative");
        assert_eq!(e.to_string(), "s.toml: links.delay_s: expected a delay in [0, 60] s, got -1");
        let e = Links { delay_s: 61.0, ..Links::default() }.validate(2, &ctx).expect_err("too long");
        assert!(e.to_string().contains("got 61"), "{e}");
        let e = Links { delay_s: 1.0, jitter_s: 2.0, ..Links::default() }.validate(2, &ctx).expect_err("jitter");
        assert_eq!(e.to_string(), "s.toml: links.jitter_s: expected a jitter in [0, delay_s = 1] s, got 2");
        let ships = [("R3".to_string(), ShipLink::default())].into();
        let e = Links { ships, ..Links::default() }.validate(2, &ctx).expect_err("no R3");
        assert_eq!(e.to_string(), "s.toml: links.ships.R3: expected a ship of the scenario (R1…R2), got `R3`");
    }

    #[test]
    fn a_ship_has_its_own_link_or_the_fleets() {
        let own = ShipLink { delay_s: 2.0, jitter_s: 0.5 };
        let l = Links { delay_s: 1.0, jitter_s: 0.0, ships: [("R2".to_string(), own)].into() };
        assert_eq!(l.of(RadarId(1)), own);
        assert_eq!(l.of(RadarId(0)), ShipLink { delay_s: 1.0, jitter_s: 0.0 });
        assert!((own.travel_s(0.0) - 1.5).abs() < 1e-12 && (own.travel_s(0.5) - 2.0).abs() < 1e-12);
        assert!(Links::default().is_off() && !l.is_off());
    }
}
