//! One owner of the run and study directory layout (docs/architecture.md): only `mimo-store`
//! (`layout.rs`: `RunDir`, `ScoreDir`, `StudyDir`) joins a table or file name onto a path. This
//! test reads the library code of every other crate (`crates/*/src`, test modules left out) and
//! fails on a path built by hand: `.join("name")` with a literal, `.join(NAME_CONST)`,
//! `run_file_name(…)`, or a literal naming a file of a run or study directory.

use std::path::{Path, PathBuf};

/// File names of the run and study directories that only `mimo-store` may spell.
const LAYOUT_FILES: &[&str] = &["manifest.json", "summary.json", "study.json", "plan.toml", "report.md"];

/// Why `line` builds a layout path by hand, if it does.
fn hand_built(line: &str) -> Option<&'static str> {
    let code = line.split("//").next().unwrap_or("");
    let mut rest = code;
    while let Some(at) = rest.find(".join(") {
        let arg = &rest[at + 6..];
        if let Some(lit) = arg.strip_prefix('"') {
            let lit = lit.split('"').next().unwrap_or("");
            // `.join(", ")` or `.join("\n")` of a list of words is not a path: a path part is
            // made of name characters only.
            let name_char = |c: char| c.is_alphanumeric() || "_.-=/".contains(c);
            if lit.chars().any(char::is_alphanumeric) && lit.chars().all(name_char) {
                return Some("joins a literal name onto a path");
            }
        } else if arg.chars().next().is_some_and(|c| c.is_ascii_uppercase())
            && arg.chars().take_while(|c| *c != ')').all(|c| c.is_ascii_uppercase() || c == '_' || c.is_ascii_digit())
        {
            return Some("joins a file-name constant onto a path");
        }
        rest = &rest[at + 6..];
    }
    if code.contains("run_file_name(") {
        return Some("spells a table's run file name");
    }
    let spelled = LAYOUT_FILES.iter().any(|f| code.contains(&format!("\"{f}\"")))
        || code.split('"').skip(1).step_by(2).any(|lit| {
            lit.strip_suffix(".parquet").is_some_and(|stem| !stem.is_empty() && !stem.contains(char::is_whitespace))
        });
    spelled.then_some("spells a file name of a run or study directory")
}

/// The library code of a source file: up to its test module.
fn library_code(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines().enumerate().take_while(|(_, l)| !l.trim_start().starts_with("#[cfg(test)]"))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).expect("read_dir").flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn the_detector_finds_hand_built_paths() {
    for bad in [
        r#"let f = dir.join("tracks").join(name);"#,
        "let m = run.join(MANIFEST_FILE);",
        "let f = format!(\"{t}/{}\", run_file_name(k));",
        r#"let s = score_dir.join(format!("{x}")); let t = "summary.json";"#,
        r#"write(&dir.join(x), "results.parquet")"#,
    ] {
        assert!(hand_built(bad).is_some(), "not caught: {bad}");
    }
    for fine in [
        r#"names.join(", ")"#,
        r#"lines.join("\n")"#,
        r#"name.strip_suffix(".parquet")"#,
        r#"parts.join(" | ")"#,
        "let f = run.table_file(\"tracks\", k);",
        "let p = base.join(s);",
        r#"// dir.join("tracks") in a comment"#,
    ] {
        assert!(hand_built(fine).is_none(), "wrongly caught: {fine}");
    }
}

#[test]
fn only_mimo_store_builds_run_and_study_directory_paths() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut found = Vec::new();
    for e in std::fs::read_dir(&crates).expect("crates").flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name == "mimo-store" || !e.path().join("src").is_dir() {
            continue;
        }
        let mut files = Vec::new();
        rust_files(&e.path().join("src"), &mut files);
        for f in files {
            let text = std::fs::read_to_string(&f).expect("read");
            for (i, line) in library_code(&text) {
                if let Some(why) = hand_built(line) {
                    found.push(format!("{}:{}: {why}: {}", f.display(), i + 1, line.trim()));
                }
            }
        }
    }
    assert!(found.is_empty(), "paths built outside mimo-store (use mimo_store::layout):\n{}", found.join("\n"));
}
