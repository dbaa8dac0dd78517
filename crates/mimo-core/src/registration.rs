//! Registration biases of one radar (docs/model.md §5.5): constant errors of its range, of the
//! two direction cosines of its faces and of its ship's heading, which every measurement it
//! takes part in carries and no reported covariance includes.

use serde::{Deserialize, Serialize};

/// The typical standard deviations of the registration biases, multiplied by a scenario's
/// `[biases] scale` (docs/model.md §5.5 gives the reasons for each value).
pub mod typical {
    /// Range bias σ (m): a third of the 30-m range resolution of the default 5-MHz waveform, an
    /// uncalibrated delay of 67 ns two way.
    pub const RANGE_M: f64 = 10.0;
    /// Direction-cosine bias σ of u and of v: 1 mrad, a thirtieth of the default 2° beam, the
    /// residual of a face's mechanical alignment and monopulse calibration.
    pub const UV: f64 = 1e-3;
    /// Heading bias σ (deg): 0.1°, the heading accuracy of a naval gyrocompass or inertial
    /// navigator.
    pub const HEADING_DEG: f64 = 0.1;
}

/// The largest magnitudes a bias may have (set or drawn), with the reason: beyond them the
/// small-bias model of docs/model.md §5.5 (and any registration) stops making sense.
pub mod bounds {
    /// Range bias (m): 1 km, a third of a default track window.
    pub const RANGE_M: f64 = 1000.0;
    /// Direction-cosine bias: 0.1 (about 6°, three beamwidths).
    pub const UV: f64 = 0.1;
    /// Heading bias (deg): 10°.
    pub const HEADING_DEG: f64 = 10.0;
    /// Largest `scale` of the typical σ's: 100 (then a 3σ draw still lies inside the bounds above
    /// for range and heading; a draw beyond a bound is clamped to it).
    pub const SCALE: f64 = 100.0;
}

/// One radar's constant registration biases.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RadarBias {
    /// Range bias (m): a monostatic range reads `range_m` too long; a bistatic range sum carries
    /// the transmitter's and the receiver's, so its equivalent range ρ half their sum.
    #[serde(default)]
    pub range_m: f64,
    /// Bias of the measured direction cosine u in the receiving face.
    #[serde(default)]
    pub u: f64,
    /// Bias of the measured direction cosine v in the receiving face.
    #[serde(default)]
    pub v: f64,
    /// Heading bias (deg, clockwise): the radar reports a target at true azimuth A at A + this.
    #[serde(default)]
    pub heading_deg: f64,
}

impl RadarBias {
    /// Every component zero.
    pub fn is_zero(&self) -> bool {
        *self == RadarBias::default()
    }

    /// Each component clamped to its [`bounds`].
    pub fn clamped(self) -> RadarBias {
        RadarBias {
            range_m: self.range_m.clamp(-bounds::RANGE_M, bounds::RANGE_M),
            u: self.u.clamp(-bounds::UV, bounds::UV),
            v: self.v.clamp(-bounds::UV, bounds::UV),
            heading_deg: self.heading_deg.clamp(-bounds::HEADING_DEG, bounds::HEADING_DEG),
        }
    }

    /// The components with their names and bounds, in table order.
    pub fn components(&self) -> [(&'static str, f64, f64); 4] {
        [
            ("range_m", self.range_m, bounds::RANGE_M),
            ("u", self.u, bounds::UV),
            ("v", self.v, bounds::UV),
            ("heading_deg", self.heading_deg, bounds::HEADING_DEG),
        ]
    }
}
