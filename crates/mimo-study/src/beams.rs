//! The radars' faces and beams a score's usage by purpose needs (docs/design.md §6, "Usage by
//! purpose"), from a scenario: the one definition `mimo score` and a study's items both pass.

use mimo_metrics::BeamGeometry;
use mimo_scenario::{Scenario, ShipFrames};

/// Every ship's radar with its faces over the run (sampled as the engine samples them,
/// `ShipFrames`) and the half-power beamwidths of the scenario's pattern model.
pub fn beam_geometry(scenario: &Scenario) -> BeamGeometry {
    let model = scenario.fidelity.pattern;
    scenario.ships.iter().fold(BeamGeometry::none(), |g, ship| {
        let frames = ShipFrames::new(ship, scenario.duration_s);
        g.with_radar(
            &ship.id.to_string(),
            &ship.radar,
            model,
            Box::new(move |t_s, face| frames.face_at(t_s, usize::from(face))),
        )
    })
}
