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
        bias_scale: cell.applied(Axis::BiasScale),
        link_delay_s: cell.applied(Axis::LinkDelayS),
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

/// Memory the worlds of one study may take (docs/studies.md "Limits"): 3 GiB of the 4 GiB
/// budget of a `mimo` command (docs/design.md §7), the rest for the runs in flight.
pub const WORLDS_BUDGET_BYTES: u64 = 3 << 30;

/// Memory a world of `s` plus `raid_targets` raid aircraft holds, estimated from its size
/// (s.build_trajectories): every target's position and velocity at every flight step of the run
/// and its margin, and every moving ship's faces at every frame sample.
pub fn world_bytes(s: &Scenario, raid_targets: u32) -> u64 {
    let duration_s = s.duration_s.max(0.0);
    let nodes = ((duration_s + mimo_scenario::MARGIN_S) / mimo_scenario::STEP_S).ceil() as u64 + 2;
    let targets =
        (s.targets.len() as u64 + u64::from(raid_targets)) * nodes * 2 * std::mem::size_of::<glam::DVec3>() as u64;
    let face = std::mem::size_of::<mimo_core::face::FaceFrame>() as u64;
    let samples = (duration_s / mimo_scenario::ShipFrames::STEP_S).ceil() as u64 + 3;
    let ships: u64 = s
        .ships
        .iter()
        .map(|sh| if sh.speed_mps == 0.0 { 1 } else { samples } * sh.radar.face_azimuths_deg.len() as u64 * face)
        .sum();
    targets + ships
}

/// The distinct (scenario, stress) keys of the cells, in order of first use, and each cell's key.
fn distinct_worlds(cells: &[Cell], seed: u64) -> (Vec<(usize, Stress)>, Vec<usize>) {
    let mut keys: Vec<(usize, Stress)> = Vec::new();
    let mut world_of = Vec::with_capacity(cells.len());
    for cell in cells {
        let key = (cell.scenario, stress_of(cell, seed));
        match keys.iter().position(|k| *k == key) {
            Some(k) => world_of.push(k),
            None => {
                keys.push(key);
                world_of.push(keys.len() - 1);
            }
        }
    }
    (keys, world_of)
}

/// Refuse worlds that would not fit in [`WORLDS_BUDGET_BYTES`], before any is built.
fn check_world_memory(plan: &Plan, keys: &[(usize, Stress)], scenarios: &[Scenario]) -> Result<(), PlanError> {
    let bytes: u64 =
        keys.iter().map(|(i, st)| world_bytes(&scenarios[*i], st.raid.as_ref().map_or(0, |r| r.targets))).sum();
    if bytes <= WORLDS_BUDGET_BYTES {
        return check_item_memory(plan, keys, scenarios, bytes);
    }
    Err(PlanError {
        file: plan.file.display().to_string(),
        key: "axes".into(),
        expected: format!(
            "at most {} MiB of worlds in memory: {} distinct (scenario, stress point) worlds of these scenarios' \
             targets and durations take about {} MiB (fewer axis values or scenarios, or a shorter duration_s)",
            WORLDS_BUDGET_BYTES >> 20,
            keys.len(),
            bytes >> 20
        ),
        at: None,
    })
}

/// Refuse a plan one of whose items would not fit, alone, beside its worlds (`worlds_bytes`) in
/// the budget of a command ([`crate::inflight`]).
fn check_item_memory(
    plan: &Plan,
    keys: &[(usize, Stress)],
    scenarios: &[Scenario],
    worlds_bytes: u64,
) -> Result<(), PlanError> {
    let budget = mimo_metrics::memory::MEMORY_BUDGET_BYTES;
    let item = keys
        .iter()
        .map(|(i, st)| {
            let s = &scenarios[*i];
            let targets = s.targets.len() + st.raid.as_ref().map_or(0, |r| r.targets as usize);
            crate::inflight::item_bytes_of(targets, s.duration_s)
        })
        .max()
        .unwrap_or(0);
    if worlds_bytes.saturating_add(item) <= budget {
        return Ok(());
    }
    Err(PlanError {
        file: plan.file.display().to_string(),
        key: "axes".into(),
        expected: format!(
            "at most {} MiB in memory: the worlds take about {} MiB and the largest run (targets × duration_s) \
             about {} MiB (fewer raid_targets or a shorter duration_s)",
            budget >> 20,
            worlds_bytes >> 20,
            item >> 20
        ),
        at: None,
    })
}

/// Load every scenario, apply every stress point and build every world.
pub fn prepare(plan: &Plan) -> Result<Prepared, PlanError> {
    grid::check_size(plan)?;
    let cells = grid::cells(plan);
    let scenarios: Vec<Scenario> = (0..plan.scenarios.len()).map(|i| load(plan, i)).collect::<Result<_, _>>()?;
    let (keys, world_of) = distinct_worlds(&cells, plan.seed);
    check_world_memory(plan, &keys, &scenarios)?;
    let mut worlds = Vec::with_capacity(keys.len());
    for (scenario, stress) in &keys {
        let cell = &cells[world_of.iter().position(|&w| w == worlds.len()).unwrap_or(0)];
        let mut s = scenarios[*scenario].clone();
        let point: Vec<String> =
            cell.point.iter().map(|(a, v)| format!("{} = {}", a.name(), grid::value_text(*v))).collect();
        let fail = |e: String| PlanError {
            file: plan.file.display().to_string(),
            key: format!("axes ({})", point.join(", ")),
            expected: format!("a scenario that can be flown: scenario {}: {e}", plan.scenarios[*scenario].label()),
            at: None,
        };
        stress.apply(&mut s).map_err(|e| fail(e.to_string()))?;
        worlds.push(World::new(s).map_err(|e| fail(e.to_string()))?);
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

    /// A run too large to fit beside its worlds in the budget is refused before any world is
    /// built, naming the key; the same raid over a shorter run is accepted.
    #[test]
    fn a_run_too_large_for_the_budget_is_refused() {
        let text = |duration_s: f64| {
            format!(
                "scenarios = [7]\nruns = 1\nduration_s = {duration_s}\n[[methods]]\nname = \"a\"\nta = \"default\"\n\
                 [axes]\nraid_targets = [512]"
            )
        };
        let p = Plan::parse(&text(3600.0), Path::new("p.toml")).expect("plan");
        let e = prepare(&p).err().expect("too large");
        assert_eq!(e.key, "axes", "{e}");
        assert!(e.expected.contains("largest run"), "{e}");
        let p = Plan::parse(&text(60.0), Path::new("p.toml")).expect("plan");
        assert_eq!(prepare(&p).expect("fits").worlds[0].scenario.targets.len(), 7 + 512);
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
