//! Bad input gets a one-line error naming the file, the field and what was expected.

use mimo_scenario::{ScenarioError, load_path, load_standard, load_str};
use std::path::Path;

/// The smallest valid scenario (one ship, one jet), shared by the parser tests.
const BASE: &str = include_str!("data/minimal.toml");

fn load(text: &str) -> Result<mimo_scenario::Scenario, ScenarioError> {
    load_str(text, "my.toml", None)
}

fn err(text: &str) -> ScenarioError {
    let e = load(text).expect_err("should be rejected");
    let msg = e.to_string();
    assert!(!msg.contains('\n'), "one line: {msg}");
    assert!(msg.starts_with("my.toml"), "names the file: {msg}");
    e
}

fn invalid(text: &str, field: &str, expected: &str) {
    match err(text) {
        ScenarioError::Invalid { field: f, expected: e, .. } => {
            assert_eq!(f, field);
            assert!(e.contains(expected), "{e:?} should contain {expected:?}");
        }
        other => panic!("expected Invalid for {field}, got {other:?}"),
    }
}

#[test]
fn a_minimal_inline_scenario_loads_and_flies() {
    let s = load(BASE).expect("valid");
    assert_eq!(s.name, "inline");
    assert_eq!(s.target_ids(), ["X"]);
    assert_eq!(s.ships[0].array_height_m, 20.0);
    assert_eq!(s.ships[0].radar, mimo_core::params::RadarParams::default());
    let t = s.build_trajectories().expect("flies");
    assert_eq!(t.truth_rows(0, 10.0).len(), 1001);
    // Without a duration the default is 1000 s; without a name, the file stem.
    let s = load_str(&BASE.replace("duration_s = 100.0", "").replace("name = \"inline\"", ""), "dir/custom.toml", None)
        .expect("valid");
    assert_eq!((s.duration_s, s.name.as_str()), (1000.0, "custom"));
}

#[test]
fn toml_syntax_errors_give_line_and_column() {
    let text = BASE.replace("duration_s = 100.0", "duration_s = = 100.0");
    match err(&text) {
        ScenarioError::Syntax { line, column, .. } => assert_eq!((line, column), (3, 14)),
        other => panic!("{other:?}"),
    }
    let msg = err(&text).to_string();
    assert!(msg.starts_with("my.toml:3:14: TOML syntax error:"), "{msg}");
    match err("[[ships]\nid = 1") {
        ScenarioError::Syntax { line: 1, .. } => {}
        other => panic!("{other:?}"),
    }
}

#[test]
fn unknown_fields_are_rejected_with_their_place() {
    let text = BASE.replace("heading_deg = 0.0", "heading_deg = 0.0\ncolour = \"grey\"");
    match err(&text) {
        ScenarioError::UnknownField { field, line, .. } => {
            assert_eq!(field, "colour");
            assert_eq!(line, 16);
        }
        other => panic!("{other:?}"),
    }
    // Also at the top level, in an aircraft, in the fidelity table and in a radar table.
    for (from, to, field) in [
        ("name = \"inline\"", "name = \"inline\"\nduraton_s = 5", "duraton_s"),
        ("speed_mps = 200.0", "speed_mps = 200.0\nmach = 0.8", "mach"),
        ("speed_mps = 200.0", "speed_mps = 200.0\n[fidelity]\nrefractoin = true", "refractoin"),
        ("heading_deg = 0.0\n", "heading_deg = 0.0\nradar = { frequncy_hz = 3e9 }\n", "frequncy_hz"),
    ] {
        match err(&BASE.replace(from, to)) {
            ScenarioError::UnknownField { field: f, .. } => assert_eq!(f, field),
            other => panic!("{field}: {other:?}"),
        }
    }
}

#[test]
fn wrong_types_and_missing_fields_are_schema_errors() {
    match err(&BASE.replace("duration_s = 100.0", "duration_s = \"long\"")) {
        ScenarioError::Schema { line: 3, message, .. } => assert!(message.contains("invalid type"), "{message}"),
        other => panic!("{other:?}"),
    }
    match err(&BASE.replace("lat_deg = 36.0\n", "")) {
        ScenarioError::Schema { message, .. } => {
            assert!(message.contains("missing field `lat_deg`"), "{message}")
        }
        other => panic!("{other:?}"),
    }
    let text = BASE.replace("speed_mps = 200.0", "speed_mps = 200.0\nmanoeuvres = [{ kind = \"loop\", at_s = 1.0 }]");
    assert!(matches!(err(&text), ScenarioError::Schema { .. }));
}

#[test]
fn impossible_values_are_rejected() {
    invalid(
        &BASE.replace("lat_deg = 36.0", "lat_deg = 95.0"),
        "ships[0].lat_deg",
        "a latitude between -90 and 90 degrees, got 95",
    );
    let msg = err(&BASE.replace("lat_deg = 36.0", "lat_deg = 95.0")).to_string();
    assert_eq!(msg, "my.toml: ships[0].lat_deg: expected a latitude between -90 and 90 degrees, got 95");
    invalid(&BASE.replace("heading_deg = 0.0", "heading_deg = 0.0\nspeed_mps = -3.0"), "ships[0].speed_mps", "got -3");
    invalid(&BASE.replace("speed_mps = 200.0", "speed_mps = -200.0"), "aircraft[0].speed_mps", "got -200");
    invalid(
        &BASE.replace("heading_deg = 0.0\n", "heading_deg = 0.0\nradar = { aperture_x_m = 0.0 }\n"),
        "ships[0].radar.aperture_x_m",
        "positive",
    );
    invalid(
        &BASE.replace("heading_deg = 0.0\n", "heading_deg = 0.0\nradar = { beamwidth_factor = 0.0 }\n"),
        "ships[0].radar.beamwidth_factor",
        "positive",
    );
    invalid(
        &BASE.replace("heading_deg = 0.0\n", "heading_deg = 0.0\nradar = { peak_power_w = -1e5 }\n"),
        "ships[0].radar.peak_power_w",
        "positive",
    );
    invalid(&BASE.replace("duration_s = 100.0", "duration_s = 0.0"), "duration_s", "duration");
    invalid(&BASE.replace("alt_m = 5000.0", "alt_m = 50000.0"), "aircraft[0].start.alt_m", "altitude");
    invalid(&BASE.replace("rcs_m2 = 5.0", "rcs_m2 = -5.0"), "aircraft_types.jet.rcs_m2", "RCS");
    invalid(&BASE.replace("id = \"R1\"", "id = \"R2\""), "ships[0].id", "R1");
    invalid(&BASE.replace("id = \"R1\"", "id = \"radar one\""), "ships[0].id", "radar id");
    invalid(&BASE.replace("type = \"jet\"", "type = \"glider\""), "aircraft[0].type", "jet");
    invalid(&format!("{BASE}\n[fidelity]\ntruth_rate_hz = 0.0\n"), "fidelity.truth_rate_hz", "rate");
}

#[test]
fn zero_or_unknown_targets_are_rejected() {
    invalid(&BASE.replace("name = \"inline\"", "name = \"inline\"\ntargets = []"), "targets", "at least one target");
    invalid(&BASE.replace("name = \"inline\"", "name = \"inline\"\ntargets = [\"Y\"]"), "targets[0]", "`Y`");
    invalid(&BASE.replace("name = \"inline\"", "name = \"inline\"\ntargets = [\"X\", \"X\"]"), "targets[1]", "once");
    // No aircraft at all.
    let no_aircraft = &BASE[..BASE.find("[[aircraft]]").expect("has aircraft")];
    invalid(no_aircraft, "targets", "at least one target");
    // No ships.
    let no_ships = BASE.replace("[[ships]]\nid = \"R1\"\nlat_deg = 36.0\nlon_deg = -70.0\nheading_deg = 0.0\n", "");
    invalid(&no_ships, "ships", "at least one ship");
}

#[test]
fn unknown_standard_scenario_number() {
    for n in [0, 8, 99] {
        let e = load_standard(n).expect_err("not a standard scenario");
        assert_eq!(e, ScenarioError::UnknownScenario { number: n, max: 7 });
        assert!(e.to_string().starts_with(&format!("unknown standard scenario {n}: expected a number from 1 to 7")));
    }
}

#[test]
fn manoeuvre_and_formation_mistakes_are_caught() {
    let turns = "speed_mps = 200.0\nmanoeuvres = [\n  { kind = \"turn\", at_s = 10.0, turn_deg = 90.0, load_factor = 2.0 },\n  { kind = \"turn\", at_s = 12.0, turn_deg = 90.0, load_factor = 2.0 },\n]";
    invalid(&BASE.replace("speed_mps = 200.0", turns), "aircraft[0].manoeuvres[1].at_s", "do not overlap");
    let weak = "speed_mps = 200.0\nmanoeuvres = [{ kind = \"turn\", at_s = 10.0, turn_deg = 90.0, load_factor = 1.0 }]";
    invalid(&BASE.replace("speed_mps = 200.0", weak), "aircraft[0].manoeuvres[0].load_factor", "(1, 12]");
    // A turn the airframe cannot fly is found when the trajectories are built.
    let hard = "speed_mps = 200.0\nmanoeuvres = [{ kind = \"turn\", at_s = 10.0, turn_deg = 90.0, load_factor = 6.0 }]";
    let s = load(&BASE.replace("speed_mps = 200.0", hard)).expect("loads");
    match s.build_trajectories().expect_err("too hard") {
        ScenarioError::Envelope { target, t_s, what } => {
            assert_eq!(target, "X");
            assert!((10.0..12.0).contains(&t_s), "{t_s}");
            assert!(what.contains("above max_accel_g 3"), "{what}");
        }
        other => panic!("{other:?}"),
    }
    let slow = "speed_mps = 200.0\nmanoeuvres = [{ kind = \"speed\", at_s = 10.0, to_mps = 50.0, accel_mps2 = 5.0 }]";
    let s = load(&BASE.replace("speed_mps = 200.0", slow)).expect("loads");
    assert!(matches!(s.build_trajectories(), Err(ScenarioError::Envelope { .. })));
    // A split whose groups miss a member, and a crossover moving a stranger.
    let formation = r#"
[[formations]]
name = "pair"
type = "jet"
start = { lat_deg = 36.5, lon_deg = -70.5, alt_m = 5000.0 }
heading_deg = 90.0
speed_mps = 200.0
members = [{ id = "P1", right_m = -100.0 }, { id = "P2", right_m = 100.0 }]
crossovers = [{ start_s = 10.0, duration_s = 20.0, moves = [{ id = "P3", right_m = 100.0 }] }]
"#;
    invalid(&format!("{BASE}{formation}"), "formations[0].crossovers[0].moves[0].id", "P1, P2");
    let split = formation.replace(
        "crossovers = [{ start_s = 10.0, duration_s = 20.0, moves = [{ id = \"P3\", right_m = 100.0 }] }]",
        "split = { at_s = 50.0, groups = [{ name = \"one\", members = [\"P1\"] }] }",
    );
    invalid(&format!("{BASE}{split}"), "formations[0].split.groups", "missing: P2");
    let ok = split.replace("members = [\"P1\"] }]", "members = [\"P1\"] }, { name = \"two\", members = [\"P2\"] }]");
    let s = load(&format!("{BASE}{ok}")).expect("valid");
    assert_eq!(s.target_ids(), ["P1", "P2", "X"]);
    s.build_trajectories().expect("flies");
    // Duplicate target ids across flights.
    let dup = formation.replace("\"P1\"", "\"X\"").replace(
        "crossovers = [{ start_s = 10.0, duration_s = 20.0, moves = [{ id = \"P3\", right_m = 100.0 }] }]",
        "",
    );
    invalid(&format!("{BASE}{dup}"), "aircraft[0].id", "also defined");
}

#[test]
fn includes_resolve_beside_the_file_and_from_builtins() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    write(d, "fleet.toml", &BASE[BASE.find("[[ships]]").expect("ships")..BASE.find("[[aircraft]]").expect("aircraft")]);
    write(
        d,
        "sub/jets.toml",
        &format!(
            "{}\n{}",
            &BASE[BASE.find("[aircraft_types.jet]").expect("types")..BASE.find("[[ships]]").expect("ships")],
            &BASE[BASE.find("[[aircraft]]").expect("aircraft")..]
        ),
    );
    write(
        d,
        "mine.toml",
        "include = [\"fleet.toml\", \"sub/jets.toml\", \"builtin:fighters.toml\"]\ntargets = [\"X\", \"F-2\"]\nduration_s = 300.0\n",
    );
    let s = load_path(d.join("mine.toml")).expect("loads");
    assert_eq!((s.name.as_str(), s.duration_s), ("mine", 300.0));
    assert_eq!(s.target_ids(), ["X", "F-2"]);
    s.build_trajectories().expect("flies");
    // Overriding a standard scenario's settings by including it.
    write(d, "short7.toml", "include = [\"builtin:7.toml\"]\nduration_s = 200.0\nname = \"short\"\n");
    let s = load_path(d.join("short7.toml")).expect("loads");
    assert_eq!((s.name.as_str(), s.duration_s, s.targets.len()), ("short", 200.0, 7));
    // Errors in an included file name that file.
    write(d, "bad.toml", "include = [\"fleet.toml\", \"broken.toml\"]\n");
    write(d, "broken.toml", "[[ships]]\nid = \"R2\"\nlat_deg = 95.0\nlon_deg = 0.0\nheading_deg = 0.0\n");
    let e = load_path(d.join("bad.toml")).expect_err("bad latitude");
    assert!(e.to_string().contains("broken.toml: ships[0].lat_deg: expected a latitude"), "{e}");
    // Missing files, missing built-ins and cycles.
    write(d, "missing.toml", "include = [\"nope.toml\"]\n");
    assert!(matches!(load_path(d.join("missing.toml")), Err(ScenarioError::Io { .. })));
    assert!(matches!(load_path(d.join("absent.toml")), Err(ScenarioError::Io { .. })));
    write(d, "nobuiltin.toml", "include = [\"builtin:ships2.toml\"]\n");
    assert!(matches!(load_path(d.join("nobuiltin.toml")), Err(ScenarioError::Include { .. })));
    write(d, "a.toml", "include = [\"b.toml\"]\n");
    write(d, "b.toml", "include = [\"a.toml\"]\n");
    match load_path(d.join("a.toml")) {
        Err(ScenarioError::Include { reason, .. }) => assert!(reason.contains("cycle")),
        other => panic!("{other:?}"),
    }
    // Defining the same ship twice.
    write(
        d,
        "twice.toml",
        "include = [\"fleet.toml\", \"sub/jets.toml\"]\n[[ships]]\nid = \"R1\"\nlat_deg = 36.0\nlon_deg = -70.0\nheading_deg = 0.0\n",
    );
    let e = load_path(d.join("twice.toml")).expect_err("duplicate ship");
    assert!(e.to_string().contains("twice.toml: ships[0].id: expected a ship id not defined before"), "{e}");
}

fn write(dir: &Path, name: &str, text: &str) {
    let p = dir.join(name);
    if let Some(parent) = p.parent() {
        std::fs::create_dir_all(parent).expect("mkdir");
    }
    std::fs::write(p, text).expect("write");
}

#[test]
fn text_without_a_directory_can_only_include_builtins() {
    let text = "include = [\"ships.toml\"]\n";
    match load_str(text, "t.toml", None) {
        Err(ScenarioError::Include { reason, .. }) => {
            assert!(reason.contains("builtin:"), "{reason}")
        }
        other => panic!("{other:?}"),
    }
    let text = "include = [\"builtin:ships.toml\", \"builtin:airliners.toml\"]\ntargets = [\"B\"]\n";
    let s = load_str(text, "t.toml", None).expect("loads");
    assert_eq!(s.target_ids(), ["B"]);
    assert_eq!(s.ships.len(), 4);
}

/// Polarimetry (docs/model.md §3.5): a type's matrix loads and scales with a target's own RCS;
/// bad statistics and polarization without SW1 are refused, naming the field.
#[test]
fn polarimetry_loads_scales_and_is_checked() {
    let pol = "\n[aircraft_types.jet.polarimetry]\nhh_m2 = 5.0\nvv_m2 = 10.0\nhv_m2 = 0.5\nhh_vv_correlation = 0.3\nrotation_deg = 20.0\n";
    let with = BASE.replace("max_accel_g = 3.0\n", &format!("max_accel_g = 3.0\n{pol}"));
    let s = load(&with).expect("valid");
    let p = s.targets[0].polarimetry.expect("polarimetry");
    assert_eq!((p.hh_m2, p.vv_m2, p.hv_m2, p.rotation_deg), (5.0, 10.0, 0.5, 20.0));
    // The aircraft's own 2.5 m² halves the type's 5 m²: the whole matrix halves.
    let own = with.replace("speed_mps = 200.0", "speed_mps = 200.0\nrcs_m2 = 2.5");
    let p = load(&own).expect("valid").targets[0].polarimetry.expect("polarimetry");
    assert_eq!((p.hh_m2, p.vv_m2, p.hv_m2), (2.5, 5.0, 0.25));
    invalid(
        &with.replace("hh_vv_correlation = 0.3", "hh_vv_correlation = 1.3"),
        "aircraft_types.jet.polarimetry.hh_vv_correlation",
        "between 0 and 1",
    );
    invalid(&with.replace("vv_m2 = 10.0", "vv_m2 = -1.0"), "aircraft_types.jet.polarimetry.vv_m2", "RCS");
    invalid(&format!("{BASE}\n[fidelity]\npolarization = true\nswerling = \"sw0\"\n"), "fidelity.polarization", "sw1");
    assert!(load(&format!("{BASE}\n[fidelity]\npolarization = true\n")).is_ok());
    invalid(
        &BASE.replace("heading_deg = 0.0\n", "heading_deg = 0.0\nradar = { tx_polarization_deg = 1e9 }\n"),
        "ships[0].radar.tx_polarization_deg",
        "angle",
    );
}

/// `[fidelity] two_target` (docs/model.md §4.9) defaults to off, reads `true`, and is on in every
/// standard scenario.
#[test]
fn two_target_is_read_and_on_in_the_standard_scenarios() {
    assert!(!load(BASE).expect("valid").fidelity.two_target);
    assert!(load(&format!("{BASE}\n[fidelity]\ntwo_target = true\n")).expect("valid").fidelity.two_target);
    for n in 1..=7 {
        assert!(load_standard(n).expect("standard").fidelity.two_target, "scenario {n}");
    }
}

/// `[fidelity] level` reads each rung of the ladder (docs/model.md §4.8), defaults to `auto`, and
/// an unknown rung is a one-line error naming the field.
#[test]
fn fidelity_level_reads_every_rung() {
    use mimo_core::params::FidelityLevel;
    assert_eq!(load(BASE).expect("valid").fidelity.level, FidelityLevel::Auto);
    for level in FidelityLevel::ALL {
        let s = load(&format!("{BASE}\n[fidelity]\nlevel = \"{}\"\n", level.name())).expect("valid");
        assert_eq!(s.fidelity.level, level);
        assert_eq!(FidelityLevel::parse(level.name()), Some(level));
    }
    let msg = err(&format!("{BASE}\n[fidelity]\nlevel = \"cells\"\n")).to_string();
    assert!(msg.contains("level") || msg.contains("cells"), "{msg}");
}
