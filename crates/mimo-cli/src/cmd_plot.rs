//! `mimo plot`: one run in 3-D on the globe, as one self-contained HTML page (crate mimo-plot).

use crate::CliError;
use mimo_plot::{PlotError, ViewOptions};
use std::path::PathBuf;

/// Plot a run in 3-D on the globe into one self-contained, offline HTML page.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run directory to plot (a `mimo simulate` or `mimo track` output).
    pub run: PathBuf,
    /// Monte Carlo run id to show.
    #[arg(long = "run", default_value_t = 0, value_name = "K")]
    pub run_id: u32,
    /// Window start in seconds [default: the run's start].
    #[arg(long, value_name = "T0")]
    pub from: Option<f64>,
    /// Window end in seconds [default: the run's end].
    #[arg(long, value_name = "T1")]
    pub to: Option<f64>,
    /// The HTML file to write.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
    /// Print nothing but errors.
    #[arg(long)]
    pub quiet: bool,
}

fn plot_err(e: PlotError) -> CliError {
    if e.is_bad_input() { CliError::Input(e.to_string()) } else { CliError::Other(e.to_string()) }
}

pub fn run(a: Args) -> Result<(), CliError> {
    mimo_plot::check_out(&a.out, a.force).map_err(plot_err)?;
    let opts = ViewOptions { run: a.run_id, from_s: a.from, to_s: a.to, ..ViewOptions::default() };
    let page = mimo_plot::plot_run(&a.run, &opts).map_err(plot_err)?;
    mimo_plot::write_page(&a.out, &page, a.force).map_err(plot_err)?;
    // The page drew repaired covariances where the tracks held slightly indefinite ones
    // (docs/design.md §7): said in one warning line.
    let tracks = mimo_store::layout::RunDir::new(&a.run).table_file("tracks", a.run_id);
    if !a.quiet && tracks.is_file() {
        let repairs = mimo_store::checked::repaired_covariances(&tracks, &mimo_store::schema::TRACKS)?;
        if let Some(w) = repairs.warning(&tracks.display().to_string()) {
            eprintln!("{w}");
        }
    }
    if !a.quiet {
        crate::outln!("wrote {} ({:.1} MB)", a.out.display(), page.len() as f64 / 1e6);
    }
    Ok(())
}
