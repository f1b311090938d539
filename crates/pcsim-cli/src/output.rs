//! Writing results: `summary.json`, `timeseries.csv`, and the manifest `pcsim.json` that every
//! output directory carries (its kind, the version, the command's overrides), so that `pcsim plot
//! DIR` can redraw any of them.

use anyhow::{Context, Result};
use pcsim_core::analysis::record::RunOutput;
use std::path::Path;

/// The manifest of an output directory.
pub const MANIFEST: &str = "pcsim.json";

pub use pcsim_core::analysis::report::RunSummary as Summary;

/// Write the manifest of an output directory: `{"kind": …, "pcsim_version": …}` plus `extra`.
pub fn write_manifest(dir: &Path, kind: &str, extra: serde_json::Value) -> Result<()> {
    let mut m = serde_json::json!({
        "kind": kind,
        "pcsim_version": env!("CARGO_PKG_VERSION"),
    });
    if let (Some(o), serde_json::Value::Object(e)) = (m.as_object_mut(), extra) {
        o.extend(e);
    }
    let path = dir.join(MANIFEST);
    std::fs::write(&path, serde_json::to_string_pretty(&m)? + "\n")
        .with_context(|| format!("cannot write {}", path.display()))
}

/// Read the manifest of an output directory (`None` when it has none).
pub fn read_manifest(dir: &Path) -> Result<Option<serde_json::Value>> {
    let path = dir.join(MANIFEST);
    if !path.exists() {
        return Ok(None);
    }
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    Ok(Some(serde_json::from_str(&text).with_context(|| {
        format!("{} is not valid JSON", path.display())
    })?))
}

/// Write `summary.json`, `timeseries.csv` and the manifest into `dir` (created if needed).
pub fn write_run(dir: &Path, out: &RunOutput, summary: &Summary) -> Result<()> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create output directory {}", dir.display()))?;
    let js = serde_json::to_string_pretty(summary)?;
    std::fs::write(dir.join("summary.json"), js + "\n")
        .with_context(|| format!("cannot write {}", dir.join("summary.json").display()))?;
    let path = dir.join("timeseries.csv");
    let mut w = csv::Writer::from_path(&path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    let cols = pcsim_core::analysis::report::timeseries_columns(out);
    w.write_record(cols.iter().map(|c| c.name.as_str()))?;
    let mut rec = Vec::with_capacity(cols.len());
    for k in 0..out.time_s.len() {
        rec.clear();
        for c in &cols {
            rec.push(format!("{:.*}", c.decimals, c.values[k]));
        }
        w.write_record(&rec)?;
    }
    w.flush()?;
    write_manifest(dir, "run", serde_json::json!({}))
}
