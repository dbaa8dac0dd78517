//! Everything a study needs before it runs anything: every cell, and the world each cell flies
//! in (its scenario with the cell's stress applied and the trajectories built). Worlds are shared
//! by every method and run of the same scenario and stress point. A scenario that cannot be
//! loaded, or that a stress value pushes out of its flight envelope, is an error naming the plan
//! key before anything is written.

use crate::grid::{self, Cell};
use crate::plan::{Axis, Plan, PlanError, ScenarioRef};
use mimo_scenario::stress::Raid;
use mimo_scenario::{Scenario, Stress};
use mimo_sim::{SearchConfig, World};

/// The cells of a plan and their worlds.
pub struct Prepared {
    /// Every cell, in grid order.
    pub cells: Vec<Cell>,
    /// The distinct worlds.
    pub worlds: Vec<World>,
    /// Per cell, its world.
    pub world_of: Vec<usize>,
}

fn stress_of(cell: &Cell, seed: u64) -> Stress {
    Stress {
        rcs_offset_db: cell.applied(Axis::RcsOffsetDb),
        pfa: cell.applied(Axis::Pfa),
        formation_spacing_scale: cell.applied(Axis::FormationSpacingScale),
        peak_power_offset_db: cell.applied(Axis::PeakPowerOffsetDb),
        raid: cell.applied(Axis::RaidTargets).map(|n| Raid { targets: n as u32, seed }),
    }
}

/// The background search of a cell (its `search_pulses`, if applied).
pub fn search_of(cell: &Cell) -> SearchConfig {
    match cell.applied(Axis::SearchPulses) {
        Some(n) => SearchConfig::default().scaled_pulses(n as u32),
        None => SearchConfig::default(),
    }
}

fn load(plan: &Plan, i: usize) -> Result<Scenario, PlanError> {
    let err = |e: String| PlanError {
        file: plan.file.display().to_string(),
        key: format!("scenarios[{i}]"),
        expected: e,
        at: None,
    };
    let mut s = match &plan.scenarios[i] {
        ScenarioRef::Standard(n) => mimo_scenario::load_standard(*n),
        ScenarioRef::File(p) => mimo_scenario::load_path(p),
    }
    .map_err(|e| err(e.to_string()))?;
    if let Some(d) = plan.duration_s {
        s.duration_s = d;
    }
    if let Some(level) = plan.fidelity {
        s.fidelity.level = level;
    }
    Ok(s)
}

/// Load every scenario, apply every stress point and build every world.
pub fn prepare(plan: &Plan) -> Result<Prepared, PlanError> {
    let cells = grid::cells(plan);
    let scenarios: Vec<Scenario> = (0..plan.scenarios.len()).map(|i| load(plan, i)).collect::<Result<_, _>>()?;
    let mut keys: Vec<(usize, Stress)> = Vec::new();
    let mut worlds = Vec::new();
    let mut world_of = Vec::with_capacity(cells.len());
    for cell in &cells {
        let key = (cell.scenario, stress_of(cell, plan.seed));
        if let Some(k) = keys.iter().position(|k| *k == key) {
            world_of.push(k);
            continue;
        }
        let mut s = scenarios[cell.scenario].clone();
        let point: Vec<String> =
            cell.point.iter().map(|(a, v)| format!("{} = {}", a.name(), grid::value_text(*v))).collect();
        let fail = |e: String| PlanError {
            file: plan.file.display().to_string(),
            key: format!("axes ({})", point.join(", ")),
            expected: format!("a scenario that can be flown: scenario {}: {e}", plan.scenarios[cell.scenario].label()),
            at: None,
        };
        key.1.apply(&mut s).map_err(|e| fail(e.to_string()))?;
        let world = World::new(s).map_err(|e| fail(e.to_string()))?;
        keys.push(key);
        worlds.push(world);
        world_of.push(worlds.len() - 1);
    }
    Ok(Prepared { cells, worlds, world_of })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn plan(axes: &str) -> Plan {
        let text = format!(
            "scenarios = [7]\nruns = 1\nduration_s = 200\n[[methods]]\nname = \"a\"\nta = \"default\"\n\
             [[methods]]\nname = \"b\"\nta = \"imm\"\n[axes]\n{axes}"
        );
        Plan::parse(&text, Path::new("p.toml")).expect("plan")
    }

    #[test]
    fn worlds_are_shared_and_carry_the_stress() {
        let p = plan("rcs_offset_db = [0, -10]\nsearch_pulses = [1, 2]");
        let prep = prepare(&p).expect("prepare");
        assert_eq!(prep.cells.len(), 2 * 4);
        assert_eq!(prep.worlds.len(), 2, "search pulses and methods need no world of their own");
        let (w0, w1) = (&prep.worlds[prep.world_of[0]], &prep.worlds[prep.world_of[2]]);
        for (a, b) in w0.scenario.targets.iter().zip(&w1.scenario.targets) {
            assert!((b.rcs_m2 / a.rcs_m2 - 0.1).abs() < 1e-12);
        }
        assert_eq!(w0.scenario.duration_s, 200.0);
        assert_eq!(w0.scenario.fidelity.level, mimo_core::params::FidelityLevel::Auto, "the scenario's own");
        let text = "scenarios = [7]\nruns = 1\nfidelity = \"voltage\"\n[[methods]]\nname = \"a\"\nta = \"default\"\n";
        let pv = Plan::parse(text, Path::new("p.toml")).expect("plan");
        let wv = &prepare(&pv).expect("prepare").worlds[0];
        assert_eq!(wv.scenario.fidelity.level, mimo_core::params::FidelityLevel::Voltage, "the plan's override");
        assert_eq!(search_of(&prep.cells[0]).bands[0].n_pulses, 1);
        assert_eq!(search_of(&prep.cells[1]).bands[0].n_pulses, 2);
    }

    #[test]
    fn a_stress_that_breaks_the_scenario_names_the_point() {
        // Ten times the spacing: the crossover's lateral acceleration (0.88 g at 600 m) exceeds the
        // fighters' 5 g.
        let e = prepare(&plan("formation_spacing_scale = [1, 10]")).err().expect("envelope");
        assert!(e.key.contains("formation_spacing_scale = 10"), "{e}");
        assert!(e.expected.contains("envelope"), "{e}");
    }
}
