//! Method sweeps in study plans: expansion into one method per value with the value in its
//! configuration, the family columns of the study tables, and every bad sweep refused with the
//! plan file and key path.

use mimo_study::plan::{Architecture, MethodTa, Plan};
use std::path::Path;

const PLAN: &str = r#"
scenarios = [7]
runs = 2
[[methods]]
name = "mimo"
ta = "default"
sweep = { "resource_manager.max_ta_share" = [0.5, 0.25, 0.125] }
[[methods]]
name = "conv"
ta = "default"
config = { resource_manager = { mimo = false } }
sweep = { "resource_manager.max_ta_share" = [0.25, 0.5] }
[[methods]]
name = "single"
ta = "imm"
architecture = "conventional"
"#;

fn parse(text: &str) -> Result<Plan, mimo_study::PlanError> {
    Plan::parse(text, Path::new("studies/sweep.toml"))
}

#[test]
fn a_sweep_expands_into_one_method_per_value() {
    let p = parse(PLAN).expect("plan");
    let names: Vec<&str> = p.methods.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["mimo@0.5", "mimo@0.25", "mimo@0.125", "conv@0.25", "conv@0.5", "single"]);
    for m in &p.methods[..5] {
        let MethodTa::Builtin { config, .. } = &m.ta else { panic!("builtin") };
        let v = m.knob_value.expect("swept");
        assert_eq!(config["resource_manager"]["max_ta_share"], serde_json::json!(v), "{}", m.name);
        assert_eq!(m.overrides["resource_manager"]["max_ta_share"], serde_json::json!(v));
        assert_eq!(m.knob.as_deref(), Some("resource_manager.max_ta_share"));
    }
    let conv = &p.methods[3];
    assert_eq!((conv.family.as_str(), conv.architecture), ("conv", Architecture::Conventional));
    let MethodTa::Builtin { config, .. } = &conv.ta else { panic!("builtin") };
    assert_eq!(config["resource_manager"]["mimo"], serde_json::json!(false), "the entry's config is kept");
    assert_eq!(p.methods[0].architecture, Architecture::Mimo);
    let single = &p.methods[5];
    assert_eq!((single.knob.clone(), single.knob_value, single.architecture), (None, None, Architecture::Conventional));
    assert_eq!(mimo_study::grid::cells(&p).len(), 6);
}

#[test]
fn every_bad_sweep_names_the_plan_and_the_key() {
    let sweep = "sweep = { \"resource_manager.max_ta_share\" = [0.5, 0.25, 0.125] }";
    let cases: &[(&str, &str)] = &[
        ("sweep = {}", "methods[0].sweep"),
        ("sweep = { \"resource_manager.max_ta_sharez\" = [0.5] }", "methods[0].sweep.resource_manager.max_ta_sharez"),
        (
            "sweep = { \"resource_manager.max_ta_share\" = [\"half\"] }",
            "methods[0].sweep.resource_manager.max_ta_share[0]",
        ),
        ("sweep = { \"resource_manager.max_ta_share\" = [] }", "methods[0].sweep.resource_manager.max_ta_share"),
        (
            "sweep = { \"resource_manager.max_ta_share\" = [0.5, 0.5] }",
            "methods[0].sweep.resource_manager.max_ta_share[1]",
        ),
        ("sweep = { \"resource_manager.mimo\" = [1.0] }", "methods[0].sweep.resource_manager.mimo[0]"),
        ("sweep = { \"resource_manager.pd_target\" = [0.9, 2.0] }", "methods[0].sweep.resource_manager.pd_target[1]"),
        // The budget rule is checked at plan validation, before the key is looked up.
        (
            "sweep = { \"resource_manager.power_budget_w\" = [4.0, 0.0] }",
            "methods[0].sweep.resource_manager.power_budget_w[1]",
        ),
        (
            "sweep = { \"resource_manager.power_budget_w\" = [-1.0] }",
            "methods[0].sweep.resource_manager.power_budget_w[0]",
        ),
        ("sweep = [0.5]", "methods[0].sweep"),
        (
            "sweep = { \"resource_manager.max_ta_share\" = [0.5] }\narchitecture = \"bistatic\"",
            "methods[0].architecture",
        ),
    ];
    for (to, key) in cases {
        let text = PLAN.replacen(sweep, to, 1);
        assert_ne!(text, PLAN);
        let e = parse(&text).expect_err(key);
        assert_eq!(e.key, *key, "{e}");
        assert!(e.to_string().starts_with("studies/sweep.toml: "), "{e}");
    }
    // The test article's own rules apply to every value, as to a config override.
    let e = parse(&PLAN.replacen("[0.5, 0.25, 0.125]", "[0.25, 0.0]", 1)).expect_err("a share of 0");
    assert_eq!(e.key, "methods[0].sweep.resource_manager.max_ta_share[1]", "{e}");
    assert!(e.expected.contains("(0, 1]"), "{e}");
}

#[test]
fn a_grid_sweep_expands_into_every_combination() {
    let text = PLAN.replacen(
        "sweep = { \"resource_manager.max_ta_share\" = [0.5, 0.25, 0.125] }",
        "sweep = { \"resource_manager.max_ta_share\" = [0.5, 0.25], \"resource_manager.pd_target\" = [0.8, 0.9, 0.95] }",
        1,
    );
    let p = parse(&text).expect("plan");
    let names: Vec<&str> = p.methods.iter().filter(|m| m.family == "mimo").map(|m| m.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "mimo@max_ta_share:0.5,pd_target:0.8",
            "mimo@max_ta_share:0.5,pd_target:0.9",
            "mimo@max_ta_share:0.5,pd_target:0.95",
            "mimo@max_ta_share:0.25,pd_target:0.8",
            "mimo@max_ta_share:0.25,pd_target:0.9",
            "mimo@max_ta_share:0.25,pd_target:0.95",
        ]
    );
    let m = &p.methods[4];
    let MethodTa::Builtin { config, .. } = &m.ta else { panic!("builtin") };
    assert_eq!(config["resource_manager"]["max_ta_share"], serde_json::json!(0.25));
    assert_eq!(config["resource_manager"]["pd_target"], serde_json::json!(0.9));
    assert_eq!(m.knob.as_deref(), Some("resource_manager.max_ta_share × resource_manager.pd_target"));
    assert_eq!(m.knob_value, None, "a grid has no single knob value");
    assert_eq!(
        m.grid,
        vec![("resource_manager.max_ta_share".into(), 0.25), ("resource_manager.pd_target".into(), 0.9)]
    );
    // A grid value the test article refuses is named by its key and index.
    let bad = text.replacen("[0.8, 0.9, 0.95]", "[0.8, 1.5]", 1);
    let e = parse(&bad).expect_err("pd_target 1.5");
    assert_eq!(e.key, "methods[0].sweep.resource_manager.pd_target[1]", "{e}");
}

#[test]
fn refinement_settings_are_read_and_bad_ones_named() {
    let with = |refine: &str| {
        PLAN.replacen("[[methods]]\nname = \"mimo\"", &format!("{refine}\n[[methods]]\nname = \"mimo\""), 1)
    };
    let p = parse(&with("[refine]\nfraction = 0.1\nrounds = 2")).expect("plan");
    assert_eq!(p.refine_rounds, 2);
    let r = p.methods[0].refine.expect("the swept family is refined");
    assert_eq!((r.fraction, r.rounds), (0.1, 2));
    assert_eq!(p.methods[5].refine, None, "an unswept method is not refined by [refine]");
    assert_eq!(parse(PLAN).expect("plan").refine_rounds, 0);
    // An entry's own refine overrides the plan's.
    let own = PLAN.replacen("name = \"conv\"", "name = \"conv\"\nrefine = { fraction = 0.02, rounds = 5 }", 1);
    let p = parse(&own).expect("plan");
    assert_eq!(p.methods[3].refine.map(|r| (r.fraction, r.rounds)), Some((0.02, 5)));
    assert_eq!((p.methods[0].refine, p.refine_rounds), (None, 5));
    let cases: &[(&str, &str, &str)] = &[
        ("[refine]\nfraction = 0.0", "refine.fraction", "(0, 1)"),
        ("[refine]\nfraction = 1.0", "refine.fraction", "(0, 1)"),
        ("[refine]\nfraction = -0.5", "refine.fraction", "(0, 1)"),
        ("[refine]\nrounds = -1", "refine.rounds", "0 to 20"),
        ("[refine]\nrounds = 21", "refine.rounds", "0 to 20"),
        ("[refine]\nfractions = 0.1", "refine.fractions", "unknown key"),
    ];
    for (refine, key, expected) in cases {
        let e = parse(&with(refine)).expect_err(key);
        assert_eq!(e.key, *key, "{e}");
        assert!(e.expected.contains(expected), "{e}");
        assert!(e.to_string().starts_with("studies/sweep.toml"), "{e}");
    }
    // Refining a family that sweeps nothing, or a key that takes whole numbers only.
    let single = PLAN.replacen("ta = \"imm\"", "ta = \"imm\"\nrefine = { fraction = 0.05, rounds = 1 }", 1);
    let e = parse(&single).expect_err("no sweep");
    assert_eq!(e.key, "methods[2].refine", "{e}");
    assert!(e.expected.contains("swept family"), "{e}");
}
