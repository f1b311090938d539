//! The EVA figures (the paper's Figs. 4–7), drawn from a sweep's files (`eva.csv`,
//! `cases/*_distribution.csv`, `cases/*_window.csv`), so that a sweep, a merged sweep and `pcsim
//! plot DIR` draw the same: E(x) for several speeds and for several tensions (linear and
//! logarithmic), E(d_e) with each case's EVA marked by both criteria, and the EVA length against
//! speed and against tension with the step criterion's band over a span (issue 53, item 4).

use anyhow::{bail, Context, Result};
use pcsim_core::analysis::eva::EvaRow;
use std::path::{Path, PathBuf};

use super::{figure, Figure, Line, PALETTE};

/// One case of a sweep, as its files hold it.
struct Case {
    speed_kmh: f64,
    tension_kn: f64,
    damping: String,
    step_m: f64,
    fraction: f64,
    eva_step_m: Option<f64>,
    eva_fraction_m: Option<f64>,
    /// The step criterion's EVA over a span (issue 53, item 4): its least and its largest value
    /// (either empty where eva.csv has none: a sweep written before the band, or a position
    /// without a value).
    step_span_m: [Option<f64>; 2],
    xi_m: Vec<f64>,
    density: Vec<f64>,
    window_m: Vec<f64>,
    window_j: Vec<f64>,
}

fn read_columns(path: &Path, n: usize) -> Result<Vec<Vec<f64>>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut cols = vec![Vec::new(); n];
    for (i, line) in text.lines().enumerate().skip(1) {
        let v: Vec<f64> = line
            .split(',')
            .map(|s| s.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .with_context(|| format!("{} line {}: not numbers", path.display(), i + 1))?;
        if v.len() < n {
            bail!(
                "{} line {}: {} columns, need {n}",
                path.display(),
                i + 1,
                v.len()
            );
        }
        for (c, x) in cols.iter_mut().zip(v) {
            c.push(x);
        }
    }
    Ok(cols)
}

fn read_sweep(dir: &Path) -> Result<Vec<Case>> {
    let p = dir.join("eva.csv");
    let text =
        std::fs::read_to_string(&p).with_context(|| format!("cannot read {}", p.display()))?;
    let mut lines = text.lines();
    if lines.next() != Some(EvaRow::HEADER) {
        bail!("{} is not an eva.csv of this version of pcsim", p.display());
    }
    let cdir = dir.join("cases");
    let entries: Vec<String> = std::fs::read_dir(&cdir)
        .with_context(|| format!("cannot read {}", cdir.display()))?
        .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
        .collect();
    let mut cases = Vec::new();
    for l in lines.filter(|l| !l.is_empty()) {
        let f: Vec<&str> = l.split(',').collect();
        if f.len() < 15 {
            bail!("{}: bad row `{l}`", p.display());
        }
        let num = |i: usize| -> Result<f64> {
            f[i].parse()
                .with_context(|| format!("{}: column {i} of `{l}`", p.display()))
        };
        let opt = |i: usize| -> Option<f64> { f[i].parse().ok() };
        let index: usize = f[0]
            .parse()
            .with_context(|| format!("{}: `{l}`", p.display()))?;
        if f.get(15).is_some_and(|s| *s != "0") {
            continue; // another realisation of a Monte Carlo sweep (montecarlo.csv holds them)
        }
        let find = |suffix: &str| -> Result<PathBuf> {
            let prefix = format!("case{index:04}_");
            entries
                .iter()
                .find(|e| e.starts_with(&prefix) && e.ends_with(suffix))
                .map(|e| cdir.join(e))
                .with_context(|| format!("{} has no {prefix}…{suffix}", cdir.display()))
        };
        let d = read_columns(&find("_distribution.csv")?, 2)?;
        let w = read_columns(&find("_window.csv")?, 2)?;
        cases.push(Case {
            speed_kmh: num(1)?,
            tension_kn: num(2)?,
            damping: f[3].to_string(),
            step_m: num(4)?,
            fraction: num(6)?,
            eva_step_m: opt(7),
            eva_fraction_m: opt(8),
            step_span_m: [
                f.get(16).and_then(|s| s.parse().ok()),
                f.get(17).and_then(|s| s.parse().ok()),
            ],
            xi_m: d[0].clone(),
            density: d[1].clone(),
            window_m: w[0].clone(),
            window_j: w[1].clone(),
        });
    }
    if cases.is_empty() {
        bail!("{} has no cases: nothing to plot", p.display());
    }
    Ok(cases)
}

/// Energy at a window length (linear between the tabulated lengths).
fn energy_at(c: &Case, d: f64) -> Option<f64> {
    let i = c.window_m.iter().position(|&w| w >= d)?;
    if i == 0 {
        return c.window_j.first().copied();
    }
    let (w0, w1) = (c.window_m[i - 1], c.window_m[i]);
    let t = (d - w0) / (w1 - w0);
    Some(c.window_j[i - 1] + t * (c.window_j[i] - c.window_j[i - 1]))
}

/// Redraw the EVA figures of a sweep directory.
pub fn redraw(dir: &Path) -> Result<Vec<PathBuf>> {
    let all = read_sweep(dir)?;
    let damping = all[0].damping.clone();
    let cs: Vec<&Case> = all.iter().filter(|c| c.damping == damping).collect();
    let mut files = density_figures(dir, &cs, &damping)?;
    files.extend(window_energy_figure(dir, &cs, &damping)?);
    files.extend(length_figures(dir, &cs, &damping)?);
    Ok(files)
}

/// Figs. 4–5: the energy density around the pantograph (±300 m at most), by speed at the first
/// tension and by tension at the first speed, linear and logarithmic.
fn density_figures(dir: &Path, cs: &[&Case], damping: &str) -> Result<Vec<PathBuf>> {
    let (t0, v0) = (cs[0].tension_kn, cs[0].speed_kmh);
    let mut files = Vec::new();
    let density = |c: &Case| -> Vec<(f64, f64)> {
        c.xi_m
            .iter()
            .zip(&c.density)
            .filter(|(x, _)| x.abs() <= 300.0)
            .map(|(&x, &e)| (x, e))
            .collect()
    };
    let by_speed = |c: &Case| (c.tension_kn == t0).then(|| format!("{} km/h", c.speed_kmh));
    let by_tension = |c: &Case| (c.speed_kmh == v0).then(|| format!("{} kN", c.tension_kn));
    type Pick<'a> = (&'a str, String, &'a dyn Fn(&Case) -> Option<String>);
    let picks: [Pick; 2] = [
        (
            "eva_density_speeds",
            format!("Energy density around the pantograph (snapshot), T = {t0} kN ({damping})"),
            &by_speed,
        ),
        (
            "eva_density_tensions",
            format!("Energy density around the pantograph (snapshot), V = {v0} km/h ({damping})"),
            &by_tension,
        ),
    ];
    for (stem, title, pick) in picks {
        for log in [false, true] {
            let lines: Vec<Line> = cs
                .iter()
                .filter_map(|c| pick(c).map(|l| Line::new(l, density(c))))
                .take(PALETTE.len())
                .collect();
            files.extend(figure(
                &dir.join(if log {
                    format!("{stem}_log")
                } else {
                    stem.to_string()
                }),
                &Figure {
                    title: &title,
                    x_label: "Position relative to the pantograph x − x_p [m]",
                    y_label: "Energy density E(x) [J/m]",
                    lines,
                    log_y: log,
                    vmarks: vec![],
                    hmarks: vec![],
                },
            )?);
        }
    }
    Ok(files)
}

/// Fig. 6: E(d_e), each case's EVA marked by both criteria.
fn window_energy_figure(dir: &Path, cs: &[&Case], damping: &str) -> Result<Vec<PathBuf>> {
    let shown: Vec<&&Case> = cs.iter().take(PALETTE.len()).collect();
    let mut lines: Vec<Line> = shown
        .iter()
        .map(|c| {
            Line::new(
                format!("{} km/h, {} kN", c.speed_kmh, c.tension_kn),
                c.window_m
                    .iter()
                    .zip(&c.window_j)
                    .map(|(&d, &e)| (d, e))
                    .collect(),
            )
        })
        .collect();
    let step_pts: Vec<(f64, f64)> = shown
        .iter()
        .filter_map(|c| c.eva_step_m.and_then(|d| Some((d, energy_at(c, d)?))))
        .collect();
    let frac_pts: Vec<(f64, f64)> = shown
        .iter()
        .filter_map(|c| c.eva_fraction_m.and_then(|d| Some((d, energy_at(c, d)?))))
        .collect();
    lines.push(Line::dots(
        format!("EVA, step criterion (Δd = {} m)", cs[0].step_m),
        step_pts,
        plotters::style::RGBColor(0, 0, 0),
    ));
    lines.push(Line::dots(
        format!("EVA, {:.0} % of the total energy", 100.0 * cs[0].fraction),
        frac_pts,
        plotters::style::RGBColor(120, 120, 120),
    ));
    figure(
        &dir.join("eva_window_energy"),
        &Figure {
            title: &format!("Window energy E(d_e) (Eq. 21), {damping}"),
            x_label: "Window length d_e [m]",
            y_label: "Window energy E(d_e) [J]",
            lines,
            log_y: false,
            vmarks: vec![],
            hmarks: vec![],
        },
    )
}

/// Fig. 7: the EVA length against speed and against tension, both criteria.
fn length_figures(dir: &Path, cs: &[&Case], damping: &str) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let mut tensions: Vec<f64> = cs.iter().map(|c| c.tension_kn).collect();
    tensions.sort_by(f64::total_cmp);
    tensions.dedup();
    let mut speeds: Vec<f64> = cs.iter().map(|c| c.speed_kmh).collect();
    speeds.sort_by(f64::total_cmp);
    speeds.dedup();
    let axis = |groups: &[f64], by_speed: bool| -> Vec<Line> {
        let mut lines = Vec::new();
        for (k, &g) in groups.iter().take(PALETTE.len() / 2).enumerate() {
            let sel: Vec<&&Case> = cs
                .iter()
                .filter(|c| {
                    if by_speed {
                        c.tension_kn == g
                    } else {
                        c.speed_kmh == g
                    }
                })
                .collect();
            let x = |c: &Case| if by_speed { c.speed_kmh } else { c.tension_kn };
            let unit = if by_speed { "kN" } else { "km/h" };
            let colour = PALETTE[k % PALETTE.len()];
            lines.push(
                Line::new(
                    format!("{g} {unit}, step criterion"),
                    sel.iter()
                        .filter_map(|c| c.eva_step_m.map(|e| (x(c), e)))
                        .collect(),
                )
                .styled(colour, 2)
                .marked(),
            );
            // The step criterion's band over a span: its least and largest value, as dots.
            let band: Vec<(f64, f64)> = sel
                .iter()
                .flat_map(|c| c.step_span_m.iter().flatten().map(|&e| (x(c), e)))
                .collect();
            if !band.is_empty() {
                lines.push(Line::dots(
                    format!("{g} {unit}, step criterion over a span (least, largest)"),
                    band,
                    colour,
                ));
            }
            lines.push(
                Line::new(
                    format!("{g} {unit}, {:.0} %", 100.0 * cs[0].fraction),
                    sel.iter()
                        .filter_map(|c| c.eva_fraction_m.map(|e| (x(c), e)))
                        .collect(),
                )
                .styled(colour, 1)
                .marked(),
            );
        }
        lines
    };
    if speeds.len() > 1 {
        files.extend(figure(
            &dir.join("eva_length_vs_speed"),
            &Figure {
                title: &format!("EVA length against speed, {damping}"),
                x_label: "Speed [km/h]",
                y_label: "EVA length d_e [m]",
                lines: axis(&tensions, true),
                log_y: false,
                vmarks: vec![],
                hmarks: vec![],
            },
        )?);
    }
    if tensions.len() > 1 {
        files.extend(figure(
            &dir.join("eva_length_vs_tension"),
            &Figure {
                title: &format!("EVA length against contact-wire tension, {damping}"),
                x_label: "Contact-wire tension [kN]",
                y_label: "EVA length d_e [m]",
                lines: axis(&speeds, false),
                log_y: false,
                vmarks: vec![],
                hmarks: vec![],
            },
        )?);
    }
    Ok(files)
}
