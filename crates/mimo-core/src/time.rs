//! Simulation time.
//!
//! The event engine orders events by integer nanoseconds since scenario start ([`SimTime`]), so
//! that two events never swap order through floating-point rounding. Tables carry `t_s` (f64
//! seconds), converted at the edge with [`SimTime::as_secs`].

use serde::{Deserialize, Serialize};

/// Time since scenario start in integer nanoseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default, Serialize, Deserialize)]
pub struct SimTime(pub i64);

impl SimTime {
    /// Scenario start.
    pub const ZERO: SimTime = SimTime(0);

    /// From seconds, rounded to the nearest nanosecond.
    pub fn from_secs(t_s: f64) -> SimTime {
        SimTime((t_s * 1e9).round() as i64)
    }

    /// Seconds as f64.
    pub fn as_secs(self) -> f64 {
        self.0 as f64 * 1e-9
    }

    /// This time plus a duration in seconds (rounded to the nearest nanosecond).
    pub fn plus_secs(self, dt_s: f64) -> SimTime {
        SimTime(self.0 + (dt_s * 1e9).round() as i64)
    }
}

impl std::ops::Sub for SimTime {
    type Output = f64;
    /// Difference in seconds.
    fn sub(self, rhs: SimTime) -> f64 {
        (self.0 - rhs.0) as f64 * 1e-9
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_order() {
        let a = SimTime::from_secs(0.1);
        let b = SimTime::from_secs(0.2);
        assert_eq!(a.0, 100_000_000);
        assert!(a < b);
        assert_eq!(a.plus_secs(0.1), b);
        assert!((b - a - 0.1).abs() < 1e-15);
        assert!((SimTime::from_secs(1000.0).as_secs() - 1000.0).abs() < 1e-12);
    }
}
