//! The figures of a run: the contact force of each pantograph, raw and 0–20 Hz filtered, against
//! position (as the paper's Fig. 3), and the contact-point height.

use anyhow::{anyhow, bail, Context, Result};
use pcsim_core::analysis::record::RunOutput;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

use super::{legend, range, register_font, safe, xrange, Chart, COLOURS, RAW};
use crate::output::Summary;

/// One pantograph's traces.
pub struct Trace {
    pub name: String,
    pub position_m: Vec<f64>,
    pub force_n: Vec<f64>,
    pub force_filtered_n: Vec<f64>,
    pub height_m: Vec<f64>,
}

/// Everything the plots need.
pub struct PlotData {
    pub case_name: String,
    pub speed_kmh: f64,
    pub span_m: Option<f64>,
    pub analysis_m: [f64; 2],
    pub traces: Vec<Trace>,
}

impl PlotData {
    /// The plot data of a finished run.
    pub fn from_run(summary: &Summary, span_m: Option<f64>, out: &RunOutput) -> Self {
        PlotData {
            case_name: summary.case_name.clone(),
            speed_kmh: summary.speed_kmh,
            span_m,
            analysis_m: out.analysis_m,
            traces: out
                .pantographs
                .iter()
                .map(|p| Trace {
                    name: p.name.clone(),
                    position_m: p.position_m.clone(),
                    force_n: p.force_n.clone(),
                    force_filtered_n: p.force_filtered_n.clone(),
                    height_m: p.wire_height_m.clone(),
                })
                .collect(),
        }
    }
}

/// Keep at most ~`max` points, preserving each bucket's minimum and maximum (peaks survive).
fn decimate(x: &[f64], y: &[f64], max: usize) -> Vec<(f64, f64)> {
    let n = x.len();
    if n <= max {
        return x.iter().copied().zip(y.iter().copied()).collect();
    }
    let bucket = n.div_ceil(max / 2);
    let mut out = Vec::with_capacity(max + 2);
    for c in (0..n).step_by(bucket) {
        let end = (c + bucket).min(n);
        let (mut imin, mut imax) = (c, c);
        for i in c..end {
            if y[i] < y[imin] {
                imin = i;
            }
            if y[i] > y[imax] {
                imax = i;
            }
        }
        let (a, b) = if imin < imax {
            (imin, imax)
        } else {
            (imax, imin)
        };
        out.push((x[a], y[a]));
        if b != a {
            out.push((x[b], y[b]));
        }
    }
    out
}

/// Every k-th point, at most ~`max` (for smooth, already filtered signals).
fn stride(x: &[f64], y: &[f64], max: usize) -> Vec<(f64, f64)> {
    let k = x.len().div_ceil(max).max(1);
    x.iter()
        .copied()
        .zip(y.iter().copied())
        .step_by(k)
        .collect()
}

fn span_marks<DB: DrawingBackend>(
    chart: &mut ChartContext<
        '_,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    d: &PlotData,
    x: (f64, f64),
    y: (f64, f64),
) -> Result<()> {
    // The analysis section, shaded.
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(d.analysis_m[0], y.0), (d.analysis_m[1], y.1)],
            RGBColor(255, 240, 200).mix(0.35).filled(),
        )))
        .map_err(|e| anyhow!("{e:?}"))?;
    if let Some(s) = d.span_m {
        let first = (x.0 / s).ceil() as i64;
        let last = (x.1 / s).floor() as i64;
        chart
            .draw_series((first..=last).map(|k| {
                PathElement::new(
                    vec![(k as f64 * s, y.0), (k as f64 * s, y.1)],
                    BLACK.mix(0.18),
                )
            }))
            .map_err(|e| anyhow!("{e:?}"))?
            .label(format!("supports (every {s} m); shaded: analysis section"))
            .legend(|(x, y)| PathElement::new(vec![(x, y - 6), (x, y + 6)], BLACK.mix(0.4)));
    }
    Ok(())
}

/// A chart against track position with the house style (labels with units, integer ticks).
fn track_chart<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    title: String,
    y_desc: &str,
    x: (f64, f64),
    y: (f64, f64),
) -> Result<Chart<'a, DB>> {
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(50)
        .y_label_area_size(65)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
        .map_err(|e| anyhow!("{e:?}"))?;
    chart
        .configure_mesh()
        .x_desc("Position along the track [m]")
        .y_desc(y_desc)
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.0}"))
        .x_labels(20)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .light_line_style(WHITE)
        .draw()
        .map_err(|e| anyhow!("{e:?}"))?;
    Ok(chart)
}

fn force_chart<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    d: &PlotData,
    t: &Trace,
) -> Result<()> {
    root.fill(&WHITE).map_err(|e| anyhow!("{e:?}"))?;
    let x = xrange(t.position_m.iter().copied());
    let y = range(
        t.force_n
            .iter()
            .copied()
            .chain(t.force_filtered_n.iter().copied()),
    );
    let title = format!(
        "{}: contact force, {} pantograph, {:.0} km/h",
        d.case_name, t.name, d.speed_kmh
    );
    let mut chart = track_chart(&root, title, "Contact force [N]", x, y)?;
    span_marks(&mut chart, d, x, y)?;
    chart
        .draw_series(LineSeries::new(
            decimate(&t.position_m, &t.force_n, 8000),
            RAW.stroke_width(1),
        ))
        .map_err(|e| anyhow!("{e:?}"))?
        .label("raw")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RAW.stroke_width(2)));
    chart
        .draw_series(LineSeries::new(
            stride(&t.position_m, &t.force_filtered_n, 6000),
            COLOURS[0].stroke_width(2),
        ))
        .map_err(|e| anyhow!("{e:?}"))?
        .label("0–20 Hz (zero-phase Butterworth)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], COLOURS[0].stroke_width(2)));
    legend(&mut chart)?;
    root.present().map_err(|e| anyhow!("{e:?}"))?;
    Ok(())
}

fn height_chart<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, d: &PlotData) -> Result<()> {
    root.fill(&WHITE).map_err(|e| anyhow!("{e:?}"))?;
    let x = xrange(d.traces.iter().flat_map(|t| t.position_m.iter().copied()));
    let y = range(
        d.traces
            .iter()
            .flat_map(|t| t.height_m.iter().map(|h| h * 1e3)),
    );
    let title = format!(
        "{}: contact-point height, {:.0} km/h",
        d.case_name, d.speed_kmh
    );
    let mut chart = track_chart(
        &root,
        title,
        "Contact-wire height at the contact point [mm]",
        x,
        y,
    )?;
    span_marks(&mut chart, d, x, y)?;
    for (i, t) in d.traces.iter().enumerate() {
        let c = COLOURS[i % COLOURS.len()];
        let mm: Vec<f64> = t.height_m.iter().map(|h| h * 1e3).collect();
        chart
            .draw_series(LineSeries::new(
                stride(&t.position_m, &mm, 6000),
                c.stroke_width(2),
            ))
            .map_err(|e| anyhow!("{e:?}"))?
            .label(format!("{} pantograph", t.name))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
    }
    legend(&mut chart)?;
    root.present().map_err(|e| anyhow!("{e:?}"))?;
    Ok(())
}

/// Draw all plots into `dir` as SVG and PNG; returns the files written.
pub fn draw_all(dir: &Path, d: &PlotData) -> Result<Vec<PathBuf>> {
    register_font();
    let size = (1800, 650);
    let mut files = Vec::new();
    for t in &d.traces {
        let stem = dir.join(format!("contact_force_{}", safe(&t.name)));
        let svg = stem.with_extension("svg");
        force_chart(SVGBackend::new(&svg, size).into_drawing_area(), d, t)
            .with_context(|| format!("drawing {}", svg.display()))?;
        let png = stem.with_extension("png");
        force_chart(BitMapBackend::new(&png, size).into_drawing_area(), d, t)
            .with_context(|| format!("drawing {}", png.display()))?;
        files.extend([svg, png]);
    }
    let stem = dir.join("contact_height");
    let svg = stem.with_extension("svg");
    height_chart(SVGBackend::new(&svg, size).into_drawing_area(), d)
        .with_context(|| format!("drawing {}", svg.display()))?;
    let png = stem.with_extension("png");
    height_chart(BitMapBackend::new(&png, size).into_drawing_area(), d)
        .with_context(|| format!("drawing {}", png.display()))?;
    files.extend([svg, png]);
    Ok(files)
}

/// Read a finished run's `summary.json` and `timeseries.csv` back into plot data.
pub fn read_run(dir: &Path) -> Result<PlotData> {
    let sp = dir.join("summary.json");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&sp).with_context(|| {
            format!(
                "cannot read {} (is {} a run's output directory?)",
                sp.display(),
                dir.display()
            )
        })?)
        .with_context(|| format!("{} is not valid JSON", sp.display()))?;
    let tp = dir.join("timeseries.csv");
    let mut rdr =
        csv::Reader::from_path(&tp).with_context(|| format!("cannot read {}", tp.display()))?;
    let header: Vec<String> = rdr.headers()?.iter().map(String::from).collect();
    let names: Vec<String> = header
        .iter()
        .filter_map(|h| h.strip_suffix("_position_m").map(String::from))
        .collect();
    if names.is_empty() {
        bail!("{} has no `<pantograph>_position_m` column", tp.display());
    }
    let col = |n: &str, suffix: &str| header.iter().position(|h| *h == format!("{n}_{suffix}"));
    let mut traces: Vec<Trace> = names
        .iter()
        .map(|n| Trace {
            name: n.clone(),
            position_m: vec![],
            force_n: vec![],
            force_filtered_n: vec![],
            height_m: vec![],
        })
        .collect();
    let idx: Vec<[usize; 4]> = names
        .iter()
        .map(|n| {
            let c = |s| col(n, s).ok_or_else(|| anyhow!("{} lacks column {n}_{s}", tp.display()));
            Ok([
                c("position_m")?,
                c("force_n")?,
                c("force_filtered_n")?,
                c("height_m")?,
            ])
        })
        .collect::<Result<_>>()?;
    for (line, rec) in rdr.records().enumerate() {
        let rec = rec.with_context(|| format!("{} line {}", tp.display(), line + 2))?;
        for (t, ix) in traces.iter_mut().zip(&idx) {
            let v = |i: usize| -> Result<f64> {
                rec.get(i)
                    .and_then(|s| s.parse::<f64>().ok())
                    .ok_or_else(|| {
                        anyhow!(
                            "{} line {}: bad number in column {}",
                            tp.display(),
                            line + 2,
                            header[i]
                        )
                    })
            };
            t.position_m.push(v(ix[0])?);
            t.force_n.push(v(ix[1])?);
            t.force_filtered_n.push(v(ix[2])?);
            t.height_m.push(v(ix[3])?);
        }
    }
    let a = &summary["analysis_section_m"];
    Ok(PlotData {
        case_name: summary["case_name"].as_str().unwrap_or("run").to_string(),
        speed_kmh: summary["speed_kmh"].as_f64().unwrap_or(0.0),
        span_m: summary["span_m"].as_f64(),
        analysis_m: [a[0].as_f64().unwrap_or(0.0), a[1].as_f64().unwrap_or(0.0)],
        traces,
    })
}
