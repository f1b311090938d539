//! Writing results: `summary.json`, `timeseries.csv`, and the manifest `pcsim.json` that every
//! output directory carries (its kind, the version, the command's overrides), so that `pcsim plot
//! DIR` can redraw any of them.

use anyhow::{Context, Result};
use pcsim_core::analysis::record::RunOutput;
use pcsim_core::analysis::stats::{ContactStats, LateralStats};
use pcsim_core::model::irregularity::IrregularityReport;
use pcsim_core::model::wind::WindReport;
use pcsim_core::RunStatistics;
use serde::Serialize;
use std::path::Path;

use crate::common::round_ns;

/// The manifest of an output directory.
pub const MANIFEST: &str = "pcsim.json";

#[derive(Serialize)]
pub struct PantographSummary {
    pub name: String,
    pub stats: Option<ContactStats>,
    /// The contact point across the head (lateral motion modelled): flags and the wear
    /// histogram.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lateral: Option<LateralStats>,
}

#[derive(Serialize)]
pub struct Summary {
    pub case_name: String,
    pub speed_kmh: f64,
    /// Contact-wire tension used, N.
    pub contact_wire_tension_n: f64,
    pub span_m: f64,
    pub simulated_time_s: f64,
    pub wall_time_s: f64,
    pub analysis_section_m: [f64; 2],
    pub modes_per_wire: usize,
    pub dt_s: f64,
    /// The kernels that ran: `portable` (the same bytes on every machine) or `x86-64-v3`.
    pub kernels: String,
    pub max_slack_droppers: usize,
    pub steps_with_slack_percent: f64,
    pub run_statistics: RunStatistics,
    /// The flags that overrode case values, as given.
    pub overrides: Vec<String>,
    pub warnings: Vec<String>,
    pub pantographs: Vec<PantographSummary>,
    /// The crosswind (mean speed, spectrum, seed, turbulence intensity achieved).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wind: Option<WindReport>,
    /// The contact-wire irregularity's sources (kind, seed, RMS target and achieved).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub irregularity: Vec<IrregularityReport>,
}

impl Summary {
    pub fn new(
        case: &pcsim_core::Case,
        out: &RunOutput,
        wall_time_s: f64,
        overrides: Vec<String>,
        warnings: Vec<String>,
    ) -> Self {
        Summary {
            case_name: crate::common::case_name(case),
            speed_kmh: case.run.speed_kmh,
            contact_wire_tension_n: case.catenary.contact_wire.tension_n,
            span_m: case.catenary.span_m,
            simulated_time_s: round_ns(out.simulated_time_s()),
            wall_time_s: (wall_time_s * 1e3).round() / 1e3,
            analysis_section_m: out.analysis_m,
            modes_per_wire: out.n_modes,
            dt_s: out.dt_s,
            kernels: pcsim_core::solve::Isa::detect().name().into(),
            max_slack_droppers: out.max_slack_droppers,
            steps_with_slack_percent: out.steps_with_slack_percent,
            run_statistics: out.run_statistics,
            overrides,
            warnings,
            pantographs: out
                .pantographs
                .iter()
                .map(|p| PantographSummary {
                    name: p.name.clone(),
                    stats: p.stats,
                    lateral: p.lateral.clone(),
                })
                .collect(),
            wind: out.wind.clone(),
            irregularity: out.irregularity.clone(),
        }
    }
}

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
    let mut header = vec!["time_s".to_string()];
    for (i, p) in out.pantographs.iter().enumerate() {
        let tag = if p.name.is_empty() {
            format!("p{i}")
        } else {
            p.name.clone()
        };
        for col in ["position_m", "force_n", "force_filtered_n", "height_m"] {
            header.push(format!("{tag}_{col}"));
        }
        if !p.lateral_m.is_empty() {
            header.push(format!("{tag}_lateral_m"));
            if p.head_half_width_m.is_some() {
                header.push(format!("{tag}_head_margin_m"));
            }
        }
    }
    w.write_record(&header)?;
    let mut rec = Vec::with_capacity(header.len());
    for (k, t) in out.time_s.iter().enumerate() {
        rec.clear();
        rec.push(format!("{t:.6}"));
        for p in &out.pantographs {
            rec.push(format!("{:.4}", p.position_m[k]));
            rec.push(format!("{:.4}", p.force_n[k]));
            rec.push(format!("{:.4}", p.force_filtered_n[k]));
            rec.push(format!("{:.6}", p.wire_height_m[k]));
            if let Some(z) = p.lateral_m.get(k) {
                rec.push(format!("{z:.6}"));
                if let Some(h) = p.head_half_width_m {
                    rec.push(format!("{:.6}", h - z.abs()));
                }
            }
        }
        w.write_record(&rec)?;
    }
    w.flush()?;
    write_manifest(dir, "run", serde_json::json!({}))
}
