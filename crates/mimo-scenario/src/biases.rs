//! A scenario's registration biases (`[biases]`, docs/model.md §5.5): per radar, constant
//! errors of range, of the face direction cosines u and v and of the ship's heading, drawn once
//! per run from standard deviations times `scale`, or set per radar.
//!
//! ```toml
//! [biases]
//! scale = 1.0                 # times the σ's below; 0 (the default) draws nothing
//! sigma_range_m = 10.0        # the typical σ's (mimo_core::registration::typical), optional
//! sigma_u = 1e-3
//! sigma_v = 1e-3
//! sigma_heading_deg = 0.1
//! [biases.radars.R2]          # set explicitly (not drawn, not scaled); a missing key is 0
//! range_m = 15.0
//! heading_deg = -0.2
//! ```

use crate::error::ScenarioError;
use crate::flight::Ctx;
use mimo_core::ids::RadarId;
use mimo_core::registration::{RadarBias, bounds, typical};
use mimo_core::rng::{Stream, domain};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

fn sigma_range() -> f64 {
    typical::RANGE_M
}
fn sigma_uv() -> f64 {
    typical::UV
}
fn sigma_heading() -> f64 {
    typical::HEADING_DEG
}

/// The `[biases]` table of a scenario.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Biases {
    /// Multiplies the σ's; 0 draws no bias.
    #[serde(default)]
    pub scale: f64,
    /// Range bias σ (m) at scale 1.
    #[serde(default = "sigma_range")]
    pub sigma_range_m: f64,
    /// Bias σ of the direction cosine u at scale 1.
    #[serde(default = "sigma_uv")]
    pub sigma_u: f64,
    /// Bias σ of the direction cosine v at scale 1.
    #[serde(default = "sigma_uv")]
    pub sigma_v: f64,
    /// Heading bias σ (deg) at scale 1.
    #[serde(default = "sigma_heading")]
    pub sigma_heading_deg: f64,
    /// Biases set explicitly, by radar id (`R1`, …): used as given in every run.
    #[serde(default)]
    pub radars: BTreeMap<String, RadarBias>,
}

impl Default for Biases {
    fn default() -> Biases {
        Biases {
            scale: 0.0,
            sigma_range_m: typical::RANGE_M,
            sigma_u: typical::UV,
            sigma_v: typical::UV,
            sigma_heading_deg: typical::HEADING_DEG,
            radars: BTreeMap::new(),
        }
    }
}

impl Biases {
    /// No radar has a bias: nothing is drawn and no radar is set (every run's measurements are
    /// those of a perfectly registered network, byte for byte).
    pub fn is_off(&self) -> bool {
        self.scale == 0.0 && self.radars.values().all(RadarBias::is_zero)
    }

    /// Every value checked, for a scenario of `n_radars` radars; `ctx` is the `[biases]` table.
    pub(crate) fn validate(&self, n_radars: usize, ctx: &Ctx) -> Result<(), ScenarioError> {
        let (lo, hi) = (0.0, bounds::SCALE);
        if !(self.scale.is_finite() && self.scale >= lo && self.scale <= hi) {
            return Err(ctx.err("scale", format!("a number in [{lo}, {hi}], got {}", self.scale)));
        }
        let sigmas = [
            ("sigma_range_m", self.sigma_range_m, bounds::RANGE_M),
            ("sigma_u", self.sigma_u, bounds::UV),
            ("sigma_v", self.sigma_v, bounds::UV),
            ("sigma_heading_deg", self.sigma_heading_deg, bounds::HEADING_DEG),
        ];
        for (key, s, hi) in sigmas {
            if !(s.is_finite() && (0.0..=hi).contains(&s)) {
                return Err(ctx.err(key, format!("a standard deviation in [0, {hi}], got {s}")));
            }
        }
        for (id, b) in &self.radars {
            let at = ctx.sub("radars").sub(id);
            match RadarId::parse(id) {
                Some(r) if r.index() < n_radars => {}
                _ => {
                    let last = RadarId(n_radars.saturating_sub(1) as u8);
                    return Err(at.err("", format!("a radar of the scenario (R1…{last}), got `{id}`")));
                }
            }
            for (key, x, hi) in b.components() {
                if !(x.is_finite() && x.abs() <= hi) {
                    return Err(at.err(key, format!("a bias in [-{hi}, {hi}], got {x}")));
                }
            }
        }
        Ok(())
    }

    /// Every radar's biases in run `run` of master seed `seed`: set ones as given, the others
    /// drawn as independent normals of σ·scale (clamped to their bounds) from the radar's own
    /// stream `(seed, BIAS, run, radar)`, so a run's biases do not depend on other runs or radars.
    pub fn draw(&self, seed: u64, run: u32, n_radars: usize) -> Vec<RadarBias> {
        (0..n_radars)
            .map(|i| {
                let id = RadarId(i as u8).to_string();
                if let Some(b) = self.radars.get(&id) {
                    return *b;
                }
                if self.scale == 0.0 {
                    return RadarBias::default();
                }
                let mut s = Stream::new(seed, &[domain::BIAS, u64::from(run), i as u64]);
                let k = self.scale;
                RadarBias {
                    range_m: k * self.sigma_range_m * s.normal(),
                    u: k * self.sigma_u * s.normal(),
                    v: k * self.sigma_v * s.normal(),
                    heading_deg: k * self.sigma_heading_deg * s.normal(),
                }
                .clamped()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_have_the_set_spread_and_repeat_with_the_seed() {
        let b = Biases { scale: 2.0, ..Biases::default() };
        let n = 4000;
        let mut sums = [0.0f64; 4];
        for run in 0..n {
            for r in b.draw(7, run, 1) {
                let z = [r.range_m / 20.0, r.u / 2e-3, r.v / 2e-3, r.heading_deg / 0.2];
                for (s, z) in sums.iter_mut().zip(z) {
                    *s += z * z;
                }
            }
        }
        // Each mean square of a unit normal over 4000 draws: 1 ± 0.022 (1σ); band ±5σ.
        for s in sums {
            assert!((s / f64::from(n) - 1.0).abs() < 0.11, "{s}");
        }
        assert_eq!(b.draw(7, 3, 4), b.draw(7, 3, 4));
        assert_ne!(b.draw(7, 3, 4), b.draw(8, 3, 4));
        // A radar's draw does not depend on how many radars there are.
        assert_eq!(b.draw(7, 3, 4)[..2], b.draw(7, 3, 2)[..]);
    }

    #[test]
    fn set_biases_are_used_as_given_and_off_draws_zero() {
        let set = RadarBias { range_m: 12.0, u: 0.0, v: 1e-3, heading_deg: -0.3 };
        let b = Biases { radars: [("R2".to_string(), set)].into(), ..Biases::default() };
        let d = b.draw(1, 0, 3);
        assert_eq!(d[1], set);
        assert!(d[0].is_zero() && d[2].is_zero());
        assert!(Biases::default().is_off() && !b.is_off());
    }

    #[test]
    fn bad_values_name_the_key_and_the_range() {
        let ctx = Ctx::new("s.toml", "biases");
        let e = Biases { scale: -1.0, ..Biases::default() }.validate(2, &ctx).expect_err("negative scale");
        assert_eq!(e.to_string(), "s.toml: biases.scale: expected a number in [0, 100], got -1");
        let e = Biases { sigma_u: f64::NAN, ..Biases::default() }.validate(2, &ctx).expect_err("nan sigma");
        assert!(e.to_string().contains("biases.sigma_u: expected a standard deviation in [0, 0.1]"), "{e}");
        let set = [("R3".to_string(), RadarBias::default())].into();
        let e = Biases { radars: set, ..Biases::default() }.validate(2, &ctx).expect_err("no R3");
        assert_eq!(e.to_string(), "s.toml: biases.radars.R3: expected a radar of the scenario (R1…R2), got `R3`");
        let set = [("R1".to_string(), RadarBias { range_m: f64::INFINITY, ..RadarBias::default() })].into();
        let e = Biases { radars: set, ..Biases::default() }.validate(2, &ctx).expect_err("inf range");
        assert!(e.to_string().contains("biases.radars.R1.range_m: expected a bias in [-1000, 1000]"), "{e}");
    }
}
