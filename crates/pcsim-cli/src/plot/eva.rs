//! The EVA figures (the paper's Figs. 4–7).

use anyhow::Result;
use std::path::{Path, PathBuf};

use super::{line_plot, Line, PALETTE};

/// The EVA figures in the style of the paper's Figs. 4–7, from the first damping of the sweep:
/// E(x) for several speeds and for several tensions (snapshots), E(d_e), and the EVA length
/// against speed and against tension.
pub fn draw_eva(
    dir: &Path,
    cases: &[(f64, f64, String, &pcsim_core::analysis::eva::EvaOutput)],
) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let Some(first) = cases.first() else {
        return Ok(files);
    };
    let damping = first.2.clone();
    let cs: Vec<_> = cases.iter().filter(|c| c.2 == damping).collect();
    let t0 = cs[0].1;
    let v0 = cs[0].0;
    // The paper's Figs. 4-5 show the neighbourhood of the pantograph: ±300 m at most.
    let density = |o: &pcsim_core::analysis::eva::EvaOutput| -> Vec<(f64, f64)> {
        o.xi_m
            .iter()
            .zip(&o.snapshot.density_j_per_m)
            .filter(|(x, _)| x.abs() <= 300.0)
            .map(|(&x, &e)| (x, e))
            .collect()
    };
    let by_speed: Vec<Line> = cs
        .iter()
        .filter(|c| c.1 == t0)
        .map(|c| Line {
            label: format!("{} km/h", c.0),
            points: density(c.3),
        })
        .collect();
    files.extend(line_plot(
        &dir.join("eva_density_speeds"),
        &format!("Energy density around the pantograph (snapshot), T = {t0} kN ({damping})"),
        "Position relative to the pantograph x − x_p [m]",
        "Energy density E(x) [J/m]",
        &by_speed,
        false,
    )?);
    let by_tension: Vec<Line> = cs
        .iter()
        .filter(|c| c.0 == v0)
        .map(|c| Line {
            label: format!("{} kN", c.1),
            points: density(c.3),
        })
        .collect();
    files.extend(line_plot(
        &dir.join("eva_density_tensions"),
        &format!("Energy density around the pantograph (snapshot), V = {v0} km/h ({damping})"),
        "Position relative to the pantograph x − x_p [m]",
        "Energy density E(x) [J/m]",
        &by_tension,
        false,
    )?);
    let windows: Vec<Line> = cs
        .iter()
        .take(PALETTE.len())
        .map(|c| Line {
            label: format!("{} km/h, {} kN", c.0, c.1),
            points: c
                .3
                .window_m
                .iter()
                .zip(&c.3.snapshot.window_j)
                .map(|(&d, &e)| (d, e))
                .collect(),
        })
        .collect();
    files.extend(line_plot(
        &dir.join("eva_window_energy"),
        &format!("Window energy E(d_e) (Eq. 21), {damping}"),
        "Window length d_e [m]",
        "Window energy E(d_e) [J]",
        &windows,
        false,
    )?);
    let mut tensions: Vec<f64> = cs.iter().map(|c| c.1).collect();
    tensions.dedup();
    tensions.sort_by(f64::total_cmp);
    tensions.dedup();
    let mut speeds: Vec<f64> = cs.iter().map(|c| c.0).collect();
    speeds.sort_by(f64::total_cmp);
    speeds.dedup();
    let eva_line = |pts: Vec<(f64, Option<f64>)>| -> Vec<(f64, f64)> {
        pts.into_iter()
            .filter_map(|(x, y)| y.map(|y| (x, y)))
            .collect()
    };
    if speeds.len() > 1 {
        let lines: Vec<Line> = tensions
            .iter()
            .take(PALETTE.len())
            .map(|&t| Line {
                label: format!("{t} kN"),
                points: eva_line(
                    cs.iter()
                        .filter(|c| c.1 == t)
                        .map(|c| (c.0, c.3.snapshot.eva_step_m))
                        .collect(),
                ),
            })
            .collect();
        files.extend(line_plot(
            &dir.join("eva_length_vs_speed"),
            &format!(
                "EVA length (step criterion, Δd = {} m) against speed, {damping}",
                first.3.settings.step_m
            ),
            "Speed [km/h]",
            "EVA length d_e [m]",
            &lines,
            true,
        )?);
    }
    if tensions.len() > 1 {
        let lines: Vec<Line> = speeds
            .iter()
            .take(PALETTE.len())
            .map(|&v| Line {
                label: format!("{v} km/h"),
                points: eva_line(
                    cs.iter()
                        .filter(|c| c.0 == v)
                        .map(|c| (c.1, c.3.snapshot.eva_step_m))
                        .collect(),
                ),
            })
            .collect();
        files.extend(line_plot(
            &dir.join("eva_length_vs_tension"),
            &format!(
                "EVA length (step criterion, Δd = {} m) against contact-wire tension, {damping}",
                first.3.settings.step_m
            ),
            "Contact-wire tension [kN]",
            "EVA length d_e [m]",
            &lines,
            true,
        )?);
    }
    Ok(files)
}
