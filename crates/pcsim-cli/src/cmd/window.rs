//! `pcsim window`: the accuracy-based length of the real-time window over a grid of speeds and
//! tensions (issue 13), beside the energy-based EVA lengths and the energy criterion that
//! predicts it best. Runs on the sweep engine: jobs, shards, merge, fingerprints, seeds.

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use pcsim_core::analysis::sweep::Shard;
use pcsim_core::study::specs::{with_flags, GridSpec, WindowSweepSpec};
use pcsim_core::study::sweeps::WindowRow;
use pcsim_core::study::window_search::{fit_criteria, EnergyCurves, Tolerances};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::common::{apply, shown, Ctx};
use crate::output::{write_file, write_manifest};
use crate::sweep_dir::{merge, write_montecarlo, SweepKind};

#[derive(Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct WindowArgs {
    #[command(subcommand)]
    sub: Option<WindowSub>,
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name.
    #[arg(long)]
    preset: Option<String>,
    /// The pantograph the window follows (the rig's): leading, trailing, a name or an index
    /// (sets the case's run.window_pantograph; default: the case's, else the leading one).
    #[arg(long, value_name = "NAME")]
    pantograph: Option<String>,
    /// Speeds, comma-separated: km/h, or with a unit. Default: the case's speed.
    #[arg(long, value_delimiter = ',', value_name = "KM/H")]
    speed: Vec<String>,
    /// Contact-wire tensions, comma-separated: kN, or with a unit. Default: the case's.
    #[arg(long, value_delimiter = ',', value_name = "KN")]
    tension: Vec<String>,
    /// Tolerance on the mean of the 0–20 Hz force against the full model, % (`1%` or `1`).
    #[arg(long, default_value = "1%", value_name = "PCT")]
    mean_tol: String,
    /// Tolerance on σ of the 0–20 Hz force, %.
    #[arg(long, default_value = "3%", value_name = "PCT")]
    sigma_tol: String,
    /// Tolerance on the actual maximum of the 0–20 Hz force, %.
    #[arg(long, default_value = "5%", value_name = "PCT")]
    max_tol: String,
    /// Shortest window searched, m [default: half a span].
    #[arg(long, value_name = "M")]
    min_window: Option<String>,
    /// Longest window searched, m: the length found matches, and so does every longer window at
    /// the resolution up to this one (with --coarse-only, every longer window the search ran:
    /// printed with the answer) [default: 400 m].
    #[arg(long, value_name = "M")]
    max_window: Option<String>,
    /// Step of the coarse scan (--coarse-only), m.
    #[arg(long, default_value = "20", value_name = "M")]
    coarse: String,
    /// Resolution of the search, m.
    #[arg(long, default_value = "1", value_name = "M")]
    resolution: String,
    /// The quick answer: a coarse scan from --max-window down, refined below the lowest coarse
    /// window that matches. The windows between the coarse points above it are not run, so a
    /// longer window may fail (the output names them). By default every window at the
    /// resolution from --max-window down to the first that fails is run: the length found is
    /// the shortest with every longer window matching (about (max − length)/resolution windows
    /// per case, against about 20).
    #[arg(long, conflicts_with = "full_scan")]
    coarse_only: bool,
    /// The default search (every window at the resolution from --max-window down to the first
    /// that fails); kept for scripts written when it was not the default.
    #[arg(long)]
    full_scan: bool,
    /// Output directory.
    #[arg(long, default_value = "out/window")]
    out: PathBuf,
    /// Worker threads, at least 1 [default: all cores].
    #[arg(long)]
    jobs: Option<usize>,
    /// Run only the cases with index ≡ I (mod N), as `I/N`.
    #[arg(long)]
    shard: Option<String>,
    /// Monte Carlo: N realisations of the case's random inputs per grid point.
    #[arg(long, value_name = "N")]
    seeds: Option<usize>,
    /// No figures.
    #[arg(long)]
    no_plot: bool,
    /// Also write report.html (the tables and every figure).
    #[arg(long)]
    report: bool,
}

#[derive(Subcommand)]
enum WindowSub {
    /// Join the shards of one window sweep into one directory (and fit the criteria again).
    Merge {
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        #[arg(long, default_value = "out/window")]
        out: PathBuf,
        #[arg(long)]
        no_plot: bool,
    },
}

/// The header of `window.csv` (the core's row).
pub const HEADER: &str = WindowRow::HEADER;

const COLUMNS: &str = "length_m: the accuracy-based window length (empty: not reached within --max-window); *_err_pct: the errors of that window against the full model; eva_*: the energy-based lengths of `pcsim eva` (snapshot, maximum over the passage, time average; step criterion Δd = 1 m, 0.01 J; fraction 0.99); *_total_j: the energies the fraction criteria refer to; fine_checked_to_m: every window at the resolution from length_m up to this length was run and matches (above it the coarse windows only, up to --max-window; --max-window itself with --full-scan)";

/// The window sweep directory.
pub const WINDOW: SweepKind = SweepKind {
    kind: pcsim_core::study::StudyKind::Window,
    csv: "window.csv",
    header: HEADER,
    columns: COLUMNS,
    finish,
};

fn stem(job_index: usize, speed: f64, tension_kn: f64) -> String {
    format!("case{job_index:04}_v{speed}_t{tension_kn}")
}

/// A percentage flag (`3%` or `3`); its range is the core's to check (`Tolerances::check`).
pub(crate) fn pct(flag: &str, s: &str) -> Result<f64> {
    let t = s.trim().trim_end_matches('%').trim();
    t.parse()
        .map_err(|_| anyhow::anyhow!("{flag} `{s}`: give a percentage, e.g. 3% or 3"))
}

pub(crate) fn metres(flag: &str, s: &str) -> Result<f64> {
    crate::common::length(flag, s)
}

/// The flags as the core's spec, which holds the defaults, the checks and the fingerprint.
fn spec_of(a: &WindowArgs, base: &pcsim_core::Case) -> Result<(WindowSweepSpec, Shard)> {
    let (speeds, tensions, shard) =
        crate::common::sweep_flags(&a.speed, &a.tension, a.jobs, a.shard.as_deref())?;
    // The flags become the core's spec, which holds the defaults, the checks and the fingerprint.
    let d = WindowSweepSpec::default();
    let spec = WindowSweepSpec {
        grid: GridSpec {
            speeds_kmh: speeds,
            tensions_n: tensions,
            dampings: Vec::new(),
            seeds: crate::common::seeds_flag(a.seeds, base)?,
            shard,
        },
        tolerances: Tolerances {
            mean_pct: pct("--mean-tol", &a.mean_tol)?,
            sigma_pct: pct("--sigma-tol", &a.sigma_tol)?,
            max_pct: pct("--max-tol", &a.max_tol)?,
        },
        min_window_m: a
            .min_window
            .as_deref()
            .map(|s| metres("--min-window", s))
            .transpose()?,
        max_window_m: match &a.max_window {
            Some(s) => metres("--max-window", s)?,
            None => d.max_window_m,
        },
        coarse_m: metres("--coarse", &a.coarse)?,
        resolution_m: metres("--resolution", &a.resolution)?,
        coarse_only: a.coarse_only,
    };
    spec.check(base)
        .map_err(|e| with_flags(e, &WindowSweepSpec::FLAGS))?;
    Ok((spec, shard))
}

pub fn window(a: WindowArgs, ctx: &Ctx) -> Result<i32> {
    if let Some(WindowSub::Merge { dirs, out, no_plot }) = a.sub {
        return merge(&WINDOW, &dirs, &out, no_plot);
    }
    let (base, case_text) =
        crate::common::load_case_with_text(a.case.as_ref(), a.preset.as_deref())?;
    let base = crate::common::window_pantograph(apply(&base, &[])?, a.pantograph.as_deref());
    let (spec, shard) = spec_of(&a, &base)?;
    let search = spec.search(&base);
    let tol = spec.tolerances;
    let (jobs, mine) = spec.jobs(&base).context("in the window sweep")?;
    let fingerprint = spec.fingerprint(&base)?;
    let (od, pb) = crate::sweep_dir::begin(&a.out, &case_text, "window", mine.len(), ctx)?;
    let dir = od.path();
    std::fs::create_dir_all(dir.join("cases"))
        .with_context(|| format!("cannot create {}", dir.join("cases").display()))?;
    let results = spec.run(&base, &mine, &ctx.budget, a.jobs, &|| pb.inc());
    pb.finish();
    let results = results?;
    for c in &results {
        write_case_files(dir, c)?;
    }
    let rows: Vec<&WindowRow> = results.iter().map(|c| &c.row).collect();
    let csv = crate::sweep_dir::rows_csv(HEADER, rows.iter().map(|r| r.to_csv()));
    write_file(&dir.join("window.csv"), &csv)?;
    write_manifest(
        dir,
        "window",
        crate::output::StudyManifest {
            tolerances_pct: Some(tol),
            search_m: Some(search),
            ..crate::sweep_dir::shard_manifest(
                &fingerprint,
                jobs.len(),
                shard,
                mine.iter().map(|j| j.index).collect(),
                COLUMNS,
            )
        },
    )?;
    print_rows(&rows, &tol, &search);
    if shard == Shard::ALL {
        finish(dir)?;
        if let Ok(fit) = std::fs::read_to_string(dir.join("fit.csv")) {
            if let Some(best) = fit.lines().nth(1) {
                let f: Vec<&str> = best.split(',').collect();
                if f[3] == "0" {
                    println!("no energy criterion fitted: no case reached an accuracy-based length (the errors of the longest windows are above)");
                } else {
                    println!(
                        "best energy criterion over the grid: {} (RMS error {} m, largest {} m, {} cases, {} misses)",
                        f[0], f[1], f[2], f[3], f[4]
                    );
                }
            }
        }
    }
    let files = if !a.no_plot && shard == Shard::ALL {
        od.in_target(&crate::plot::redraw_kind(
            dir,
            pcsim_core::study::StudyKind::Window,
        )?)
    } else {
        Vec::new()
    };
    od.commit()?;
    println!(
        "wrote {} and {}",
        shown(&a.out, "window.csv"),
        shown(&a.out, "fit.csv")
    );
    if !files.is_empty() {
        crate::plot::report(&files);
    }
    if a.report {
        println!("report: {}", crate::report::write(&a.out)?.display());
    }
    Ok(0)
}

/// A case's files: the errors of every window tried and its energy curves.
fn write_case_files(dir: &Path, c: &pcsim_core::study::sweeps::WindowCase) -> Result<()> {
    let st = stem(c.job.index, c.job.speed_kmh, c.job.tension_n / 1e3);
    let mut errs = String::from("window_m,mean_err_pct,sigma_err_pct,max_err_pct\n");
    for e in &c.search.evaluated {
        let _ = writeln!(
            errs,
            "{},{:.6},{:.6},{:.6}",
            e.window_m, e.mean_pct, e.sigma_pct, e.max_pct
        );
    }
    write_file(&dir.join("cases").join(format!("{st}_errors.csv")), errs)?;
    let cv = &c.curves;
    let mut en = String::from("window_m,snapshot_j,max_j,mean_j\n");
    for i in 0..cv.window_m.len() {
        let _ = writeln!(
            en,
            "{},{:.9e},{:.9e},{:.9e}",
            cv.window_m[i], cv.snapshot_j[i], cv.max_j[i], cv.mean_j[i]
        );
    }
    write_file(&dir.join("cases").join(format!("{st}_energy.csv")), en)?;
    Ok(())
}

/// The rows on the terminal, with each answer's claim (what was run above it).
fn print_rows(
    rows: &[&WindowRow],
    tol: &Tolerances,
    search: &pcsim_core::study::window_search::SearchSettings,
) {
    println!(
        "accuracy-based window length (mean ±{}%, σ ±{}%, max ±{}% of the full model; {}–{} m, coarse {} m, resolution {} m)",
        tol.mean_pct, tol.sigma_pct, tol.max_pct, search.min_m, search.max_m, search.coarse_m, search.resolution_m
    );
    println!(
        "{:>6} {:>6} {:>5} {:>12} {:>14} {:>14} {:>14}",
        "km/h", "kN", "seed", "length [m]", "EVA step [m]", "EVA 99% [m]", "EVA 99% max"
    );
    for r in rows {
        let show = |v: Option<f64>| v.map_or("—".to_string(), |x| format!("{x:.3}"));
        println!(
            "{:>6} {:>6} {:>5} {:>12} {:>14} {:>14} {:>14}",
            r.speed_kmh,
            r.tension_kn,
            r.seed_offset,
            show(r.length_m),
            show(r.eva_step_m),
            show(r.eva_fraction_m),
            show(r.eva_fraction_max_m)
        );
    }
    for r in rows {
        // Each criterion's error: of the length found, or of the longest window when none is.
        let errors = match (r.length_m, r.mean_err_pct, r.sigma_err_pct, r.max_err_pct) {
            (None, Some(m), Some(s), Some(x)) => {
                format!(": mean {m:+.2} %, σ {s:+.2} %, max {x:+.2} %")
            }
            (Some(l), Some(m), Some(s), Some(x)) => {
                format!("; at {l} m: mean {m:+.2} %, σ {s:+.2} %, max {x:+.2} %")
            }
            _ => String::new(),
        };
        println!(
            "  {} km/h, {} kN, seed {}: {}{errors}",
            r.speed_kmh,
            r.tension_kn,
            r.seed_offset,
            pcsim_core::study::window_search::claim(r.length_m, r.fine_checked_to_m, search)
        );
    }
}

/// Read a case's energy curves back, with the totals of its row.
fn read_curves(dir: &Path, stem: &str, totals: [f64; 3]) -> Result<EnergyCurves> {
    let p = dir.join("cases").join(format!("{stem}_energy.csv"));
    let text =
        std::fs::read_to_string(&p).with_context(|| format!("cannot read {}", p.display()))?;
    let mut c = EnergyCurves {
        window_m: vec![],
        snapshot_j: vec![],
        max_j: vec![],
        mean_j: vec![],
        snapshot_total_j: totals[0],
        max_total_j: totals[1],
        mean_total_j: totals[2],
    };
    for (i, l) in text.lines().enumerate().skip(1) {
        let v: Vec<f64> = l
            .split(',')
            .map(|s| s.parse::<f64>())
            .collect::<Result<_, _>>()
            .with_context(|| format!("{} line {}", p.display(), i + 1))?;
        if v.len() < 4 {
            bail!("{} line {}: need 4 columns", p.display(), i + 1);
        }
        c.window_m.push(v[0]);
        c.snapshot_j.push(v[1]);
        c.max_j.push(v[2]);
        c.mean_j.push(v[3]);
    }
    Ok(c)
}

/// Over the whole grid (after a run or a merge): the fit of every energy criterion against the
/// accuracy-based lengths (`fit.csv`, best first), and the Monte Carlo summary with seeds.
fn finish(dir: &Path) -> Result<()> {
    let p = dir.join("window.csv");
    let text =
        std::fs::read_to_string(&p).with_context(|| format!("cannot read {}", p.display()))?;
    let mut cases = Vec::new();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let col = |name: &str| -> Result<usize> {
        header
            .iter()
            .position(|h| *h == name)
            .with_context(|| format!("{}: no column `{name}`", p.display()))
    };
    let [c_index, c_speed, c_tension, c_length, c_snap, c_max, c_mean] = [
        "index",
        "speed_kmh",
        "tension_kn",
        "length_m",
        "snapshot_total_j",
        "max_total_j",
        "mean_total_j",
    ]
    .map(col);
    let (c_index, c_speed, c_tension, c_length) = (c_index?, c_speed?, c_tension?, c_length?);
    let (c_snap, c_max, c_mean) = (c_snap?, c_max?, c_mean?);
    for l in lines.filter(|l| !l.is_empty()) {
        let f: Vec<&str> = l.split(',').collect();
        if f.len() != header.len() {
            bail!("{}: bad row `{l}`", p.display());
        }
        let num = |i: usize| -> Result<f64> {
            f[i].parse()
                .with_context(|| format!("{}: column `{}` of `{l}`", p.display(), header[i]))
        };
        let index: usize = f[c_index]
            .parse()
            .with_context(|| format!("{}: `{l}`", p.display()))?;
        let st = stem(index, num(c_speed)?, num(c_tension)?);
        let curves = read_curves(dir, &st, [num(c_snap)?, num(c_max)?, num(c_mean)?])?;
        cases.push((f[c_length].parse::<f64>().ok(), curves));
    }
    let refs: Vec<(Option<f64>, &EnergyCurves)> = cases.iter().map(|(a, c)| (*a, c)).collect();
    let fits = fit_criteria(&refs);
    let mut out = String::from("criterion,rms_error_m,max_error_m,cases,misses\n");
    for f in &fits {
        let _ = writeln!(
            out,
            "{},{:.3},{:.3},{},{}",
            f.criterion, f.rms_error_m, f.max_error_m, f.cases, f.misses
        );
    }
    write_file(&dir.join("fit.csv"), out)?;
    write_montecarlo(
        dir,
        "window.csv",
        &["speed_kmh", "tension_kn"],
        &["length_m", "eva_step_m", "eva_fraction_m"],
    )
}
