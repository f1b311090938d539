//! Figures (plotters; SVG, and PNG with an embedded DejaVu Sans font so no system fonts are
//! needed), by figure family: `run.rs` (contact force and height along the track, the paper's
//! Fig. 3), `eva.rs` (energy distribution and EVA, Figs. 4–7), `realtime.rs` (the window against
//! the full model, Figs. 8–9). This file holds the house style they share.

pub mod compare;
pub mod design;
pub mod eva;
pub mod montecarlo;
pub mod realtime;
pub mod run;
pub mod sensitivity;
pub mod window;

use anyhow::{anyhow, Context, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

use pcsim_core::study::StudyKind;

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

/// The smallest and largest finite value (`(0, 1)` when there is none): a non-finite sample
/// never sets an axis (an infinite axis made the drawing spin forever).
fn finite_bounds(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = vals
        .filter(|v| v.is_finite())
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
    if lo > hi {
        (0.0, 1.0)
    } else {
        (lo, hi)
    }
}

/// Data range with a margin, and extra head-room at the top for the legend.
pub(crate) fn range(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = finite_bounds(vals);
    let span = (hi - lo).max(1e-9);
    (lo - 0.05 * span, hi + 0.30 * span)
}

pub(crate) fn xrange(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = finite_bounds(vals);
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

/// One line of a figure.
pub struct Line {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    /// Stroke width in pixels.
    pub width: u32,
    /// A colour of its own (otherwise the palette's next).
    pub colour: Option<RGBColor>,
    /// Mark every point with a dot.
    pub marks: bool,
}

impl Line {
    /// A plain line in the palette's next colour.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Line {
            label: label.into(),
            points,
            width: 2,
            colour: None,
            marks: false,
        }
    }

    /// The same line with a dot at every point.
    pub fn marked(mut self) -> Self {
        self.marks = true;
        self
    }

    /// Marks only, no line.
    pub fn dots(label: impl Into<String>, points: Vec<(f64, f64)>, colour: RGBColor) -> Self {
        Line {
            label: label.into(),
            points,
            width: 0,
            colour: Some(colour),
            marks: true,
        }
    }

    /// The same line in a given colour and width.
    pub fn styled(mut self, colour: RGBColor, width: u32) -> Self {
        self.colour = Some(colour);
        self.width = width;
        self
    }
}

/// A figure of lines against a common x axis.
pub struct Figure<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub lines: Vec<Line>,
    /// Logarithmic y axis (values ≤ 0 are left out).
    pub log_y: bool,
    /// Vertical marks: (x, label).
    pub vmarks: Vec<(f64, String)>,
    /// Horizontal reference lines: (y, label).
    pub hmarks: Vec<(f64, String)>,
}

/// The dash patterns the lines of a figure take in turn (dash, gap; `(0, 0)` solid), so that
/// series differ by more than colour and width, in print and in the legend.
const DASHES: [(u32, u32); 4] = [(0, 0), (14, 6), (4, 5), (24, 6)];

/// The figure with its y axis limited to `y_max`, for when a few values would squash the ones
/// that matter: the points above are not drawn, and a note inside the plot says how many, of
/// which series, and their range.
pub struct Clipped<'a> {
    /// The figure.
    pub figure: Figure<'a>,
    /// The y axis's upper end (linear axes).
    pub y_max: f64,
}

fn figure_chart<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    f: &Figure,
    y_max: Option<f64>,
) -> Result<()> {
    root.fill(&WHITE).map_err(|e| anyhow!("{e:?}"))?;
    let ty = |y: f64| if f.log_y { y.log10() } else { y };
    let keep = |y: f64| y.is_finite() && (!f.log_y || y > 0.0) && y_max.is_none_or(|m| y <= m);
    let outliers = outliers_of(f, y_max);
    let lines: Vec<Vec<(f64, f64)>> = f
        .lines
        .iter()
        .map(|l| {
            l.points
                .iter()
                .filter(|p| p.0.is_finite() && keep(p.1))
                .map(|&(x, y)| (x, ty(y)))
                .collect()
        })
        .collect();
    let xs = lines
        .iter()
        .flatten()
        .map(|p| p.0)
        .chain(f.vmarks.iter().map(|m| m.0));
    let x = xrange(xs);
    let ys: Vec<f64> = lines
        .iter()
        .flatten()
        .map(|p| p.1)
        .chain(f.hmarks.iter().filter(|m| keep(m.0)).map(|m| ty(m.0)))
        .chain((!f.log_y).then_some(0.0))
        .collect();
    if ys.is_empty() || !x.0.is_finite() {
        anyhow::bail!("nothing to draw in `{}`", f.title);
    }
    let y = match y_max {
        Some(m) => (range(ys.into_iter()).0, m),
        None => range(ys.into_iter()),
    };
    let mut chart = ChartBuilder::on(&root)
        .caption(f.title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
        .map_err(|e| anyhow!("{e:?}"))?;
    let log = f.log_y;
    chart
        .configure_mesh()
        .x_desc(f.x_label)
        .y_desc(f.y_label)
        .x_label_formatter(&|v| {
            if (x.1 - x.0) > 20.0 {
                format!("{v:.0}")
            } else {
                format!("{v:.1}")
            }
        })
        .y_label_formatter(&|v| {
            if log {
                format!("{:.0e}", 10f64.powf(*v))
            } else if (y.1 - y.0) > 20.0 {
                format!("{v:.0}")
            } else {
                format!("{v:.2}")
            }
        })
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .light_line_style(WHITE)
        .draw()
        .map_err(|e| anyhow!("{e:?}"))?;
    draw_marks(&mut chart, f, (x, y), &keep, &ty)?;
    draw_lines(&mut chart, f, lines)?;
    legend(&mut chart)?;
    note_outliers(&root, &outliers)?;
    root.present().map_err(|e| anyhow!("{e:?}"))?;
    Ok(())
}

/// What a linear axis topped at `y_max` leaves out, per series: (label, count, smallest,
/// largest).
fn outliers_of(f: &Figure, y_max: Option<f64>) -> Vec<(String, usize, f64, f64)> {
    match y_max {
        Some(m) => f
            .lines
            .iter()
            .filter_map(|l| {
                let v: Vec<f64> = l.points.iter().map(|p| p.1).filter(|&y| y > m).collect();
                (!v.is_empty()).then(|| {
                    let (lo, hi) = v
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| {
                            (a.min(y), b.max(y))
                        });
                    (l.label.clone(), v.len(), lo, hi)
                })
            })
            .collect(),
        None => Vec::new(),
    }
}

/// The vertical marks (the first eight in the legend) and the horizontal ones the axis holds.
fn draw_marks<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    f: &Figure,
    (x, y): ((f64, f64), (f64, f64)),
    keep: &dyn Fn(f64) -> bool,
    ty: &dyn Fn(f64) -> f64,
) -> Result<()> {
    for (k, (xm, label)) in f.vmarks.iter().enumerate() {
        let c = BLACK.mix(0.55);
        let series = chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(*xm, y.0), (*xm, y.1)],
                c.stroke_width(1),
            )))
            .map_err(|e| anyhow!("{e:?}"))?;
        if k < 8 {
            series
                .label(label.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x + 10, y - 6), (x + 10, y + 6)], c));
        }
    }
    for (ym, label) in &f.hmarks {
        if !keep(*ym) {
            continue;
        }
        let c = BLACK.mix(0.4);
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(x.0, ty(*ym)), (x.1, ty(*ym))],
                c.stroke_width(1),
            )))
            .map_err(|e| anyhow!("{e:?}"))?
            .label(label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
    }
    Ok(())
}

/// Every series: a line (solid or dashed by its index, with its points marked when asked), or
/// marks only (width 0: squares and triangles in turn).
fn draw_lines<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    f: &Figure,
    lines: Vec<Vec<(f64, f64)>>,
) -> Result<()> {
    for (i, (l, pts)) in f.lines.iter().zip(lines).enumerate() {
        let c = l.colour.unwrap_or(PALETTE[i % PALETTE.len()]);
        let w = l.width;
        let (dash, gap) = DASHES[i % DASHES.len()];
        let err = |e| anyhow!("{e:?}");
        if w == 0 {
            // Marks only: squares and triangles in turn (a circle marks the lines' points).
            if i % 2 == 0 {
                chart
                    .draw_series(pts.iter().map(|&p| {
                        EmptyElement::at(p) + Rectangle::new([(-5, -5), (5, 5)], c.filled())
                    }))
                    .map_err(err)?
                    .label(l.label.clone())
                    .legend(move |(x, y)| {
                        Rectangle::new([(x + 5, y - 5), (x + 15, y + 5)], c.filled())
                    });
            } else {
                chart
                    .draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 7, c.filled())))
                    .map_err(err)?
                    .label(l.label.clone())
                    .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 7, c.filled()));
            }
            continue;
        }
        let style = c.stroke_width(w);
        let series = if dash == 0 {
            chart.draw_series(LineSeries::new(pts.clone(), style))
        } else {
            chart.draw_series(DashedLineSeries::new(pts.clone(), dash, gap, style))
        };
        let marks = l.marks;
        series
            .map_err(err)?
            .label(l.label.clone())
            .legend(move |(x, y)| {
                let s = c.stroke_width(w.max(2));
                // A dot on the legend's line where the series marks its points.
                let dot = Circle::new((14, 0), 4, c.mix(if marks { 1.0 } else { 0.0 }).filled());
                // A solid line is one dash longer than the legend's line.
                let (d, g) = if dash == 0 { (1000, 1) } else { (dash, gap) };
                EmptyElement::at((x, y))
                    + plotters::element::DashedPathElement::new(vec![(0, 0), (28, 0)], d, g, s)
                    + dot
            });
        if l.marks {
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, c.filled())))
                .map_err(err)?;
        }
    }
    Ok(())
}

/// A note on the figure naming the points above a topped axis.
fn note_outliers<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    outliers: &[(String, usize, f64, f64)],
) -> Result<()> {
    if !outliers.is_empty() {
        let note = outliers
            .iter()
            .map(|(l, n, lo, hi)| {
                format!("{n} point(s) of \"{l}\" above the axis ({lo:.0}–{hi:.0})")
            })
            .collect::<Vec<_>>()
            .join("; ");
        root.draw(&Text::new(
            format!("Not shown: {note}"),
            (100, 44),
            ("sans-serif", 15).into_font().color(&BLACK.mix(0.8)),
        ))
        .map_err(|e| anyhow!("{e:?}"))?;
    }
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

/// Write a figure as `stem.svg` and `stem.png`; returns the two paths.
pub fn figure(stem: &Path, f: &Figure) -> Result<Vec<PathBuf>> {
    figure_with(stem, f, None)
}

/// [`figure`] with its y axis limited ([`Clipped`]).
pub fn clipped_figure(stem: &Path, c: &Clipped) -> Result<Vec<PathBuf>> {
    figure_with(stem, &c.figure, Some(c.y_max))
}

fn figure_with(stem: &Path, f: &Figure, y_max: Option<f64>) -> Result<Vec<PathBuf>> {
    register_font();
    let size = (1200, 700);
    let svg = stem.with_extension("svg");
    figure_chart(SVGBackend::new(&svg, size).into_drawing_area(), f, y_max)
        .with_context(|| format!("drawing {}", svg.display()))?;
    let png = stem.with_extension("png");
    figure_chart(BitMapBackend::new(&png, size).into_drawing_area(), f, y_max)
        .with_context(|| format!("drawing {}", png.display()))?;
    Ok(vec![svg, png])
}

/// Redraw the figures of a complete output directory from its files (its manifest says its
/// kind; an incomplete or foreign directory is refused), under the directory's lock, and list
/// the figures in its manifest.
pub fn redraw(dir: &Path) -> Result<Vec<PathBuf>> {
    let _lock = crate::output::Lock::take(dir)?;
    let m = crate::output::read_complete_manifest(dir)?;
    let files = redraw_kind(dir, m.kind)?;
    crate::output::add_to_manifest(dir, &files)?;
    Ok(files)
}

/// Redraw the figures of a directory of `kind` from its files (a command's own staging
/// directory, before it is committed): one arm per kind, matched exhaustively.
pub fn redraw_kind(dir: &Path, kind: StudyKind) -> Result<Vec<PathBuf>> {
    let mut files = match kind {
        StudyKind::Run => run::redraw(dir),
        StudyKind::Eva => eva::redraw(dir),
        StudyKind::Realtime => realtime::redraw(dir),
        StudyKind::MonteCarlo => montecarlo::redraw(dir),
        StudyKind::Window => window::redraw(dir),
        StudyKind::Compare => compare::redraw(dir),
        StudyKind::Design => design::redraw(dir),
        // Its figures are declared as data (below).
        StudyKind::Wear => Ok(Vec::new()),
        // A response declares its figures as data (below); one written before them has none.
        StudyKind::PantographFrf if dir.join("figures.json").is_file() => Ok(Vec::new()),
        StudyKind::PantographFrf | StudyKind::PantographFit => anyhow::bail!(
            "{}: a pantograph's fit draws its figures when it is made (and a response written before pcsim declared its figures); run `pcsim pantograph {}` again to redraw them",
            dir.display(),
            kind.name().trim_start_matches("pantograph-")
        ),
    }?;
    files.extend(declared(dir)?);
    Ok(files)
}

/// The figures a study declared as data (`figures.json`, read back through the core's
/// [`pcsim_core::study::Figure`]; none when the directory has no such file), each drawn as a
/// line chart: the same code for every study that declares its figures.
fn declared(dir: &Path) -> Result<Vec<PathBuf>> {
    let p = dir.join("figures.json");
    if !p.is_file() {
        return Ok(Vec::new());
    }
    let text =
        std::fs::read_to_string(&p).with_context(|| format!("cannot read {}", p.display()))?;
    let figures: Vec<pcsim_core::study::Figure> = serde_json::from_str(&text)
        .with_context(|| format!("{} is not pcsim's figures.json", p.display()))?;
    let dots = [
        RGBColor(200, 60, 40),
        RGBColor(40, 90, 200),
        RGBColor(30, 140, 60),
    ];
    let mut files = Vec::new();
    for f in &figures {
        let lines = (f.series.iter().enumerate())
            .map(|(k, s)| {
                let pts: Vec<(f64, f64)> = s.x.iter().copied().zip(s.y.iter().copied()).collect();
                if s.dots {
                    Line::dots(s.label.clone(), pts, dots[k % dots.len()])
                } else {
                    Line::new(s.label.clone(), pts)
                }
            })
            .collect();
        let fig = Figure {
            title: &f.title,
            x_label: &f.x_label,
            y_label: &f.y_label,
            lines,
            log_y: f.log_y,
            vmarks: Vec::new(),
            hmarks: Vec::new(),
        };
        files.extend(figure(&dir.join(safe(&f.name)), &fig)?);
    }
    Ok(files)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A figure whose axis is chosen by the values that matter names what it leaves out (issue 22,
    /// item 2): the series, how many points, their range; and its series differ by dash pattern.
    #[test]
    fn a_clipped_figure_notes_its_outliers_and_dashes_its_series() {
        let dir = std::env::temp_dir().join(format!("pcsim-clip-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let files = clipped_figure(
            &dir.join("f"),
            &Clipped {
                figure: Figure {
                    title: "t",
                    x_label: "x",
                    y_label: "y",
                    lines: vec![
                        Line::new("accuracy", vec![(150.0, 120.0), (222.0, 140.0)]),
                        Line::new("99 %", vec![(150.0, 780.0), (222.0, 1440.0)]),
                    ],
                    log_y: false,
                    vmarks: Vec::new(),
                    hmarks: Vec::new(),
                },
                y_max: 200.0,
            },
        )
        .unwrap();
        let svg = std::fs::read_to_string(&files[0]).unwrap();
        assert!(svg.contains("Not shown: 2 point(s) of"), "no note");
        assert!(
            svg.contains("99 %") && svg.contains("(780–1440)"),
            "the note names the series and range"
        );
        // The second series is dashed: many short segments where the first is one polyline.
        assert!(svg.matches("<polyline").count() > 10, "dashes");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
