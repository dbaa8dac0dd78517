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

/// A scenario small enough to simulate in a moment (one ship, one jet, 60 s).
pub const SMALL: &str = r#"
name = "small"
duration_s = 60.0

[aircraft_types.jet]
rcs_m2 = 5.0
min_speed_mps = 100.0
max_speed_mps = 300.0
max_accel_g = 3.0

[[ships]]
id = "R1"
lat_deg = 36.0
lon_deg = -70.0
heading_deg = 0.0

[[aircraft]]
id = "X"
type = "jet"
start = { lat_deg = 36.5, lon_deg = -70.0, alt_m = 5000.0 }
heading_deg = 180.0
speed_mps = 200.0
"#;

/// Copy the directory tree `from` to `to`.
pub fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("mkdir");
    for e in std::fs::read_dir(from).expect("read_dir").flatten() {
        let p = e.path();
        if p.is_dir() {
            copy_dir(&p, &to.join(e.file_name()));
        } else {
            std::fs::copy(&p, to.join(e.file_name())).expect("copy");
        }
    }
}
