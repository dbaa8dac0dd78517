//! A target's polarimetric scattering statistics (docs/model.md §3.5), shared by the scenario
//! files (which set them per aircraft type) and the radar model (which draws the scattering
//! matrix from them when `fidelity.polarization` is on).

use serde::{Deserialize, Serialize};

/// Second-order statistics of a target's 2×2 complex scattering matrix `S` in the target's own
/// H/V basis, and the rotation `β` of that basis about the line of sight relative to the radars'
/// H/V basis.
///
/// `E|s_HH|² = hh_m2`, `E|s_VV|² = vv_m2`, `E|s_HV|² = E|s_VH|² = hv_m2`; `s_HH` and `s_VV` are
/// jointly circular Gaussian with correlation coefficient `hh_vv_correlation`; cross-pol terms
/// are uncorrelated with the co-pol ones.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Polarimetry {
    /// Mean co-polar RCS, horizontal (m²).
    pub hh_m2: f64,
    /// Mean co-polar RCS, vertical (m²).
    pub vv_m2: f64,
    /// Mean cross-polar RCS (m²).
    pub hv_m2: f64,
    /// Correlation coefficient between `s_HH` and `s_VV` (0–1).
    pub hh_vv_correlation: f64,
    /// Rotation `β` of the target's H/V basis about the line of sight (deg).
    pub rotation_deg: f64,
}

/// Cross-polar RCS of the default model relative to the mean co-polar RCS.
pub const DEFAULT_CROSS_POLAR_RATIO: f64 = 0.1;
/// HH–VV correlation of the default model.
pub const DEFAULT_HH_VV_CORRELATION: f64 = 0.5;

impl Polarimetry {
    /// The default model for a mean RCS `σ̄`: `E|s_HH|² = E|s_VV|² = σ̄`, `E|s_HV|² = 0.1 σ̄`,
    /// HH–VV correlation 0.5, no rotation.
    pub fn default_for(rcs_m2: f64) -> Polarimetry {
        Polarimetry {
            hh_m2: rcs_m2,
            vv_m2: rcs_m2,
            hv_m2: DEFAULT_CROSS_POLAR_RATIO * rcs_m2,
            hh_vv_correlation: DEFAULT_HH_VV_CORRELATION,
            rotation_deg: 0.0,
        }
    }

    /// Every mean RCS multiplied by `k` (an RCS offset or override scales the whole matrix).
    pub fn scaled(self, k: f64) -> Polarimetry {
        Polarimetry { hh_m2: self.hh_m2 * k, vv_m2: self.vv_m2 * k, hv_m2: self.hv_m2 * k, ..self }
    }

    /// Check the statistics; returns the offending field and what was wanted.
    pub fn validate(&self) -> Result<(), (String, String)> {
        for (name, x) in [("hh_m2", self.hh_m2), ("vv_m2", self.vv_m2)] {
            if !(x.is_finite() && x > 0.0 && x <= 1e6) {
                return Err((name.into(), format!("a mean RCS in (0, 1e6] m², got {x}")));
            }
        }
        if !(self.hv_m2.is_finite() && self.hv_m2 >= 0.0 && self.hv_m2 <= 1e6) {
            return Err(("hv_m2".into(), format!("a mean RCS in [0, 1e6] m², got {}", self.hv_m2)));
        }
        if !(self.hh_vv_correlation.is_finite() && (0.0..=1.0).contains(&self.hh_vv_correlation)) {
            return Err(("hh_vv_correlation".into(), format!("between 0 and 1, got {}", self.hh_vv_correlation)));
        }
        if !(self.rotation_deg.is_finite() && self.rotation_deg.abs() <= 360.0) {
            return Err((
                "rotation_deg".into(),
                format!("an angle between -360 and 360 degrees, got {}", self.rotation_deg),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_model_and_scaling() {
        let p = Polarimetry::default_for(2.0);
        assert_eq!((p.hh_m2, p.vv_m2, p.hv_m2, p.hh_vv_correlation), (2.0, 2.0, 0.2, 0.5));
        let q = p.scaled(0.5);
        assert_eq!((q.hh_m2, q.vv_m2, q.hv_m2, q.hh_vv_correlation), (1.0, 1.0, 0.1, 0.5));
        assert!(p.validate().is_ok());
        assert_eq!(
            Polarimetry { hh_vv_correlation: 1.5, ..p }.validate().err().map(|e| e.0).as_deref(),
            Some("hh_vv_correlation")
        );
        assert_eq!(Polarimetry { hv_m2: -1.0, ..p }.validate().err().map(|e| e.0).as_deref(), Some("hv_m2"));
    }
}
