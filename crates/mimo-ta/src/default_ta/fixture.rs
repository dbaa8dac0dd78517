//! A test fixture: the default test article after a minute of scenario 7, with the ships'
//! geometry, for tests that plan looks on a real tracker.

use super::{DefaultTa, DefaultTaConfig};
use crate::geometry::ShipGeometry;
use mimo_core::records::RunTables;
use mimo_sim::engine::Engine;
use mimo_sim::{EngineConfig, SearchConfig, World};

/// The default test article (default configuration) after 60 s of scenario 7 with seed 3, and
/// the ships' geometry.
pub fn minute_of_scenario_7() -> (DefaultTa, ShipGeometry) {
    let mut s = mimo_scenario::load_standard(7).expect("scenario 7");
    s.duration_s = 60.0;
    let world = World::new(s).expect("world");
    let cfg = EngineConfig {
        seed: 3,
        duration_s: 60.0,
        record_voltages: false,
        search: SearchConfig::default(),
        ta_config: serde_json::Value::Null,
    };
    let mut ta = DefaultTa::new("default", DefaultTaConfig::default());
    mimo_sim::run_one(&world, &cfg, 0, &mut ta, &mut RunTables::default()).expect("run");
    let geom = ShipGeometry::from_start(&Engine::start_info(&world, 0, &cfg, true));
    (ta, geom)
}
