//! The crate graph of docs/architecture.md: every normal dependency between workspace crates is
//! one the architecture allows. A new edge must be argued for in the document first.

use std::collections::BTreeMap;
use std::process::Command;

/// (crate, the workspace crates it may use), read from the table of docs/architecture.md: rows
/// `| \`mimo-x\` | one job | core, scenario |`, where `—` is none and `all` is any.
fn allowed_by_the_document(root: &str) -> BTreeMap<String, Vec<String>> {
    let doc = std::fs::read_to_string(format!("{root}/docs/architecture.md")).expect("docs/architecture.md");
    let mut out = BTreeMap::new();
    for line in doc.lines() {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        // ["", "`mimo-x`", "one job", "may use", ""]
        if cells.len() != 5 || !cells[1].starts_with("`mimo-") {
            continue;
        }
        let name = cells[1].trim_matches('`').to_string();
        let may: Vec<String> = match cells[3] {
            "—" => Vec::new(),
            "all" => vec!["*".to_string()],
            list => list.split(',').map(|c| format!("mimo-{}", c.trim())).collect(),
        };
        out.insert(name, may);
    }
    out
}

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
    let allowed = allowed_by_the_document(root);
    assert!(allowed.len() >= 12, "the crate table of docs/architecture.md was not found: {allowed:?}");
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
            let may_use = |c: &str| may.iter().any(|m| m == c);
            if normal && names.contains(&dep) && !may_use("*") && !may_use(dep) {
                wrong.push(format!("{name} depends on {dep}"));
            }
        }
    }
    assert!(wrong.is_empty(), "dependencies the architecture does not allow: {wrong:?}");
}
