//! `mimo scenarios`.

use crate::CliError;

/// List the standard scenarios.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Print each scenario's full resolved definition as JSON instead of the table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<(), CliError> {
    let list = mimo_scenario::list_standard()?;
    if a.json {
        let v: Vec<_> = list.iter().map(|(n, s)| serde_json::json!({"number": n, "scenario": s})).collect();
        println!("{}", serde_json::to_string_pretty(&v).map_err(|e| CliError::Other(e.to_string()))?);
        return Ok(());
    }
    println!("{:<3} {:<12} {:>10}  {:<28} ships", "#", "name", "duration_s", "targets");
    for (n, s) in &list {
        let ships: Vec<String> = s.ships.iter().map(|x| x.id.to_string()).collect();
        println!(
            "{:<3} {:<12} {:>10}  {:<28} {}",
            n,
            s.name,
            s.duration_s,
            s.target_ids().join(", "),
            ships.join(", ")
        );
    }
    println!();
    println!("Ships:");
    if let Some((_, s)) = list.first() {
        for sh in &s.ships {
            println!(
                "  {}  {:.4}°N {:.4}°E  heading {:>5.1}°  speed {:>4.1} m/s  {} faces at {:?}° (bow-relative)",
                sh.id,
                sh.lat_deg,
                sh.lon_deg,
                sh.heading_deg,
                sh.speed_mps,
                sh.radar.face_azimuths_deg.len(),
                sh.radar.face_azimuths_deg
            );
        }
    }
    Ok(())
}
