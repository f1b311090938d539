//! `pcsim eva`: EVA sweeps over speed, tension and damping, in parallel, with shards and merge.

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use pcsim_core::case::Damping;
use pcsim_core::eva::{run_eva, EvaOutput, EvaSettings};
use pcsim_core::model::Model;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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
    /// Speeds, km/h (comma-separated). Default: the case's speed.
    #[arg(long, value_delimiter = ',')]
    speed: Vec<f64>,
    /// Contact-wire tensions, kN (comma-separated). Default: the case's tension.
    #[arg(long, value_delimiter = ',')]
    tension: Vec<f64>,
    /// Dampings (comma-separated): `preset`, `rayleigh:ALPHA:BETA` or `modal:RATIO`.
    #[arg(long, value_delimiter = ',', default_value = "preset")]
    damping: Vec<String>,
    /// Output directory.
    #[arg(long, default_value = "out/eva")]
    out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    jobs: Option<usize>,
    /// Run only the cases with index ≡ I (mod N), as `I/N`.
    #[arg(long)]
    shard: Option<String>,
    /// Step Δd between window lengths, m.
    #[arg(long, default_value_t = 1.0)]
    step: f64,
    /// Tolerance of the paper's criterion, J.
    #[arg(long, default_value_t = 0.01)]
    tol: f64,
    /// Energy fraction of the step-independent criterion.
    #[arg(long, default_value_t = 0.99)]
    fraction: f64,
    /// Largest window length, m (default: the model length).
    #[arg(long)]
    max_window: Option<f64>,
    /// Snapshot position of the leading pantograph, m (default: mid-model).
    #[arg(long)]
    snapshot_at: Option<f64>,
    /// No plots.
    #[arg(long)]
    no_plot: bool,
}

#[derive(Subcommand)]
enum EvaSub {
    /// Join the eva.csv (and case files) of shard directories into one.
    Merge {
        /// Shard output directories.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Merged output directory.
        #[arg(long, default_value = "out/eva")]
        out: PathBuf,
    },
}

/// One case of the grid.
#[derive(Clone)]
struct Job {
    index: usize,
    speed_kmh: f64,
    tension_kn: f64,
    damping: String,
}

fn parse_damping(s: &str, preset: &Damping) -> Result<Damping> {
    let parts: Vec<&str> = s.split(':').collect();
    let num = |x: &str| -> Result<f64> {
        let v: f64 = x
            .parse()
            .with_context(|| format!("--damping `{s}`: `{x}` is not a number"))?;
        if !(v.is_finite() && v >= 0.0) {
            bail!("--damping `{s}`: values must be finite and ≥ 0");
        }
        Ok(v)
    };
    Ok(match parts.as_slice() {
        ["preset"] => preset.clone(),
        ["rayleigh", a, b] => Damping::Rayleigh {
            alpha: num(a)?,
            beta: num(b)?,
        },
        ["modal", z] => Damping::Modal { ratio: num(z)? },
        _ => bail!("--damping `{s}`: use `preset`, `rayleigh:ALPHA:BETA` or `modal:RATIO`"),
    })
}

fn damping_label(d: &Damping) -> String {
    match d {
        Damping::Rayleigh { alpha, beta } => format!("rayleigh:{alpha}:{beta}"),
        Damping::Modal { ratio } => format!("modal:{ratio}"),
    }
}

const HEADER: &str = "index,speed_kmh,tension_kn,damping,step_m,tolerance_j,fraction,eva_step_m,eva_fraction_m,converged_energy_j,total_energy_j,eva_step_max_m,eva_fraction_max_m,eva_step_mean_m,eva_fraction_mean_m";

fn opt(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.3}")).unwrap_or_default()
}

fn row(job: &Job, o: &EvaOutput) -> String {
    let s = &o.settings;
    format!(
        "{},{},{},{},{},{},{},{},{},{},{:.6},{},{},{},{}",
        job.index,
        job.speed_kmh,
        job.tension_kn,
        job.damping,
        s.step_m,
        s.tolerance_j,
        s.fraction,
        opt(o.snapshot.eva_step_m),
        opt(o.snapshot.eva_fraction_m),
        o.snapshot
            .converged_j
            .map(|x| format!("{x:.6}"))
            .unwrap_or_default(),
        o.snapshot.total_j,
        opt(o.max.eva_step_m),
        opt(o.max.eva_fraction_m),
        opt(o.mean.eva_step_m),
        opt(o.mean.eva_fraction_m),
    )
}

fn case_stem(job: &Job) -> String {
    format!(
        "case{:04}_v{}_t{}",
        job.index, job.speed_kmh, job.tension_kn
    )
}

fn write_case_files(dir: &Path, job: &Job, o: &EvaOutput) -> Result<()> {
    let cdir = dir.join("cases");
    std::fs::create_dir_all(&cdir)?;
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
    std::fs::write(cdir.join(format!("{}_distribution.csv", case_stem(job))), s)?;
    let mut s = String::from("window_m,snapshot_j,max_j,mean_j\n");
    for i in 0..o.window_m.len() {
        let _ = writeln!(
            s,
            "{},{:.6},{:.6},{:.6}",
            o.window_m[i], o.snapshot.window_j[i], o.max.window_j[i], o.mean.window_j[i]
        );
    }
    std::fs::write(cdir.join(format!("{}_window.csv", case_stem(job))), s)?;
    Ok(())
}

pub fn eva(a: EvaArgs, quiet: bool) -> Result<i32> {
    if let Some(EvaSub::Merge { dirs, out }) = a.sub {
        return merge(&dirs, &out);
    }
    let base = crate::commands::load_case(a.case.as_ref(), a.preset.as_deref())?;
    let speeds = if a.speed.is_empty() {
        vec![base.run.speed_kmh]
    } else {
        a.speed.clone()
    };
    let tensions = if a.tension.is_empty() {
        vec![base.catenary.contact_wire.tension_n / 1e3]
    } else {
        a.tension.clone()
    };
    let dampings: Vec<(String, Damping)> = a
        .damping
        .iter()
        .map(|d| parse_damping(d, &base.catenary.damping).map(|x| (damping_label(&x), x)))
        .collect::<Result<_>>()?;
    for (name, v) in [
        ("--step", a.step),
        ("--tol", a.tol),
        ("--max-window", a.max_window.unwrap_or(1.0)),
    ] {
        if !(v.is_finite() && v > 0.0) {
            bail!("{name} = {v}: must be a finite number > 0");
        }
    }
    if !(a.fraction > 0.0 && a.fraction < 1.0) {
        bail!("--fraction = {}: must lie in (0, 1)", a.fraction);
    }
    let (shard_i, shard_n) = match &a.shard {
        None => (0, 1),
        Some(s) => {
            let (i, n) = s
                .split_once('/')
                .with_context(|| format!("--shard `{s}`: use I/N, e.g. 0/4"))?;
            let (i, n): (usize, usize) = (
                i.trim().parse().context("--shard I")?,
                n.trim().parse().context("--shard N")?,
            );
            if n == 0 || i >= n {
                bail!("--shard `{s}`: need 0 ≤ I < N");
            }
            (i, n)
        }
    };
    let mut jobs = Vec::new();
    let mut cases = Vec::new();
    for (dl, d) in &dampings {
        for &t in &tensions {
            for &v in &speeds {
                let index = jobs.len();
                let mut c = base.clone();
                c.run.speed_kmh = v;
                c.catenary.contact_wire.tension_n = t * 1e3;
                c.catenary.damping = d.clone();
                // Validate every case up front: a bad grid point fails before any work is done.
                Model::from_case(&c)
                    .with_context(|| format!("case {index}: {v} km/h, {t} kN, {dl}"))?;
                jobs.push(Job {
                    index,
                    speed_kmh: v,
                    tension_kn: t,
                    damping: dl.clone(),
                });
                cases.push(c);
            }
        }
    }
    let mine: Vec<usize> = (0..jobs.len()).filter(|i| i % shard_n == shard_i).collect();
    let settings = EvaSettings {
        step_m: a.step,
        max_window_m: a.max_window,
        tolerance_j: a.tol,
        fraction: a.fraction,
        snapshot_at_m: a.snapshot_at,
        ..EvaSettings::default()
    };
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let pb = crate::progress::styled(
        mine.len() as u64,
        "eva [{bar:40}] {pos}/{len} cases {elapsed_precise} eta {eta}",
        quiet,
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.jobs.unwrap_or(0))
        .build()?;
    let results: Vec<Result<(usize, EvaOutput)>> = pool.install(|| {
        mine.par_iter()
            .map(|&i| {
                let (model, _) = Model::from_case(&cases[i])?;
                let out = run_eva(model, &settings, &mut |_| true)
                    .map_err(|e| anyhow::anyhow!("case {i}: {e}"))?;
                write_case_files(&a.out, &jobs[i], &out)?;
                pb.inc(1);
                Ok((i, out))
            })
            .collect()
    });
    pb.finish_and_clear();
    let mut done: Vec<(usize, EvaOutput)> = results.into_iter().collect::<Result<_>>()?;
    done.sort_by_key(|(i, _)| *i);
    let mut csv = String::from(HEADER);
    csv.push('\n');
    for (i, o) in &done {
        csv.push_str(&row(&jobs[*i], o));
        csv.push('\n');
    }
    std::fs::write(a.out.join("eva.csv"), &csv)?;
    println!(
        "EVA (Δd = {} m, tolerance {} J, fraction {}), snapshot at {} m; window energies in J",
        a.step,
        a.tol,
        a.fraction,
        done.first().map(|d| d.1.snapshot_at_m).unwrap_or(0.0)
    );
    println!(
        "{:>6} {:>8} {:<22} {:>12} {:>12} {:>14} {:>12}",
        "km/h", "kN", "damping", "EVA step [m]", "EVA 99% [m]", "converged [J]", "total [J]"
    );
    for (i, o) in &done {
        let j = &jobs[*i];
        let f = |v: Option<f64>| v.map(|x| format!("{x:.1}")).unwrap_or_else(|| "—".into());
        println!(
            "{:>6} {:>8} {:<22} {:>12} {:>12} {:>14} {:>12.3}",
            j.speed_kmh,
            j.tension_kn,
            j.damping,
            f(o.snapshot.eva_step_m),
            f(o.snapshot.eva_fraction_m),
            f(o.snapshot.converged_j),
            o.snapshot.total_j
        );
    }
    println!(
        "wrote {}/eva.csv and {}/cases/",
        a.out.display(),
        a.out.display()
    );
    if !a.no_plot && shard_n == 1 {
        let files = crate::plots::draw_eva(
            &a.out,
            &done
                .iter()
                .map(|(i, o)| {
                    (
                        jobs[*i].speed_kmh,
                        jobs[*i].tension_kn,
                        jobs[*i].damping.clone(),
                        o,
                    )
                })
                .collect::<Vec<_>>(),
        )?;
        crate::plots::report(&files);
    }
    Ok(0)
}

/// Join shard directories: rows sorted by case index, each index once.
fn merge(dirs: &[PathBuf], out: &Path) -> Result<i32> {
    let mut rows: Vec<(usize, String)> = Vec::new();
    for d in dirs {
        let p = d.join("eva.csv");
        let text =
            std::fs::read_to_string(&p).with_context(|| format!("cannot read {}", p.display()))?;
        let mut lines = text.lines();
        if lines.next() != Some(HEADER) {
            bail!(
                "{} is not an eva.csv of this version of pcsim (header differs)",
                p.display()
            );
        }
        for l in lines.filter(|l| !l.is_empty()) {
            let idx: usize = l
                .split(',')
                .next()
                .and_then(|s| s.parse().ok())
                .with_context(|| format!("{}: bad row `{l}`", p.display()))?;
            rows.push((idx, l.to_string()));
        }
        let cdir = d.join("cases");
        if cdir.is_dir() {
            std::fs::create_dir_all(out.join("cases"))?;
            for e in std::fs::read_dir(&cdir)? {
                let e = e?;
                std::fs::copy(e.path(), out.join("cases").join(e.file_name()))?;
            }
        }
    }
    rows.sort_by_key(|r| r.0);
    for w in rows.windows(2) {
        if w[0].0 == w[1].0 {
            bail!("case {} appears in more than one shard", w[0].0);
        }
    }
    if let Some(missing) = rows.iter().enumerate().find(|(k, r)| *k != r.0) {
        bail!("case {} is missing from the shards", missing.0);
    }
    std::fs::create_dir_all(out)?;
    let mut csv = String::from(HEADER);
    csv.push('\n');
    for (_, r) in &rows {
        csv.push_str(r);
        csv.push('\n');
    }
    std::fs::write(out.join("eva.csv"), csv)?;
    println!(
        "merged {} cases from {} shards into {}/eva.csv",
        rows.len(),
        dirs.len(),
        out.display()
    );
    Ok(0)
}
