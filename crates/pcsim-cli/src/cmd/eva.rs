//! `pcsim eva`: EVA sweeps over speed, tension and damping, in parallel, with shards and a merge
//! that refuses shards of different sweeps.

use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use pcsim_core::analysis::eva::{EvaOutput, EvaRow, EvaSettings};
use pcsim_core::analysis::sweep::{parse_damping, Job, Shard};
use pcsim_core::study::specs::{with_flags, EvaSweepSpec, GridSpec};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::common::{apply, shown, Ctx, Override};
use crate::output::{write_file, write_manifest};
use crate::sweep_dir::{merge, SweepKind};

#[derive(Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct EvaArgs {
    #[command(subcommand)]
    sub: Option<EvaSub>,
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name.
    #[arg(long)]
    preset: Option<String>,
    /// Speeds, comma-separated: km/h, or with a unit (250km/h). Default: the case's speed.
    #[arg(long, value_delimiter = ',', value_name = "KM/H")]
    speed: Vec<String>,
    /// Contact-wire tensions, comma-separated: kN, or with a unit (9.8kN, 9800N). Default: the
    /// case's tension.
    #[arg(long, value_delimiter = ',', value_name = "KN")]
    tension: Vec<String>,
    /// Dampings (comma-separated): `preset`, `rayleigh:ALPHA:BETA` or `modal:RATIO`.
    #[arg(long, value_delimiter = ',', default_value = "preset")]
    damping: Vec<String>,
    /// Output directory.
    #[arg(long, default_value = "out/eva")]
    out: PathBuf,
    /// Worker threads, at least 1 [default: all cores].
    #[arg(long)]
    jobs: Option<usize>,
    /// Run only the cases with index ≡ I (mod N), as `I/N`.
    #[arg(long)]
    shard: Option<String>,
    /// Step Δd between window lengths, m.
    #[arg(long, default_value_t = EvaSettings::default().step_m)]
    step: f64,
    /// Tolerance of the paper's criterion, J.
    #[arg(long, default_value_t = EvaSettings::default().tolerance_j)]
    tol: f64,
    /// Energy fraction of the step-independent criterion.
    #[arg(long, default_value_t = EvaSettings::default().fraction)]
    fraction: f64,
    /// Largest window length, m (default: the model length).
    #[arg(long)]
    max_window: Option<f64>,
    /// Snapshot position of the leading pantograph, m (default: mid-model).
    #[arg(long)]
    snapshot_at: Option<f64>,
    /// Positions across the snapshot's span at which the EVA is taken too (eva.csv's band,
    /// `*_span_min_m`, `*_span_max_m`; 0: none).
    #[arg(long, value_name = "N", default_value_t = EvaSettings::default().span_positions)]
    span_positions: usize,
    /// No figures.
    #[arg(long)]
    no_plot: bool,
    /// Also write report.html (the tables and every figure; not with --shard or --no-plot).
    #[arg(long)]
    report: bool,
    /// Monte Carlo: run every grid point for N realisations of the case's random inputs
    /// (irregularity, turbulent wind: seeds offset by 0..N) and write montecarlo.csv.
    #[arg(long, value_name = "N")]
    seeds: Option<usize>,
}

#[derive(Subcommand)]
enum EvaSub {
    /// Join the shards of one sweep (their eva.csv, case files and manifests) into one directory.
    Merge {
        /// Shard output directories: every shard of the sweep, once.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Merged output directory (not one of the shards).
        #[arg(long, default_value = "out/eva")]
        out: PathBuf,
        /// No figures.
        #[arg(long)]
        no_plot: bool,
    },
}

/// What the columns of `eva.csv` mean (written into the manifest).
const COLUMNS: &str = "lengths in m, energies in J; an EVA column is empty where its criterion was not reached within the largest window; *_max_m and *_mean_m are the EVA of the maximum over the passage and of the time average; *_span_min_m and *_span_max_m the smallest and largest snapshot EVA over the snapshot's span (eva.span_positions positions from its first support; *_span_max_m empty where a position has no value)";

fn case_stem(job: &Job) -> String {
    format!(
        "case{:04}_v{}_t{}",
        job.index,
        job.speed_kmh,
        job.tension_n / 1e3
    )
}

fn write_case_files(dir: &Path, job: &Job, o: &EvaOutput) -> Result<()> {
    let cdir = dir.join("cases");
    std::fs::create_dir_all(&cdir).with_context(|| format!("cannot create {}", cdir.display()))?;
    let mut s = String::from("xi_m,snapshot_j_per_m,max_j_per_m,mean_j_per_m\n");
    for i in 0..o.xi_m.len() {
        let _ = writeln!(
            s,
            "{:.4},{:.6e},{:.6e},{:.6e}",
            o.xi_m[i],
            o.snapshot.density_j_per_m[i],
            o.max.density_j_per_m[i],
            o.mean.density_j_per_m[i]
        );
    }
    write_file(
        &cdir.join(format!("{}_distribution.csv", case_stem(job))),
        s,
    )?;
    let mut s = String::from("window_m,snapshot_j,max_j,mean_j\n");
    for i in 0..o.window_m.len() {
        let _ = writeln!(
            s,
            "{},{:.6},{:.6},{:.6}",
            o.window_m[i], o.snapshot.window_j[i], o.max.window_j[i], o.mean.window_j[i]
        );
    }
    write_file(&cdir.join(format!("{}_window.csv", case_stem(job))), s)?;
    Ok(())
}

/// What the grid's flags were read as, for an error in a grid point.
fn grid_note(speed: &[String], tension: &[String]) -> String {
    let mut o: Vec<Override> = Vec::new();
    if !speed.is_empty() {
        o.push(Override {
            flag: format!("--speed {}", speed.join(",")),
            reading: "km/h unless a unit is given".into(),
            path: String::new(),
            value: 0.0,
        });
    }
    if !tension.is_empty() {
        o.push(Override {
            flag: format!("--tension {}", tension.join(",")),
            reading: "kN unless a unit is given; write 9800N for newtons".into(),
            path: String::new(),
            value: 0.0,
        });
    }
    format!("in the sweep (with {})", crate::common::override_note(&o))
}

/// The rows on the terminal.
fn print_rows(s: &EvaSettings, done: &[&EvaOutput], rows: &[&EvaRow]) {
    let span = done.first().map_or(String::new(), |d| {
        match (d.span_positions_m.first(), d.span_positions_m.last()) {
            (Some(a), Some(b)) => format!(
                "; over the span, the snapshot at {} positions from {a:.1} to {b:.1} m",
                d.span_positions_m.len()
            ),
            _ => String::new(),
        }
    });
    println!(
        "EVA (Δd = {} m, tolerance {} J, fraction {}), snapshot at {} m{span}; window energies in J",
        s.step_m,
        s.tolerance_j,
        s.fraction,
        done.first().map(|d| d.snapshot_at_m).unwrap_or(0.0)
    );
    println!(
        "{:>6} {:>8} {:<22} {:>12} {:>17} {:>12} {:>14} {:>12}",
        "km/h",
        "kN",
        "damping",
        "EVA step [m]",
        "over the span [m]",
        "EVA 99% [m]",
        "converged [J]",
        "total [J]"
    );
    for r in rows {
        let f = |v: Option<f64>| {
            v.map(|x| format!("{x:.1}"))
                .unwrap_or_else(|| "not reached".into())
        };
        let band = match (r.eva_step_span_min_m, r.eva_step_span_max_m) {
            (Some(a), Some(b)) => format!("{a:.1}–{b:.1}"),
            (Some(a), None) => format!("{a:.1}–?"),
            _ => "—".into(),
        };
        println!(
            "{:>6} {:>8} {:<22} {:>12} {:>17} {:>12} {:>14} {:>12.3}",
            r.speed_kmh,
            r.tension_kn,
            r.damping,
            f(r.eva_step_m),
            band,
            f(r.eva_fraction_m),
            f(r.converged_energy_j),
            r.total_energy_j
        );
    }
}

/// The eva sweep directory.
pub const EVA: SweepKind = SweepKind {
    kind: pcsim_core::study::StudyKind::Eva,
    csv: "eva.csv",
    header: EvaRow::HEADER,
    columns: COLUMNS,
    finish: |dir| {
        crate::sweep_dir::write_montecarlo(
            dir,
            "eva.csv",
            &["speed_kmh", "tension_kn", "damping"],
            &[
                "eva_step_m",
                "eva_fraction_m",
                "eva_step_max_m",
                "eva_fraction_max_m",
            ],
        )
    },
};

/// The flags as the core's spec, which holds the defaults, the checks and the fingerprint; every
/// grid point is checked up front, with the flags named on error.
fn spec_of(a: &EvaArgs, base: &pcsim_core::Case, ctx: &Ctx) -> Result<(EvaSweepSpec, Shard)> {
    let dampings = a
        .damping
        .iter()
        .map(|d| parse_damping(d, &base.catenary.damping))
        .collect::<Result<Vec<_>, _>>()?;
    let (speeds, tensions, shard) =
        crate::common::sweep_flags(&a.speed, &a.tension, a.jobs, a.shard.as_deref())?;
    // The flags become the core's spec, which holds the defaults, the checks and the fingerprint.
    let spec = EvaSweepSpec {
        grid: GridSpec {
            speeds_kmh: speeds,
            tensions_n: tensions,
            dampings,
            seeds: crate::common::seeds_flag(a.seeds, base)?,
            shard,
        },
        settings: EvaSettings {
            step_m: a.step,
            max_window_m: a.max_window,
            tolerance_j: a.tol,
            fraction: a.fraction,
            snapshot_at_m: a.snapshot_at,
            span_positions: a.span_positions,
            budget: ctx.budget,
            ..EvaSettings::default()
        },
    };
    spec.check()
        .map_err(|e| with_flags(e, &EvaSweepSpec::FLAGS))?;
    Ok((spec, shard))
}

pub fn eva(a: EvaArgs, ctx: &Ctx) -> Result<i32> {
    if let Some(EvaSub::Merge { dirs, out, no_plot }) = a.sub {
        return merge(&EVA, &dirs, &out, no_plot);
    }
    let (base, case_text) =
        crate::common::load_case_with_text(a.case.as_ref(), a.preset.as_deref())?;
    let base = apply(&base, &[])?;
    let (spec, shard) = spec_of(&a, &base, ctx)?;
    let (jobs, mine) = spec
        .grid
        .jobs(&base)
        .with_context(|| grid_note(&a.speed, &a.tension))?;
    let fingerprint = spec.fingerprint(&base);
    let (od, pb) = crate::sweep_dir::begin(&a.out, &case_text, "eva", mine.len(), ctx)?;
    let dir = od.path();
    let results = spec.run(&mine, &ctx.budget, a.jobs, &|| pb.inc());
    pb.finish();
    let results = results?;
    for c in &results {
        write_case_files(dir, &c.job, &c.output)?;
    }
    let done: Vec<&EvaOutput> = results.iter().map(|c| &c.output).collect();
    let rows: Vec<&EvaRow> = results.iter().map(|c| &c.row).collect();
    let csv = crate::sweep_dir::rows_csv(EvaRow::HEADER, rows.iter().map(|r| r.to_csv()));
    write_file(&dir.join("eva.csv"), &csv)?;
    if shard == Shard::ALL {
        (EVA.finish)(dir)?;
    }
    write_manifest(
        dir,
        "eva",
        crate::sweep_dir::shard_manifest(
            &fingerprint,
            jobs.len(),
            shard,
            mine.iter().map(|j| j.index).collect(),
            COLUMNS,
        ),
    )?;
    let files = if !a.no_plot && shard == Shard::ALL && !mine.is_empty() {
        od.in_target(&crate::plot::redraw_kind(
            dir,
            pcsim_core::study::StudyKind::Eva,
        )?)
    } else {
        Vec::new()
    };
    od.commit()?;
    if a.report && shard == Shard::ALL && !mine.is_empty() {
        println!("report: {}", crate::report::write(&a.out)?.display());
    }
    if mine.is_empty() {
        println!(
            "shard {}/{} holds none of the {} cases: wrote {} (header only) and {}, which `eva merge` needs",
            shard.index,
            shard.count,
            jobs.len(),
            shown(&a.out, "eva.csv"),
            shown(&a.out, "pcsim.json")
        );
        return Ok(0);
    }
    print_rows(&spec.settings, &done, &rows);
    println!(
        "wrote {} and {}",
        shown(&a.out, "eva.csv"),
        shown(&a.out, "cases")
    );
    if !files.is_empty() {
        crate::plot::report(&files);
    }
    Ok(0)
}
