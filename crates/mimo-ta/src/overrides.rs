//! Configuration overrides: `--ta-config FILE.toml`, `--set key=value` and a study method's
//! `config` table, merged over a test article's default configuration.
//!
//! A test article's configuration is a JSON object (what its manifest records). Overrides are
//! merged into it key by key; a key the default does not have is an error that names the key
//! path and the keys that exist there, so a typo never passes silently. A `null` default (an
//! optional setting) takes any value, and an object with a `kind` tag (an enum such as the
//! initiator) is replaced whole when the override changes its kind. The merged object is then
//! parsed into the test article's typed configuration, which checks types and ranges.

use mimo_scenario::text_file::{MAX_TEXT_FILE_BYTES, read_text_file};
use serde_json::{Map, Value};
use std::path::Path;

/// A bad override. Each names the key path and what was expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConfigError {
    /// The key does not exist in the test article's configuration.
    #[error("unknown key '{key}' (expected one of: {known})")]
    UnknownKey {
        /// Dotted key path.
        key: String,
        /// The keys that exist at that level.
        known: String,
    },
    /// The value does not fit the key.
    #[error("key '{key}': {why}")]
    BadValue {
        /// Dotted key path.
        key: String,
        /// What was expected.
        why: String,
    },
    /// A `--set` argument that is not `key=value`.
    #[error("--set '{0}': expected key=value (for example resource_manager.mimo=false)")]
    BadSet(String),
    /// A configuration file that cannot be read or parsed.
    #[error("{path}: {why}")]
    File {
        /// The file.
        path: String,
        /// What went wrong.
        why: String,
    },
    /// An unknown test article.
    #[error("unknown test article '{name}' (expected one of: {known})")]
    UnknownTa {
        /// The name asked for.
        name: String,
        /// The built-in names.
        known: String,
    },
}

/// Read a TOML file of overrides into a JSON object.
pub fn read_file(path: &Path) -> Result<Value, ConfigError> {
    let file = |why: String| ConfigError::File { path: path.display().to_string(), why };
    let text = read_text_file(path, MAX_TEXT_FILE_BYTES).map_err(|e| file(e.to_string()))?;
    let t: toml::Table = toml::from_str(&text).map_err(|e| file(e.message().to_string()))?;
    toml_to_json(&toml::Value::Table(t), "")
}

/// A TOML value as JSON. NaN and ±∞ are refused, naming the key path (`key`, dotted; empty at
/// the root): JSON cannot hold them, and converted they would read as an unset `null`.
pub fn toml_to_json(v: &toml::Value, key: &str) -> Result<Value, ConfigError> {
    let at = |k: &str| if key.is_empty() { k.to_string() } else { format!("{key}.{k}") };
    match v {
        toml::Value::Float(x) if !x.is_finite() => {
            Err(ConfigError::BadValue { key: key.to_string(), why: format!("expected a finite number, got {x}") })
        }
        toml::Value::Table(t) => t
            .iter()
            .map(|(k, v)| Ok((k.clone(), toml_to_json(v, &at(k))?)))
            .collect::<Result<Map<_, _>, _>>()
            .map(Value::Object),
        toml::Value::Array(a) => a
            .iter()
            .enumerate()
            .map(|(i, v)| toml_to_json(v, &format!("{key}[{i}]")))
            .collect::<Result<Vec<_>, _>>()
            .map(Value::Array),
        other => {
            serde_json::to_value(other).map_err(|e| ConfigError::BadValue { key: key.to_string(), why: e.to_string() })
        }
    }
}

/// Parse one `--set key.path=value`: the value is read as a TOML value (`true`, `3.5`, `"x"`,
/// `[1, 2]`), or taken as a string when it is not one (`kind=imm`).
pub fn parse_set(arg: &str) -> Result<(String, Value), ConfigError> {
    let (key, text) = arg.split_once('=').ok_or_else(|| ConfigError::BadSet(arg.to_string()))?;
    let key = key.trim();
    if key.is_empty() || key.split('.').any(str::is_empty) {
        return Err(ConfigError::BadSet(arg.to_string()));
    }
    let text = text.trim();
    let value = match toml::from_str::<toml::Table>(&format!("v = {text}")) {
        Ok(t) => match t.get("v") {
            Some(v) => toml_to_json(v, key)?,
            None => Value::Null,
        },
        Err(_) => Value::String(text.to_string()),
    };
    Ok((key.to_string(), value))
}

/// Put `value` at the dotted `key` of an object, creating intermediate objects.
pub fn set_path(obj: &mut Value, key: &str, value: Value) {
    let mut cur = obj;
    let parts: Vec<&str> = key.split('.').collect();
    for (i, part) in parts.iter().enumerate() {
        if !cur.is_object() {
            *cur = Value::Object(Map::new());
        }
        let Value::Object(m) = cur else { return };
        if i + 1 == parts.len() {
            m.insert((*part).to_string(), value);
            return;
        }
        cur = m.entry((*part).to_string()).or_insert_with(|| Value::Object(Map::new()));
    }
}

/// The overrides of a file (optional) and `--set` arguments, as one object (later ones win).
pub fn collect(file: Option<&Path>, sets: &[String]) -> Result<Value, ConfigError> {
    let mut out = match file {
        Some(p) => read_file(p)?,
        None => Value::Object(Map::new()),
    };
    for s in sets {
        let (k, v) = parse_set(s)?;
        set_path(&mut out, &k, v);
    }
    Ok(out)
}

/// Merge `over` into `base`, refusing keys `base` does not have (see the module docs).
pub fn merge(base: &Value, over: &Value) -> Result<Value, ConfigError> {
    merge_at(base, over, "")
}

fn merge_at(base: &Value, over: &Value, prefix: &str) -> Result<Value, ConfigError> {
    let (Value::Object(b), Value::Object(o)) = (base, over) else {
        return Ok(over.clone());
    };
    // A tagged enum whose kind changes is replaced whole; its parser checks the new fields.
    if let (Some(bk), Some(ok)) = (b.get("kind"), o.get("kind"))
        && bk != ok
    {
        return Ok(over.clone());
    }
    let mut out = b.clone();
    for (k, v) in o {
        let key = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
        match b.get(k) {
            None => {
                let mut known: Vec<&str> = b.keys().map(String::as_str).collect();
                known.sort_unstable();
                return Err(ConfigError::UnknownKey { key, known: known.join(", ") });
            }
            Some(Value::Null) => {
                out.insert(k.clone(), v.clone());
            }
            Some(bv) => {
                if bv.is_object() && !v.is_object() {
                    return Err(ConfigError::BadValue { key, why: "expected a table of settings".into() });
                }
                out.insert(k.clone(), merge_at(bv, v, &key)?);
            }
        }
    }
    Ok(Value::Object(out))
}

/// Parse a merged configuration into a typed one. A value of the wrong type is an error naming
/// its key path (`resource_manager.power_budget_w`); `(config)` only when the whole is wrong.
pub fn parse<T: serde::de::DeserializeOwned>(merged: &Value) -> Result<T, ConfigError> {
    serde_path_to_error::deserialize(merged.clone()).map_err(|e| {
        let key = e.path().to_string();
        let key = if key == "." { "(config)".to_string() } else { key };
        ConfigError::BadValue { key, why: e.into_inner().to_string() }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn set_values_parse_as_toml_or_strings() {
        assert_eq!(parse_set("a.b=true").expect("ok"), ("a.b".to_string(), json!(true)));
        assert_eq!(parse_set("x=3.5").expect("ok"), ("x".to_string(), json!(3.5)));
        assert_eq!(parse_set("kind=imm").expect("ok"), ("kind".to_string(), json!("imm")));
        assert_eq!(parse_set("l=[1, 2]").expect("ok"), ("l".to_string(), json!([1, 2])));
        assert!(matches!(parse_set("novalue"), Err(ConfigError::BadSet(_))));
        assert!(matches!(parse_set("a..b=1"), Err(ConfigError::BadSet(_))));
        // JSON has no NaN or infinity: they would read as an unset key, so they are refused.
        for text in ["inf", "-inf", "nan", "[1.0, inf]"] {
            let e = parse_set(&format!("rm.power_budget_w={text}")).expect_err(text);
            assert!(matches!(&e, ConfigError::BadValue { key, .. } if key.starts_with("rm.power_budget_w")), "{e}");
        }
        let t: toml::Value = toml::from_str("a = { b = [1.0, nan] }").expect("toml");
        let e = toml_to_json(&t, "").expect_err("nan");
        assert_eq!(e, ConfigError::BadValue { key: "a.b[1]".into(), why: "expected a finite number, got NaN".into() });
    }

    #[test]
    fn merge_keeps_known_keys_and_names_unknown_ones() {
        let base = json!({"tracker": {"kind": "default", "gate": {"p": 0.999}}, "rm": {"mimo": true, "opt": null}});
        let mut over = json!({});
        set_path(&mut over, "rm.mimo", json!(false));
        set_path(&mut over, "rm.opt", json!(3));
        let m = merge(&base, &over).expect("merge");
        assert_eq!(m["rm"]["mimo"], json!(false));
        assert_eq!(m["rm"]["opt"], json!(3));
        assert_eq!(m["tracker"]["gate"]["p"], json!(0.999));
        let bad = json!({"rm": {"mimmo": false}});
        let err = merge(&base, &bad).expect_err("typo");
        assert_eq!(err, ConfigError::UnknownKey { key: "rm.mimmo".into(), known: "mimo, opt".into() });
        assert!(err.to_string().contains("rm.mimmo"));
        let not_table = json!({"tracker": 3});
        assert!(matches!(merge(&base, &not_table), Err(ConfigError::BadValue { .. })));
    }

    #[test]
    fn a_wrong_type_names_its_key_path() {
        #[derive(Debug, serde::Deserialize)]
        struct Rm {
            #[allow(dead_code)]
            power_budget_w: Option<f64>,
        }
        #[derive(Debug, serde::Deserialize)]
        struct Config {
            #[allow(dead_code)]
            resource_manager: Rm,
        }
        let e = parse::<Config>(&json!({"resource_manager": {"power_budget_w": "abc"}})).expect_err("type");
        assert_eq!(
            e,
            ConfigError::BadValue {
                key: "resource_manager.power_budget_w".into(),
                why: "invalid type: string \"abc\", expected f64".into()
            }
        );
        let e = parse::<Config>(&json!(3)).expect_err("not a table");
        assert!(matches!(e, ConfigError::BadValue { key, .. } if key == "(config)"));
    }

    #[test]
    fn a_tagged_enum_is_replaced_when_its_kind_changes() {
        let base = json!({"init": {"kind": "one_point", "velocity_std_mps": 300.0}});
        let over = json!({"init": {"kind": "two_point", "max_speed_mps": 700.0}});
        let m = merge(&base, &over).expect("merge");
        assert_eq!(m["init"], json!({"kind": "two_point", "max_speed_mps": 700.0}));
    }
}
