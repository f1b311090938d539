//! `pcsim hil`: replay a contact-force/position file through the real-time catenary (the Rust
//! reference the FMU is tested against).

use anyhow::{bail, Context, Result};
use clap::Args;
use pcsim_core::solve::realtime::{Coupling, RealtimeCatenary};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct HilArgs {
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name.
    #[arg(long)]
    preset: Option<String>,
    /// Window length, m.
    #[arg(long, default_value_t = 215.0)]
    window: f64,
    /// Input CSV: time_s, contact_force_n, pantograph_position_m (relative to the case's start),
    /// one row per internal step; each row is held over its step.
    #[arg(long)]
    input: PathBuf,
    /// Output CSV: time_s, wire_height_m, wire_velocity_m_s, contact_force_n after each step.
    #[arg(long)]
    out: PathBuf,
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

pub fn hil(a: HilArgs) -> Result<i32> {
    let mut case = crate::common::load_case(a.case.as_ref(), a.preset.as_deref())?;
    case.pantographs.truncate(1);
    let rows = read_input(&a.input)?;
    let mut rt = RealtimeCatenary::new(&case, a.window, Coupling::Hil)?;
    let x0 = case.run.start_m;
    let mut s = String::from("time_s,wire_height_m,wire_velocity_m_s,contact_force_n\n");
    for r in &rows {
        rt.set_input(r[1], x0 + r[2]);
        let o = rt.step();
        let _ = writeln!(
            s,
            "{:.9},{:.12e},{:.12e},{:.12e}",
            r[0] + rt.dt_s(),
            o.wire_height_m,
            o.wire_velocity_m_s,
            o.contact_force_n
        );
    }
    std::fs::write(&a.out, s).with_context(|| format!("cannot write {}", a.out.display()))?;
    println!(
        "replayed {} steps through a {} m window; wrote {}",
        rows.len(),
        a.window,
        a.out.display()
    );
    Ok(0)
}
