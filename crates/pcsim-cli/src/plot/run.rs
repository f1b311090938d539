//! The figures of a run: the contact force of each pantograph, raw and 0–20 Hz filtered, against
//! position (as the paper's Fig. 3), and the contact-point height. Drawn from the run's files
//! (`summary.json`, `timeseries.csv`), so `--plot` and `pcsim plot DIR` draw the same.

use anyhow::{anyhow, bail, Context, Result};
use pcsim_core::analysis::report::RunSummary;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

use super::{legend, range, register_font, safe, xrange, Chart, COLOURS, RAW};

/// One pantograph's traces.
pub struct Trace {
    pub name: String,
    pub position_m: Vec<f64>,
    pub force_n: Vec<f64>,
    pub force_filtered_n: Vec<f64>,
    pub height_m: Vec<f64>,
    /// Lateral position of the contact point, m (empty without lateral motion).
    pub lateral_m: Vec<f64>,
    /// From summary.json (lateral motion): half-widths, and the histogram (from, bin, counts),
    /// mm.
    pub head_half_width_m: Option<f64>,
    pub working_half_width_m: Option<f64>,
    pub histogram: Option<(f64, f64, Vec<f64>)>,
    /// Each collector strip's raw contact force, N (none without strips).
    pub strips: Vec<Vec<f64>>,
}

/// Everything the plots need.
pub struct PlotData {
    pub case_name: String,
    pub speed_kmh: f64,
    pub span_m: Option<f64>,
    /// The supports of a line whose spans differ, m.
    pub supports_m: Vec<f64>,
    /// A line's overlaps (first and last shared support), m.
    pub overlaps_m: Vec<[f64; 2]>,
    /// A line's hard spots (section insulators, neutral sections), m.
    pub hard_spots_m: Vec<[f64; 2]>,
    pub analysis_m: [f64; 2],
    /// The flags that overrode case values (named in the titles).
    pub overrides: Vec<String>,
    pub traces: Vec<Trace>,
}

impl PlotData {
    /// The title suffix naming the overrides.
    fn with(&self) -> String {
        if self.overrides.is_empty() {
            String::new()
        } else {
            format!(" (with {})", self.overrides.join(", "))
        }
    }
}

/// The supports' colour (dark brown: neither a series nor the grid).
const SUPPORT: RGBColor = RGBColor(120, 72, 30);

/// Width of the plot area in pixels: one envelope column per pixel.
const COLUMNS: usize = 1650;

/// Per pixel column over `[x0, x1]`: the column's centre, the smallest, the largest and the mean
/// of the values falling in it (empty columns are skipped).
fn columns(x: &[f64], y: &[f64], x0: f64, x1: f64) -> Vec<(f64, f64, f64, f64)> {
    let w = (x1 - x0) / COLUMNS as f64;
    let mut acc = vec![(f64::INFINITY, f64::NEG_INFINITY, 0.0, 0usize); COLUMNS];
    for (&xi, &yi) in x.iter().zip(y) {
        if !(xi.is_finite() && yi.is_finite()) {
            continue;
        }
        let c = (((xi - x0) / w).floor().max(0.0) as usize).min(COLUMNS - 1);
        let a = &mut acc[c];
        a.0 = a.0.min(yi);
        a.1 = a.1.max(yi);
        a.2 += yi;
        a.3 += 1;
    }
    acc.iter()
        .enumerate()
        .filter(|(_, a)| a.3 > 0)
        .map(|(c, a)| (x0 + (c as f64 + 0.5) * w, a.0, a.1, a.2 / a.3 as f64))
        .collect()
}

/// The track's `sections` shaded over the height `y` in `colour` (at its opacity), with one
/// legend entry `label` (none drawn when there are none).
fn shade<DB: DrawingBackend>(
    chart: &mut ChartContext<
        '_,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    sections: &[[f64; 2]],
    y: (f64, f64),
    (colour, opacity): (RGBColor, f64),
    label: &str,
) -> Result<()> {
    if sections.is_empty() {
        return Ok(());
    }
    chart
        .draw_series(
            (sections.iter())
                .map(|o| Rectangle::new([(o[0], y.0), (o[1], y.1)], colour.mix(opacity).filled())),
        )
        .map_err(|e| anyhow!("{e:?}"))?
        .label(label)
        .legend(move |(x, y)| {
            Rectangle::new([(x - 6, y - 5), (x + 6, y + 5)], colour.mix(0.5).filled())
        });
    Ok(())
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
    // A line's overlaps, shaded too (the tension lengths change there), and its hard spots.
    shade(
        chart,
        &d.overlaps_m,
        y,
        (RGBColor(120, 170, 255), 0.22),
        "overlaps (two contact wires; the tension length changes)",
    )?;
    shade(
        chart,
        &d.hard_spots_m,
        y,
        (RGBColor(230, 90, 90), 0.25),
        "section insulators and neutral sections",
    )?;
    // The supports: dashed, in a colour of their own (the grid is solid light grey), with a
    // tick at the foot of the axis.
    let support_at =
        |s: f64| DashedPathElement::new(vec![(s, y.0), (s, y.1)], 6, 5, SUPPORT.stroke_width(1));
    let legend_mark = |(x, y): (i32, i32)| {
        DashedPathElement::new(
            vec![(x + 10, y - 8), (x + 10, y + 8)],
            4,
            3,
            SUPPORT.stroke_width(2),
        )
    };
    let supports: Vec<f64> = if let Some(s) = d.span_m {
        let first = (x.0 / s).ceil() as i64;
        let last = ((x.1 / s).floor() as i64).min(first + 5000);
        (first..=last).map(|k| k as f64 * s).collect()
    } else {
        d.supports_m
            .iter()
            .copied()
            .filter(|&s| s >= x.0 && s <= x.1)
            .collect()
    };
    if !supports.is_empty() {
        let label = match d.span_m {
            Some(s) => format!("supports (every {s} m, dashed); shaded: analysis section"),
            None => "supports (spans differ, dashed); shaded: analysis section".to_string(),
        };
        chart
            .draw_series(supports.iter().map(|&s| support_at(s)))
            .map_err(|e| anyhow!("{e:?}"))?
            .label(label)
            .legend(legend_mark);
        let tick = 0.03 * (y.1 - y.0);
        chart
            .draw_series(supports.iter().map(|&s| {
                PathElement::new(vec![(s, y.0), (s, y.0 + tick)], SUPPORT.stroke_width(3))
            }))
            .map_err(|e| anyhow!("{e:?}"))?;
    }
    Ok(())
}

/// A chart against track position with the house style (labels with units, integer ticks).
/// Draw `y` over `x_m` as its min/max envelope per pixel column of the range `x` (a filled
/// band: about a dozen samples fall in one column, and a line through them would zig-zag
/// between the extremes), with a legend entry in `colour` (the band at opacity `alpha`).
fn envelope<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    (x_m, y): (&[f64], &[f64]),
    x: (f64, f64),
    (colour, alpha): (RGBColor, f64),
    label: &str,
) -> Result<()> {
    let cols = columns(x_m, y, x.0, x.1);
    let mut band: Vec<(f64, f64)> = cols.iter().map(|c| (c.0, c.2)).collect();
    band.extend(cols.iter().rev().map(|c| (c.0, c.1)));
    chart
        .draw_series(std::iter::once(Polygon::new(
            band,
            colour.mix(alpha).filled(),
        )))
        .map_err(|e| anyhow!("{e:?}"))?
        .label(label)
        .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], colour.filled()));
    Ok(())
}

fn track_chart<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    title: String,
    y_desc: &str,
    x: (f64, f64),
    y: (f64, f64),
) -> Result<Chart<'a, DB>> {
    track_chart_with(root, title, y_desc, x, y, 0)
}

/// [`track_chart`] with `y_decimals` decimals on the y axis.
fn track_chart_with<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    title: String,
    y_desc: &str,
    x: (f64, f64),
    y: (f64, f64),
    y_decimals: usize,
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
        .y_label_formatter(&|v| format!("{v:.y_decimals$}"))
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
        "{}: contact force, {} pantograph, {} km/h{}",
        d.case_name,
        t.name,
        d.speed_kmh,
        d.with()
    );
    let mut chart = track_chart(&root, title, "Contact force [N]", x, y)?;
    span_marks(&mut chart, d, x, y)?;
    // Both forces as min/max envelopes per pixel column.
    envelope(
        &mut chart,
        (&t.position_m, &t.force_n),
        x,
        (RAW, 0.8),
        "raw (min–max per pixel column)",
    )?;
    envelope(
        &mut chart,
        (&t.position_m, &t.force_filtered_n),
        x,
        (COLOURS[0], 0.85),
        "0–20 Hz, zero-phase Butterworth (min–max per pixel column)",
    )?;
    // Each collector strip's own raw force (their sum is the raw force above).
    for (k, f) in t.strips.iter().enumerate() {
        envelope(
            &mut chart,
            (&t.position_m, f),
            x,
            (COLOURS[(k + 1) % COLOURS.len()], 0.6),
            &format!("strip {} raw (min–max per pixel column)", k + 1),
        )?;
    }
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
        "{}: contact-point height, {} km/h{}",
        d.case_name,
        d.speed_kmh,
        d.with()
    );
    let mut chart = track_chart(
        &root,
        title,
        "Contact-point height above the contact wire's design height at the supports [mm]",
        x,
        y,
    )?;
    span_marks(&mut chart, d, x, y)?;
    for (i, t) in d.traces.iter().enumerate() {
        let c = COLOURS[i % COLOURS.len()];
        let mm: Vec<f64> = t.height_m.iter().map(|h| h * 1e3).collect();
        let cols = columns(&t.position_m, &mm, x.0, x.1);
        chart
            .draw_series(LineSeries::new(
                cols.iter().map(|c| (c.0, c.3)),
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

/// The contact point's lateral position against track position, with the head's ends and the
/// working range (issue 12: blow-off).
fn lateral_chart<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    d: &PlotData,
    t: &Trace,
) -> Result<()> {
    root.fill(&WHITE).map_err(|e| anyhow!("{e:?}"))?;
    let x = xrange(t.position_m.iter().copied());
    let mm: Vec<f64> = t.lateral_m.iter().map(|z| z * 1e3).collect();
    let marks: Vec<(f64, &str)> = [
        (t.head_half_width_m, "end of the head"),
        (t.working_half_width_m, "limit of the working range"),
    ]
    .iter()
    .filter_map(|(w, l)| w.map(|w| (w * 1e3, *l)))
    .collect();
    let y = range(
        mm.iter()
            .copied()
            .chain(marks.iter().flat_map(|m| [m.0, -m.0])),
    );
    let title = format!(
        "{}: contact point across the head, {} pantograph, {} km/h{}",
        d.case_name,
        t.name,
        d.speed_kmh,
        d.with()
    );
    let mut chart = track_chart(
        &root,
        title,
        "Contact point from the track centre line [mm]",
        x,
        y,
    )?;
    span_marks(&mut chart, d, x, y)?;
    for (k, (w, label)) in marks.iter().enumerate() {
        let c = if k == 0 { COLOURS[1] } else { COLOURS[2] };
        chart
            .draw_series(
                [-1.0, 1.0]
                    .iter()
                    .map(|s| PathElement::new(vec![(x.0, s * w), (x.1, s * w)], c.stroke_width(2))),
            )
            .map_err(|e| anyhow!("{e:?}"))?
            .label(format!("{label} (±{w:.0} mm)"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
    }
    envelope(
        &mut chart,
        (&t.position_m, &mm),
        x,
        (COLOURS[0], 0.85),
        "contact point (min–max per pixel column)",
    )?;
    legend(&mut chart)?;
    root.present().map_err(|e| anyhow!("{e:?}"))?;
    Ok(())
}

/// The wear histogram: share of the analysis section's samples per 10 mm of the strip.
fn wear_figure(dir: &Path, d: &PlotData, t: &Trace) -> Result<Vec<PathBuf>> {
    let Some((from, bin, counts)) = &t.histogram else {
        return Ok(Vec::new());
    };
    let total: f64 = counts.iter().sum::<f64>().max(1.0);
    let mut stairs = Vec::with_capacity(2 * counts.len());
    for (i, c) in counts.iter().enumerate() {
        let x0 = from + i as f64 * bin;
        stairs.push((x0, 100.0 * c / total));
        stairs.push((x0 + bin, 100.0 * c / total));
    }
    let mut vmarks = Vec::new();
    for (w, l) in [
        (t.working_half_width_m, "working range"),
        (t.head_half_width_m, "end of the head"),
    ] {
        if let Some(w) = w {
            vmarks.push((-w * 1e3, format!("{l} (±{:.0} mm)", w * 1e3)));
            vmarks.push((w * 1e3, String::new()));
        }
    }
    let title = format!(
        "{}: where the contact point runs on the strip (wear), {} pantograph, {} km/h{}",
        d.case_name,
        t.name,
        d.speed_kmh,
        d.with()
    );
    super::figure(
        &dir.join(format!("wear_{}", safe(&t.name))),
        &super::Figure {
            title: &title,
            x_label: "Contact point from the track centre line [mm]",
            y_label: "Share of the analysis section's samples [%]",
            lines: vec![super::Line::new(format!("per {bin:.0} mm"), stairs)],
            log_y: false,
            vmarks,
            hmarks: Vec::new(),
        },
    )
}

/// One dropper's row of `droppers.csv`: position, wire, largest tension range, damage.
struct DropperRow {
    x_m: f64,
    wire: String,
    max_range_n: f64,
    damage: Option<f64>,
}

/// `droppers.csv` of a run with `--dropper-forces`, if there is one.
fn read_droppers(dir: &Path) -> Result<Option<Vec<DropperRow>>> {
    let path = dir.join("droppers.csv");
    if !path.is_file() {
        return Ok(None);
    }
    let mut r =
        csv::Reader::from_path(&path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut rows = Vec::new();
    for rec in r.records() {
        let rec = rec.with_context(|| format!("cannot read {}", path.display()))?;
        let num = |i: usize| -> Result<f64> {
            rec.get(i)
                .and_then(|v| v.parse().ok())
                .with_context(|| format!("{}: column {i} of a row is not a number", path.display()))
        };
        rows.push(DropperRow {
            x_m: num(1)?,
            wire: rec.get(2).unwrap_or_default().to_string(),
            max_range_n: num(8)?,
            damage: rec.get(9).and_then(|v| v.parse().ok()),
        });
    }
    Ok(Some(rows))
}

/// Every dropper along the line: Miner's damage of the run's passage (per million passages,
/// when the case gives an S–N curve), else its largest tension range; one colour and marker per
/// wire (tension length), the overlaps shaded.
fn dropper_chart<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    d: &PlotData,
    rows: &[DropperRow],
) -> Result<()> {
    root.fill(&WHITE).map_err(|e| anyhow!("{e:?}"))?;
    let damage = rows.iter().all(|r| r.damage.is_some()) && !rows.is_empty();
    let v = |r: &DropperRow| {
        if damage {
            r.damage.unwrap_or(0.0) * 1e6
        } else {
            r.max_range_n
        }
    };
    let x = xrange(rows.iter().map(|r| r.x_m));
    let (_, hi) = range(rows.iter().map(v));
    let y = (0.0, hi.max(1e-12));
    let (what, unit) = if damage {
        (
            "Miner's damage of one passage",
            "Damage per million passages (Miner's sum × 1e6)",
        )
    } else {
        (
            "largest tension range (no S–N curve in the case)",
            "Largest rainflow range of the tension [N]",
        )
    };
    let title = format!(
        "{}: droppers, {what}, {} km/h{}",
        d.case_name,
        d.speed_kmh,
        d.with()
    );
    let mut chart = track_chart_with(&root, title, unit, x, y, 3)?;
    span_marks(&mut chart, d, x, y)?;
    let mut wires: Vec<&str> = rows.iter().map(|r| r.wire.as_str()).collect();
    wires.dedup();
    wires.sort_unstable();
    wires.dedup();
    for (k, w) in wires.iter().enumerate() {
        let c = COLOURS[k % COLOURS.len()];
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.wire == *w)
            .map(|r| (r.x_m, v(r)))
            .collect();
        chart
            .draw_series(
                pts.iter()
                    .map(|&(xi, yi)| PathElement::new(vec![(xi, 0.0), (xi, yi)], c.mix(0.6))),
            )
            .map_err(|e| anyhow!("{e:?}"))?;
        // Circles, squares and triangles in turn: the wires differ in shape as well as colour.
        let label = format!("droppers on {w}");
        let err = |e| anyhow!("{e:?}");
        match k % 3 {
            0 => {
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 4, c.filled())))
                    .map_err(err)?
                    .label(label)
                    .legend(move |(lx, ly)| Circle::new((lx + 10, ly), 4, c.filled()));
            }
            1 => {
                chart
                    .draw_series(pts.iter().map(|&p| {
                        EmptyElement::at(p) + Rectangle::new([(-4, -4), (4, 4)], c.filled())
                    }))
                    .map_err(err)?
                    .label(label)
                    .legend(move |(lx, ly)| {
                        Rectangle::new([(lx + 6, ly - 4), (lx + 14, ly + 4)], c.filled())
                    });
            }
            _ => {
                chart
                    .draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 6, c.filled())))
                    .map_err(err)?
                    .label(label)
                    .legend(move |(lx, ly)| TriangleMarker::new((lx + 10, ly), 6, c.filled()));
            }
        }
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
    for t in d.traces.iter().filter(|t| !t.lateral_m.is_empty()) {
        let stem = dir.join(format!("lateral_{}", safe(&t.name)));
        let svg = stem.with_extension("svg");
        lateral_chart(SVGBackend::new(&svg, size).into_drawing_area(), d, t)
            .with_context(|| format!("drawing {}", svg.display()))?;
        let png = stem.with_extension("png");
        lateral_chart(BitMapBackend::new(&png, size).into_drawing_area(), d, t)
            .with_context(|| format!("drawing {}", png.display()))?;
        files.extend([svg, png]);
        files.extend(wear_figure(dir, d, t)?);
    }
    if let Some(rows) = read_droppers(dir)? {
        let stem = dir.join("droppers");
        let svg = stem.with_extension("svg");
        dropper_chart(SVGBackend::new(&svg, size).into_drawing_area(), d, &rows)
            .with_context(|| format!("drawing {}", svg.display()))?;
        let png = stem.with_extension("png");
        dropper_chart(BitMapBackend::new(&png, size).into_drawing_area(), d, &rows)
            .with_context(|| format!("drawing {}", png.display()))?;
        files.extend([svg, png]);
    }
    Ok(files)
}

/// Redraw a run's figures from its files.
pub fn redraw(dir: &Path) -> Result<Vec<PathBuf>> {
    let summary = read_summary(dir)?;
    let mut files = draw_all(dir, &read_run_with(dir, &summary)?)?;
    files.extend(super::sensitivity::draw(dir, &summary)?);
    Ok(files)
}

/// A finished run's `summary.json`, read back through the type that wrote it.
fn read_summary(dir: &Path) -> Result<RunSummary> {
    let sp = dir.join("summary.json");
    serde_json::from_str(&std::fs::read_to_string(&sp).with_context(|| {
        format!(
            "cannot read {} (is {} a run's output directory?)",
            sp.display(),
            dir.display()
        )
    })?)
    .with_context(|| format!("{} is not a run's summary", sp.display()))
}

/// Read a finished run's `summary.json` and `timeseries.csv` back into plot data.
pub fn read_run(dir: &Path) -> Result<PlotData> {
    read_run_with(dir, &read_summary(dir)?)
}

/// [`read_run`] with the run's summary already read.
fn read_run_with(dir: &Path, summary: &RunSummary) -> Result<PlotData> {
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
            lateral_m: vec![],
            head_half_width_m: None,
            working_half_width_m: None,
            histogram: None,
            strips: vec![],
        })
        .collect();
    // Each strip's force column, `<pantograph>_strip<k>_force_n`, k from 1.
    let strip_idx: Vec<Vec<usize>> = names
        .iter()
        .map(|n| {
            (1..)
                .map_while(|k| col(n, &format!("strip{k}_force_n")))
                .collect()
        })
        .collect();
    for (t, ix) in traces.iter_mut().zip(&strip_idx) {
        t.strips = vec![Vec::new(); ix.len()];
    }
    let lat_idx: Vec<Option<usize>> = names.iter().map(|n| col(n, "lateral_m")).collect();
    heads_from_summary(&mut traces, summary);
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
        // Every number of the row by one reader, its error naming the line and the column.
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
        for (t, ix) in traces.iter_mut().zip(&idx) {
            t.position_m.push(v(ix[0])?);
            t.force_n.push(v(ix[1])?);
            t.force_filtered_n.push(v(ix[2])?);
            t.height_m.push(v(ix[3])?);
        }
        for (t, ix) in traces.iter_mut().zip(&strip_idx) {
            for (k, &i) in ix.iter().enumerate() {
                t.strips[k].push(v(i)?);
            }
        }
        for (t, li) in traces.iter_mut().zip(&lat_idx) {
            if let Some(i) = li {
                t.lateral_m.push(v(*i)?);
            }
        }
    }
    if traces.iter().any(|t| t.position_m.is_empty()) {
        bail!(
            "{} has no rows: the run recorded no steps, there is nothing to plot",
            tp.display()
        );
    }
    // Samples with a non-finite value are left out of the figures, and said so.
    for t in &mut traces {
        drop_non_finite(t, &tp);
    }
    if traces.iter().any(|t| t.position_m.is_empty()) {
        bail!(
            "{}: no sample has finite values, there is nothing to plot",
            tp.display()
        );
    }
    Ok(plot_data(summary, traces))
}

/// Each pantograph's head and working range and wear histogram, from the run's summary.
fn heads_from_summary(traces: &mut [Trace], summary: &RunSummary) {
    for (t, p) in traces.iter_mut().zip(&summary.pantographs) {
        if let Some(l) = &p.lateral {
            t.head_half_width_m = l.head_half_width_m;
            t.working_half_width_m = l.working_half_width_m;
            let h = &l.histogram;
            t.histogram = Some((
                h.from_mm,
                h.bin_mm,
                h.counts.iter().map(|&c| c as f64).collect(),
            ));
        }
    }
}

/// Leave out of trace `t` the samples with a non-finite value, and say so (`tp` the file).
fn drop_non_finite(t: &mut Trace, tp: &Path) {
    let keep: Vec<bool> = (0..t.position_m.len())
        .map(|k| {
            [
                t.position_m[k],
                t.force_n[k],
                t.force_filtered_n[k],
                t.height_m[k],
            ]
            .iter()
            .chain(t.lateral_m.get(k))
            .chain(t.strips.iter().filter_map(|f| f.get(k)))
            .all(|v| v.is_finite())
        })
        .collect();
    let dropped = keep.iter().filter(|k| !**k).count();
    if dropped > 0 {
        eprintln!(
            "warning: {}: pantograph {}: {dropped} samples with a non-finite value are left out of the figures",
            tp.display(),
            t.name
        );
        for v in [
            &mut t.position_m,
            &mut t.force_n,
            &mut t.force_filtered_n,
            &mut t.height_m,
            &mut t.lateral_m,
        ]
        .into_iter()
        .chain(t.strips.iter_mut())
        {
            if v.len() == keep.len() {
                let mut i = 0;
                v.retain(|_| {
                    i += 1;
                    keep[i - 1]
                });
            }
        }
    }
}

/// The plot data of a run: its summary's description and the traces read.
fn plot_data(summary: &RunSummary, traces: Vec<Trace>) -> PlotData {
    PlotData {
        case_name: summary.case_name.clone(),
        speed_kmh: summary.speed_kmh,
        span_m: summary.span_m.filter(|s| *s > 0.0),
        supports_m: summary.supports_m.clone(),
        overlaps_m: summary.overlaps_m.clone(),
        hard_spots_m: {
            let mut v: Vec<[f64; 2]> = (summary.pantographs.iter())
                .flat_map(|p| p.hard_spots.iter().map(|h| h.section_m))
                .collect();
            v.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
            v.dedup();
            v
        },
        analysis_m: summary.analysis_section_m,
        overrides: summary.overrides.clone(),
        traces,
    }
}
