//! What several commands share: reading a case, and running one with a progress bar.

use anyhow::{bail, Context, Result};
use pcsim_core::analysis::record::{simulate, RunOutput};
use pcsim_core::{presets, Case, Setup, SimError};
use std::path::PathBuf;
use std::time::Instant;

use crate::progress::bar;

/// Load a case from a file or a preset.
pub fn load_case(path: Option<&PathBuf>, preset: Option<&str>) -> Result<Case> {
    match (path, preset) {
        (Some(p), None) => {
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("cannot read case file '{}'", p.display()))?;
            let (case, _) = Case::from_toml_str(&text)
                .with_context(|| format!("in case file '{}'", p.display()))?;
            Ok(case)
        }
        (None, Some(name)) => Ok(presets::load(name)?.0),
        (Some(_), Some(_)) => bail!("give a case file or --preset, not both"),
        (None, None) => bail!("give a case file or --preset NAME (see `pcsim presets`)"),
    }
}

/// The name a case reports itself with.
pub fn case_name(case: &Case) -> String {
    if case.meta.name.is_empty() {
        "case".to_string()
    } else {
        case.meta.name.clone()
    }
}

/// Validate and run a case with a progress bar; print its warnings. Returns the output, the
/// wall time and the warnings.
pub fn run_with_progress(
    case: &Case,
    label: &str,
    quiet: bool,
) -> Result<(RunOutput, f64, Vec<String>)> {
    let setup = Setup::from_case(case)?;
    let warnings: Vec<String> = setup.warnings.iter().map(|w| w.to_string()).collect();
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    let pb = bar(label, quiet);
    let t0 = Instant::now();
    let out = simulate(&setup, &mut |f| {
        pb.set_position((f * 1000.0) as u64);
        true
    })
    .map_err(|e: SimError| anyhow::anyhow!(e))?;
    pb.finish_and_clear();
    Ok((out, t0.elapsed().as_secs_f64(), warnings))
}
