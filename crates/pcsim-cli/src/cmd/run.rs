//! `pcsim run`: one case, `summary.json`, `timeseries.csv` and (with `--plot`) the figures.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

use crate::common::{case_name, load_case, run_with_progress};
use crate::output::{write_run, Summary};

#[derive(Args)]
pub struct RunArgs {
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name (see `pcsim presets`).
    #[arg(long)]
    preset: Option<String>,
    /// Override the train speed, km/h.
    #[arg(long)]
    speed: Option<f64>,
    /// Override the contact-wire tension, kN.
    #[arg(long)]
    tension: Option<f64>,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Also draw the plots (SVG and PNG) into the output directory.
    #[arg(long)]
    plot: bool,
}

pub fn run(a: RunArgs, quiet: bool) -> Result<i32> {
    let mut case = load_case(a.case.as_ref(), a.preset.as_deref())?;
    if let Some(v) = a.speed {
        case.run.speed_kmh = v;
    }
    if let Some(t) = a.tension {
        case.catenary.contact_wire.tension_n = t * 1e3;
    }
    let (out, wall, warnings) = run_with_progress(&case, "run", quiet)?;
    let summary = Summary::new(&case, &out, wall, warnings);
    write_run(&a.out, &out, &summary)?;
    if a.plot {
        let data = crate::plot::run::PlotData::from_run(&summary, Some(case.catenary.span_m), &out);
        let files = crate::plot::run::draw_all(&a.out, &data)?;
        crate::plot::report(&files);
    }
    println!(
        "{} at {:.0} km/h: {:.2} s simulated in {:.2} s wall ({:.1}x real time), {} modes/wire",
        case_name(&case),
        case.run.speed_kmh,
        out.simulated_time_s(),
        wall,
        out.simulated_time_s() / wall,
        out.n_modes
    );
    for p in &out.pantographs {
        match &p.stats {
            Some(s) => println!(
                "  {:<10} Fm {:6.1} N  σ {:5.1} N  (0-5 Hz {:4.1}, 5-20 Hz {:4.1})  max {:6.1}  min {:6.1}  uplift@support {:5.1} mm  loss {:.2} %",
                p.name, s.mean_n, s.std_n, s.std_0_5hz_n, s.std_5_20hz_n, s.actual_max_n, s.actual_min_n, s.max_uplift_at_support_mm, s.loss_of_contact_percent
            ),
            None => println!("  {:<10} did not cross the analysis section", p.name),
        }
    }
    println!(
        "wrote {}/summary.json and {}/timeseries.csv",
        a.out.display(),
        a.out.display()
    );
    Ok(0)
}
