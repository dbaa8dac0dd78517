//! Draw `reports/fidelity.png` from `reports/fidelity.json` (written by `scripts/fidelity.sh`):
//!
//! `cargo run --example fidelity_chart -- reports/fidelity.json reports/fidelity.png`

use mimo_report::{FidelityPoint, draw_fidelity};
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let input = args.get(1).map_or("reports/fidelity.json", String::as_str);
    let output = args.get(2).map_or("reports/fidelity.png", String::as_str);
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(input)?)?;
    let rungs = v["rungs"].as_array().ok_or("no rungs in the report")?;
    let points: Vec<FidelityPoint> = rungs
        .iter()
        .map(|r| FidelityPoint {
            label: r["level"].as_str().unwrap_or("?").to_string(),
            sim_s_per_wall_s: r["sim_s_per_wall_s"].as_f64().unwrap_or(f64::NAN),
            agreement: r["agreement"].as_f64().unwrap_or(f64::NAN),
        })
        .collect();
    let title = format!(
        "Fidelity ladder: scenario {}, {} × {} s, {} build, 1 thread",
        v["scenario"],
        v["runs"],
        v["duration_s"],
        v["build"].as_str().unwrap_or("dev")
    );
    draw_fidelity(&points, &title, Path::new(output))?;
    println!("wrote {output}");
    Ok(())
}
