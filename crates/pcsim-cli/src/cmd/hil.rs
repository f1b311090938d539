//! `pcsim hil`: replay a contact-force/position file through the core's real-time session (the
//! Rust reference the FMU and the C API are tested against). The time column must advance by the
//! case's Δt; every row goes through the session's step contract, and a row it refuses (or rolls
//! back) is written with its status and reason instead of a height. Any such row makes the
//! command an error (exit status 2) after the file is written.

use anyhow::{bail, Context, Result};
use clap::Args;
use pcsim_core::session::{Coupling, RealtimeSession, DEFAULT_MAX_SPEED_KMH};
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
    /// Input CSV with a header and the columns time_s, contact_force_n, position_from_start_m
    /// (relative to the case's start), one row per internal step Δt; each row is held over its
    /// step.
    #[arg(long)]
    input: PathBuf,
    /// Output CSV: time_s, wire_height_m, wire_velocity_m_s, contact_force_n after each step (in
    /// their shortest round-trip form: they read back bit for bit), and its status (`ok`, or the code of the reason it was refused or rolled back).
    #[arg(long)]
    out: PathBuf,
    /// The pantograph the window follows (the rig's): leading, trailing, a name or an index
    /// (sets the case's run.window_pantograph; default: the case's, else the leading one).
    #[arg(long, value_name = "NAME")]
    pantograph: Option<String>,
    /// Fastest plausible pantograph, km/h: a position that moves faster between two rows is
    /// refused.
    #[arg(long, default_value_t = DEFAULT_MAX_SPEED_KMH)]
    max_speed_kmh: f64,
}

/// The header an input file must start with (the columns, in this order).
pub const INPUT_HEADER: &str = "time_s,contact_force_n,position_from_start_m";

fn read_input(p: &Path) -> Result<Vec<[f64; 3]>> {
    let text =
        crate::common::read_input(p).with_context(|| format!("cannot read {}", p.display()))?;
    let mut lines = text.lines();
    let header = lines.next().with_context(|| {
        format!(
            "{} is empty: need the header `{INPUT_HEADER}` and one row per step",
            p.display()
        )
    })?;
    let cols: Vec<&str> = header.split(',').map(|c| c.trim()).collect();
    if cols != INPUT_HEADER.split(',').collect::<Vec<_>>() {
        bail!(
            "{} line 1: the header is `{}`, but an input must start with `{INPUT_HEADER}` (time in s, contact force in N, position in m from the case's start)",
            p.display(),
            header.trim()
        );
    }
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
        // A non-finite force or position is the step contract's to refuse; the time must be read.
        if v.len() != 3 || !v[0].is_finite() {
            bail!("{} line {}: need three numbers (time_s, contact_force_n, position_from_start_m) with a finite time", p.display(), i + 1);
        }
        rows.push([v[0], v[1], v[2]]);
    }
    if rows.is_empty() {
        bail!(
            "{} has a header but no rows: nothing to replay",
            p.display()
        );
    }
    Ok(rows)
}

pub fn hil(a: HilArgs, ctx: &Ctx) -> Result<i32> {
    let case = crate::common::load_case(a.case.as_ref(), a.preset.as_deref())?;
    let case = crate::common::window_pantograph(case, a.pantograph.as_deref());
    if !(a.max_speed_kmh.is_finite() && a.max_speed_kmh > 0.0) {
        bail!(
            "--max-speed-kmh {}: must be a finite speed > 0",
            a.max_speed_kmh
        );
    }
    let window = length("--window", &a.window)?;
    let rows = read_input(&a.input)?;
    let mut rt = RealtimeSession::with_budget(&case, window, Coupling::Hil, &ctx.budget)?;
    rt.set_max_speed_kmh(a.max_speed_kmh)?;
    let dt = rt.dt_s();
    let x0 = rt.start_position_m();
    let mut s = String::from("time_s,wire_height_m,wire_velocity_m_s,contact_force_n,status\n");
    let t0 = rows.first().map_or(0.0, |r| r[0]);
    let mut refused: Vec<(usize, String)> = Vec::new();
    let pb = crate::progress::Progress::new(
        "hil",
        rows.len() as u64,
        ctx.progress,
        "hil [{bar:40}] {pos}/{len} steps {elapsed_precise} eta {eta}",
    );
    for (k, r) in rows.iter().enumerate() {
        if k % 1024 == 0 {
            pb.set(k as u64);
        }
        let line = k + 2;
        let want = t0 + k as f64 * dt;
        if (r[0] - want).abs() > 1e-6 * dt + 1e-9 * want.abs() {
            bail!(
                "{} line {line}: time {} s, but rows must advance by the case's Δt = {dt} s (expected {want} s)",
                a.input.display(),
                r[0]
            );
        }
        match rt.step(r[1], x0 + r[2]) {
            Ok(o) => {
                let _ = writeln!(
                    s,
                    "{:.9},{:?},{:?},{:?},ok",
                    r[0] + dt,
                    o.wire_height_m,
                    o.wire_velocity_m_s,
                    o.contact_force_n
                );
            }
            Err(e) => {
                let _ = writeln!(s, "{:.9},,,,{}", r[0] + dt, e.code());
                refused.push((line, e.to_string()));
            }
        }
    }
    pb.finish();
    crate::output::write_file_atomic(&a.out, s)?;
    println!(
        "replayed {} steps through a {window} m window; wrote {}",
        rows.len() - refused.len(),
        a.out.display()
    );
    if let Some((line, why)) = refused.first() {
        bail!(
            "{} of {} rows were not stepped (their status is in {}); the first, {} line {line}: {why}",
            refused.len(),
            rows.len(),
            a.out.display(),
            a.input.display()
        );
    }
    Ok(0)
}
