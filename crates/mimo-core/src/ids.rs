//! Radar and target identifiers.
//!
//! Radars are `R1`…`R4` (index 0…3); targets are `F-1`…`F-4` (fighters) and `A`, `B`, `C`
//! (airliners) in the standard scenarios, but a user's scenario may name targets freely.

use serde::{Deserialize, Serialize};
use std::fmt;

/// A radar (one per ship), `R1`…`Rn`. The wrapped value is the zero-based index.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct RadarId(pub u8);

impl RadarId {
    /// Parse `R1`…`R255`.
    pub fn parse(s: &str) -> Option<RadarId> {
        let n: u16 = s.strip_prefix('R')?.parse().ok()?;
        if (1..=255).contains(&n) { Some(RadarId((n - 1) as u8)) } else { None }
    }

    /// Zero-based index.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Display for RadarId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "R{}", self.0 as u16 + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radar_ids_round_trip() {
        for i in 0..4u8 {
            let id = RadarId(i);
            assert_eq!(RadarId::parse(&id.to_string()), Some(id));
        }
        assert_eq!(RadarId(0).to_string(), "R1");
        assert_eq!(RadarId::parse("R0"), None);
        assert_eq!(RadarId::parse("X1"), None);
    }
}
