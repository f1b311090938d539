//! The sensitivity figure of a run with `--sensitivity` (issue 42, item 2): per pantograph, the
//! ranged values that move the contact force's standard deviation most, each a bar from the
//! statistic with the value at its low end to the statistic at its high end, the case's own
//! value a vertical line (a "tornado" chart). Drawn from `summary.json`'s `sensitivity`, read
//! back through the core's `RunSummary`.

use anyhow::{anyhow, Context, Result};
use pcsim_core::analysis::report::RunSummary;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

use super::{register_font, safe, COLOURS};

/// The most movers a figure shows.
const MOST: usize = 12;

/// One bar: the value's path, the statistic at the low and the high end.
struct Bar {
    path: String,
    at_low: f64,
    at_high: f64,
}

fn chart<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    value: f64,
    bars: &[Bar],
) -> Result<()> {
    let err = |e| anyhow!("{e:?}");
    root.fill(&WHITE).map_err(err)?;
    let (mut lo, mut hi) = (value, value);
    for b in bars {
        lo = lo.min(b.at_low.min(b.at_high));
        hi = hi.max(b.at_low.max(b.at_high));
    }
    let pad = 0.08 * (hi - lo).max(1e-9);
    let n = bars.len().max(1) as f64;
    let mut c = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(10)
        .build_cartesian_2d((lo - pad)..(hi + pad), 0.0..n)
        .map_err(err)?;
    c.configure_mesh()
        .disable_y_mesh()
        .disable_y_axis()
        .x_desc("standard deviation of the contact force [N]: the value at its range's low end (blue) and high end (red)")
        .draw()
        .map_err(err)?;
    for (k, b) in bars.iter().enumerate() {
        let y = n - k as f64 - 0.5;
        for (x, colour) in [(b.at_low, COLOURS[0]), (b.at_high, COLOURS[1])] {
            c.draw_series(std::iter::once(Rectangle::new(
                [(value.min(x), y - 0.3), (value.max(x), y + 0.3)],
                colour.mix(0.7).filled(),
            )))
            .map_err(err)?;
        }
        c.draw_series(std::iter::once(Text::new(
            format!("{}  ({:+.3} N)", b.path, b.at_high - b.at_low),
            (lo - 0.9 * pad, y + 0.45),
            ("sans-serif", 15),
        )))
        .map_err(err)?;
    }
    c.draw_series(std::iter::once(PathElement::new(
        vec![(value, 0.0), (value, n)],
        BLACK.stroke_width(2),
    )))
    .map_err(err)?;
    root.present().map_err(err)
}

/// The figures of `summary` (a run's `summary.json`) into `dir`: none without a sensitivity.
pub fn draw(dir: &Path, summary: &RunSummary) -> Result<Vec<PathBuf>> {
    register_font();
    let mut files = Vec::new();
    let Some(s) = &summary.sensitivity else {
        return Ok(files);
    };
    for p in &s.pantographs {
        let name = p.name.as_str();
        let Some(band) = p.statistics.iter().find(|b| b.statistic == "std_n") else {
            continue;
        };
        let bars: Vec<Bar> = (band.movers.iter().take(MOST))
            .filter_map(|m| {
                Some(Bar {
                    path: m.path.clone(),
                    at_low: m.at_low.filter(|v| v.is_finite())?,
                    at_high: m.at_high.filter(|v| v.is_finite())?,
                })
            })
            .collect();
        let title = format!(
            "{}: what moves σ of {name} (band {:.2}–{:.2} N over every run)",
            summary.case_name, band.low, band.high
        );
        let size = (1400, 120 + 48 * bars.len().max(1) as u32);
        let stem = dir.join(format!("sensitivity_{}", safe(name)));
        let svg = stem.with_extension("svg");
        chart(
            SVGBackend::new(&svg, size).into_drawing_area(),
            &title,
            band.value,
            &bars,
        )
        .with_context(|| format!("drawing {}", svg.display()))?;
        let png = stem.with_extension("png");
        chart(
            BitMapBackend::new(&png, size).into_drawing_area(),
            &title,
            band.value,
            &bars,
        )
        .with_context(|| format!("drawing {}", png.display()))?;
        files.extend([svg, png]);
    }
    Ok(files)
}
