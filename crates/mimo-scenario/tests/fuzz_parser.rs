//! Property tests of the scenario parser (docs/design.md §7): whatever the text, loading returns
//! a scenario or a one-line error naming the file — never a panic; a valid scenario carries the
//! values written into it; a resolved scenario survives its JSON round trip (the manifest's
//! `scenario.resolved`). The cargo-fuzz target `scenario_parser` (fuzz/) runs the same entry
//! point for longer.

use mimo_scenario::load_str;
use proptest::prelude::*;

/// The smallest valid scenario (one ship, one jet), shared by the parser tests.
const BASE: &str = include_str!("data/minimal.toml");

fn check_error(text: &str) {
    if let Err(e) = load_str(text, "fuzz.toml", None) {
        let msg = e.to_string();
        assert!(!msg.contains('\n'), "one line: {msg}");
        assert!(msg.starts_with("fuzz.toml"), "names the file: {msg}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_text_never_panics(text in "\\PC{0,400}") {
        check_error(&text);
    }

    #[test]
    fn mutated_scenarios_never_panic(at in 0usize..BASE.len(), len in 0usize..12, with in "[-0-9a-z_.=\\[\\]{}\" \n]{0,12}") {
        let mut text = BASE.as_bytes().to_vec();
        let end = (at + len).min(text.len());
        text.splice(at..end, with.bytes());
        if let Ok(t) = String::from_utf8(text) {
            check_error(&t);
        }
    }

    #[test]
    fn valid_values_round_trip(lat in -80.0f64..80.0, lon in -179.0f64..179.0, speed in 101.0f64..299.0, dur in 1.0f64..3600.0) {
        let text = BASE
            .replace("duration_s = 100.0", &format!("duration_s = {dur:?}"))
            .replace("lat_deg = 36.0", &format!("lat_deg = {lat:?}"))
            .replace("lon_deg = -70.0\nheading", &format!("lon_deg = {lon:?}\nheading"))
            .replace("speed_mps = 200.0", &format!("speed_mps = {speed:?}"));
        let s = load_str(&text, "fuzz.toml", None).expect("valid");
        prop_assert_eq!(s.duration_s, dur);
        prop_assert_eq!(s.ships[0].lat_deg, lat);
        prop_assert_eq!(s.ships[0].lon_deg, lon);
        let back: mimo_scenario::Scenario =
            serde_json::from_value(serde_json::to_value(&s).expect("json")).expect("from json");
        prop_assert_eq!(back, s);
    }
}
