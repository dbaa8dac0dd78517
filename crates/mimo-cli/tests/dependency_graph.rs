//! The build graph of the `mimo` binary stays small (docs/decisions/0100-a-small-build-graph.md):
//! no network client, TLS stack or async runtime (a benchmark reading and writing local files needs
//! none, and each costs minutes of a first build), and no more distinct packages than
//! [`MAX_PACKAGES`]. `cargo tree` resolves the graph for this machine's platform from Cargo.lock.

use std::collections::BTreeSet;
use std::process::Command;

/// The ceiling on distinct packages (name and version) in `cargo tree -p mimo-cli -e
/// normal,build`: 148 when it was set, against 364 while polars was in the graph.
const MAX_PACKAGES: usize = 170;

/// Packages whose presence means a network client, TLS or an async runtime entered the build.
const FORBIDDEN: &[&str] = &[
    "reqwest",
    "hyper",
    "hyper-util",
    "h2",
    "http",
    "rustls",
    "native-tls",
    "openssl",
    "openssl-sys",
    "ring",
    "aws-lc-rs",
    "tokio",
    "async-std",
    "smol",
    "object_store",
    "ureq",
    "curl",
];

/// The distinct packages (`name vX.Y.Z`) of the binary's normal and build dependencies.
fn packages_of_the_binary() -> BTreeSet<String> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let out = Command::new(env!("CARGO"))
        .args(["tree", "-p", "mimo-cli", "-e", "normal,build", "--prefix", "none", "--offline", "--locked"])
        .current_dir(root)
        .output()
        .expect("cargo tree runs");
    assert!(out.status.success(), "cargo tree: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|line| {
            let mut words = line.split_whitespace();
            Some(format!("{} {}", words.next()?, words.next()?))
        })
        .collect()
}

#[test]
fn the_binary_has_no_network_tls_or_async_runtime_and_few_packages() {
    let packages = packages_of_the_binary();
    let names: BTreeSet<&str> = packages.iter().filter_map(|p| p.split(' ').next()).collect();
    assert!(names.contains("mimo-cli") && names.contains("parquet"), "cargo tree output not understood");
    let forbidden: Vec<&str> = FORBIDDEN.iter().copied().filter(|p| names.contains(*p)).collect();
    assert!(forbidden.is_empty(), "the mimo binary's build graph gained {forbidden:?}");
    assert!(
        packages.len() <= MAX_PACKAGES,
        "the mimo binary's build graph has {} packages, more than the ceiling of {MAX_PACKAGES}",
        packages.len()
    );
}
