//! Stress transformations of a scenario, for studies that look for where a method fails
//! (docs/design.md §9): every target's RCS offset in dB, every radar's false-alarm probability
//! and peak power, the spacing of the formation fighters, a raid of added aircraft
//! ([`crate::raid`]), the scale of the registration biases and the ships' link delay.
//!
//! Each is applied to a resolved [`Scenario`] before its trajectories are built, so the result
//! is an ordinary scenario, recorded whole in the run's manifest. Values outside a physical range
//! are refused with the range named; a spacing that makes a formation fly outside its envelope
//! (a tighter turn radius is not changed, but crossover accelerations grow with the spacing) is
//! caught when the trajectories are built, like any other scenario.

use crate::model::{Crossover, Formation, Group, Scenario};

/// The bounds every stress value is checked against, with the reason.
pub mod bounds {
    /// RCS offset (dB): ±40 dB spans a 0.02-m² stealthy fighter to a 20 000-m² ship.
    pub const RCS_OFFSET_DB: (f64, f64) = (-40.0, 40.0);
    /// False-alarm probability per cell: above 1e-2 every search dwell is flooded with false
    /// alarms; below 1e-12 the threshold exceeds 27.6 (14.4 dB).
    pub const PFA: (f64, f64) = (1e-12, 1e-2);
    /// Spacing scale of the formation: 0.05 puts the 300-m line abreast 15 m apart; 10 spreads it
    /// over 9 km.
    pub const FORMATION_SPACING_SCALE: (f64, f64) = (0.05, 10.0);
    /// Peak power offset (dB): ±30 dB is 100 W to 100 MW for the default 100-kW radar.
    pub const PEAK_POWER_OFFSET_DB: (f64, f64) = (-30.0, 30.0);
    /// Raid aircraft added to a scenario: a whole number from 0 (none) to 4096, eight times a
    /// dense raid of 512 on the network.
    pub const RAID_TARGETS: (f64, f64) = (0.0, crate::raid::MAX_RAID_TARGETS as f64);
    /// Scale of the typical registration-bias σ's (docs/model.md §5.5): 0 (none) to 100.
    pub const BIAS_SCALE: (f64, f64) = (0.0, mimo_core::registration::bounds::SCALE);
    /// Every ship's link delay (s, docs/model.md §5.6): 0 (perfect) to a minute.
    pub const LINK_DELAY_S: (f64, f64) = (0.0, crate::links::MAX_DELAY_S);
}

/// A raid: how many aircraft, and the seed they are drawn from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Raid {
    /// Number of aircraft (at most [`crate::raid::MAX_RAID_TARGETS`]).
    pub targets: u32,
    /// The seed of the draw (a study's or a simulation's master seed).
    pub seed: u64,
}

/// Stress values; `None` leaves the scenario's own value.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Stress {
    /// Added to every target's mean RCS (dB).
    pub rcs_offset_db: Option<f64>,
    /// Every radar's per-cell false-alarm probability.
    pub pfa: Option<f64>,
    /// Multiplies every offset between formation members (along, right, up, crossover moves and
    /// vertical passes, group reference points).
    pub formation_spacing_scale: Option<f64>,
    /// Added to every radar's peak power (dB).
    pub peak_power_offset_db: Option<f64>,
    /// Aircraft added before the other stresses are applied, so that they apply to them too.
    pub raid: Option<Raid>,
    /// The scale of the registration biases' σ's (`[biases] scale`); set biases are kept.
    pub bias_scale: Option<f64>,
    /// Every ship's link delay (s); jitters are kept within it.
    pub link_delay_s: Option<f64>,
}

/// A stress value outside its range: the axis, the value and the range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{axis} = {value}: expected a {} in [{lo}, {hi}]", if *axis == "raid_targets" { "whole number" } else { "value" })]
pub struct StressError {
    /// The axis name.
    pub axis: &'static str,
    /// The value given.
    pub value: f64,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
}

/// Check a raid size given as a number (a plan value): a whole number in [`bounds::RAID_TARGETS`].
pub fn check_raid_targets(value: f64) -> Result<u32, StressError> {
    let (lo, hi) = bounds::RAID_TARGETS;
    check("raid_targets", value, (lo, hi))?;
    if value.fract() != 0.0 {
        return Err(StressError { axis: "raid_targets", value, lo, hi });
    }
    Ok(value as u32)
}

/// Check one value against its bounds.
pub fn check(axis: &'static str, value: f64, (lo, hi): (f64, f64)) -> Result<(), StressError> {
    if value.is_finite() && value >= lo && value <= hi { Ok(()) } else { Err(StressError { axis, value, lo, hi }) }
}

fn scale_crossovers(cs: &mut [Crossover], k: f64) {
    for c in cs {
        for m in &mut c.moves {
            m.along_m = m.along_m.map(|x| x * k);
            m.right_m = m.right_m.map(|x| x * k);
            m.up_m = m.up_m.map(|x| x * k);
            m.pass_up_m *= k;
        }
    }
}

fn scale_group(g: &mut Group, k: f64) {
    if let Some(r) = &mut g.reference {
        r.along_m *= k;
        r.right_m *= k;
        r.up_m *= k;
    }
    scale_crossovers(&mut g.crossovers, k);
    if let Some(s) = &mut g.split {
        s.groups.iter_mut().for_each(|g| scale_group(g, k));
    }
}

fn scale_formation(f: &mut Formation, k: f64) {
    for m in &mut f.members {
        m.along_m *= k;
        m.right_m *= k;
        m.up_m *= k;
    }
    scale_crossovers(&mut f.crossovers, k);
    if let Some(s) = &mut f.split {
        s.groups.iter_mut().for_each(|g| scale_group(g, k));
    }
}

impl Stress {
    /// Check every value against [`bounds`].
    pub fn check(&self) -> Result<(), StressError> {
        let opt = |axis, v: Option<f64>, b| v.map_or(Ok(()), |v| check(axis, v, b));
        opt("rcs_offset_db", self.rcs_offset_db, bounds::RCS_OFFSET_DB)?;
        opt("pfa", self.pfa, bounds::PFA)?;
        opt("formation_spacing_scale", self.formation_spacing_scale, bounds::FORMATION_SPACING_SCALE)?;
        opt("peak_power_offset_db", self.peak_power_offset_db, bounds::PEAK_POWER_OFFSET_DB)?;
        opt("bias_scale", self.bias_scale, bounds::BIAS_SCALE)?;
        opt("link_delay_s", self.link_delay_s, bounds::LINK_DELAY_S)?;
        self.raid.map_or(Ok(()), |r| check_raid_targets(f64::from(r.targets)).map(|_| ()))
    }

    /// Apply to a resolved scenario (checked first).
    pub fn apply(&self, s: &mut Scenario) -> Result<(), StressError> {
        self.check()?;
        if let Some(r) = self.raid {
            crate::raid::add_raid(s, r.targets, r.seed);
        }
        if let Some(db) = self.rcs_offset_db {
            let k = 10f64.powf(db / 10.0);
            s.targets.iter_mut().for_each(|t| {
                t.rcs_m2 *= k;
                t.polarimetry = t.polarimetry.map(|p| p.scaled(k));
            });
        }
        if let Some(pfa) = self.pfa {
            s.ships.iter_mut().for_each(|sh| sh.radar.pfa = pfa);
        }
        if let Some(db) = self.peak_power_offset_db {
            let k = 10f64.powf(db / 10.0);
            s.ships.iter_mut().for_each(|sh| sh.radar.peak_power_w *= k);
        }
        if let Some(k) = self.formation_spacing_scale {
            s.formations.iter_mut().for_each(|f| scale_formation(f, k));
        }
        if let Some(k) = self.bias_scale {
            s.biases.scale = k;
        }
        if let Some(d) = self.link_delay_s {
            s.links.set_delay(d);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn separation_at(s: &Scenario, t: f64, a: &str, b: &str) -> f64 {
        let tr = s.build_trajectories().expect("trajectories");
        let (i, j) = (tr.index_of(a).expect("a"), tr.index_of(b).expect("b"));
        (tr.position_at(i, t) - tr.position_at(j, t)).length()
    }

    #[test]
    fn stress_values_change_what_they_name_and_nothing_else() {
        let base = crate::load_standard(7).expect("scenario 7");
        let mut s = base.clone();
        let stress = Stress {
            rcs_offset_db: Some(-3.0),
            pfa: Some(1e-4),
            formation_spacing_scale: Some(2.0),
            peak_power_offset_db: Some(10.0),
            raid: None,
            bias_scale: Some(2.0),
            link_delay_s: Some(0.5),
        };
        stress.apply(&mut s).expect("apply");
        for (a, b) in s.targets.iter().zip(&base.targets) {
            assert!((a.rcs_m2 / b.rcs_m2 - 10f64.powf(-0.3)).abs() < 1e-12);
        }
        for (a, b) in s.ships.iter().zip(&base.ships) {
            assert_eq!(a.radar.pfa, 1e-4);
            assert!((a.radar.peak_power_w / b.radar.peak_power_w - 10.0).abs() < 1e-12);
            assert_eq!(a.lat_deg, b.lat_deg);
        }
        assert_eq!((s.biases.scale, s.links.delay_s), (2.0, 0.5));
        assert!(base.biases.is_off() && base.links.is_off());
        // Twice the spacing: the line-abreast neighbours F-1/F-3 (300 m apart at t = 0) at 600 m.
        let d0 = separation_at(&base, 0.0, "F-1", "F-3");
        let d1 = separation_at(&s, 0.0, "F-1", "F-3");
        assert!((d1 / d0 - 2.0).abs() < 1e-6, "{d0} -> {d1}");
        // After the crossover too (offsets of the moves scale as well).
        let d0 = separation_at(&base, 130.0, "F-1", "F-3");
        let d1 = separation_at(&s, 130.0, "F-1", "F-3");
        assert!((d1 / d0 - 2.0).abs() < 1e-3, "{d0} -> {d1}");
        // The airliners fly exactly as before.
        let (tb, ts) = (base.build_trajectories().expect("t"), s.build_trajectories().expect("t"));
        let a = tb.index_of("A").expect("A");
        assert_eq!(tb.position_at(a, 500.0), ts.position_at(a, 500.0));
    }

    #[test]
    fn values_outside_their_range_are_refused() {
        let mut s = crate::load_standard(1).expect("scenario 1");
        let e = Stress { pfa: Some(2.0), ..Stress::default() }.apply(&mut s).expect_err("pfa 2");
        assert_eq!(e.axis, "pfa");
        assert!(e.to_string().contains("[0.000000000001, 0.01]"), "{e}");
        assert!(Stress { formation_spacing_scale: Some(-1.0), ..Stress::default() }.check().is_err());
        assert!(Stress { rcs_offset_db: Some(f64::NAN), ..Stress::default() }.check().is_err());
        assert!(Stress { bias_scale: Some(-0.5), ..Stress::default() }.check().is_err());
        assert!(Stress { link_delay_s: Some(61.0), ..Stress::default() }.check().is_err());
        assert!(Stress::default().check().is_ok());
    }
}
