//! `pcsim plot DIR`: redraw the figures of a finished run from its files.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub struct PlotArgs {
    /// Output directory of a finished `pcsim run`.
    dir: PathBuf,
}

pub fn plot(a: PlotArgs) -> Result<i32> {
    let data = crate::plot::run::read_run(&a.dir)?;
    let files = crate::plot::run::draw_all(&a.dir, &data)?;
    crate::plot::report(&files);
    Ok(0)
}
