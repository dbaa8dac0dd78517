//! The one registry of built-in test articles: their names, what they are, their default
//! configurations, and how to build one from a (merged) configuration.

use crate::cued::{Cued, CuedConfig};
use crate::default_ta::{DefaultTa, DefaultTaConfig, check_optional_numbers};
use crate::overrides::{ConfigError, merge, parse};
use crate::passive::Passive;
use mimo_sim::World;
use mimo_sim::test_article::TestArticle;
use mimo_track::initiation::MOfN;
use mimo_track::initiation_evidence::FalseTrackConfig;
use mimo_track::{AssociationMethod, InitiationExclusion, TrackerConfig, TrackerKind};
use serde_json::Value;

/// A built-in test article.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Builtin {
    /// Its name (`--tracker NAME`, a study method's `ta`).
    pub name: &'static str,
    /// One line on what it is.
    pub about: &'static str,
    /// Whether it tracks, so that `mimo track` can re-run it offline.
    pub tracks: bool,
}

/// Every built-in test article.
pub const BUILTINS: &[Builtin] = &[
    Builtin {
        name: "default",
        about: "the baseline: IMM tracker, JPDA with second returns, adaptive revisit and energy, MIMO dwells",
        tracks: true,
    },
    Builtin {
        name: "gnn",
        about: "the former default: EKF (NCV) tracker, GNN, adaptive revisit and energy, MIMO dwells",
        tracks: true,
    },
    Builtin { name: "imm", about: "the baseline with an IMM (CV-low + CV-high) instead of the EKF", tracks: true },
    Builtin { name: "jpda", about: "the baseline with JPDA instead of GNN association", tracks: true },
    Builtin { name: "imm-jpda", about: "the baseline with an IMM and JPDA association", tracks: true },
    Builtin {
        name: "cued",
        about: "truth-cued fixed schedule, no tracking (reads truth: a radar-model check)",
        tracks: false,
    },
    Builtin { name: "none", about: "background search only, no tracking", tracks: false },
];

/// The built-in of that name.
pub fn builtin(name: &str) -> Result<&'static Builtin, ConfigError> {
    BUILTINS.iter().find(|b| b.name == name).ok_or_else(|| ConfigError::UnknownTa {
        name: name.to_string(),
        known: BUILTINS.iter().map(|b| b.name).collect::<Vec<_>>().join(", "),
    })
}

fn default_ta_config(kind: TrackerKind, association_method: AssociationMethod) -> DefaultTaConfig {
    let mut tracker = TrackerConfig { association_method, ..TrackerConfig::for_kind(kind) };
    // The built-in test articles confirm on 2 of 2 looks (a false alarm costs one confirmation
    // look, not two) and look at a confirmed track at least every 2 s (docs/model.md §6.4, §7.1;
    // docs/decisions/0028-confirmation-revisit-group-looks.md).
    tracker.confirmation = MOfN { m: 2, n: 2 };
    tracker.revisit.t_max_s = 2.0;
    if association_method == AssociationMethod::Jpda {
        // JPDA updates every track near a return, so a duplicate started from a gate-missing
        // return would be kept alive: JPDA never initiates inside a track's resolution cell
        // (docs/model.md §6.4, §6.8).
        tracker.initiation_exclusion = InitiationExclusion::resolution_cell();
    }
    DefaultTaConfig { tracker, ..DefaultTaConfig::default() }
}

/// The default test article (docs/decisions/0031-imm-jpda-default.md): the IMM with JPDA, whose
/// initiation exclusion keeps the resolution cell but not the wide NIS gate, and where a return a
/// track's gate holds besides the track's preferred one may start a track (β < 0.5,
/// docs/model.md §6.4): the second aircraft of a pair the two-target estimator split.
fn the_default_config() -> DefaultTaConfig {
    let mut c = default_ta_config(TrackerKind::Imm, AssociationMethod::Jpda);
    c.tracker.initiation_exclusion.nis = 0.0;
    c.tracker.second_return_max_beta = 0.5;
    // False-track management (docs/model.md §6.4): only a detection as strong as a 1e-8 false
    // alarm starts a track, and at most 400 tentative tracks live at once, the weakest shed first.
    c.tracker.false_tracks = FalseTrackConfig { power_pfa: 1e-8, max_tentative: 400 };
    c
}

/// A built-in test article's default configuration (what its manifest records without overrides).
pub fn default_config(name: &str) -> Result<Value, ConfigError> {
    let b = builtin(name)?;
    let v = match b.name {
        "default" => serde_json::to_value(the_default_config()),
        "gnn" => serde_json::to_value(default_ta_config(TrackerKind::Default, AssociationMethod::Gnn)),
        "imm" => serde_json::to_value(default_ta_config(TrackerKind::Imm, AssociationMethod::Gnn)),
        "jpda" => serde_json::to_value(default_ta_config(TrackerKind::Default, AssociationMethod::Jpda)),
        "imm-jpda" => serde_json::to_value(default_ta_config(TrackerKind::Imm, AssociationMethod::Jpda)),
        "cued" => serde_json::to_value(CuedConfig::default()),
        _ => Ok(Value::Object(serde_json::Map::new())),
    };
    v.map_err(|e| ConfigError::BadValue { key: "(config)".into(), why: e.to_string() })
}

/// The configuration of a built-in with `overrides` merged in, checked: an unknown key, a wrong
/// type or an out-of-range value is an error naming the key.
pub fn resolve_config(name: &str, overrides: &Value) -> Result<Value, ConfigError> {
    let merged = merge(&default_config(name)?, overrides)?;
    match builtin(name)?.name {
        "default" | "gnn" | "imm" | "jpda" | "imm-jpda" => {
            check_optional_numbers(&merged).map_err(|(key, why)| ConfigError::BadValue { key, why })?;
            let c: DefaultTaConfig = parse(&merged)?;
            c.tracker.validate().map_err(|e| ConfigError::BadValue { key: "tracker".into(), why: e.to_string() })?;
            c.resource_manager.validate().map_err(|(key, why)| ConfigError::BadValue { key, why })?;
            c.registration.validate().map_err(|(key, why)| ConfigError::BadValue { key, why })?;
            c.search_manager.validate().map_err(|(key, why)| ConfigError::BadValue { key, why })?;
        }
        "cued" => {
            let c: CuedConfig = parse(&merged)?;
            if !(c.period_s.is_finite() && c.period_s > 0.0) {
                return Err(ConfigError::BadValue {
                    key: "period_s".into(),
                    why: "a positive number of seconds".into(),
                });
            }
        }
        _ => {}
    }
    Ok(merged)
}

/// Build built-in `name` with a configuration from [`resolve_config`]. The cued schedule reads
/// the world's truth; every other built-in learns the ships from its `start` event only.
pub fn build<'w>(name: &str, config: &Value, world: &'w World) -> Result<Box<dyn TestArticle + 'w>, ConfigError> {
    Ok(match builtin(name)?.name {
        "default" | "gnn" | "imm" | "jpda" | "imm-jpda" => Box::new(DefaultTa::new(name, parse(config)?)),
        "cued" => Box::new(Cued::new(world, parse(config)?)),
        _ => Box::new(Passive),
    })
}

/// The built-in `name` as the tracker and rule of the resource-manager role
/// ([`crate::resource_manager`]): one of the built-ins that track and plan looks (`default`,
/// `gnn`, `imm`, `jpda`, `imm-jpda`), with a configuration from [`resolve_config`].
pub fn build_rule(name: &str, config: &Value) -> Result<DefaultTa, ConfigError> {
    match builtin(name)?.name {
        "default" | "gnn" | "imm" | "jpda" | "imm-jpda" => Ok(DefaultTa::new(name, parse(config)?)),
        other => Err(ConfigError::BadValue {
            key: "(test article)".into(),
            why: format!("'{other}' has no tracker and rule for an external resource manager"),
        }),
    }
}

/// How the dwell schedule of a run with this test article is made, for the manifest.
pub fn schedule_description(name: &str) -> String {
    match name {
        "cued" => "truth-cued fixed schedule (no tracking; reads truth) plus background search".into(),
        "none" => "background search only".into(),
        other => format!("closed loop: background search plus dwells requested by the '{other}' test article"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn every_builtin_has_a_default_configuration_that_resolves() {
        for b in BUILTINS {
            let c = resolve_config(b.name, &json!({})).expect("defaults are valid");
            assert_eq!(c, default_config(b.name).expect("default"));
        }
        assert_eq!(default_config("imm").expect("imm")["tracker"]["kind"], json!("imm"));
        let c = default_config("imm-jpda").expect("imm-jpda");
        assert_eq!((&c["tracker"]["kind"], &c["tracker"]["association_method"]), (&json!("imm"), &json!("jpda")));
        assert_eq!(default_config("jpda").expect("jpda")["tracker"]["association_method"], json!("jpda"));
    }

    #[test]
    fn overrides_are_checked() {
        let c = resolve_config("default", &json!({"resource_manager": {"mimo": false}})).expect("conventional");
        assert_eq!(c["resource_manager"]["mimo"], json!(false));
        let e = resolve_config("default", &json!({"resource_manager": {"mimoo": false}})).expect_err("typo");
        assert!(e.to_string().contains("resource_manager.mimoo"), "{e}");
        let e = resolve_config("default", &json!({"resource_manager": {"pd_target": 1.5}})).expect_err("range");
        assert!(e.to_string().contains("pd_target"), "{e}");
        let e = resolve_config("default", &json!({"resource_manager": {"mimo": "yes"}})).expect_err("type");
        assert!(matches!(e, ConfigError::BadValue { .. }), "{e}");
        assert!(matches!(resolve_config("kalman", &json!({})), Err(ConfigError::UnknownTa { .. })));
        assert!(resolve_config("none", &json!({"x": 1})).is_err());
    }
}
