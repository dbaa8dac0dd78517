//! The crate graph of docs/architecture.md: every normal dependency between workspace crates is
//! one the architecture allows. A new edge must be argued for in the document first.

use std::collections::BTreeMap;
use std::process::Command;

/// (crate, the workspace crates it may use), as in docs/architecture.md.
const ALLOWED: &[(&str, &[&str])] = &[
    ("mimo-core", &[]),
    ("mimo-scenario", &["mimo-core"]),
    ("mimo-radar", &["mimo-core"]),
    ("mimo-track", &["mimo-core"]),
    ("mimo-sim", &["mimo-core", "mimo-scenario", "mimo-radar"]),
    ("mimo-ta", &["mimo-core", "mimo-scenario", "mimo-radar", "mimo-track", "mimo-sim"]),
    ("mimo-store", &["mimo-core"]),
    ("mimo-metrics", &["mimo-core"]),
    ("mimo-report", &["mimo-metrics"]),
    ("mimo-plot", &["mimo-core", "mimo-scenario", "mimo-radar", "mimo-store", "mimo-metrics"]),
    ("mimo-study", &["mimo-core", "mimo-scenario", "mimo-sim", "mimo-ta", "mimo-store", "mimo-metrics", "mimo-report"]),
    ("mimo-cli", &["*"]),
];

#[test]
fn workspace_dependencies_follow_the_architecture() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let out = Command::new(env!("CARGO"))
        .args(["metadata", "--format-version", "1", "--no-deps", "--offline"])
        .current_dir(root)
        .output()
        .expect("cargo metadata runs");
    assert!(out.status.success(), "cargo metadata: {}", String::from_utf8_lossy(&out.stderr));
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout).expect("metadata JSON");
    let packages = meta["packages"].as_array().expect("packages");
    let names: Vec<&str> = packages.iter().filter_map(|p| p["name"].as_str()).collect();
    let allowed: BTreeMap<&str, &[&str]> = ALLOWED.iter().copied().collect();
    let mut wrong = Vec::new();
    for p in packages {
        let name = p["name"].as_str().expect("name");
        let Some(may) = allowed.get(name) else {
            wrong.push(format!("{name} is not in docs/architecture.md"));
            continue;
        };
        for d in p["dependencies"].as_array().expect("dependencies") {
            let dep = d["name"].as_str().expect("dependency name");
            let normal = d["kind"].is_null();
            if normal && names.contains(&dep) && !may.contains(&"*") && !may.contains(&dep) {
                wrong.push(format!("{name} depends on {dep}"));
            }
        }
    }
    assert!(wrong.is_empty(), "dependencies the architecture does not allow: {wrong:?}");
}
