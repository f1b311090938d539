//! `pcsim plot DIR`: redraw the figures of any output directory pcsim writes (a run, an EVA
//! sweep, a merged sweep, a real-time window study) from its files.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub struct PlotArgs {
    /// An output directory of `pcsim run`, `eva`, `eva merge` or `realtime`.
    dir: PathBuf,
}

pub fn plot(a: PlotArgs) -> Result<i32> {
    let files = crate::plot::redraw(&a.dir)?;
    crate::plot::report(&files);
    Ok(0)
}
