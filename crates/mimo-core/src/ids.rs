//! Radar and target identifiers.
//!
//! Radars are `R1`…`R4` (index 0…3); targets are `F-1`…`F-4` (fighters) and `A`, `B`, `C`
//! (airliners) in the standard scenarios, but a user's scenario may name targets freely.

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// A radar (one per ship), `R1`…`Rn`. The wrapped value is the zero-based index. It is written
/// as the string `"R1"` wherever it is serialized (scenario files, manifests, the test-article
/// protocol), and read from that string (or, for old manifests, from the zero-based index).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct RadarId(pub u8);

impl Serialize for RadarId {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for RadarId {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<RadarId, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Repr {
            Name(String),
            Index(u8),
        }
        match Repr::deserialize(d)? {
            Repr::Name(s) => RadarId::parse(&s)
                .ok_or_else(|| serde::de::Error::custom(format!("expected a radar id R1, R2, …, got `{s}`"))),
            Repr::Index(i) => Ok(RadarId(i)),
        }
    }
}

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

    #[test]
    fn radar_ids_serialize_as_names() {
        let json = serde_json::to_string(&vec![RadarId(0), RadarId(3)]).expect("json");
        assert_eq!(json, r#"["R1","R4"]"#);
        let back: Vec<RadarId> = serde_json::from_str(&json).expect("parse");
        assert_eq!(back, vec![RadarId(0), RadarId(3)]);
        let old: RadarId = serde_json::from_str("2").expect("index");
        assert_eq!(old, RadarId(2));
        assert!(serde_json::from_str::<RadarId>(r#""Q1""#).is_err());
    }
}
