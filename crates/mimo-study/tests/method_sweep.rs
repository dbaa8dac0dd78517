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
        (
            "sweep = { \"resource_manager.max_ta_share\" = [0.5], \"resource_manager.pd_target\" = [0.9] }",
            "methods[0].sweep",
        ),
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
