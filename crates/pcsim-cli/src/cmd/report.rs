//! `pcsim report DIR`: the report of an output directory (the library is `report/`).

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub struct ReportArgs {
    /// An output directory of pcsim (run, eva, window, realtime, Monte Carlo, compare, design,
    /// pantograph frf and fit).
    dir: PathBuf,
}

pub fn report(a: ReportArgs) -> Result<i32> {
    let path = crate::report::write(&a.dir)?;
    println!("wrote {}", path.display());
    Ok(0)
}
