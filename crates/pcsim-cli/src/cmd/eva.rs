//! `pcsim eva`: EVA sweeps over speed, tension and damping, in parallel, with shards and merge.

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use pcsim_core::analysis::eva::{run_eva, EvaOutput, EvaRow, EvaSettings};
use pcsim_core::analysis::sweep::{merge_rows, parse_damping, Grid, Job, Shard};
use pcsim_core::Setup;
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
    let base = crate::common::load_case(a.case.as_ref(), a.preset.as_deref())?;
    let dampings = a
        .damping
        .iter()
        .map(|d| parse_damping(d, &base.catenary.damping))
        .collect::<Result<Vec<_>, _>>()?;
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
    let shard = match &a.shard {
        None => Shard::ALL,
        Some(s) => Shard::parse(s)?,
    };
    let grid = Grid::new(
        base,
        a.speed.clone(),
        a.tension.iter().map(|t| t * 1e3).collect(),
        dampings,
    );
    let jobs = grid.jobs()?;
    let mine: Vec<&Job> = jobs.iter().filter(|j| shard.contains(j.index)).collect();
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
    let results = pcsim_core::analysis::sweep::parallel_map(&mine, a.jobs, |job| {
        let setup = Setup::from_case(&job.case)?;
        let out = run_eva(&setup, &settings, &mut |_| true)
            .map_err(|e| anyhow::anyhow!("case {}: {e}", job.index))?;
        write_case_files(&a.out, job, &out)?;
        pb.inc(1);
        Ok::<_, anyhow::Error>(out)
    });
    pb.finish_and_clear();
    let done: Vec<EvaOutput> = results.into_iter().collect::<Result<_>>()?;
    let rows: Vec<EvaRow> = mine
        .iter()
        .zip(&done)
        .map(|(j, o)| EvaRow::new(j.index, j.speed_kmh, j.tension_n / 1e3, &j.damping, o))
        .collect();
    let mut csv = String::from(EvaRow::HEADER);
    csv.push('\n');
    for r in &rows {
        csv.push_str(&r.to_csv());
        csv.push('\n');
    }
    std::fs::write(a.out.join("eva.csv"), &csv)?;
    println!(
        "EVA (Δd = {} m, tolerance {} J, fraction {}), snapshot at {} m; window energies in J",
        a.step,
        a.tol,
        a.fraction,
        done.first().map(|d| d.snapshot_at_m).unwrap_or(0.0)
    );
    println!(
        "{:>6} {:>8} {:<22} {:>12} {:>12} {:>14} {:>12}",
        "km/h", "kN", "damping", "EVA step [m]", "EVA 99% [m]", "converged [J]", "total [J]"
    );
    for r in &rows {
        let f = |v: Option<f64>| v.map(|x| format!("{x:.1}")).unwrap_or_else(|| "—".into());
        println!(
            "{:>6} {:>8} {:<22} {:>12} {:>12} {:>14} {:>12.3}",
            r.speed_kmh,
            r.tension_kn,
            r.damping,
            f(r.eva_step_m),
            f(r.eva_fraction_m),
            f(r.converged_energy_j),
            r.total_energy_j
        );
    }
    println!(
        "wrote {}/eva.csv and {}/cases/",
        a.out.display(),
        a.out.display()
    );
    if !a.no_plot && shard == Shard::ALL {
        let cases: Vec<_> = mine
            .iter()
            .zip(&done)
            .map(|(j, o)| (j.speed_kmh, j.tension_n / 1e3, j.damping.clone(), o))
            .collect();
        let files = crate::plot::eva::draw_eva(&a.out, &cases)?;
        crate::plot::report(&files);
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
        if lines.next() != Some(EvaRow::HEADER) {
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
    let rows = merge_rows(rows)?;
    std::fs::create_dir_all(out)?;
    let mut csv = String::from(EvaRow::HEADER);
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
