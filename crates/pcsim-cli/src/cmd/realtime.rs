//! `pcsim realtime`: the moving-window catenary (SIL) against the full model, for several window
//! lengths (paper §4.2, Figs. 8–9). The command reads its arguments into the core's
//! [`RealtimeStudy`] and drives it (`crate::driver`).

use anyhow::Result;
use clap::Args;
use pcsim_core::study::realtime::RealtimeStudy;
use std::path::PathBuf;

use crate::common::{apply, case_name, length, setup, Ctx, Override};

#[derive(Args)]
pub struct RealtimeArgs {
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name.
    #[arg(long)]
    preset: Option<String>,
    /// Window lengths, comma-separated: m, or with a unit (215m, 0.215km).
    #[arg(long, value_delimiter = ',', required = true, value_name = "M")]
    window: Vec<String>,
    /// Train speed (default: the case's): km/h, or with a unit (250km/h, 69m/s).
    #[arg(long, value_name = "KM/H")]
    speed: Option<String>,
    /// The pantograph the window follows (the rig's): leading, trailing, a name or an index
    /// (sets the case's run.window_pantograph; default: the case's, else the leading one).
    #[arg(long, value_name = "NAME")]
    pantograph: Option<String>,
    /// Output directory.
    #[arg(long, default_value = "out/realtime")]
    out: PathBuf,
    /// No figures.
    #[arg(long)]
    no_plot: bool,
}

pub fn realtime(a: RealtimeArgs, ctx: &Ctx) -> Result<i32> {
    let (base, case_text) =
        crate::common::load_case_with_text(a.case.as_ref(), a.preset.as_deref())?;
    let mut overrides = Vec::new();
    if let Some(v) = &a.speed {
        overrides.push(Override::speed(v)?);
    }
    let case = crate::common::window_pantograph(apply(&base, &overrides)?, a.pantograph.as_deref());
    let together = case.pantographs.len();
    let case = pcsim_core::compile::window_case(&case)?;
    let windows_m: Vec<f64> = a
        .window
        .iter()
        .map(|w| length("--window", w))
        .collect::<Result<_>>()?;
    let s = setup(&case, &overrides, ctx)?;
    for w in &s.warnings {
        eprintln!("warning: {w}");
    }
    let name = case_name(&case);
    let manifest = crate::output::StudyManifest {
        case_name: Some(name.clone()),
        speed_kmh: Some(case.run.speed_kmh),
        analysis_m: Some(case.run.analysis_m),
        overrides: Some(overrides.iter().map(|o| o.flag.clone()).collect()),
        ..Default::default()
    };
    let study = RealtimeStudy {
        case,
        case_name: name,
        windows_m,
        together,
    };
    crate::driver::drive(
        &study,
        crate::driver::Drive {
            out: &a.out,
            case_text: Some(&case_text),
            spec_text: None,
            plot: !a.no_plot,
            report: false,
            manifest,
            unit: "runs",
        },
        ctx,
    )?;
    Ok(0)
}
