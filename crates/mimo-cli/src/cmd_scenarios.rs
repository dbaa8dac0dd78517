//! `mimo scenarios`.

use crate::CliError;

/// List the standard scenarios.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Print each scenario's full resolved definition as JSON instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Also draw the geometry of scenario 7 (ships and every target's trajectory) to this PNG or
    /// SVG file.
    #[arg(long, value_name = "FILE")]
    pub map: Option<std::path::PathBuf>,
    /// Replace the --map file if it exists and is a map this command drew.
    #[arg(long)]
    pub force: bool,
}

/// Draw scenario 7's ships (at t = 0) and trajectories.
fn draw_map(path: &std::path::Path) -> Result<(), CliError> {
    let s = mimo_scenario::load_standard(7)?;
    let traj = s.build_trajectories()?;
    let ships: Vec<(String, f64, f64)> = s.ships.iter().map(|sh| (sh.id.to_string(), sh.lat_deg, sh.lon_deg)).collect();
    let mut truth: Vec<(String, Vec<(f64, f64)>)> =
        s.target_ids().iter().map(|id| (id.to_string(), Vec::new())).collect();
    for r in traj.truth_rows(0, 0.2) {
        if let Some(e) = truth.iter_mut().find(|(id, _)| *id == r.target) {
            e.1.push((r.lat_deg, r.lon_deg));
        }
    }
    let title = format!("{}: ships R1–R4 and targets over {} s", s.name, s.duration_s);
    // Drawn beside the target and renamed, so a failed drawing leaves no half-written file.
    let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    let name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.partial-{}.{ext}", std::process::id()));
    mimo_store::output::register(&tmp);
    // Marked as mimo's map by the drawing (by content), so that `--force` may replace it later
    // and nothing else.
    let drawn = mimo_report::draw_geometry(&ships, &truth, &title, &tmp)
        .map_err(|e| CliError::Other(format!("{}: write failed: {e}", path.display())))
        .and_then(|()| {
            std::fs::rename(&tmp, path).map_err(|e| CliError::Other(format!("{}: write failed: {e}", path.display())))
        });
    if drawn.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    mimo_store::output::unregister(&tmp);
    drawn
}

pub fn run(a: Args) -> Result<(), CliError> {
    if let Some(path) = &a.map {
        let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase());
        if !matches!(ext.as_deref(), Some("png" | "svg")) {
            return Err(CliError::input(format!("--map: {}: expected a .png or .svg file name", path.display())));
        }
        let what = "a map mimo scenarios --map drew";
        mimo_store::output::check_file_output(path, a.force, mimo_store::recognise::is_map_image, what)?;
        draw_map(path)?;
    }
    let list = mimo_scenario::list_standard()?;
    if a.json {
        let v: Vec<_> = list.iter().map(|(n, s)| serde_json::json!({"number": n, "scenario": s})).collect();
        crate::outln!("{}", serde_json::to_string_pretty(&v).map_err(|e| CliError::Other(e.to_string()))?);
        return Ok(());
    }
    crate::outln!("{:<3} {:<12} {:>10}  {:<28} ships", "#", "name", "duration_s", "targets");
    for (n, s) in &list {
        let ships: Vec<String> = s.ships.iter().map(|x| x.id.to_string()).collect();
        crate::outln!(
            "{:<3} {:<12} {:>10}  {:<28} {}",
            n,
            s.name,
            s.duration_s,
            s.target_ids().join(", "),
            ships.join(", ")
        );
    }
    crate::outln!();
    crate::outln!("Ships:");
    if let Some((_, s)) = list.first() {
        for sh in &s.ships {
            crate::outln!(
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
