//! `pcsim hil`: replay a contact-force/position file through the real-time catenary (the Rust
//! reference the FMU is tested against). The input is checked: the time column must advance by
//! the case's Δt, and every position must lie inside the modelled catenary and move no faster
//! than a plausible speed.

use anyhow::{bail, Context, Result};
use clap::Args;
use pcsim_core::solve::realtime::{Coupling, RealtimeCatenary, DEFAULT_MAX_SPEED_KMH};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::common::{length, Ctx};

#[derive(Args)]
pub struct HilArgs {
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name.
    #[arg(long)]
    preset: Option<String>,
    /// Window length: m, or with a unit [default: 215 m].
    #[arg(long, value_name = "M", default_value = "215")]
    window: String,
    /// Input CSV with a header and the columns time_s, contact_force_n, pantograph_position_m
    /// (relative to the case's start), one row per internal step Δt; each row is held over its
    /// step.
    #[arg(long)]
    input: PathBuf,
    /// Output CSV: time_s, wire_height_m, wire_velocity_m_s, contact_force_n after each step.
    #[arg(long)]
    out: PathBuf,
    /// Fastest plausible pantograph, km/h: a position that moves faster between two rows is
    /// refused.
    #[arg(long, default_value_t = DEFAULT_MAX_SPEED_KMH)]
    max_speed_kmh: f64,
}

fn read_input(p: &Path) -> Result<Vec<[f64; 3]>> {
    let text =
        std::fs::read_to_string(p).with_context(|| format!("cannot read {}", p.display()))?;
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let v: Vec<f64> = line
            .split(',')
            .map(|s| s.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .with_context(|| format!("{} line {}: not three numbers", p.display(), i + 1))?;
        if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
            bail!("{} line {}: need three finite numbers (time_s, contact_force_n, pantograph_position_m)", p.display(), i + 1);
        }
        rows.push([v[0], v[1], v[2]]);
    }
    Ok(rows)
}

pub fn hil(a: HilArgs, ctx: &Ctx) -> Result<i32> {
    let mut case = crate::common::load_case(a.case.as_ref(), a.preset.as_deref())?;
    case.pantographs.truncate(1);
    if !(a.max_speed_kmh.is_finite() && a.max_speed_kmh > 0.0) {
        bail!(
            "--max-speed-kmh {}: must be a finite speed > 0",
            a.max_speed_kmh
        );
    }
    let window = length("--window", &a.window)?;
    let rows = read_input(&a.input)?;
    crate::common::setup(&case, &[], ctx)?;
    let mut rt = RealtimeCatenary::new(&case, window, Coupling::Hil)?;
    rt.set_max_speed_kmh(a.max_speed_kmh);
    let dt = rt.dt_s();
    let x0 = case.run.start_m;
    let mut s = String::from("time_s,wire_height_m,wire_velocity_m_s,contact_force_n\n");
    let t0 = rows.first().map_or(0.0, |r| r[0]);
    for (k, r) in rows.iter().enumerate() {
        let line = k + 2;
        let want = t0 + k as f64 * dt;
        if (r[0] - want).abs() > 1e-6 * dt + 1e-9 * want.abs() {
            bail!(
                "{} line {line}: time {} s, but rows must advance by the case's Δt = {dt} s (expected {want} s)",
                a.input.display(),
                r[0]
            );
        }
        let x = x0 + r[2];
        let elapsed = if k == 0 { f64::INFINITY } else { dt };
        rt.check_input(r[1], x, elapsed)
            .map_err(|e| anyhow::anyhow!("{} line {line}: {e}", a.input.display()))?;
        rt.set_input(r[1], x);
        let o = rt.step();
        let _ = writeln!(
            s,
            "{:.9},{:.12e},{:.12e},{:.12e}",
            r[0] + dt,
            o.wire_height_m,
            o.wire_velocity_m_s,
            o.contact_force_n
        );
    }
    std::fs::write(&a.out, s).with_context(|| format!("cannot write {}", a.out.display()))?;
    println!(
        "replayed {} steps through a {window} m window; wrote {}",
        rows.len(),
        a.out.display()
    );
    Ok(0)
}
