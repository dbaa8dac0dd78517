//! Helpers shared by the in-process end-to-end tests of `mimo`.
#![allow(dead_code)]

use std::path::Path;

/// Run `mimo ARGS…` in-process (`mimo_cli::main_with_args`); its exit status.
pub fn mimo(args: &[&str]) -> i32 {
    let mut v = vec!["mimo".to_string()];
    v.extend(args.iter().map(|s| s.to_string()));
    mimo_cli::main_with_args(v)
}

/// A path as a command-line argument.
pub fn p(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}
