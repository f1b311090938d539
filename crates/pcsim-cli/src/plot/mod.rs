//! Figures (plotters; SVG, and PNG with an embedded DejaVu Sans font so no system fonts are
//! needed), by figure family: `run.rs` (contact force and height along the track, the paper's
//! Fig. 3), `eva.rs` (energy distribution and EVA, Figs. 4–7), `realtime.rs` (the window against
//! the full model, Figs. 8–9). This file holds the house style they share.

pub mod eva;
pub mod realtime;
pub mod run;

use anyhow::{anyhow, Context, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

static FONT: Once = Once::new();

/// Register the embedded DejaVu Sans font for the bitmap backend (no system fonts needed).
pub(crate) fn register_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../../assets/DejaVuSans.ttf");
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

pub(crate) const COLOURS: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];
pub(crate) const RAW: RGBColor = RGBColor(170, 170, 170);

/// Data range with a margin, and extra head-room at the top for the legend.
pub(crate) fn range(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = vals.fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
    let span = (hi - lo).max(1e-9);
    (lo - 0.05 * span, hi + 0.30 * span)
}

pub(crate) fn xrange(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = vals.fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
    let pad = 0.01 * (hi - lo).max(1e-9);
    (lo - pad, hi + pad)
}

pub(crate) type Chart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// The legend box of every plot.
pub(crate) fn legend<'a, DB: DrawingBackend + 'a>(chart: &mut Chart<'a, DB>) -> Result<()> {
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.5))
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|e| anyhow!("{e:?}"))?;
    Ok(())
}

pub(crate) fn safe(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// One line of a generic plot.
pub struct Line {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

fn line_chart<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    xl: &str,
    yl: &str,
    lines: &[Line],
    marks: bool,
) -> Result<()> {
    root.fill(&WHITE).map_err(|e| anyhow!("{e:?}"))?;
    let x = xrange(lines.iter().flat_map(|l| l.points.iter().map(|p| p.0)));
    let y = range(
        lines
            .iter()
            .flat_map(|l| l.points.iter().map(|p| p.1))
            .chain(std::iter::once(0.0)),
    );
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(50)
        .y_label_area_size(75)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
        .map_err(|e| anyhow!("{e:?}"))?;
    chart
        .configure_mesh()
        .x_desc(xl)
        .y_desc(yl)
        .x_label_formatter(&|v| {
            if (x.1 - x.0) > 20.0 {
                format!("{v:.0}")
            } else {
                format!("{v:.1}")
            }
        })
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .light_line_style(WHITE)
        .draw()
        .map_err(|e| anyhow!("{e:?}"))?;
    for (i, l) in lines.iter().enumerate() {
        let c = PALETTE[i % PALETTE.len()];
        chart
            .draw_series(LineSeries::new(l.points.clone(), c.stroke_width(2)))
            .map_err(|e| anyhow!("{e:?}"))?
            .label(l.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
        if marks {
            chart
                .draw_series(l.points.iter().map(|&p| Circle::new(p, 4, c.filled())))
                .map_err(|e| anyhow!("{e:?}"))?;
        }
    }
    legend(&mut chart)?;
    root.present().map_err(|e| anyhow!("{e:?}"))?;
    Ok(())
}

pub(crate) const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// Write a line plot as SVG and PNG; returns the two paths.
pub fn line_plot(
    stem: &Path,
    title: &str,
    xl: &str,
    yl: &str,
    lines: &[Line],
    marks: bool,
) -> Result<Vec<PathBuf>> {
    register_font();
    let size = (1200, 700);
    let svg = stem.with_extension("svg");
    line_chart(
        SVGBackend::new(&svg, size).into_drawing_area(),
        title,
        xl,
        yl,
        lines,
        marks,
    )
    .with_context(|| format!("drawing {}", svg.display()))?;
    let png = stem.with_extension("png");
    line_chart(
        BitMapBackend::new(&png, size).into_drawing_area(),
        title,
        xl,
        yl,
        lines,
        marks,
    )
    .with_context(|| format!("drawing {}", png.display()))?;
    Ok(vec![svg, png])
}

/// Print the plot files written (one line).
pub fn report(files: &[PathBuf]) {
    println!(
        "plots: {}",
        files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
}
